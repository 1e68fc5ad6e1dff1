// The membrane's strain from a reference map (strain_model = "reference_map";
// solver/membrane/reference_map.hpp, NormalExtension::apply_reference_map). It must
//  - give Gs = A P_R A^T exactly for a linear map X = A^-1 (x - c), at the current normal;
//  - rebuild, from a map known only in the band's core and constant along the normals, the
//    surface's Gs in the whole band (to second order in h / R), tangential (Gs n = 0 to
//    round-off), and I beyond the band;
//  - start from X = x at the surface's rest state: Gs = P to second order;
//  - agree on 1 and 2 ranks;
//  - with a reference shape (map_projection), put a map that has drifted off the reference
//    surface back onto it.
#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "core/matrix3.hpp"
#include "interface/shapes.hpp"
#include "membrane/kinematics.hpp"
#include "membrane/normal_extension.hpp"
#include "membrane/reference_map.hpp"
#include "membrane_test_grid.hpp"
#include "operators/flow_operators.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace efsi;

namespace {

using efsi::test::GridSetup;

const Real3 kCentre{0.011, -0.017, 0.013};
constexpr real kRadius = 0.4;

/// A general (non-symmetric) deformation A; its 2D restriction keeps z unstretched.
Matrix3 deformation(int dim) {
    Matrix3 A{{{1.3, 0.25, -0.1}, {-0.15, 0.8, 0.2}, {0.05, 0.1, 1.15}}};
    if (dim == 2) A[0][2] = A[1][2] = A[2][0] = A[2][1] = 0, A[2][2] = 1;
    return A;
}

Matrix3 product(const Matrix3& a, const Matrix3& b) {
    Matrix3 c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                c[i][j] += a[i][k] * b[k][j];
    return c;
}

Real3 unit(Real3 v) {
    const real l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / l, v[1] / l, v[2] / l};
}

/// A P_R A^T for the reference normal N.
Matrix3 exact_gs(const Matrix3& A, const Real3& N) {
    Matrix3 P = identity_matrix();
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            P[a][b] -= N[a] * N[b];
    return product(product(A, P), transpose(A));
}

} // namespace

TEST(ReferenceMap, LinearMapGivesAPrAt) {
    for (int dim : {2, 3}) {
        const Matrix3 A = deformation(dim);
        const Matrix3 Ai = inverse(A);
        for (const Real3 N0 : {Real3{1, 0, 0}, Real3{0.3, -0.7, 0.5}, Real3{-0.2, 0.9, -0.4}}) {
            Real3 N = N0;
            if (dim == 2) N[2] = 0;
            N = unit(N);
            // The current normal: A^-T N, normalised.
            const Real3 n = unit(mat_vec(transpose(Ai), N));
            const Matrix3 G = surface_tensor_from_map(Ai, n, dim);
            const Matrix3 E = exact_gs(A, N);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    EXPECT_NEAR(G[a][b], E[a][b], 1e-13) << "dim " << dim << " (" << a << b << ")";
            const Real3 gn = mat_vec(G, n);
            for (int a = 0; a < 3; ++a)
                EXPECT_NEAR(gn[a], 0.0, 1e-14);
        }
    }
}

// The copy's turn into a cell's tangent plane (normal_extension.cpp, step 3): a surface
// tensor lying in the plane normal to m, turned to the plane normal to n, lies in that plane
// (G n = 0), keeps its trace and area ratio and is the same tensor when m = n; the projection
// P G P it replaces loses area as the cosine of the tilt.
TEST(ReferenceMap, TurnIntoPlaneKeepsTraceAndArea) {
    for (int dim : {2, 3}) {
        const Matrix3 A = deformation(dim);
        const Real3 N = dim == 3 ? unit(Real3{0.3, -0.7, 0.5}) : unit(Real3{0.6, -0.8, 0});
        const Matrix3 G = exact_gs(A, N);
        const Real3 gm = unit(mat_vec(transpose(inverse(A)), N)); // G gm = 0
        for (real tilt : {0.0, 0.2, 0.8}) {
            // n: gm turned by `tilt` radians about an axis normal to it (in-plane in 2D).
            const Real3 e = dim == 3 ? unit(Real3{gm[1], -gm[0], 0}) : Real3{-gm[1], gm[0], 0};
            Real3 n{};
            for (int a = 0; a < 3; ++a)
                n[a] = std::cos(tilt) * gm[a] + std::sin(tilt) * e[a];
            const Matrix3 T = turned_into_plane(G, n, dim);
            const Real3 tn = mat_vec(T, n);
            for (int a = 0; a < 3; ++a)
                EXPECT_NEAR(tn[a], 0.0, 1e-12) << "dim " << dim << " tilt " << tilt;
            EXPECT_NEAR(T[0][0] + T[1][1] + T[2][2], G[0][0] + G[1][1] + G[2][2], 1e-12);
            EXPECT_NEAR(second_invariant(T), second_invariant(G), 1e-12);
            if (tilt == 0.0) {
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        EXPECT_NEAR(T[a][b], G[a][b], 1e-13);
            }
            if (dim == 3 && tilt > 0) {
                // The projection keeps less area than G has.
                const Matrix3 P = tangential_part(G, n, dim);
                EXPECT_LT(second_invariant(P), second_invariant(G) * std::cos(tilt) + 1e-12);
            }
        }
    }
}

namespace {

struct Result {
    real band_error = 0; ///< max |Gs - Gs(foot point)| over the band
    real normal_leak = 0;
    real beyond = 0; ///< max |Gs - I| beyond the reach (outside)
    /// Over the band beyond the core: (|X - c| - R) / R, the map's radial error (its mean
    /// and its largest magnitude); with A = I the exact map lies on the sphere.
    real radial_mean = 0, radial_max = 0;
    /// Over the band, the area ratio J = sqrt(II(Gs)) against the exact one (1 for A = I):
    /// the mean error (a bias) and the largest |J - mean of its 2 dim neighbours| (grid-scale
    /// roughness).
    real area_bias = 0, area_roughness = 0;
};

/// Deterministic noise in [-1, 1] per cell and direction.
real noise(int i, int j, int k, int d) {
    std::uint32_t h = std::uint32_t(i) * 73856093u ^ std::uint32_t(j) * 19349663u ^
                      std::uint32_t(k) * 83492791u ^ std::uint32_t(d + 1) * 2654435761u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return real(h % 20001u) / 10000.0 - 1.0;
}

/// A sphere of radius R = 8 m cells carrying the map X(x) = c + A^-1 (cp(x) - c) (cp the
/// closest point): known near the core (and garbage elsewhere) when `rest` is
/// false; X = x everywhere and the whole band extended when `rest` is true (A = I).
/// `shrink`: the core's map scaled by 1 - shrink about the centre (a map drifted inward);
/// `project`: the extension projects onto the reference sphere (a disc in 2D).
/// `area_filter`: the extension's low-passed area ratio; `jitter`: noise of this amplitude
/// (in cells) added to the core's map.
/// `stretch`: phi's profile drawn out by this factor (psi = distance / stretch, |grad psi| =
/// 1 / stretch); `newton`: the extension's Newton foot points.
Result run(int dim, int m, bool rest, bool identity = false, bool cubic = true, real shrink = 0,
           bool project = false, bool area_filter = false, real jitter = 0, real stretch = 1,
           bool newton = false) {
    const real h = 0.05 / m;
    GridSetup s = efsi::test::make_setup(dim, {32 * m, 34 * m, 30 * m}, h, BoundaryType::Periodic);
    Body body("capsule", BodyKind::Membrane, false, dim, true, /*reference_map=*/true);
    body.allocate(make_patch(Box{{0, 0, 0}, s.g.cells}, *s.dec));
    const real eps = h;
    const Matrix3 A = rest || identity ? identity_matrix() : deformation(dim);
    const Matrix3 Ai = inverse(A);
    auto radial = [&](const Real3& x) {
        Real3 r{x[0] - kCentre[0], x[1] - kCentre[1], dim == 3 ? x[2] - kCentre[2] : 0.0};
        return r;
    };
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const Real3 r = radial(x);
        const real rr = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        const real sd = rr - kRadius;
        const real v = 0.5 * (1 - std::tanh(sd / (stretch * eps)));
        body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
        // The core and a margin the trilinear stencil around a foot point reads (up to
        // sqrt(3) h from the surface; in a run these cells hold the previous extension).
        const bool core = std::abs(sd) <= 1.0 * h + 3.6 * h;
        Real3 cp{0, 0, 0}; // closest point minus c
        for (int d = 0; d < dim; ++d)
            cp[d] = r[d] * kRadius / rr;
        Real3 X = mat_vec(Ai, cp); // minus c
        for (int d = 0; d < dim; ++d)
            X[d] *= 1 - shrink;
        for (int d = 0; d < dim; ++d)
            body.reference_map()[d](i, j, k) =
                rest ? 0.0
                     : (core ? X[d] + kCentre[d] - x[d] + jitter * h * noise(i, j, k, d)
                             : 0.37 * (d + 1));
    });
    s.halos->fill(body.phi(), body.patch());
    NormalExtension ext(*s.halos, "capsule", 1.0, 1.0, -1, cubic, area_filter, newton);
    const std::unique_ptr<Shape> sphere =
        dim == 3 ? make_sphere(kCentre, kRadius) : make_cylinder(kCentre, kRadius);
    ext.apply_reference_map(body, rest, project ? sphere.get() : nullptr);
    Result res;
    const real band = std::atanh(1 - 2e-5) * eps;
    const real reach = ext.reach_cells() * h;
    const SymmetricTensorField& G = body.tensor();
    real radial_sum = 0, radial_count = 0, area_sum = 0, area_count = 0;
    auto area_ratio = [&](const Int3& p) {
        Matrix3 gs{};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                gs[a][b] = G.value(a, b, p);
        return std::sqrt(std::max(second_invariant(gs), real(0)));
    };
    // J of A P_R A^T with A = I and of the rest state is 1 (the roughness test needs no more).
    const bool unit_area = rest || identity;
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const Real3 r = radial(x);
        const real rr = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        const real sd = rr - kRadius;
        const Int3 p{i, j, k};
        const Real3 n = unit(r);
        if (std::abs(sd) <= band && rr > 0.5 * kRadius) {
            // At the foot point the reference normal is A^T n (normalised): Gs = A P_R A^T.
            const Matrix3 E = exact_gs(A, unit(mat_vec(transpose(A), n)));
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    const real e = std::abs(G.value(a, b, p) - E[a][b]);
                    res.band_error = std::max(res.band_error, e);
                }
            // Gs n with the grid's own normal (central differences of psi, as the extension).
            auto psi = [&](int di, int dj, int dk) {
                const real v =
                    std::clamp(1 - 2 * body.phi()(i + di, j + dj, k + dk), -1 + 1e-15, 1 - 1e-15);
                return eps * std::atanh(v);
            };
            Real3 gp{psi(1, 0, 0) - psi(-1, 0, 0), psi(0, 1, 0) - psi(0, -1, 0),
                     dim == 3 ? psi(0, 0, 1) - psi(0, 0, -1) : 0.0};
            gp = unit(gp);
            for (int a = 0; a < 3; ++a) {
                real gn = 0;
                for (int b = 0; b < 3; ++b)
                    gn += G.value(a, b, p) * gp[b];
                res.normal_leak = std::max(res.normal_leak, std::abs(gn));
            }
        }
        // The band's inner part (|psi| <= 4 eps, phi in [3e-4, 1 - 3e-4]): J and its neighbours'.
        if (std::abs(sd) <= 4 * eps && rr > 0.5 * kRadius) {
            const real J = area_ratio(p);
            if (unit_area) {
                area_sum += J - 1;
                area_count += 1;
            }
            real mean = 0;
            for (int d = 0; d < dim; ++d)
                mean += area_ratio(shifted(p, d, 1)) + area_ratio(shifted(p, d, -1));
            mean /= 2 * dim;
            res.area_roughness = std::max(res.area_roughness, std::abs(J - mean));
        }
        if (std::abs(sd) > 1.5 * h && std::abs(sd) <= band) {
            real X2 = 0;
            for (int d = 0; d < dim; ++d) {
                const real Xd = body.reference_map()[d](i, j, k) + x[d] - kCentre[d];
                X2 += Xd * Xd;
            }
            const real e = (std::sqrt(X2) - kRadius) / kRadius;
            radial_sum += e;
            radial_count += 1;
            res.radial_max = std::max(res.radial_max, std::abs(e));
        }
        if (sd > reach + 0.5 * h)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    res.beyond =
                        std::max(res.beyond, std::abs(G.value(a, b, p) - (a == b ? 1.0 : 0.0)));
    });
    res.band_error = efsi::test::global_max(res.band_error);
    res.normal_leak = efsi::test::global_max(res.normal_leak);
    res.beyond = efsi::test::global_max(res.beyond);
    res.radial_max = efsi::test::global_max(res.radial_max);
    res.radial_mean =
        efsi::test::global_sum_real(radial_sum) / efsi::test::global_sum_real(radial_count);
    if (unit_area)
        res.area_bias =
            efsi::test::global_sum_real(area_sum) / efsi::test::global_sum_real(area_count);
    res.area_roughness = efsi::test::global_max(res.area_roughness);
    return res;
}

} // namespace

TEST(ReferenceMap, BandHoldsTheSurfaceStrainToSecondOrder) {
    for (int dim : {2, 3}) {
        const Result coarse = run(dim, 1, false);
        const Result fine = run(dim, 2, false);
        // Gs from X near the surface, then copied along the normals (trilinear): measured
        // 0.036 / 0.0115 at R = 8 / 16 cells in 3D (order 1.66), 2D below it.
        EXPECT_LT(fine.band_error, 1.5e-2) << "dim " << dim;
        const real order = std::log2(coarse.band_error / fine.band_error);
        EXPECT_GT(order, 1.5) << "dim " << dim << ": errors " << coarse.band_error << ", "
                              << fine.band_error;
        EXPECT_LT(coarse.normal_leak, 1e-12) << "dim " << dim;
        EXPECT_EQ(coarse.beyond, 0.0) << "dim " << dim;
    }
}

TEST(ReferenceMap, RestStateFromXEqualsXIsTheProjection) {
    for (int dim : {2, 3}) {
        const Result coarse = run(dim, 1, true);
        const Result fine = run(dim, 2, true);
        EXPECT_LT(fine.band_error, 1.5e-2) << "dim " << dim;
        const real order = std::log2(coarse.band_error / fine.band_error);
        EXPECT_GT(order, 1.7) << "dim " << dim << ": errors " << coarse.band_error << ", "
                              << fine.band_error;
    }
}

// The extension copies the map from the core to the foot points. Its error there is not
// noise: the trilinear interpolant of a map lying on a curved surface falls inside it (by
// ~h^2 / (8 R) per step), and the core's transport reads the extended cells, so the stored
// map shrank and the membrane's strain grew by ~0.2 % per shear time in the d/16 capsule
// (docs/method.md, "The reference map"). The cubic interpolant's error is O(h^4).
TEST(ReferenceMap, CubicExtensionKeepsTheMapOnTheSurface) {
    for (int dim : {2, 3}) {
        const Result lin1 = run(dim, 1, false, true, false);
        const Result lin2 = run(dim, 2, false, true, false);
        const Result cub1 = run(dim, 1, false, true, true);
        const Result cub2 = run(dim, 2, false, true, true);
        // Trilinear: biased inward, second order.
        EXPECT_LT(lin1.radial_mean, 0.0) << "dim " << dim;
        EXPECT_GT(std::log2(lin1.radial_max / lin2.radial_max), 1.5) << "dim " << dim;
        // Cubic: at least ten times smaller at R = 8 cells, and of higher order.
        EXPECT_LT(cub1.radial_max, 0.1 * lin1.radial_max)
            << "dim " << dim << ": " << cub1.radial_max << " vs " << lin1.radial_max;
        EXPECT_GT(std::log2(cub1.radial_max / cub2.radial_max), 3.0)
            << "dim " << dim << ": " << cub1.radial_max << ", " << cub2.radial_max;
        EXPECT_LT(std::abs(cub1.radial_mean), 0.1 * std::abs(lin1.radial_mean)) << "dim " << dim;
    }
}

// A profile drawn out to |grad psi| = 1 / 1.4 (as the flow leaves a red cell's trailing rim,
// docs/method.md "What tears the trailing rim"): psi is then 1 / 1.4 of the distance, so the
// foot point psi along the normal falls short of the surface and the band's outer cells hold
// no strain. The Newton foot point, psi / |grad psi| along it, lands on the surface; the band
// then holds the surface's strain as accurately as with a resolved profile.
TEST(ReferenceMap, NewtonFootPointsFindADrawnOutSurface) {
    for (int dim : {2, 3}) {
        const Result resolved = run(dim, 1, false);
        const Result resolved_newton = run(dim, 1, false, false, true, 0, false, false, 0, 1, true);
        const Result plain = run(dim, 1, false, false, true, 0, false, false, 0, 1.4, false);
        const Result newton = run(dim, 1, false, false, true, 0, false, false, 0, 1.4, true);
        // A resolved profile: the same foot points either way (|grad psi| = 1 to O(h^2)).
        EXPECT_LT(std::abs(resolved_newton.band_error - resolved.band_error),
                  0.1 * resolved.band_error)
            << "dim " << dim;
        EXPECT_GT(plain.band_error, 0.5) << "dim " << dim;
        EXPECT_LT(newton.band_error, 2 * resolved.band_error)
            << "dim " << dim << ": " << newton.band_error << " vs " << resolved.band_error;
        EXPECT_LT(newton.normal_leak, 1e-12) << "dim " << dim;
    }
}

// A map that has drifted inward (the core's X scaled by 1 - 0.01 about the centre, the
// membrane then 2 % over-stretched) and is extended and projected onto the reference sphere
// holds the band's strain of the map that never drifted, to round-off (the projection along
// the radius undoes a radial scaling exactly; 2D's Newton steps stop at |level| < 1e-13 of
// the radius, and Gs differences X over h ~ R / 256), and lies on the sphere.
TEST(ReferenceMap, ProjectionPutsADriftedMapBackOnTheReferenceSurface) {
    for (int dim : {2, 3}) {
        const Result drifted = run(dim, 1, false, true, true, 0.01, false);
        const Result projected = run(dim, 1, false, true, true, 0.01, true);
        const Result exact = run(dim, 1, false, true, true, 0.0, true);
        EXPECT_GT(drifted.radial_max, 0.009) << "dim " << dim;
        EXPECT_LT(projected.radial_max, 1e-13) << "dim " << dim;
        EXPECT_GT(drifted.band_error, 0.02) << "dim " << dim;
        EXPECT_NEAR(projected.band_error, exact.band_error, 1e-10) << "dim " << dim;
        EXPECT_LT(projected.band_error, 0.5 * drifted.band_error) << "dim " << dim;
    }
}

// The area ratio J of the strain rebuilt from an undeformed map (A = I: J = 1 exactly). The
// copy to the band takes a mean of the Gs tensors around each foot point, whose tangent
// planes turn from cell to cell: that mean loses area (J ~0.2 % low at R = 8 cells in 3D, a
// prestress of 0.2 % of the area modulus, 11 % of Es for a Skalak membrane with C = 100).
// With the area filter each cell's J is set to the mean of the scalar J instead: no bias
// beyond 2e-4 (with second-order differences of X it was 0.4 % high: hence fourth order).
TEST(ReferenceMap, UndeformedMapHasUnitAreaRatio) {
    for (int dim : {2, 3}) {
        const Result plain = run(dim, 1, false, true, true, 0.0, false, false);
        const Result filtered = run(dim, 1, false, true, true, 0.0, false, true);
        EXPECT_LT(plain.area_bias, -1e-3) << "dim " << dim;
        EXPECT_LT(std::abs(filtered.area_bias), 2e-4)
            << "dim " << dim << ": " << filtered.area_bias;
    }
}

// Grid-scale noise in the map (0.01 cell in the core) gives the rebuilt strain a rough area
// ratio; the area filter's (1, 2, 1) mean removes most of it (the grid-scale area mode grew
// in an area-stiff membrane: docs/method.md, "The area ratio, low-passed").
TEST(ReferenceMap, AreaFilterSmoothsAGridScaleAreaRatio) {
    for (int dim : {2, 3}) {
        const Result smooth = run(dim, 1, false, true, true, 0.0, false, false, 0.0);
        const Result rough = run(dim, 1, false, true, true, 0.0, false, false, 0.01);
        const Result filtered = run(dim, 1, false, true, true, 0.0, false, true, 0.01);
        EXPECT_GT(rough.area_roughness, 5 * smooth.area_roughness) << "dim " << dim;
        EXPECT_LT(filtered.area_roughness, 0.5 * rough.area_roughness)
            << "dim " << dim << ": " << filtered.area_roughness << " vs " << rough.area_roughness;
        EXPECT_LT(std::abs(filtered.area_bias), 1e-3) << "dim " << dim;
    }
}

// A thin slab (the middle of a strongly deformed capsule, a red cell's dimple) whose phi is
// the product of its two faces' profiles, as transport leaves it: in the middle, psi is
// shallower than the distance, so a cell's foot point x - psi n lands inside the slab, off
// the surface. Such cells hold no strain (Gs = 0, which the force leaves out); every cell
// whose foot point is on the surface holds the rest strain P. Both kinds must occur.
TEST(ReferenceMap, FootPointOffTheSurfaceHoldsNoStrain) {
    const real h = 0.01;
    GridSetup s = efsi::test::make_setup(3, {24, 40, 24}, h, BoundaryType::Periodic);
    Body body("slab", BodyKind::Membrane, false, 3, true, /*reference_map=*/true);
    body.allocate(make_patch(Box{{0, 0, 0}, s.g.cells}, *s.dec));
    const real eps = h, y0 = 0.2, half = 2.0 * h; // 4 cells thick
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const real top = 0.5 * (1 - std::tanh((x[1] - y0 - half) / eps));
        const real bottom = 0.5 * (1 - std::tanh((y0 - half - x[1]) / eps));
        const real v = top * bottom;
        body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
        for (int d = 0; d < 3; ++d)
            body.reference_map()[d](i, j, k) = 0; // X = x: the rest state
    });
    s.halos->fill(body.phi(), body.patch());
    NormalExtension ext(*s.halos, "slab", 1.0, 1.0, -1, true, true);
    ext.apply_reference_map(body, true, nullptr);
    const SymmetricTensorField& G = body.tensor();
    int off = 0, on = 0;
    real worst = 0;
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const real f = body.phi()(i, j, k);
        if (f <= 1e-5 || f >= 1 - 1e-5) return;
        const Int3 p{i, j, k};
        real norm = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                norm += std::abs(G.value(a, b, p));
        if (norm == 0) {
            ++off;
            // only in the slab's inner half
            EXPECT_LT(std::abs(x[1] - y0), half) << "y = " << x[1];
            return;
        }
        ++on;
        const Matrix3 P{Real3{1, 0, 0}, Real3{0, 0, 0}, Real3{0, 0, 1}};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                worst = std::max(worst, std::abs(G.value(a, b, p) - P[a][b]));
    });
    const int off_all = int(s.dec->sum(real(off))), on_all = int(s.dec->sum(real(on)));
    EXPECT_GT(off_all, 0);
    EXPECT_GT(on_all, off_all);
    EXPECT_LT(s.dec->max(worst), 1e-6);
}

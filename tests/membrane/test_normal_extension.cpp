// Normal extension of a membrane's Gs (solver/membrane/normal_extension): after each step
// the band's Gs is the core's, copied outward along the normals and projected on the
// tangent plane. It must
//  - reproduce a field that is constant along the normals (P A P around a sphere, A any
//    constant symmetric tensor) from its core values alone, to the interpolation's second
//    order, whatever the band held before;
//  - leave every band cell tangential (Gs n = 0 to round-off, n the normal of phi);
//  - reset the cells beyond the band to I;
//  - agree on 1 and 2 ranks (foot points across the rank boundary).
#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "membrane/normal_extension.hpp"
#include "membrane_test_grid.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <array>
#include <cmath>

using namespace efsi;

namespace {

using efsi::test::GridSetup;

const Real3 kCentre{0.011, -0.017, 0.013};
constexpr real kRadius = 0.4;

Real3 offset(const Real3& x, int dim) {
    return {x[0] - kCentre[0], x[1] - kCentre[1], dim == 3 ? x[2] - kCentre[2] : 0.0};
}

real norm(const Real3& r) {
    return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/// The constant tensor A whose tangential part P A P the band should hold.
real a_entry(int a, int b, int dim) {
    static const real A[3][3] = {{1.3, 0.2, -0.1}, {0.2, 0.8, 0.15}, {-0.1, 0.15, 1.1}};
    if (dim == 2 && (a == 2 || b == 2)) return a == b ? 1.0 : 0.0;
    return A[a][b];
}

/// (P A P)_ab at x with n the radial unit vector.
real pap(const Real3& x, int a, int b, int dim) {
    const Real3 r = offset(x, dim);
    const real rr = norm(r);
    const Real3 n{r[0] / rr, r[1] / rr, r[2] / rr};
    auto P = [&](int i, int j) { return (i == j ? 1.0 : 0.0) - n[i] * n[j]; };
    real v = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            v += P(a, i) * a_entry(i, j, dim) * P(j, b);
    return v;
}

struct Result {
    real core_to_band_error = 0; ///< max |Gs - P A P| over the band, |s| <= 5.75 eps
    real normal_leak = 0;        ///< max |Gs n| over the band, n = grad psi / |grad psi|
    real beyond = 0;             ///< max |Gs - I| beyond the reach
};

Result run(int dim, int m) {
    const real h = 0.05 / m; // R = 8 m cells
    GridSetup s = efsi::test::make_setup(dim, {32 * m, 34 * m, 30 * m}, h, BoundaryType::Periodic);
    Body body("capsule", BodyKind::Membrane, false, dim);
    body.allocate(make_patch(Box{{0, 0, 0}, s.g.cells}, *s.dec));
    const real eps = h;
    const real core = 1.0 * h;
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const real sd = norm(offset(x, dim)) - kRadius;
        const real v = 0.5 * (1 - std::tanh(sd / eps));
        body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
        // The exact field in the core (and a margin the trilinear stencil reads from), a
        // wrong one (5 I + 0.3 everywhere) elsewhere: the band must be rebuilt from the core.
        // (The stencil around a foot point reaches sqrt(3) h along the normal; a wide margin.)
        const bool keep = std::abs(sd) <= core + 3.6 * h;
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b) {
                const int sl = SymmetricTensorField::slot(a, b, dim);
                if (sl < 0) continue;
                body.tensor().comp[sl](i, j, k) =
                    keep ? pap(x, a, b, dim) : (a == b ? 5.0 : 0.0) + 0.3;
            }
    });
    s.halos->fill(body.phi(), body.patch());
    NormalExtension ext(*s.halos, "capsule", 1.0, 1.0);
    run_now(ext.apply(body), *s.halos);
    Result r;
    const real band = std::atanh(1 - 2e-5) * eps;
    const real reach = ext.reach_cells() * h;
    const SymmetricTensorField& G = body.tensor();
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const Real3 rv = offset(x, dim);
        const real rr = norm(rv);
        const real sd = rr - kRadius;
        const Int3 p{i, j, k};
        if (std::abs(sd) <= band && rr > 0.5 * kRadius) {
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    r.core_to_band_error = std::max(r.core_to_band_error,
                                                    std::abs(G.value(a, b, p) - pap(x, a, b, dim)));
            // The normal of phi (central differences of psi, as the extension's own).
            Real3 gp{0, 0, 0};
            real g2 = 0;
            auto psi = [&](int di, int dj, int dk) {
                const real v =
                    std::clamp(1 - 2 * body.phi()(i + di, j + dj, k + dk), -1 + 1e-15, 1 - 1e-15);
                return eps * std::atanh(v);
            };
            gp[0] = psi(1, 0, 0) - psi(-1, 0, 0);
            gp[1] = psi(0, 1, 0) - psi(0, -1, 0);
            if (dim == 3) gp[2] = psi(0, 0, 1) - psi(0, 0, -1);
            for (int d = 0; d < 3; ++d)
                g2 += gp[d] * gp[d];
            for (int a = 0; a < 3; ++a) {
                real gn = 0;
                for (int b = 0; b < 3; ++b)
                    gn += G.value(a, b, p) * gp[b] / std::sqrt(g2);
                r.normal_leak = std::max(r.normal_leak, std::abs(gn));
            }
        }
        if (sd > reach + 0.5 * h) // outside only: far inside, psi saturates to the same test
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    r.beyond =
                        std::max(r.beyond, std::abs(G.value(a, b, p) - (a == b ? 1.0 : 0.0)));
    });
    r.core_to_band_error = efsi::test::global_max(r.core_to_band_error);
    r.normal_leak = efsi::test::global_max(r.normal_leak);
    r.beyond = efsi::test::global_max(r.beyond);
    return r;
}

} // namespace

TEST(NormalExtension, ReproducesAFieldConstantAlongNormalsToSecondOrder) {
    for (int dim : {2, 3}) {
        const Result coarse = run(dim, 1);
        const Result fine = run(dim, 2);
        // Interpolation of a smooth field at the foot point, and the foot point itself
        // (psi and n from central differences of the smoothed phi): second order in h/R.
        EXPECT_LT(coarse.core_to_band_error, 2e-2) << "dim " << dim;
        const real order = std::log2(coarse.core_to_band_error / fine.core_to_band_error);
        EXPECT_GT(order, 1.7) << "dim " << dim << ": errors " << coarse.core_to_band_error << ", "
                              << fine.core_to_band_error;
        EXPECT_LT(coarse.normal_leak, 1e-13) << "dim " << dim;
        EXPECT_EQ(coarse.beyond, 0.0) << "dim " << dim;
    }
}

namespace {

/// A 2D disc on the body's patch: phi a tanh profile drawn out by `stretch` (psi =
/// distance / stretch), Gs the constant tensor A in every cell.
void set_disc_2d(Body& body, const GridSetup& s, const Real3& centre, real radius, real stretch) {
    if (body.patch().empty()) return;
    const real h = s.g.dx(0);
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const real sd = std::hypot(x[0] - centre[0], x[1] - centre[1]) - radius;
        const real v = 0.5 * (1 - std::tanh(sd / (stretch * h)));
        body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
        for (int a = 0; a < 2; ++a)
            for (int b = a; b < 2; ++b)
                body.tensor().comp[SymmetricTensorField::slot(a, b, 2)](i, j, k) = a_entry(a, b, 2);
    });
}

/// psi = h atanh(1 - 2 phi) of a 2D body (smoothing width one cell).
real psi_2d(const Body& body, int i, int j, real h) {
    const real v = std::clamp(1 - 2 * body.phi()(i, j, 0), -1 + 1e-15, 1 - 1e-15);
    return h * std::atanh(v);
}

/// The largest entry of |Gs - P A P| at a 2D cell, P = I - n n.
real tangential_a_error_2d(const Body& body, const Int3& p, const real (&n)[3]) {
    real worst = 0;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            real v = 0;
            for (int c = 0; c < 3; ++c)
                for (int e = 0; e < 3; ++e)
                    v += ((a == c) - n[a] * n[c]) * a_entry(c, e, 2) * ((e == b) - n[e] * n[b]);
            worst = std::max(worst, std::abs(body.tensor().value(a, b, p) - v));
        }
    return worst;
}

} // namespace

// A drawn-out profile (|grad psi| = 1 / 1.9) with Newton foot points: the foot of a band cell
// is psi / |grad psi| away, up to 1.9 reaches, while the wide-halo copy holds one reach past
// the rank's block. On two ranks the grid is split in y at 40 cells and the disc's top is at
// 29, so the upper block's lowest cells (11-14 cells above it, within the band) have their
// Newton foot below the reach of their copy (10 cells): they must fall back to psi's own foot
// point (NormalExtension::foot_point) instead of reading outside the copy (a
// wrapped index: memory before the field's storage). Gs is the same constant tensor A in
// every cell, so any foot point inside the copy interpolates A exactly and every band cell
// must end as P A P, P the projection on the tangent of psi's own (central-difference) normal.
TEST(NormalExtension, NewtonFootBeyondTheWideHaloFallsBackToPsisFoot) {
    const real h = 0.05;
    const int dim = 2;
    GridSetup s = efsi::test::make_setup(dim, {48, 80, 1}, h, BoundaryType::Periodic);
    Body body("disc", BodyKind::Membrane, false, dim);
    body.allocate(make_patch(Box{{0, 0, 0}, s.g.cells}, *s.dec));
    set_disc_2d(body, s, Real3{0.0, s.g.origin[1] + 25 * h, 0.0}, 4 * h, 1.9);
    s.halos->fill(body.phi(), body.patch());
    NormalExtension ext(*s.halos, "disc", 1.0, 1.0, -1, true, false, /*newton_foot=*/true);
    run_now(ext.apply(body), *s.halos);
    auto psi = [&](int i, int j) { return psi_2d(body, i, j, h); };
    real worst = 0;
    long copied = 0;
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const real gx = (psi(i + 1, j) - psi(i - 1, j)) / (2 * h);
        const real gy = (psi(i, j + 1) - psi(i, j - 1)) / (2 * h);
        const real g2 = gx * gx + gy * gy;
        if (std::abs(psi(i, j)) > ext.reach_cells() * h || g2 < 0.25) return; // G = I there
        const real n[3] = {gx / std::sqrt(g2), gy / std::sqrt(g2), 0.0};
        ++copied;
        worst = std::max(worst, tangential_a_error_2d(body, {i, j, k}, n));
    });
    EXPECT_GT(efsi::test::global_max(real(copied)), 100.0);
    EXPECT_LT(efsi::test::global_max(worst), 1e-12);
}

// At a patch's own edge (no neighbour across it) the wide copies hold only kEdgeLayers of
// mirrored values. A patch whose lower edge cuts through a disc (radius 6 cells, centre 1.4
// cells above the edge row's centre) puts the lower surface, where the feet of the inside
// cells next to the edge lie, 4.6 cells past the edge, beyond the mirrored layers (the edge row
// itself has a mirrored, halved gradient: no normal). Those feet must be moved onto the filled
// cells (NormalExtension::foot_point), never read the unfilled ones (zeros): Gs is the constant A
// on the patch, so every band cell must end as P A P.
TEST(NormalExtension, FootPointsPastAnEdgesMirroredLayersStayOnTheFilledCells) {
    const real h = 0.05;
    const int dim = 2;
    GridSetup s = efsi::test::make_setup(dim, {48, 80, 1}, h, BoundaryType::Periodic);
    const int cj = 25, ci = 24;
    Body body("disc", BodyKind::Membrane, false, dim);
    body.allocate(make_patch(Box{{4, cj, 0}, {44, cj + 24, 1}}, *s.dec));
    const LocalBlock& blk = s.dec->block();
    if (blk.offset[1] <= cj && cj < blk.offset[1] + blk.cells[1]) {
        EXPECT_FALSE(body.patch().exchange[1][0]); // the lower edge is the patch's own
    }
    set_disc_2d(body, s, Real3{s.g.origin[0] + (ci + 0.5) * h, s.g.origin[1] + (cj + 1.9) * h, 0.0},
                6 * h, 1.0);
    s.halos->fill(body.phi(), body.patch());
    NormalExtension ext(*s.halos, "disc", 1.0, 1.0);
    run_now(ext.apply(body), *s.halos);
    auto psi = [&](int i, int j) { return psi_2d(body, i, j, h); };
    real worst = 0;
    long copied = 0, past_the_edge = 0;
    if (!body.patch().empty())
        for_each_in(body.patch().local, [&](int i, int j, int k) {
            const real gx = (psi(i + 1, j) - psi(i - 1, j)) / (2 * h);
            const real gy = (psi(i, j + 1) - psi(i, j - 1)) / (2 * h);
            const real g2 = gx * gx + gy * gy;
            if (std::abs(psi(i, j)) > ext.reach_cells() * h || g2 < 0.25) return;
            if (std::abs(psi(i, j)) <= ext.core_cells() * h) return; // the core keeps its own
            const real n[3] = {gx / std::sqrt(g2), gy / std::sqrt(g2), 0.0};
            ++copied;
            // The foot's row, below the edge by more than the mirrored layers.
            const real foot_j = j + blk.offset[1] - psi(i, j) / h * n[1];
            if (foot_j < cj - NormalExtension::kEdgeLayers) ++past_the_edge;
            worst = std::max(worst, tangential_a_error_2d(body, {i, j, k}, n));
        });
    EXPECT_GT(efsi::test::global_max(real(past_the_edge)), 0.0);
    EXPECT_GT(efsi::test::global_max(real(copied)), 100.0);
    EXPECT_LT(efsi::test::global_max(worst), 1e-12);
}

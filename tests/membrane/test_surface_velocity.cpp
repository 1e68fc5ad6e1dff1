// Surface velocity (solver/membrane/surface_velocity): the velocity that carries a
// membrane's Gs is u at the foot point on the surface plus s dn/dt (the layers of the band
// follow the surface as the parallel surfaces of a Kirchhoff-Love shell). It must
//  - be exact for a linear flow (against the closed form on a sphere),
//  - remove a velocity kink across the membrane: a rotation whose rate varies only with
//    the distance to the surface (the shear a membrane supports) becomes one rigid
//    rotation, so every layer of the band shares the surface's (zero) strain,
//  - agree on 1 and 2 ranks (foot points across the rank boundary).
#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "membrane/surface_velocity.hpp"
#include "membrane_test_grid.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <cmath>
#include <functional>

using namespace efsi;

namespace {

using efsi::test::GridSetup;

GridSetup make_setup(int dim, Int3 n, real h) {
    return efsi::test::make_setup(dim, n, h, BoundaryType::Periodic);
}

const Real3 kCentre{0.011, -0.017, 0.013};
constexpr real kRadius = 0.4;

Real3 offset_from_centre(const Real3& x, int dim) {
    return {x[0] - kCentre[0], x[1] - kCentre[1], dim == 3 ? x[2] - kCentre[2] : 0.0};
}

real norm(const Real3& r) {
    return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/// A smoothed sphere (circle in 2D) of radius kRadius, eps = eps_cells h.
void build_sphere(const GridSetup& s, Body& body, real eps_cells) {
    body.allocate(make_patch(Box{{0, 0, 0}, s.g.cells}, *s.dec));
    const real eps = eps_cells * s.g.dx(0);
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
        const real v =
            0.5 * (1 - std::tanh((norm(offset_from_centre(x, s.g.dim)) - kRadius) / eps));
        body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
    });
    s.halos->fill(body.phi(), body.patch());
}

using VectorFunction = std::function<Real3(const Real3&)>;

VelocityField sample(const GridSetup& s, const VectorFunction& f) {
    VelocityField u("u", s.dec->block(), s.g.dim);
    for (int c = 0; c < s.g.dim; ++c)
        for_each_in(u[c].owned(), [&](int i, int j, int k) {
            u[c](i, j, k) = f(position(s.g, s.dec->block(), face_location(c), i, j, k))[c];
        });
    s.halos->fill(u);
    return u;
}

/// Largest |v_c - f_c| over the owned faces with |r - R| <= within (all ranks).
real max_difference(const GridSetup& s, const VelocityField& v, const VectorFunction& f,
                    real within) {
    real worst = 0;
    for (int c = 0; c < s.g.dim; ++c)
        for_each_in(v[c].owned(), [&](int i, int j, int k) {
            const Real3 x = position(s.g, s.dec->block(), face_location(c), i, j, k);
            if (std::abs(norm(offset_from_centre(x, s.g.dim)) - kRadius) > within) return;
            worst = std::max(worst, std::abs(v[c](i, j, k) - f(x)[c]));
        });
    return efsi::test::global_max(worst);
}

} // namespace

// u = (gamma y, 0, 0): u_e = u(y_f) + s dn/dt with y_f = c + R n, s = r - R and
// dn/dt = -P (grad u)^T n = -gamma n_x (e_y - n_y n). Catmull-Rom reproduces linear fields,
// so only the foot point (face psi and normal from cell values by averaging and central
// differences) is approximate: the error is second order in h.
TEST(SurfaceVelocity, LinearShearMatchesTheClosedFormToSecondOrder) {
    for (int dim : {2, 3}) {
        const real gamma = 1.3;
        const VectorFunction shear = [&](const Real3& x) { return Real3{gamma * x[1], 0, 0}; };
        const VectorFunction exact = [&](const Real3& x) {
            const Real3 r = offset_from_centre(x, dim);
            const real rr = norm(r);
            const Real3 n{r[0] / rr, r[1] / rr, r[2] / rr};
            const real sd = rr - kRadius;
            const real yf = kCentre[1] + kRadius * n[1];
            return Real3{gamma * yf + sd * gamma * n[0] * n[1] * n[0],
                         -sd * gamma * n[0] * (1 - n[1] * n[1]), sd * gamma * n[0] * n[1] * n[2]};
        };
        real err[2] = {0, 0};
        for (int level = 0; level < 2; ++level) {
            const int m = 1 << level;
            const real h = 0.05 / m; // R = 8 and 16 cells
            GridSetup s = make_setup(dim, {32 * m, 34 * m, 30 * m}, h);
            Body body("capsule", BodyKind::Membrane, false, dim);
            build_sphere(s, body, 1.0);
            const VelocityField u = sample(s, shear);
            SurfaceVelocity sv(*s.halos);
            sv.load(u);
            const VelocityField& ue = sv.compute(body, 1.0);
            // The same physical band at both levels: |s| <= 3.5 h_fine (inside the reach,
            // 4.5 cells, less one cell: a face's psi is its two cells' average).
            const real within = 3.5 * 0.025;
            err[level] = max_difference(s, ue, exact, within);
            if (level == 0) {
                // Without the surface velocity the layers move with u (the test can fail).
                EXPECT_GT(max_difference(s, u, exact, within), 10 * err[0]) << "dim " << dim;
                EXPECT_LT(err[0], 0.1 * gamma * h) << "dim " << dim;
            }
            // Beyond the reach the faces keep u.
            auto kept_beyond = [&](const VelocityField& v, real reach) {
                real kept = 0;
                for (int c = 0; c < dim; ++c)
                    for_each_in(u[c].owned(), [&](int i, int j, int k) {
                        const Real3 x = position(s.g, s.dec->block(), face_location(c), i, j, k);
                        if (std::abs(norm(offset_from_centre(x, dim)) - kRadius) > reach + h)
                            kept = std::max(kept, std::abs(v[c](i, j, k) - u[c](i, j, k)));
                    });
                return efsi::test::global_max(kept);
            };
            EXPECT_EQ(kept_beyond(ue, SurfaceVelocity::default_reach * h), 0.0) << "dim " << dim;
            if (level == 0) {
                // A shorter reach (body key surface_velocity_reach): u beyond it, and u_e
                // still at the surface, where only faces within half a cell get full weight.
                const VelocityField ue_default = ue;
                const VelocityField& short_reach = sv.compute(body, 1.0, 1.5);
                EXPECT_EQ(kept_beyond(short_reach, 1.5 * h), 0.0) << "dim " << dim;
                EXPECT_GT(kept_beyond(ue_default, 1.5 * h), 0.0) << "dim " << dim;
                EXPECT_LT(max_difference(s, short_reach, exact, 0.2 * h), 0.1 * gamma * h)
                    << "dim " << dim;
            }
        }
        const real order = std::log2(err[0] / err[1]);
        EXPECT_GT(order, 1.8) << "dim " << dim << ": errors " << err[0] << ", " << err[1];
    }
}

// u = (1 + a eps ln cosh(s / eps)) omega x r: a rotation whose rate varies across the
// membrane with a smoothed kink (slope +-a on either side). Every layer of the band would
// tank-tread at its own rate; the surface velocity is the one rigid rotation omega x r.
TEST(SurfaceVelocity, KinkAcrossTheMembraneIsRemoved) {
    for (int dim : {2, 3}) {
        const real h = 0.05;
        GridSetup s = make_setup(dim, {32, 34, 30}, h); // R = 8 cells
        const real eps = h, a = 3.0;
        Body body("capsule", BodyKind::Membrane, false, dim);
        build_sphere(s, body, 1.0);
        const Real3 omega = dim == 3 ? Real3{0.3, -0.5, 0.8} : Real3{0, 0, 0.8};
        auto rotation = [&](const Real3& x, real rate) {
            const Real3 r = offset_from_centre(x, dim);
            return Real3{rate * (omega[1] * r[2] - omega[2] * r[1]),
                         rate * (omega[2] * r[0] - omega[0] * r[2]),
                         dim == 3 ? rate * (omega[0] * r[1] - omega[1] * r[0]) : 0.0};
        };
        const VectorFunction kinked = [&](const Real3& x) {
            const real sd = norm(offset_from_centre(x, dim)) - kRadius;
            return rotation(x, 1 + a * eps * std::log(std::cosh(sd / eps)));
        };
        const VectorFunction rigid = [&](const Real3& x) { return rotation(x, 1.0); };
        const VelocityField u = sample(s, kinked);
        SurfaceVelocity sv(*s.halos);
        sv.load(u);
        const VelocityField& ue = sv.compute(body, 1.0);
        const real core = 2.3 * eps; // the band's core (phi in [0.01, 0.99])
        const real before = max_difference(s, u, rigid, core);
        const real after = max_difference(s, ue, rigid, core);
        EXPECT_GT(before, 0.1 * norm(omega) * kRadius * h / kRadius) << "dim " << dim;
        EXPECT_LT(after, 0.1 * before) << "dim " << dim;
    }
}

// One SurfaceVelocity serves every membrane of a run: the result for a body must not depend
// on the bodies computed before it in the same step, on the faces its transport reads (its
// patch and three cells around it, halos included). Two spheres on disjoint patches (on two
// ranks each lies on one rank, so the other rank takes the empty-patch path).
TEST(SurfaceVelocity, SharedAcrossBodiesGivesEachBodyItsOwnResult) {
    for (int dim : {2, 3}) {
        const real h = 0.05, radius = 0.3;
        GridSetup s = make_setup(dim, {64, 34, 30}, h);
        auto sphere_at = [&](Body& body, real x0) {
            const int margin = 14; // radius 6 cells + reach 5 + the stencil
            const int ic = int(std::lround((x0 - s.g.origin[0]) / h));
            Box box{{ic - margin, 0, 0}, {ic + margin, s.g.cells[1], s.g.cells[2]}};
            body.allocate(make_patch(box, *s.dec));
            for_each_in(body.patch().local, [&](int i, int j, int k) {
                const Real3 x = position(s.g, s.dec->block(), Location::Cell, i, j, k);
                const Real3 r{x[0] - x0, x[1] - kCentre[1], dim == 3 ? x[2] - kCentre[2] : 0.0};
                const real v = 0.5 * (1 - std::tanh((norm(r) - radius) / h));
                body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
            });
            s.halos->fill(body.phi(), body.patch());
        };
        Body a("a", BodyKind::Membrane, false, dim), b("b", BodyKind::Membrane, false, dim);
        sphere_at(a, -0.45); // a's band reaches into b's region
        sphere_at(b, 0.45);
        const VelocityField u = sample(s, [](const Real3& x) { return Real3{1.3 * x[1], 0, 0}; });

        SurfaceVelocity shared(*s.halos);
        shared.load(u);
        const VelocityField ue_a = shared.compute(a, 1.0); // a copy
        const VelocityField& ue_b = shared.compute(b, 1.0);
        SurfaceVelocity alone(*s.halos);
        alone.load(u);
        const VelocityField& ue_b_alone = alone.compute(b, 1.0);

        real changed_by_a = 0, differs = 0;
        for (int c = 0; c < dim; ++c) {
            for_each_in(u[c].owned(), [&](int i, int j, int k) {
                changed_by_a = std::max(changed_by_a, std::abs(ue_a[c](i, j, k) - u[c](i, j, k)));
            });
            // Halos included: the next stage reads them.
            Box region = b.patch().global;
            for (int d = 0; d < dim; ++d) {
                region.lo[d] -= 3;
                region.hi[d] += 3;
            }
            const LocalBlock& blk = s.dec->block();
            region = shifted(region, {-blk.offset[0], -blk.offset[1], -blk.offset[2]});
            Box stored = ue_b[c].owned();
            for (int d = 0; d < dim; ++d) {
                stored.lo[d] -= ue_b[c].halo()[d];
                stored.hi[d] += ue_b[c].halo()[d];
            }
            for_each_in(intersect(region, stored), [&](int i, int j, int k) {
                differs = std::max(differs, std::abs(ue_b[c](i, j, k) - ue_b_alone[c](i, j, k)));
            });
        }
        EXPECT_GT(efsi::test::global_max(changed_by_a), 0.01) << "dim " << dim; // can fail
        EXPECT_EQ(efsi::test::global_max(differs), 0.0) << "dim " << dim;
    }
}

// The adhesion coupling (solver/adhesion/coupling, grid_transfer, placement) on 1 and 2
// ranks: receptor placement reproducible, on the surface, uniform and independent of the
// rank count; receptors carried exactly by a uniform flow and a linear shear, the
// interpolation second order in space and the midpoint rule second order in time; the
// spread bond forces integrating to F on each side; the bonds' reactions taken by the
// wall (nothing of -F in the fluid for a ligand on a no-slip wall of the domain: the fluid
// gets exactly the receptors' +F, the wall's reaction recorded as -F; onto the held faces
// of a pinned solid otherwise; a ligand anchored to nothing refused naming its region);
// the far-from-ligand skip doing no work; the time-step limits reported.
#include "adhesion/coupling.hpp"
#include "adhesion_scene.hpp"
#include "test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace efsi;
using namespace efsi::adhesion;
using efsi::test::nm;
using efsi::test::um;
using ::testing::HasSubstr;

namespace {

/// Largest minus smallest of x over the ranks: 0 when every rank holds the same value.
real spread_over_ranks(real x) {
    return test::global_max(x) + test::global_max(-x);
}

/// A configuration with one group of `count` receptors per body and one ligand patch on
/// the wall y = 0 over [lo_x, hi_x] x [lo_z, hi_z] with 50 nm spacing.
AdhesionConfig adhesion_config(std::size_t bodies, std::uint64_t count, Real3 patch_lo,
                               Real3 patch_hi) {
    AdhesionConfig a;
    a.enabled = true;
    a.seed = 11;
    a.ligand_regions.push_back({patch_lo, patch_hi, 50 * nm});
    a.ligand_density.push_back(1 / (50 * nm * 50 * nm));
    for (std::size_t k = 0; k < bodies; ++k)
        a.receptors.push_back({"", k, count, 0});
    return a;
}

/// Sum over the owned faces of every rank of force * cell volume, per component.
Real3 total_force(const VelocityField& f, const test::Channel& c) {
    Real3 t{0, 0, 0};
    for (int comp = 0; comp < 3; ++comp) {
        real s = 0;
        for_each_cell(c.dec->block().cells,
                      [&](int i, int j, int k) { s += f[comp](i, j, k) * c.g.cell_volume(); });
        t[comp] = c.dec->sum(s);
    }
    return t;
}

VelocityField zero_field(const test::Channel& c) {
    VelocityField f("force", c.dec->block(), 3);
    for (int comp = 0; comp < 3; ++comp)
        f[comp].fill(0);
    return f;
}

/// The force field of the receptors' ends alone: spread_force(+F) at every bound receptor
/// (no periodic image needed: the bodies of these scenes do not straddle a boundary).
VelocityField receptor_side(const Coupling& cp, const AdhesionParameters& p,
                            const test::Channel& c) {
    VelocityField g = zero_field(c);
    for (const Receptor& r : cp.receptors()) {
        if (!r.bound()) continue;
        const BondForce bf =
            bond_force(r.x, cp.ligands().position(r.ligand), p.bond_stiffness, p.bond_rest_length);
        spread_force(g, *c.dec, r.x, bf.on_receptor);
    }
    return g;
}

real norm(const Real3& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

} // namespace

// ---- placement ------------------------------------------------------------------------

TEST(AdhesionPlacement, EllipsoidAreaMatchesClosedForms) {
    const real pi = std::numbers::pi;
    EXPECT_NEAR(ellipsoid_area({2, 2, 2}) / (16 * pi), 1, 1e-9);
    // Oblate spheroid a = a > c (a platelet): 2 pi a^2 (1 + (1 - e^2)/e atanh e).
    for (real c : {0.5, 0.25, 0.1}) {
        const real a = 1, e = std::sqrt(1 - c * c / (a * a));
        const real exact = 2 * pi * a * a * (1 + (1 - e * e) / e * std::atanh(e));
        EXPECT_NEAR(ellipsoid_area({a, a, c}) / exact, 1, 1e-6) << "c = " << c;
        EXPECT_NEAR(ellipsoid_area({a, c, a}) / exact, 1, 1e-6) << "c = " << c;
    }
    // Prolate a = b < c: 2 pi a^2 (1 + c/(a e) asin e).
    const real a = 0.5, c = 2, e = std::sqrt(1 - a * a / (c * c));
    EXPECT_NEAR(ellipsoid_area({a, a, c}) / (2 * pi * a * a * (1 + c / (a * e) * std::asin(e))), 1,
                1e-6);
}

TEST(AdhesionPlacement, ReproducibleOnTheSurfaceUniformAndRankIndependent) {
    SurfaceEllipsoid s;
    s.centre = {1 * um, 2 * um, 3 * um};
    s.semi_axes = {1.5 * um, 1.5 * um, 0.5 * um};
    s.rotation = axis_angle_rotation({1, 1, 0}, 0.7);
    const std::vector<Receptor> a = place_receptors(s, 4000, 100, 7);
    const std::vector<Receptor> b = place_receptors(s, 4000, 100, 7);
    // Placing a subset gives the same receptors: a position depends on (seed, id) only.
    const std::vector<Receptor> tail = place_receptors(s, 1000, 3100, 7);
    const std::vector<Receptor> other = place_receptors(s, 10, 100, 8);
    ASSERT_EQ(a.size(), 4000u);
    real checksum = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].id, 100 + k);
        EXPECT_FALSE(a[k].bound());
        for (int d = 0; d < 3; ++d) {
            ASSERT_EQ(a[k].x[d], b[k].x[d]);
            checksum += a[k].x[d] * static_cast<real>(k + 1);
        }
        if (k >= 3000) {
            for (int d = 0; d < 3; ++d)
                ASSERT_EQ(a[k].x[d], tail[k - 3000].x[d]);
        }
        // On the surface: |diag(1/a) R^T (x - c)| = 1.
        real q = 0;
        for (int j = 0; j < 3; ++j) {
            real y = 0;
            for (int i = 0; i < 3; ++i)
                y += s.rotation[i][j] * (a[k].x[i] - s.centre[i]);
            q += (y / s.semi_axes[j]) * (y / s.semi_axes[j]);
        }
        ASSERT_NEAR(q, 1, 1e-12);
    }
    EXPECT_NE(other[0].x[0], a[0].x[0]); // another seed, other positions
    // The same bits on every rank (each rank placed them itself).
    EXPECT_EQ(spread_over_ranks(checksum), 0.0);
    // Uniform in area: the centroid of the receptors is the centre (by symmetry) within a
    // few standard errors; the share on the two flat faces (body |z| > c/2) is their area
    // share, computed by quadrature of the same area element.
    Real3 mean{0, 0, 0};
    std::size_t flat = 0;
    for (const Receptor& r : a) {
        real yz = 0;
        for (int i = 0; i < 3; ++i) {
            mean[i] += (r.x[i] - s.centre[i]) / static_cast<real>(a.size());
            yz += s.rotation[i][2] * (r.x[i] - s.centre[i]);
        }
        flat += std::abs(yz) > 0.5 * s.semi_axes[2] ? 1 : 0;
    }
    for (int i = 0; i < 3; ++i)
        EXPECT_LT(std::abs(mean[i]), 4 * 1.5 * um / std::sqrt(3.0 * 4000));
    // Area with |p_z| > 1/2 on the unit-sphere parametrisation, by the midpoint rule.
    real share = 0, total = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
        const real u = -1 + (i + 0.5) * 2.0 / n, rho = std::sqrt(1 - u * u);
        for (int j = 0; j < 64; ++j) {
            const real phi = 2 * std::numbers::pi * j / 64;
            const real gx = 1.5 * 0.5 * rho * std::cos(phi), gy = 1.5 * 0.5 * rho * std::sin(phi),
                       gz = 1.5 * 1.5 * u;
            const real g = std::sqrt(gx * gx + gy * gy + gz * gz);
            total += g;
            if (std::abs(u) > 0.5) share += g;
        }
    }
    share /= total;
    const real sd = std::sqrt(share * (1 - share) / 4000);
    EXPECT_NEAR(static_cast<real>(flat) / 4000, share, 4 * sd);
}

// ---- carrying the receptors -----------------------------------------------------------

TEST(AdhesionCarry, UniformFlowMovesReceptorsExactly) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    const Real3 U{1.3e-4, 0, -0.7e-4};
    // The uniform flow with the walls at rest has u = U on every face (the ghosts beyond
    // the walls are only read within half a cell of a wall; the body stays clear of them).
    VelocityField u = test::velocity_from(c, [&](int comp, const Real3&) { return U[comp]; });
    std::vector<BodyConfig> bodies{test::sphere_body("p", {1.0 * um, 2 * um, 2 * um}, 1 * um)};
    Coupling cp(adhesion_config(1, 300, {0, 0, 0}, {0, 0, 0}), bodies, *c.dec, 1000, 1e-3);
    std::vector<Real3> x;
    for (const Receptor& r : cp.receptors())
        x.push_back(r.x);
    const real dt = 1e-3;
    int wraps = 0;
    for (int step = 0; step < 40; ++step) { // 5.2 um in x, -2.8 um in z: both wrap
        cp.carry(u, dt);
        for (std::size_t k = 0; k < x.size(); ++k)
            for (int a = 0; a < 3; ++a)
                x[k][a] += dt * U[a];
        // The cloud is shifted by the box length as a whole when its centre leaves.
        for (int a : {0, 2}) {
            real lo = x[0][a], hi = x[0][a];
            for (const Real3& y : x) {
                lo = std::min(lo, y[a]);
                hi = std::max(hi, y[a]);
            }
            const real shift = -c.g.length[a] * std::floor((0.5 * (lo + hi)) / c.g.length[a]);
            if (shift != 0) ++wraps;
            for (Real3& y : x)
                y[a] += shift;
        }
        const auto r = cp.receptors();
        for (std::size_t k = 0; k < x.size(); ++k)
            for (int a = 0; a < 3; ++a)
                ASSERT_EQ(r[k].x[a], x[k][a]) << "step " << step << " receptor " << k;
    }
    EXPECT_EQ(wraps, 2); // once in x, once in z
}

TEST(AdhesionCarry, LinearShearIsExactAndParabolicFlowSecondOrder) {
    // u_x = G (y - y0) with walls moving accordingly: trilinear interpolation is exact.
    const real G = 500, y0 = 1.3 * um;
    test::Channel c = test::make_channel({16, 16, 8}, 0.25 * um, G * (0 - y0), G * (4 * um - y0));
    VelocityField u = test::velocity_from(
        c, [&](int comp, const Real3& x) { return comp == 0 ? G * (x[1] - y0) : 0.0; });
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 2 * um, 1 * um}, 0.9 * um)};
    Coupling cp(adhesion_config(1, 200, {0, 0, 0}, {0, 0, 0}), bodies, *c.dec, 1000, 1e-3);
    std::vector<Real3> x0;
    for (const Receptor& r : cp.receptors())
        x0.push_back(r.x);
    const real dt = 1e-4;
    for (int step = 0; step < 10; ++step)
        cp.carry(u, dt);
    real worst = 0;
    for (std::size_t k = 0; k < x0.size(); ++k) {
        const Receptor& r = cp.receptors()[k];
        worst = std::max({worst, std::abs(r.x[0] - (x0[k][0] + 10 * dt * G * (x0[k][1] - y0))),
                          std::abs(r.x[1] - x0[k][1]), std::abs(r.x[2] - x0[k][2])});
    }
    EXPECT_LT(worst, 1e-14 * 4 * um);

    // A parabolic profile (walls at rest): the interpolation error falls as h^2.
    std::vector<real> errors;
    for (int n : {8, 16, 32}) {
        const real H = 4 * um;
        test::Channel p = test::make_channel({n, n, 4}, H / n);
        auto exact = [&](real y) { return 4e-3 * y * (H - y) / (H * H); };
        VelocityField up = test::velocity_from(
            p, [&](int comp, const Real3& x) { return comp == 0 ? exact(x[1]) : 0.0; });
        std::vector<Real3> pts, out(64);
        for (int k = 0; k < 64; ++k) // fixed points, away from the walls' half cells
            pts.push_back({0.37 * um * k, 0.6 * um + 2.8 * um * k / 63.0, 0.11 * um * k});
        VelocityInterpolator interp;
        interp.interpolate(up, *p.dec, pts, out);
        real e = 0;
        for (int k = 0; k < 64; ++k)
            e = std::max(e, std::abs(out[k][0] - exact(pts[k][1])) + std::abs(out[k][1]) +
                                std::abs(out[k][2]));
        errors.push_back(e);
    }
    for (int m = 0; m < 2; ++m)
        EXPECT_NEAR(std::log2(errors[m] / errors[m + 1]), 2.0, 0.2) << errors[m];
}

TEST(AdhesionCarry, MidpointRuleIsSecondOrderInTime) {
    // Rigid rotation about the z axis through the box centre: a linear field, so the
    // interpolation is exact and only the time integration errs.
    test::Channel c = test::make_channel({16, 16, 8}, 0.25 * um);
    const real W = 2000, xc = 2 * um, yc = 2 * um;
    VelocityField u = test::velocity_from(c, [&](int comp, const Real3& x) {
        return comp == 0 ? -W * (x[1] - yc) : comp == 1 ? W * (x[0] - xc) : 0.0;
    });
    std::vector<real> errors;
    for (int steps : {20, 40, 80}) {
        std::vector<BodyConfig> bodies{test::sphere_body("p", {xc, yc, 1 * um}, 1 * um)};
        Coupling cp(adhesion_config(1, 50, {0, 0, 0}, {0, 0, 0}), bodies, *c.dec, 1000, 1e-3);
        std::vector<Real3> x0;
        for (const Receptor& r : cp.receptors())
            x0.push_back(r.x);
        const real T = 1.0 / W; // one radian
        for (int s = 0; s < steps; ++s)
            cp.carry(u, T / steps);
        real e = 0;
        for (std::size_t k = 0; k < x0.size(); ++k) {
            const real dx = x0[k][0] - xc, dy = x0[k][1] - yc;
            const real ex = xc + std::cos(1.0) * dx - std::sin(1.0) * dy;
            const real ey = yc + std::sin(1.0) * dx + std::cos(1.0) * dy;
            e = std::max(e, std::hypot(cp.receptors()[k].x[0] - ex, cp.receptors()[k].x[1] - ey));
        }
        errors.push_back(e);
    }
    for (int m = 0; m < 2; ++m)
        EXPECT_NEAR(std::log2(errors[m] / errors[m + 1]), 2.0, 0.1) << errors[m];
}

// ---- forces ---------------------------------------------------------------------------

TEST(AdhesionForces, SpreadForceIntegratesToFOnEachSideAndConservesMomentum) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    const Real3 F{3e-12, -7e-12, 2e-12};
    // Points: on the wall y = 0 (a ligand), near the top wall, across the periodic
    // boundaries, at a rank boundary (x = 2 um on 2 ranks), at a face and a cell centre.
    const std::vector<Real3> points{
        {1.1 * um, 0, 1.3 * um},           {0.01 * um, 3.95 * um, 3.99 * um},
        {2 * um, 1 * um, 2 * um},          {1.125 * um, 0.125 * um, 0.5 * um},
        {3.97 * um, 0.06 * um, 0.02 * um}, {2.01 * um, 2.3 * um, 1.7 * um}};
    for (const Real3& x : points) {
        VelocityField f = zero_field(c);
        spread_force(f, *c.dec, x, F);
        const Real3 t = total_force(f, c);
        for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(t[a], F[a], 1e-14 * 7e-12) << "at " << x[0] << ", " << x[1] << ", " << x[2];
        // The wall's own normal faces (v at y = 0) take nothing.
        if (c.dec->at_boundary(1, 0)) {
            for (int i = 0; i < c.dec->block().cells[0]; ++i)
                for (int k = 0; k < c.dec->block().cells[2]; ++k)
                    ASSERT_EQ(f[1](i, 0, k), 0.0);
        }
    }
    // spread_force itself: +F at one point, -F at another: zero in total.
    VelocityField f = zero_field(c);
    spread_force(f, *c.dec, points[5], F);
    spread_force(f, *c.dec, points[0], {-F[0], -F[1], -F[2]});
    const Real3 t = total_force(f, c);
    for (int a = 0; a < 3; ++a)
        EXPECT_LE(std::abs(t[a]), 1e-14 * 7e-12);
    // Away from walls the spread force is centred on the point (zero first moment).
    VelocityField g = zero_field(c);
    spread_force(g, *c.dec, points[5], F);
    real moment = 0;
    for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
        const Real3 xf = position(c.g, c.dec->block(), Location::FaceX, i, j, k);
        moment += g[0](i, j, k) * c.g.cell_volume() * (xf[0] - points[5][0]);
    });
    EXPECT_NEAR(c.dec->sum(moment), 0, 1e-14 * F[0] * um);
}

/// A sphere resting 30 nm above the vWF patch on y = 0, and a second one far from it.
struct BondScene {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> bodies{test::sphere_body("near", {2 * um, 1.03 * um, 2 * um}, 1 * um),
                                   test::sphere_body("far", {2 * um, 2.9 * um, 2 * um}, 0.9 * um)};
    AdhesionConfig cfg = [] {
        AdhesionConfig a =
            adhesion_config(2, 2000, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
        a.parameters.k_on = 2e6; // bonds form within a few steps of 1e-7 s
        return a;
    }();
};

TEST(AdhesionForces, BondsConserveMomentumAndTheFarBodyGetsNoWork) {
    BondScene s;
    Coupling cp(s.cfg, s.bodies, *s.c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(s.c);
    const real dt = 1e-7;
    std::size_t skipped = 0;
    for (std::uint64_t step = 0; step < 20; ++step) {
        cp.advance(rest, dt, step);
        skipped += cp.stats().bodies_skipped;
        EXPECT_EQ(cp.stats().bodies_near, 1u);
    }
    EXPECT_EQ(skipped, 20u);
    EXPECT_EQ(cp.bodies()[1].bonds, 0u);
    ASSERT_GT(cp.bodies()[0].bonds, 5u);
    EXPECT_EQ(cp.bond_count(), cp.ligands().bound_count());
    // The far body's receptors were never looked at: only the near body's receptors can
    // be counted as examined or skipped by the kinetics.
    EXPECT_LE(cp.stats().kinetics.examined + cp.stats().kinetics.skipped + cp.bodies()[0].bonds,
              cp.bodies()[0].end - cp.bodies()[0].begin);
    VelocityField f = zero_field(s.c);
    cp.add_bond_forces(f, dt);
    EXPECT_EQ(cp.stats().bonds_spread, cp.bond_count());
    EXPECT_GT(cp.stats().max_tension, 1e-13);
    // The ligands lie on the no-slip wall y = 0: the wall takes every -F. The fluid gets
    // the bonds' +F on the platelet and nothing else: its total is the force on the body
    // (not zero, as when -F was spread next to the wall), and the field is exactly the
    // receptors' spreading.
    const CouplingStats& st = cp.stats();
    const real scale = cp.stats().max_tension * static_cast<real>(cp.bond_count());
    ASSERT_GT(norm(st.force_on_bodies), 1e-3 * scale);
    const Real3 t = total_force(f, s.c);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t[a], st.force_on_bodies[a], 1e-13 * scale) << "component " << a;
        EXPECT_EQ(st.reaction_on_walls[a], -st.force_on_bodies[a]) << "component " << a;
        EXPECT_EQ(st.reaction_on_held[a], 0.0);
    }
    const VelocityField g = receptor_side(cp, s.cfg.parameters, s.c);
    real diff = 0, size = 0;
    for (int comp = 0; comp < 3; ++comp)
        for_each_cell(s.c.dec->block().cells, [&](int i, int j, int k) {
            diff = std::max(diff, std::abs(f[comp](i, j, k) - g[comp](i, j, k)));
            size = std::max(size, std::abs(g[comp](i, j, k)));
        });
    EXPECT_LE(test::global_max(diff), 1e-12 * test::global_max(size));
    for (std::uint64_t id = 0; id < cp.ligands().size(); ++id)
        ASSERT_EQ(cp.anchor_of(id), LigandAnchor::domain_wall);
    // Every rank holds the same bonds.
    EXPECT_EQ(spread_over_ranks(static_cast<real>(cp.bond_count())), 0.0);
    // The far body alone: no kinetics, no forces.
    AdhesionConfig far_only = s.cfg;
    far_only.receptors.erase(far_only.receptors.begin());
    Coupling lone(far_only, s.bodies, *s.c.dec, 1000, 1e-3);
    for (std::uint64_t step = 0; step < 5; ++step) {
        lone.advance(rest, dt, step);
        EXPECT_EQ(lone.stats().bodies_skipped, 1u);
        EXPECT_EQ(lone.stats().kinetics.examined + lone.stats().kinetics.skipped, 0u);
    }
    VelocityField h = zero_field(s.c);
    lone.add_bond_forces(h, dt);
    EXPECT_EQ(lone.stats().face_writes, 0u);
    EXPECT_EQ(lone.stable_time_step(), std::numeric_limits<real>::infinity());
}

TEST(AdhesionForces, TimeStepLimitsAreReportedNamingTheBodyAndTheBond) {
    BondScene s;
    Coupling cp(s.cfg, s.bodies, *s.c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(s.c);
    for (std::uint64_t step = 0; step < 20; ++step)
        cp.advance(rest, 1e-7, step);
    ASSERT_GT(cp.bond_count(), 5u);
    const real limit = cp.stable_time_step();
    ASSERT_TRUE(std::isfinite(limit));
    VelocityField f = zero_field(s.c);
    EXPECT_NO_THROW(cp.add_bond_forces(f, 0.99 * limit));
    try {
        cp.add_bond_forces(f, 1.01 * limit);
        ADD_FAILURE() << "expected a RunError above the stable time step";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("'near'"));
        EXPECT_THAT(e.what(), HasSubstr("stable_time_step"));
    }
    // The per-bond force limit: a bond whose force would move its receptor more than
    // max_step_displacement cells in one step, named with both ends.
    AdhesionConfig tight = s.cfg;
    tight.max_step_displacement = 1e-9;
    Coupling strict(tight, s.bodies, *s.c.dec, 1000, 1e-3);
    for (std::uint64_t step = 0; step < 20; ++step)
        strict.advance(rest, 1e-7, step);
    try {
        strict.add_bond_forces(f, 1e-7);
        ADD_FAILURE() << "expected a RunError above the force limit";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("receptor"));
        EXPECT_THAT(e.what(), HasSubstr("ligand"));
        EXPECT_THAT(e.what(), HasSubstr("max_step_displacement"));
        EXPECT_THAT(e.what(), HasSubstr("body 'near'"));
    }
}

TEST(AdhesionForces, ReceptorLeavingThroughAWallIsNamed) {
    test::Channel c = test::make_channel({16, 16, 8}, 0.25 * um);
    // A downward flow that would carry the receptors through the bottom wall in one step
    // (not a wall-consistent field: it stands for a step far too long).
    VelocityField u =
        test::velocity_from(c, [&](int comp, const Real3&) { return comp == 1 ? -10.0 : 0.0; });
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 2 * um, 1 * um}, 1 * um)};
    Coupling cp(adhesion_config(1, 20, {0, 0, 0}, {0, 0, 0}), bodies, *c.dec, 1000, 1e-3);
    try {
        cp.carry(u, 1e-6);
        ADD_FAILURE() << "expected a RunError";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("receptor"));
        EXPECT_THAT(e.what(), HasSubstr("body 'p'"));
        EXPECT_THAT(e.what(), HasSubstr("wall in y"));
    }
}

TEST(AdhesionForces, BondsAcrossAPeriodicBoundaryUseTheNearestImage) {
    // A patch over the whole periodic width in z and a sphere straddling z = 0 above it:
    // receptors on both sides of the boundary bind, and every bond is short.
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 0.05 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 3000, {1.0 * um, 0, 0}, {3.0 * um, 0, 4 * um});
    cfg.parameters.k_on = 2e6;
    Coupling cp(cfg, bodies, *c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(c);
    for (std::uint64_t step = 0; step < 20; ++step)
        cp.advance(rest, 1e-7, step);
    std::size_t low = 0, high = 0;
    for (const Receptor& r : cp.receptors()) {
        if (!r.bound()) continue;
        (cp.ligands().position(r.ligand)[2] < 2 * um ? low : high) += 1;
    }
    EXPECT_GT(low, 3u);
    EXPECT_GT(high, 3u);
    // Move the cloud 30 nm in -z (across the boundary for some receptors): the bonds
    // stretch by at most that much.
    VelocityField w =
        test::velocity_from(c, [&](int comp, const Real3&) { return comp == 2 ? -0.3 : 0.0; });
    cp.carry(w, 1e-7);
    VelocityField f = zero_field(c);
    cp.add_bond_forces(f, 1e-7);
    const AdhesionParameters& p = cfg.parameters;
    EXPECT_EQ(cp.stats().bonds_spread, low + high);
    EXPECT_LE(cp.stats().max_tension,
              p.bond_stiffness * (p.reactive_distance + 31 * nm - p.bond_rest_length));
    const Real3 t = total_force(f, c);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t[a], cp.stats().force_on_bodies[a], 1e-13 * cp.stats().max_tension * 40);
        EXPECT_EQ(cp.stats().reaction_on_walls[a], -cp.stats().force_on_bodies[a]);
    }
}

// A pinned slab y <= 1 um (K = 1e8 on its faces, as a fixed wall's pinning) with the vWF
// patch on its top y = 1 um, a sphere 30 nm above: the reactions go onto the slab's held
// faces. The fluid (faces with K = 0) sees the receptors' +F only; the slab's faces get
// -F in total, so the force field sums to zero; the run is the same bits on any rank count.
TEST(AdhesionForces, ReactionOnAPinnedSolidGoesOntoItsHeldFaces) {
    auto run = [](MPI_Comm comm, Real3* bodies, std::size_t* bonds) {
        test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um, 0, 0, comm);
        VelocityField pin = zero_field(c);
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
                const Real3 x = position(c.g, c.dec->block(), face_location(comp), i, j, k);
                // The faces on the slab's top y = 1 um are held too (a pinned body's face
                // pinning averages its two cells: phi = 1/2 there, K = 5e7).
                pin[comp](i, j, k) = x[1] <= 1.0 * um ? 1e8 : 0.0;
            });
        std::vector<BodyConfig> b{test::sphere_body("p", {2 * um, 2.03 * um, 2 * um}, 1 * um)};
        AdhesionConfig cfg = adhesion_config(1, 2000, {1.0 * um, 1.0 * um, 1.0 * um},
                                             {3.0 * um, 1.0 * um, 3.0 * um});
        cfg.parameters.k_on = 2e6;
        Coupling cp(cfg, b, *c.dec, 1000, 1e-3);
        const std::array<std::array<bool, 2>, 3> walls{
            {{false, false}, {true, true}, {false, false}}};
        // Not within half a cell of a domain wall, and no pinned solid given: refused,
        // naming the region.
        try {
            cp.anchor(walls, nullptr);
            ADD_FAILURE() << "expected an InputError for a ligand anchored to nothing";
        } catch (const InputError& e) {
            EXPECT_THAT(e.what(), HasSubstr("adhesion.ligand_regions[0]"));
            EXPECT_THAT(e.what(), HasSubstr("pinned solid"));
        }
        cp.anchor(walls, &pin);
        for (std::uint64_t id = 0; id < cp.ligands().size(); ++id)
            EXPECT_EQ(cp.anchor_of(id), LigandAnchor::held_body);
        const VelocityField rest = zero_field(c);
        for (std::uint64_t step = 0; step < 20; ++step)
            cp.advance(rest, 1e-7, step);
        EXPECT_GT(cp.bond_count(), 5u);
        VelocityField f = zero_field(c);
        cp.add_bond_forces(f, 1e-7);
        const CouplingStats& st = cp.stats();
        const real scale = st.max_tension * static_cast<real>(cp.bond_count());
        EXPECT_GT(norm(st.force_on_bodies), 1e-3 * scale);
        const VelocityField g = receptor_side(cp, cfg.parameters, c);
        // Where the pinning is zero (the fluid), only the receptors' +F.
        real diff = 0;
        Real3 held{0, 0, 0};
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
                const real d = f[comp](i, j, k) - g[comp](i, j, k);
                if (pin[comp](i, j, k) == 0)
                    diff = std::max(diff, std::abs(d));
                else
                    held[comp] += d * c.g.cell_volume();
            });
        EXPECT_LE(test::global_max(diff), 1e-13 * scale / c.g.cell_volume());
        const Real3 t = total_force(f, c);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(c.dec->sum(held[a]), -st.force_on_bodies[a], 1e-12 * scale);
            EXPECT_EQ(st.reaction_on_held[a], -st.force_on_bodies[a]);
            EXPECT_EQ(st.reaction_on_walls[a], 0.0);
            EXPECT_LE(std::abs(t[a]), 1e-12 * scale); // body + wall: momentum conserved
        }
        // Held shares: 1 inside the slab, about one half on its top, 0 in the fluid.
        HeldSpreader hs;
        std::vector<real> share;
        const std::vector<Real3> pts{
            {2 * um, 0.5 * um, 2 * um}, {2 * um, 1.0 * um, 2 * um}, {2 * um, 2.0 * um, 2 * um}};
        hs.held_share(pin, *c.dec, pts, share);
        EXPECT_NEAR(share[0], 1.0, 1e-7);
        EXPECT_GT(share[1], 0.3);
        EXPECT_LT(share[1], 0.7);
        EXPECT_EQ(share[2], 0.0);
        *bodies = st.force_on_bodies;
        *bonds = cp.bond_count();
    };
    Real3 fw{}, fs{};
    std::size_t bw = 0, bs = 0;
    run(MPI_COMM_WORLD, &fw, &bw);
    run(MPI_COMM_SELF, &fs, &bs);
    EXPECT_EQ(bw, bs);
    for (int a = 0; a < 3; ++a)
        EXPECT_EQ(fw[a], fs[a]);
}

TEST(AdhesionForces, LigandsOnAFreeSlipBoundaryOrInTheFluidAreRefused) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> b{test::sphere_body("p", {2 * um, 2.03 * um, 2 * um}, 1 * um)};
    // On y = 0, but that boundary is free-slip here (it takes no tangential force).
    Coupling on_wall(adhesion_config(1, 50, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um}), b,
                     *c.dec, 1000, 1e-3);
    EXPECT_NO_THROW(on_wall.anchor({{{false, false}, {true, true}, {false, false}}}, nullptr));
    EXPECT_THROW(on_wall.anchor({{{false, false}, {false, true}, {false, false}}}, nullptr),
                 InputError);
    // Two regions, the second floating in the fluid: named as [1].
    AdhesionConfig two = adhesion_config(1, 50, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    two.ligand_regions.push_back(
        {{1.0 * um, 2.0 * um, 1.0 * um}, {1.5 * um, 2.0 * um, 1.5 * um}, 50 * nm});
    two.ligand_density.push_back(1 / (50 * nm * 50 * nm));
    Coupling floating(two, b, *c.dec, 1000, 1e-3);
    try {
        floating.anchor({{{false, false}, {true, true}, {false, false}}}, nullptr);
        ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("adhesion.ligand_regions[1]"));
    }
}

TEST(AdhesionRanks, SameBitsAsTheSerialRun) {
    // The coupling on the world's decomposition and, on every rank, on a serial one
    // (MPI_COMM_SELF): the same receptor positions, bonds and face forces, bit for bit.
    const real G = 800;
    auto field = [&](const test::Channel& c) {
        return test::velocity_from(c, [&](int comp, const Real3& x) {
            return comp == 0   ? G * x[1] + 3e-4 * std::sin(x[2] / um)
                   : comp == 2 ? 1e-4 * std::cos(x[0] / um) * std::sin(x[1] * 0.7 / um)
                               : 0.0;
        });
    };
    test::Channel world = test::make_channel({16, 16, 16}, 0.25 * um, 0, G * 4 * um);
    test::Channel self = test::make_channel({16, 16, 16}, 0.25 * um, 0, G * 4 * um, MPI_COMM_SELF);
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 2 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 2000, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    cfg.parameters.k_on = 2e6;
    Coupling a(cfg, bodies, *world.dec, 1000, 1e-3), b(cfg, bodies, *self.dec, 1000, 1e-3);
    const VelocityField ua = field(world), ub = field(self);
    VelocityField fa = zero_field(world), fb = zero_field(self);
    for (std::uint64_t step = 0; step < 10; ++step) {
        a.add_bond_forces(fa, 1e-7);
        b.add_bond_forces(fb, 1e-7);
        a.advance(ua, 1e-7, step);
        b.advance(ub, 1e-7, step);
    }
    ASSERT_GT(a.bond_count(), 3u);
    for (std::size_t k = 0; k < a.receptors().size(); ++k) {
        ASSERT_EQ(a.receptors()[k].ligand, b.receptors()[k].ligand);
        for (int d = 0; d < 3; ++d)
            ASSERT_EQ(a.receptors()[k].x[d], b.receptors()[k].x[d]) << "receptor " << k;
    }
    const Int3 off = world.dec->block().offset;
    for (int comp = 0; comp < 3; ++comp)
        for_each_cell(world.dec->block().cells, [&](int i, int j, int k) {
            ASSERT_EQ(fa[comp](i, j, k), fb[comp](i + off[0], j + off[1], k + off[2]));
        });
}

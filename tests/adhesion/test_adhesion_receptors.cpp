// The receptors of the adhesion coupling (solver/adhesion/placement, grid_transfer, coupling)
// on 1 and 2 ranks: placement reproducible, on the surface, uniform in area and independent
// of the rank count; receptors carried exactly by a uniform flow and a linear shear, the
// interpolation second order in space and the midpoint rule second order in time; a
// receptor carried through a wall named with its body.
#include "adhesion/coupling.hpp"
#include "adhesion_scene.hpp"
#include "test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace efsi;
using namespace efsi::adhesion;
using efsi::test::adhesion_config;
using efsi::test::spread_over_ranks;
using efsi::test::um;
using ::testing::HasSubstr;

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

TEST(AdhesionCarry, RigidMotionKeepsReceptorsOnTheirBody) {
    // A spinning, translating sphere: every receptor stays at the radius from the moved
    // centre and keeps its distance to every other (round-off), over 400 steps that take the
    // cloud across the periodic seams in x and z (the motion's centre given in another image).
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    const Real3 centre{3.5 * um, 2 * um, 0.5 * um};
    const real r = 1 * um;
    std::vector<BodyConfig> bodies{test::sphere_body("p", centre, r)};
    AdhesionConfig cfg = adhesion_config(1, 300, {0, 0, 0}, {0, 0, 0});
    cfg.receptor_motion = ReceptorMotion::rigid;
    Coupling cp(cfg, bodies, *c.dec, 1000, 1e-3);
    ASSERT_TRUE(cp.moves_rigidly());
    RigidMotion m;
    m.centre = {centre[0] - c.g.length[0], centre[1], centre[2] + c.g.length[2]};
    m.velocity = {2e-4, 0, -1e-4};
    m.spin = {300, -150, 700};
    const std::vector<Receptor> start(cp.receptors().begin(), cp.receptors().end());
    const real dt = 1e-4;
    Real3 moved = centre; // the centre in the image the cloud is in
    int wraps = 0;
    for (int step = 0; step < 400; ++step) {
        cp.carry_rigidly({&m, 1}, dt);
        for (int a = 0; a < 3; ++a) {
            m.centre[a] += dt * m.velocity[a];
            moved[a] += dt * m.velocity[a];
        }
        const auto q = cp.receptors();
        // Follow the cloud's wraps: it is shifted by a box length as a whole.
        for (int a : {0, 2}) {
            const real s = std::round((q[0].x[a] - moved[a]) / c.g.length[a]);
            if (s != 0) ++wraps;
            moved[a] += s * c.g.length[a];
        }
        for (const Receptor& p : q)
            ASSERT_NEAR(std::hypot(p.x[0] - moved[0], p.x[1] - moved[1], p.x[2] - moved[2]), r,
                        1e-9 * r)
                << "step " << step;
    }
    EXPECT_EQ(wraps, 3); // x: 3.5 -> 11.5 um in a 4 um box (twice), z: 0.5 -> -3.5 um (once)
    const auto q = cp.receptors();
    for (std::size_t k = 1; k < q.size(); k += 37) {
        const real d0 = std::hypot(start[k].x[0] - start[0].x[0], start[k].x[1] - start[0].x[1],
                                   start[k].x[2] - start[0].x[2]);
        const real d =
            std::hypot(q[k].x[0] - q[0].x[0], q[k].x[1] - q[0].x[1], q[k].x[2] - q[0].x[2]);
        EXPECT_NEAR(d, d0, 1e-9 * r);
    }
    // The same positions on every rank.
    EXPECT_EQ(test::spread_over_ranks(q[5].x[0]), 0.0);
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

TEST(AdhesionCarry, ReceptorLeavingThroughAWallIsNamed) {
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

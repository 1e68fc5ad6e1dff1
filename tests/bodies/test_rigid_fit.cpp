// The rigid motion fitted to the flow over a body (bodies/rigid_fit.hpp) and the rigid move
// of a point (core/rigid_motion.hpp): a velocity field that is itself a rigid motion is
// recovered to round-off, on any rank count and across a periodic seam; the fit of a shear
// flow over a sphere spins at half the shear rate; a move keeps distances for any number of
// steps and turns a point by the exact angle.
#include "bodies/body_test_support.hpp"
#include "bodies/rigid_fit.hpp"
#include "core/matrix3.hpp"

#include <cmath>
#include <numbers>

using namespace efsi;
using namespace efsi::test;

namespace {

/// u_c = f(c, x) on every face of the block, halos filled.
template <class F>
VelocityField velocity_from(Bodies& s, F&& f) {
    VelocityField u("u", s.dec.block(), 3);
    const GlobalGrid& g = s.dec.grid();
    for (int c = 0; c < 3; ++c)
        for_each_in(u[c].owned(), [&](int i, int j, int k) {
            u[c](i, j, k) = f(c, position(g, s.dec.block(), face_location(c), i, j, k));
        });
    s.halos.fill(u);
    return u;
}

real distance(const Real3& a, const Real3& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

} // namespace

TEST(RigidFit, RecoversARigidVelocityField) {
    Bodies s(grid_3d(R"(
[[body]]
name = "platelet"
kind = "solid"
shear_modulus = 5.0
shape = "ellipsoid"
centre = [0.53, 0.41, 0.37]
semi_axes = [0.2, 0.12, 0.18]
axis = [0.3, 1.0, 0.2]
angle = 0.7
)"));
    const Real3 V0{0.3, -0.2, 0.1}, w{1.1, -0.7, 2.3}, x0{0.2, 0.9, 0.1};
    // A linear field: its cell-centre means are exact, so the fit is the field itself.
    const VelocityField u = velocity_from(s, [&](int c, const Real3& x) {
        return V0[c] + cross(w, {x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]})[c];
    });
    const RigidMotion m = fit_rigid_motion(s.body(0), u, s.dec, {0.53, 0.41, 0.37});
    const Real3 expected =
        cross(w, {m.centre[0] - x0[0], m.centre[1] - x0[1], m.centre[2] - x0[2]});
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(m.centre[a], (Real3{0.53, 0.41, 0.37})[a], 0.01); // the discrete centroid
        EXPECT_NEAR(m.velocity[a], V0[a] + expected[a], 1e-13);
        EXPECT_NEAR(m.spin[a], w[a], 1e-12);
    }
    // The same numbers on every rank.
    EXPECT_EQ(global_max(m.spin[2]) + global_max(-m.spin[2]), 0.0);
}

TEST(RigidFit, AcrossThePeriodicSeam) {
    // A sphere cut by the seam x = 0 and a rigid field periodic in x (a spin about x).
    Bodies s(grid_3d(R"(
[[body]]
name = "p"
kind = "solid"
shear_modulus = 5.0
shape = "sphere"
centre = [0.02, 0.5, 0.4]
radius = 0.15
)"));
    // phi redrawn here, sharp, over both sides of the seam (the patch crosses it: its x
    // indices run past the grid's, bodies/patch.hpp).
    Body& b = s.body(0);
    const GlobalGrid& g = s.dec.grid();
    for_each_in(b.phi().owned(), [&](int i, int j, int k) {
        Real3 x = position(g, s.dec.block(), Location::Cell, i, j, k);
        x[0] -= 1.2 * std::round((x[0] - 0.02) / 1.2);
        b.phi()(i, j, k) = distance(x, {0.02, 0.5, 0.4}) < 0.15 ? 1.0 : 0.0;
    });
    const real v = volume(s.dec, b) * g.cell_volume();
    ASSERT_NEAR(v, 4.0 / 3.0 * std::numbers::pi * std::pow(0.15, 3), 0.05 * v);
    const Real3 V0{0.5, 0.05, -0.02};
    const real wx = 1.7, y0 = 0.3, z0 = 0.6;
    const VelocityField u = velocity_from(s, [&](int c, const Real3& x) {
        return V0[c] + (c == 1 ? -wx * (x[2] - z0) : c == 2 ? wx * (x[1] - y0) : 0.0);
    });
    for (const Real3 near : {Real3{0.0, 0.5, 0.4}, Real3{1.2, 0.5, 0.4}}) {
        const RigidMotion m = fit_rigid_motion(s.body(0), u, s.dec, near);
        // The centroid is in the image of `near`.
        EXPECT_NEAR(m.centre[0], near[0] + 0.02, 0.01); // the discrete centroid
        EXPECT_NEAR(m.centre[0] - near[0], fit_rigid_motion(b, u, s.dec, {0.0, 0.5, 0.4}).centre[0],
                    1e-12);
        EXPECT_NEAR(m.velocity[0], V0[0], 1e-13);
        EXPECT_NEAR(m.velocity[1], V0[1] - wx * (m.centre[2] - z0), 1e-13);
        EXPECT_NEAR(m.velocity[2], V0[2] + wx * (m.centre[1] - y0), 1e-13);
        EXPECT_NEAR(m.spin[0], wx, 1e-12);
        EXPECT_NEAR(m.spin[1], 0, 1e-12);
        EXPECT_NEAR(m.spin[2], 0, 1e-12);
    }
}

TEST(RigidFit, ShearOverASphereSpinsAtHalfTheRate) {
    // u_x = G (y - y0) over a sphere centred on a grid node: its cells are symmetric under
    // x <-> y, so the fit's spin is exactly -G/2 (the rotation part of the shear).
    Bodies s(grid_3d(R"(
[[body]]
name = "p"
kind = "solid"
shear_modulus = 5.0
shape = "sphere"
centre = [0.6, 0.5, 0.4]
radius = 0.2
)"));
    const real G = 3.0, y0 = 0.45;
    const VelocityField u =
        velocity_from(s, [&](int c, const Real3& x) { return c == 0 ? G * (x[1] - y0) : 0.0; });
    const RigidMotion m = fit_rigid_motion(s.body(0), u, s.dec, {0.6, 0.5, 0.4});
    EXPECT_NEAR(m.spin[2], -G / 2, 1e-12);
    EXPECT_NEAR(m.spin[0], 0, 1e-12);
    EXPECT_NEAR(m.spin[1], 0, 1e-12);
    EXPECT_NEAR(m.velocity[0], G * (m.centre[1] - y0), 1e-13);
}

TEST(RigidMotion, KeepsDistancesAndTurnsByTheExactAngle) {
    RigidMotion m;
    m.centre = {1, 2, 3};
    m.velocity = {0.1, 0, -0.2};
    m.spin = {0, 0, std::numbers::pi / 2}; // a quarter turn about z per unit time
    const Real3 x = m.move({2, 2, 3}, 1.0);
    EXPECT_NEAR(x[0], 1 + 0.1, 1e-15);
    EXPECT_NEAR(x[1], 3, 1e-15);
    EXPECT_NEAR(x[2], 3 - 0.2, 1e-15);
    // Many small steps about a moving centre keep the distances between points.
    m.spin = {0.3, -1.2, 0.8};
    Real3 a{1.5, 2.1, 2.7}, b{0.7, 2.4, 3.3}, c = m.centre;
    const real ab = distance(a, b), ac = distance(a, c);
    for (int n = 0; n < 10000; ++n) {
        a = m.move(a, 1e-3);
        b = m.move(b, 1e-3);
        c = m.move(c, 1e-3);
        for (int k = 0; k < 3; ++k)
            m.centre[k] += 1e-3 * m.velocity[k];
    }
    EXPECT_NEAR(distance(a, b), ab, 1e-12);
    EXPECT_NEAR(distance(a, c), ac, 1e-12);
    EXPECT_NEAR(distance(c, m.centre), 0, 1e-12);
}

TEST(RigidLoad, SpreadOverTheBodyKeepsItsForceAndTorque) {
    // A sphere touching the wall y = 0 (its first cells next to it) under a force and a
    // torque about a point off its centre: the face densities sum to F and their moment about
    // the centroid is T + (p - c) x F, to round-off, on any rank count; no wall face is
    // written.
    Bodies s(grid_3d(R"(
[boundary]
y_low = "wall"
y_high = "wall"

[[body]]
name = "p"
kind = "solid"
shear_modulus = 5.0
shape = "sphere"
centre = [0.6, 0.16, 0.4]
radius = 0.15
)"));
    Body& b = s.body(0);
    s.halos.fill(b.phi(), b.patch());
    const GlobalGrid& g = s.dec.grid();
    RigidLoad load;
    load.point = {0.65, 0.1, 0.45};
    load.force = {2e-3, -5e-3, 1e-3};
    load.torque = {1e-4, -3e-4, 2e-4};
    VelocityField f("f", s.dec.block(), 3);
    for (int c = 0; c < 3; ++c)
        f[c].fill(0);
    EXPECT_GT(spread_rigid_load(b, load, s.dec, f), 0u);
    const VelocityField zero = velocity_from(s, [](int, const Real3&) { return 0.0; });
    const Real3 c = fit_rigid_motion(b, zero, s.dec, load.point).centre;
    std::array<real, 6> sum{}; // force, then moment about c
    for (int comp = 0; comp < 3; ++comp)
        for_each_in(f[comp].owned(), [&](int i, int j, int k) {
            const real v = f[comp](i, j, k) * g.cell_volume();
            if (v == 0) return;
            if (comp == 1) {
                EXPECT_GT(j + s.dec.block().offset[1], 0) << "a wall face written";
            }
            const Real3 x = position(g, s.dec.block(), face_location(comp), i, j, k);
            Real3 F{0, 0, 0};
            F[comp] = v;
            const Real3 m = cross({x[0] - c[0], x[1] - c[1], x[2] - c[2]}, F);
            sum[comp] += v;
            for (int a = 0; a < 3; ++a)
                sum[3 + a] += m[a];
        });
    s.dec.sum_in_place(sum);
    const Real3 arm{load.point[0] - c[0], load.point[1] - c[1], load.point[2] - c[2]};
    const Real3 shift = cross(arm, load.force);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(sum[a], load.force[a], 1e-15);
        EXPECT_NEAR(sum[3 + a], load.torque[a] + shift[a], 1e-15);
    }
}

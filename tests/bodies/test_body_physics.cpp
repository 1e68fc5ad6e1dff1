// The bodies behind one interface (bodies/body_physics.hpp, bodies/body_system.hpp): a
// passive body carries phi only (no tensor, force or limit) and is carried by the flow with
// its volume kept; BodySystem keeps the smallest of each named limit over the bodies.
// The solid, fixed-wall and membrane kinds have their tests beside their sources
// (tests/solid/test_solid_body.cpp, tests/membrane/test_membrane_body.cpp).
#include "bodies/body_test_support.hpp"

#include <cmath>

using namespace efsi;
using namespace efsi::test;

TEST(PassiveBody, CarriesPhiOnlyAndAddsNothing) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "tracer"
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    const BodyPhysics& p = s.physics(0);
    EXPECT_NE(dynamic_cast<const PassiveBody*>(&p), nullptr);
    EXPECT_FALSE(p.carries_tensor());
    EXPECT_TRUE(p.moves());
    EXPECT_FALSE(p.adds_force());
    EXPECT_TRUE(p.time_step_limits().empty());
    EXPECT_TRUE(s.body(0).tensor().comp.empty());
    EXPECT_FALSE(s.system.adds_force());
    EXPECT_FALSE(s.system.viscosity_varies());
    // Carried by a uniform flow: the volume is kept to round-off and the body moves.
    const real v0 = volume(s.dec, s.body(0));
    const VelocityField u = uniform_velocity(s, 0.5, 0.25);
    StageTimers timers;
    for (int n = 0; n < 8; ++n)
        s.system.advance(u, 0.01, n, timers);
    EXPECT_NEAR(volume(s.dec, s.body(0)), v0, 1e-12 * v0);
    const auto d = s.system.measure();
    EXPECT_NEAR(d[0].centroid[0], 0.6 + 0.5 * 0.08, 2e-3);
    EXPECT_NEAR(d[0].centroid[1], 0.5 + 0.25 * 0.08, 2e-3);
}

TEST(BodySystem, KeepsTheSmallestLimitOfEachName) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "soft"
kind = "solid"
shear_modulus = 2.0
shape = "cylinder"
centre = [0.3, 0.5, 0.0]
radius = 0.1

[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 0.5
shape = "cylinder"
centre = [0.9, 0.5, 0.0]
radius = 0.15
interface = "smoothed"

[[body]]
name = "stiff"
kind = "solid"
shear_modulus = 32.0
shape = "cylinder"
centre = [0.6, 0.25, 0.0]
radius = 0.1
)");
    const auto limits = s.system.time_step_limits();
    ASSERT_EQ(limits.size(), 2u);
    const TimeStepLimit* e = find_limit(limits, "elastic");
    const TimeStepLimit* m = find_limit(limits, "membrane");
    ASSERT_TRUE(e && m);
    EXPECT_EQ(e->dt, s.physics(2).time_step_limits()[0].dt);
    EXPECT_EQ(m->dt, s.physics(1).time_step_limits()[0].dt);
    EXPECT_EQ(find_limit(limits, "bending"), nullptr);
}

// D of the body bounded by phi = 1/2 (BodyDiagnostics::taylor_deformation_sharp). On a
// smoothed ellipsoid both measures give (a - b) / (a + b); faint tails of phi (as a carried
// profile grows where the flow stretches it) move the moments of phi but not the sharp body.
TEST(BodySystem, SharpTaylorDeformationIgnoresFaintTails) {
    Bodies s(R"(
[grid]
cells = [40, 40, 40]
length = [1.0, 1.0, 1.0]

[fluid]
density = 1.0
viscosity = 1.0

[time]
end_time = 1.0

[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 1.0
shape = "ellipsoid"
semi_axes = [0.3, 0.18, 0.24]
centre = [0.5, 0.5, 0.5]
interface = "smoothed"
smoothing_width = 1.0
)");
    const real exact = (0.3 - 0.18) / (0.3 + 0.18);
    const auto before = s.system.measure();
    EXPECT_NEAR(before[0].taylor_deformation, exact, 1e-3);
    EXPECT_NEAR(before[0].taylor_deformation_sharp, exact, 1e-3);
    // A faint needle of phi = 0.1 along x through the body (0.1 x 0.1 in cross-section).
    const GlobalGrid& g = s.dec.grid();
    Field& phi = s.body(0).phi();
    for_each_in(phi.owned(), [&](int i, int j, int k) {
        const Real3 x = position(g, s.dec.block(), Location::Cell, i, j, k);
        if (std::abs(x[1] - 0.5) < 0.05 && std::abs(x[2] - 0.5) < 0.05 && phi(i, j, k) < 0.1)
            phi(i, j, k) = 0.1;
    });
    s.halos.fill(phi);
    const auto after = s.system.measure();
    EXPECT_GT(after[0].taylor_deformation - before[0].taylor_deformation, 5e-3);
    EXPECT_LT(std::abs(after[0].taylor_deformation_sharp - before[0].taylor_deformation_sharp),
              1e-4);
}

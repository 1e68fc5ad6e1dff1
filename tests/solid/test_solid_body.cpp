// Solids as bodies (solid/solid_body.hpp):
//  - a free solid carries B (identity at rest, where its force vanishes exactly), the
//    viscosity of its material, and one time-step limit named "elastic" (the shear-wave
//    formula);
//  - a fixed wall (pinned solid) keeps B = I (not even stored), never moves, adds no force
//    and no limit, only its penalisation phi / (tau / dt).
#include "bodies/body_test_support.hpp"
#include "solid/solid_body.hpp"

#include <algorithm>
#include <cmath>

using namespace efsi;
using namespace efsi::test;

TEST(SolidBody, CarriesIdentityAtRestAndNamesItsElasticLimit) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "particle"
kind = "solid"
shear_modulus = 8.0
solid_viscosity = 0.3
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    const auto* solid = dynamic_cast<const SolidBody*>(&s.physics(0));
    ASSERT_NE(solid, nullptr);
    EXPECT_TRUE(solid->carries_tensor());
    EXPECT_TRUE(solid->adds_force());
    EXPECT_EQ(solid->viscosity(), 0.3);
    EXPECT_TRUE(s.system.viscosity_varies());
    // One limit, "elastic": the larger of half the shear-wave CFL, min(dx) / (2 sqrt(G /
    // rho)), and the viscous relaxation min(mu_f, mu_s) / G (here both 0.0125).
    ASSERT_EQ(solid->time_step_limits().size(), 1u);
    EXPECT_EQ(solid->time_step_limits()[0].name, "elastic");
    EXPECT_DOUBLE_EQ(solid->time_step_limits()[0].dt,
                     std::max(0.5 * 0.05 / std::sqrt(8.0 / 2.0), std::min(0.1, 0.3) / 8.0));
    // B = I at rest: B' = 0, so the elastic force vanishes exactly.
    Body& b = s.body(0);
    ASSERT_EQ(b.tensor().comp.size(), 3u);
    VelocityField force("force", s.dec.block(), s.dec.dim());
    s.system.add_forces(force);
    EXPECT_EQ(largest_force(force), 0.0);
    // A stretched B (B_xx = 1.2 in the solid) pushes.
    b.tensor().comp[0].fill(1.2);
    s.system.add_forces(force);
    EXPECT_GT(largest_force(force), 0.1);
}

TEST(FixedWall, KeepsBIdentityAddsNoForceAndIsPenalised) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "wall"
kind = "solid"
pinned = true
pin_tau_over_dt = 0.5
shape = "box"
centre = [0.6, 0.15, 0.0]
half_sizes = [0.3, 0.1, 1.0]
)");
    const BodyPhysics& p = s.physics(0);
    EXPECT_NE(dynamic_cast<const FixedWall*>(&p), nullptr);
    EXPECT_FALSE(p.carries_tensor()); // B = I is implicit: never stored, never transported
    EXPECT_FALSE(p.moves());
    EXPECT_FALSE(p.adds_force());
    EXPECT_TRUE(p.time_step_limits().empty());
    EXPECT_FALSE(s.system.adds_force());
    EXPECT_TRUE(s.body(0).tensor().comp.empty());
    EXPECT_EQ(s.system.measure()[0].tensor_trace_max, 0.0);
    // Not moved by the flow.
    const Field phi0 = s.body(0).phi();
    const VelocityField u = uniform_velocity(s, 0.5, 0.0);
    StageTimers timers;
    s.system.advance(u, 0.01, 0, timers);
    real change = 0;
    if (!s.body(0).patch().empty())
        for_each_in(phi0.owned(), [&](int i, int j, int k) {
            change = std::max(change, std::abs(s.body(0).phi()(i, j, k) - phi0(i, j, k)));
        });
    EXPECT_EQ(efsi::test::global_max(change), 0.0);
    // Penalisation chi = phi / (tau / dt) = 2 phi.
    Field chi("chi", Location::Cell, s.dec.block(), s.dec.dim());
    chi.fill(0);
    EXPECT_TRUE(s.system.add_pinning(chi));
    real worst = 0;
    if (!s.body(0).patch().empty())
        for_each_in(s.body(0).phi().owned(), [&](int i, int j, int k) {
            worst = std::max(worst, std::abs(chi(i, j, k) - 2 * s.body(0).phi()(i, j, k)));
        });
    EXPECT_EQ(efsi::test::global_max(worst), 0.0);
}

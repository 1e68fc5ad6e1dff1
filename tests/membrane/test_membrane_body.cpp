// A membrane as a body (membrane/membrane_body.hpp): its law from the case (Skalak's
// stiffest modulus), Gs = P_R from its shape (tangential: Gs n = 0, tr Gs = 2 around a
// circle), kappa_R allocated with bending, and its limits named "membrane" and "bending".
#include "bodies/body_test_support.hpp"
#include "membrane/membrane_body.hpp"
#include "membrane/membrane_force.hpp"

#include <algorithm>
#include <cmath>

using namespace efsi;
using namespace efsi::test;

TEST(MembraneBody, StartsTangentialAndNamesItsLimits) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "capsule"
kind = "membrane"
law = "skalak"
area_dilation = 3.0
elastic_modulus = 0.5
bending_modulus = 1e-4
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.25
interface = "smoothed"
)");
    const auto* m = dynamic_cast<const MembraneBody*>(&s.physics(0));
    ASSERT_NE(m, nullptr);
    EXPECT_TRUE(m->adds_force());
    EXPECT_EQ(m->viscosity(), 0.1); // the fluid's
    const GlobalGrid& g = s.cfg.grid;
    // Skalak: K = 2 Es / 3 (1 + 2 C).
    const real K = 2 * 0.5 / 3 * (1 + 2 * 3.0);
    EXPECT_DOUBLE_EQ(m->law().stiffest_modulus(), K);
    const auto& limits = m->time_step_limits();
    ASSERT_EQ(limits.size(), 2u);
    EXPECT_EQ(limits[0].name, "membrane");
    EXPECT_EQ(limits[0].dt, membrane_time_step_limit(g, 2.0, 0.1, K));
    EXPECT_EQ(limits[1].name, "bending");
    EXPECT_EQ(limits[1].dt, bending_time_step_limit(g, 2.0, 0.1, 1e-4));
    // Gs = P_R = I - n n around the circle: tr Gs = 2 (in-plane 1 + zz 1), Gs n = 0.
    const Body& b = s.body(0);
    ASSERT_NE(b.reference_curvature(), nullptr);
    real leak = 0, trace = 0;
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) {
            if (b.phi()(i, j, k) < 1e-3 || b.phi()(i, j, k) > 1 - 1e-3) return;
            const Real3 x = position(g, s.dec.block(), Location::Cell, i, j, k);
            const real dx = x[0] - 0.6, dy = x[1] - 0.5, r = std::hypot(dx, dy);
            const Int3 p{i, j, k};
            const SymmetricTensorField& G = b.tensor();
            leak = std::max(leak, std::abs(G.value(0, 0, p) * dx + G.value(0, 1, p) * dy) / r);
            leak = std::max(leak, std::abs(G.value(1, 0, p) * dx + G.value(1, 1, p) * dy) / r);
            trace = std::max(trace,
                             std::abs(G.value(0, 0, p) + G.value(1, 1, p) + G.value(2, 2, p) - 2));
        });
    EXPECT_LT(efsi::test::global_max(leak), 1e-8);
    EXPECT_LT(efsi::test::global_max(trace), 1e-8);
}

// rbc_in_tube's red cell on 70 x 35 x 35 cells (h = 24/70): 35 cells put cell centres on
// its axis, some about a dimple curvature radius outside the dimple, at a focal point of the
// surface where the level sets' curvature is unbounded (-1e15 in one cell, NaN in 21 before
// the bound). kappa_R must be finite and within 4/h everywhere, and the bound must act only
// far from the membrane.
TEST(MembraneBody, ReferenceCurvatureIsBoundedOnTheRedCellsAxis) {
    Bodies s(grid_toml("[70, 35, 35]", "[24.0, 12.0, 12.0]") + R"(
[[body]]
name = "rbc"
kind = "membrane"
shape = "biconcave"
centre = [8.0, 6.0, 6.0]
radius = 3.91
axis = [0.0, 1.0, 0.0]
angle = 1.5707963267948966
interface = "smoothed"
law = "skalak"
elastic_modulus = 9.0
area_dilation = 10.0
bending_modulus = 0.2
)");
    const Body& b = s.body(0);
    ASSERT_NE(b.reference_curvature(), nullptr);
    const real h = 24.0 / 70;
    real worst = 0, nonfinite = 0, bounded = 0, bounded_phi = 0;
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) {
            const real kr = (*b.reference_curvature())(i, j, k);
            if (!std::isfinite(kr)) {
                ++nonfinite;
                return;
            }
            worst = std::max(worst, std::abs(kr));
            if (std::abs(kr) == 4 / h || kr == 0) {
                ++bounded;
                bounded_phi = std::max(bounded_phi, b.phi()(i, j, k));
            }
        });
    EXPECT_EQ(efsi::test::global_max(nonfinite), 0.0);
    EXPECT_LE(efsi::test::global_max(worst), 4 / h);
    // The bound acted (this grid is the one that failed), and only where phi < 1e-3.
    EXPECT_GT(s.dec.sum(bounded), 0.0);
    EXPECT_LT(efsi::test::global_max(bounded_phi), 1e-3);
}

TEST(MembraneBody, ResolvableReferenceCurvatureClampsAndZeroesNaN) {
    EXPECT_EQ(resolvable_reference_curvature(1.5, 0.5), 1.5);
    EXPECT_EQ(resolvable_reference_curvature(-1e15, 0.5), -8.0);
    EXPECT_EQ(resolvable_reference_curvature(INFINITY, 0.5), 8.0);
    EXPECT_EQ(resolvable_reference_curvature(std::nan(""), 0.5), 0.0);
}

TEST(MembraneLimit, ViscousAtLowReynoldsInertialAtHigh) {
    GlobalGrid g;
    g.cells = {24, 20, 1};
    g.length = {1.2, 1.5, 0.05};
    g.dim = 2;
    EXPECT_EQ(membrane_time_step_limit(g, 1.0, 1.0, 0.0), 0.0);
    const real h = 0.05;
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e-6, 1.0, 2.0), 10 * 1.0 * h / 2.0);
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e3, 1e-9, 2.0),
                     std::sqrt(1e3 * h * h * h / (2 * 3.141592653589793 * 2.0)));
}

// A neo-Hookean capsule (cylinder) in grid_2d(); tests append keys to its [[body]].
const std::string plain_capsule = R"(
[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 0.5
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.25
interface = "smoothed"
)";

TEST(MembraneBody, ViscosityRatioSetsTheEnclosedFluidsViscosity) {
    const std::string& capsule = plain_capsule;
    for (const real ratio : {5.0, 0.2}) {
        Bodies s(grid_2d() + capsule + "viscosity_ratio = " + std::to_string(ratio) + "\n");
        const auto* m = dynamic_cast<const MembraneBody*>(&s.physics(0));
        ASSERT_NE(m, nullptr);
        EXPECT_DOUBLE_EQ(m->viscosity(), ratio * 0.1);
        EXPECT_TRUE(s.system.viscosity_varies());
        // The membrane's limit takes the smaller of the two viscosities.
        EXPECT_EQ(m->time_step_limits()[0].dt,
                  membrane_time_step_limit(s.cfg.grid, 2.0, std::min(1.0, ratio) * 0.1,
                                           m->law().stiffest_modulus()));
        // mu = mu_f + phi (lambda - 1) mu_f in every cell: lambda mu_f at the centre and mu_f
        // far outside, but for the tanh profile's tails (phi = 1 - 3e-4 at 4 cells in).
        Field mu("mu", Location::Cell, s.dec.block(), s.dec.dim(), 1);
        s.system.update_viscosity(mu);
        const Body& b = s.body(0);
        const Field& phi = b.phi();
        real mix = 0, centre = 0, far = 0;
        const GlobalGrid& g = s.cfg.grid;
        for_each_in(mu.owned(), [&](int i, int j, int k) {
            const Real3 x = position(g, s.dec.block(), Location::Cell, i, j, k);
            const real r = std::hypot(x[0] - 0.6, x[1] - 0.5);
            const Box& pl = b.patch().local;
            const bool on = !b.patch().empty() && i >= pl.lo[0] && i < pl.hi[0] && j >= pl.lo[1] &&
                            j < pl.hi[1] && k >= pl.lo[2] && k < pl.hi[2];
            const real f = on ? phi(i, j, k) : 0;
            mix = std::max(mix, std::abs(mu(i, j, k) - 0.1 * (1 + f * (ratio - 1))));
            if (r < 0.05) centre = std::max(centre, std::abs(mu(i, j, k) / (ratio * 0.1) - 1));
            if (r > 0.45) far = std::max(far, std::abs(mu(i, j, k) / 0.1 - 1));
        });
        EXPECT_LT(efsi::test::global_max(mix), 1e-15);
        EXPECT_LT(efsi::test::global_max(centre), 2e-3);
        EXPECT_LT(efsi::test::global_max(far), 2e-3);
    }
    // Ratio 1 (the default): one viscosity.
    Bodies one(grid_2d() + capsule);
    EXPECT_FALSE(one.system.viscosity_varies());
}

TEST(MembraneBody, IncrementDampingRelaxesTheViscousLimits) {
    // time.increment_damping = F adds (F - 1) mu_f to the viscosity of both limits
    // (config.hpp increment_viscosity): at this low density both are viscous, so F-fold.
    const std::string capsule = plain_capsule + "bending_modulus = 1e-4\n";
    Bodies plain(grid_2d() + capsule);
    std::string damped_text = grid_2d() + capsule;
    const std::string end = "end_time = 1.0\n";
    ASSERT_NE(damped_text.find(end), std::string::npos);
    damped_text.insert(damped_text.find(end) + end.size(), "increment_damping = 3.0\n");
    Bodies damped(damped_text);
    const auto& a = plain.physics(0).time_step_limits();
    const auto& b = damped.physics(0).time_step_limits();
    ASSERT_EQ(a.size(), 2u);
    ASSERT_EQ(b.size(), 2u);
    const GlobalGrid& g = damped.cfg.grid;
    EXPECT_EQ(b[0].dt, membrane_time_step_limit(g, 2.0, 3 * 0.1, 0.5));
    EXPECT_EQ(b[1].dt, bending_time_step_limit(g, 2.0, 3 * 0.1, 1e-4));
    EXPECT_GT(b[0].dt, a[0].dt);
}

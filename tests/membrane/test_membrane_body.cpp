// A membrane as a body (membrane/membrane_body.hpp): its law from the case (Skalak's
// stiffest modulus), Gs = P_R from its shape (tangential: Gs n = 0, tr Gs = 2 around a
// circle), kappa_R allocated with bending, and its limits named "membrane" and "bending".
#include "bodies/body_test_support.hpp"
#include "membrane/membrane_body.hpp"
#include "membrane/membrane_force.hpp"

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

TEST(MembraneLimit, ViscousAtLowReynoldsInertialAtHigh) {
    GlobalGrid g;
    g.cells = {24, 20, 1};
    g.length = {1.2, 1.5, 0.05};
    g.dim = 2;
    EXPECT_EQ(membrane_time_step_limit(g, 1.0, 1.0, 0.0), 0.0);
    const real h = 0.05;
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e-6, 1.0, 2.0), 4 * 1.0 * h / 2.0);
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e3, 1e-9, 2.0),
                     std::sqrt(1e3 * h * h * h / (2 * 3.141592653589793 * 2.0)));
}

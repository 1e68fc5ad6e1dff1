// The solid's pointwise pieces (solid/solid_mechanics.cpp): the elastic time-step limit of
// the stiffest solid, the mixture viscosity, and no elastic force from B = I.
#include "solid/solid_mechanics.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;

namespace {

GlobalGrid grid_2d() {
    GlobalGrid g;
    g.cells = {24, 20, 1};
    g.length = {1.2, 1.5, 0.05};
    g.dim = 2;
    return g;
}

} // namespace

TEST(ElasticLimit, FollowsTheStiffestSolid) {
    const GlobalGrid g = grid_2d(); // dx = 0.05, dy = 0.075
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, {}), 0.0);
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, {SolidLaw{0.0, 1.0}}), 0.0);
    const real one = elastic_time_step_limit(g, 2.0, {SolidLaw{8.0, 1.0}});
    EXPECT_DOUBLE_EQ(one, 0.5 * 0.05 / std::sqrt(8.0 / 2.0));
    // The minimum over solids is the limit of the stiffest one, bit for bit.
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, {SolidLaw{2.0, 1.0}, SolidLaw{8.0, 1.0}}), one);
}

TEST(MembraneLimit, ViscousAtLowReynoldsInertialAtHigh) {
    const GlobalGrid g = grid_2d();
    EXPECT_EQ(membrane_time_step_limit(g, 1.0, 1.0, 0.0), 0.0);
    const real h = 0.05;
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e-6, 1.0, 2.0), 4 * 1.0 * h / 2.0);
    EXPECT_DOUBLE_EQ(membrane_time_step_limit(g, 1e3, 1e-9, 2.0),
                     std::sqrt(1e3 * h * h * h / (2 * 3.141592653589793 * 2.0)));
}

// The solid's time-step limit (solid/solid_mechanics.cpp): the elastic limit of the
// stiffest solid, bit for bit the minimum over the solids.
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

// The solid's time-step limit (solid/solid_mechanics.cpp): per solid the larger of the
// shear-wave and the viscous-relaxation limits, the smallest over the solids.
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
    // Weak viscosity (mu = 1e-3): the shear-wave limit min(dx) / (2 sqrt(G / rho)) holds.
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, 1e-3, {}), 0.0);
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, 1e-3, {SolidLaw{0.0, 1e-3}}), 0.0);
    const real one = elastic_time_step_limit(g, 2.0, 1e-3, {SolidLaw{8.0, 1e-3}});
    EXPECT_DOUBLE_EQ(one, 0.5 * 0.05 / std::sqrt(8.0 / 2.0));
    // The minimum over solids is the limit of the stiffest one, bit for bit.
    EXPECT_EQ(elastic_time_step_limit(g, 2.0, 1e-3, {SolidLaw{2.0, 1e-3}, SolidLaw{8.0, 1e-3}}),
              one);
}

TEST(ElasticLimit, ViscousRelaxationWhereViscosityDampsEveryMode) {
    const GlobalGrid g = grid_2d();
    // Stokes regime (rho = 1e-3, mu = 1): the waves' limit 0.5 * 0.05 / 1e3 = 2.5e-5 is
    // far below mu / G = 0.125, which holds; mu is the smaller of the fluid's and the
    // solid's.
    EXPECT_DOUBLE_EQ(elastic_time_step_limit(g, 1e-3, 1.0, {SolidLaw{8.0, 1.0}}), 1.0 / 8.0);
    EXPECT_DOUBLE_EQ(elastic_time_step_limit(g, 1e-3, 1.0, {SolidLaw{8.0, 0.5}}), 0.5 / 8.0);
    EXPECT_DOUBLE_EQ(elastic_time_step_limit(g, 1e-3, 0.25, {SolidLaw{8.0, 1.0}}), 0.25 / 8.0);
    // Each solid takes the larger of its two limits, the run the smallest of those.
    EXPECT_DOUBLE_EQ(
        elastic_time_step_limit(g, 1e-3, 1.0, {SolidLaw{8.0, 1.0}, SolidLaw{2.0, 1.0}}), 1.0 / 8.0);
}

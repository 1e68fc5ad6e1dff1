// The estimate `efsi check` prints (simulation/run_estimate.hpp): patches counted as the
// solver lays them out, memory and work divided over the ranks, the step from the stiffest
// body's limit (named), all from the case alone.
#include "bodies/body_system.hpp"
#include "membrane/membrane_body.hpp"
#include "simulation/run_estimate.hpp"
#include "solid/solid_mechanics.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;
using efsi::test::case_from;

namespace {

const std::string box = R"(
[grid]
cells = [40, 32, 24]
length = [5.0, 4.0, 3.0]

[fluid]
density = 1.0
viscosity = 0.5

[time]
end_time = 2.0
)";

const std::string sphere = R"(
[[body]]
name = "ball"
kind = "solid"
shape = "sphere"
centre = [2.5, 2.0, 1.5]
radius = 0.5
shear_modulus = 10.0
)";

const std::string capsule = R"(
[[body]]
name = "capsule"
kind = "membrane"
shape = "sphere"
interface = "smoothed"
centre = [2.5, 2.0, 1.5]
radius = 0.5
elastic_modulus = 2.0
)";

} // namespace

TEST(RunEstimate, PatchIsTheBoxTailsAndMarginCutToTheGrid) {
    const Config c = case_from(box + sphere + capsule);
    // h = 0.125: radius 4 cells; sharp tail 1 cell, margin 4: 2 (4 + 1 + 4) = 18 per side.
    EXPECT_DOUBLE_EQ(initial_patch_cells(c.bodies[0], c.grid), 18.0 * 18.0 * 18.0);
    // Smoothed: the tanh tail to phi = 1e-8, 9.2 eps: ceil(2 (4 + 9.2 + 4)) = 35, cut to 24 in z.
    EXPECT_DOUBLE_EQ(initial_patch_cells(c.bodies[1], c.grid), 35.0 * 32.0 * 24.0);
}

TEST(RunEstimate, StepFromTheStiffestBodyAndCostOverTheRanks) {
    const Config c = case_from(box + sphere + capsule);
    CostRates r;
    r.process_bytes = 1e6;
    r.flow_bytes_per_cell = 100;
    r.flow_bytes_per_cell_hypre = 700;
    r.flow_seconds_fft = 1e-8;
    r.flow_seconds_hypre = 1e-7;
    r.solid_bytes_per_patch_cell = 300;
    r.solid_seconds_per_patch_cell = 2e-7;
    r.membrane_bytes_per_patch_cell = 500;
    r.membrane_seconds_per_patch_cell = 3e-7;
    const RunEstimate one = estimate_run(c, 1, r);
    const double cells = 40.0 * 32 * 24, solid = 18.0 * 18 * 18, membrane = 35.0 * 32 * 24;
    EXPECT_DOUBLE_EQ(one.solid_patch_cells, solid);
    EXPECT_DOUBLE_EQ(one.membrane_patch_cells, membrane);
    // The box is periodic in x and the ball may cross it: the seam copies (next test).
    const double seam = seam_copy_bytes(c, {1, 1, 1});
    EXPECT_DOUBLE_EQ(one.seam_copy_bytes_per_rank, seam);
    EXPECT_DOUBLE_EQ(one.bytes_per_rank, 1e6 + seam + 100 * cells + 300 * solid + 500 * membrane);
    // Uniform viscosity, no pinned body: the FFT flow rate.
    EXPECT_DOUBLE_EQ(one.seconds_per_step, 1e-8 * cells + 2e-7 * solid + 3e-7 * membrane);
    // The smaller of the solid's elastic and the membrane's limits, times cfl = 0.5.
    const double elastic = elastic_time_step_limit(c.grid, 1.0, 0.5, {SolidLaw{10.0, 0.5}});
    const double membrane_dt = membrane_time_step_limit(c.grid, 1.0, 0.5, 2.0);
    EXPECT_DOUBLE_EQ(one.dt, 0.5 * std::min(elastic, membrane_dt));
    EXPECT_NE(one.dt_limit.find(elastic < membrane_dt ? "'ball'" : "'capsule'"), std::string::npos);
    EXPECT_DOUBLE_EQ(one.seconds_to_end, one.seconds_per_step / one.dt * 2.0);
    // Four ranks: the process's own memory and the seam copies of its block on each, a
    // quarter of the rest and of the time.
    const RunEstimate four = estimate_run(c, 4, r);
    EXPECT_DOUBLE_EQ(four.bytes_per_rank,
                     1e6 + four.seam_copy_bytes_per_rank + (one.bytes_per_rank - 1e6 - seam) / 4);
    EXPECT_DOUBLE_EQ(four.seconds_per_step, one.seconds_per_step / 4);
    // A fixed time.dt is the step.
    const RunEstimate fixed =
        estimate_run(case_from(box + sphere + capsule, {{"time.dt", "0.001"}}), 1, r);
    EXPECT_DOUBLE_EQ(fixed.dt, 0.001);
    EXPECT_EQ(fixed.dt_limit, "time.dt");
    // No body: no step to estimate, the cost per step only.
    const RunEstimate empty = estimate_run(case_from(box), 1, r);
    EXPECT_EQ(empty.dt, 0.0);
    EXPECT_DOUBLE_EQ(empty.seconds_per_step, 1e-8 * cells);
    // A viscosity ratio makes the viscous solve hypre's: its bytes and seconds per cell.
    const RunEstimate hypre =
        estimate_run(case_from(box + sphere + capsule, {{"body[1].viscosity_ratio", "5.0"}}), 1, r);
    EXPECT_DOUBLE_EQ(hypre.bytes_per_rank, 1e6 + seam + 700 * cells + 300 * solid + 500 * membrane);
    EXPECT_DOUBLE_EQ(hypre.seconds_per_step, 1e-7 * cells + 2e-7 * solid + 3e-7 * membrane);
}

TEST(RunEstimate, SeamCopiesOfTheBodiesThatMayCrossThePeriodicSeam) {
    // The ball (a solid, 18 cells wide) may cross; the capsule's strain is carried by its
    // surface velocity, so it keeps the whole of x and never crosses.
    const Config c = case_from(box + sphere + capsule);
    EXPECT_TRUE(may_cross_seam(c, c.bodies[0]));
    EXPECT_FALSE(may_cross_seam(c, c.bodies[1]));
    // x halo: 18 + 4 rounded up to 8 = 24 cells each side; y and z halos 2; two copies of
    // three components, 8 bytes per value.
    EXPECT_DOUBLE_EQ(seam_copy_bytes(c, {1, 1, 1}), 2.0 * 3 * (40 + 48) * (32 + 4) * (24 + 4) * 8);
    // Over 1 x 2 x 2 ranks each holds its y-z block's.
    EXPECT_DOUBLE_EQ(seam_copy_bytes(c, {1, 2, 2}), 2.0 * 3 * (40 + 48) * (16 + 4) * (12 + 4) * 8);
    // x split over the ranks, walls in x, or no body that may cross: none.
    EXPECT_EQ(seam_copy_bytes(c, {2, 1, 1}), 0.0);
    const std::string walls_x = "\n[boundary]\nx_low = \"wall\"\nx_high = \"wall\"\n";
    EXPECT_EQ(seam_copy_bytes(case_from(box + walls_x + sphere), {1, 1, 1}), 0.0);
    EXPECT_EQ(seam_copy_bytes(case_from(box + capsule), {1, 1, 1}), 0.0);
    // A solid with a viscosity of its own writes mu: it keeps the whole of x.
    EXPECT_EQ(
        seam_copy_bytes(case_from(box + sphere, {{"body[0].solid_viscosity", "2.0"}}), {1, 1, 1}),
        0.0);
}

// The SMAC step with the direct FFT solves (solver.*.method = "auto") against the same
// step with hypre converged to 1e-13, for every boundary combination the box can have:
// periodic, no-slip (moving) walls, free slip, and mixtures of them per face, in 2D and
// 3D, Crank-Nicolson and backward Euler. The pressure and each velocity component (each
// with its own closure: wall faces along its normal, zero value across no-slip walls,
// zero gradient across free-slip ones) must agree to round-off on 1 to 4 ranks.
#include "flow/initial_conditions.hpp"
#include "test_support.hpp"
#include "time/smac.hpp"

#include <cmath>
#include <iostream>
#include <memory>

using namespace efsi;
using efsi::test::case_from;

namespace {

struct BoxSetup {
    std::string name;
    std::string grid; ///< [grid] section body
    std::string boundary;
    std::string scheme = "crank_nicolson";
};

/// A rough, non-solenoidal velocity as a function of the global face index.
real rough(int c, const Int3& q) {
    return 0.3 * std::sin(0.9 * q[0] + 0.5 * c) * std::cos(0.7 * q[1]) +
           0.2 * std::cos(1.3 * q[2] + 0.4 * q[0] - c) + 0.1 * c;
}

struct StepRun {
    Config cfg;
    std::unique_ptr<Decomposition> dec;
    std::unique_ptr<HaloFiller> halos;
    std::unique_ptr<FlowState> s;
    std::unique_ptr<SmacStepper> stepper;
    StageTimers timers;

    explicit StepRun(Config conf) : cfg(std::move(conf)) {
        dec = std::make_unique<Decomposition>(MPI_COMM_WORLD, cfg.grid,
                                              periodic_directions(cfg.boundaries), cfg.ranks);
        halos = std::make_unique<HaloFiller>(*dec, cfg.boundaries);
        s = std::make_unique<FlowState>(dec->block(), dec->dim());
        stepper = std::make_unique<SmacStepper>(cfg, *dec, *halos);
        set_initial_condition(cfg, *dec, *s);
        const Int3 o = dec->block().offset;
        for (int c = 0; c < s->u.dim; ++c)
            for_each_cell(dec->block().cells, [&](int i, int j, int k) {
                const Int3 p{i, j, k};
                s->u[c](p) = halos->is_fixed_wall_face(c, p[c])
                                 ? 0.0
                                 : rough(c, {o[0] + i, o[1] + j, o[2] + k});
            });
        halos->fill(s->u);
        halos->fill(s->p);
        halos->fill(s->mu);
    }
    void steps(int n) {
        for (int i = 0; i < n; ++i) {
            const StepReport r = stepper->step(*s, 0.004 * (1 + 0.25 * i), timers);
            EXPECT_TRUE(r.pressure.converged);
            EXPECT_TRUE(r.viscous.converged);
        }
    }
};

std::string case_text(const BoxSetup& su) {
    return "[grid]\n" + su.grid + "\n[fluid]\ndensity = 1.3\nviscosity = 0.05\n[boundary]\n" +
           su.boundary + "\n[time]\nend_time = 1.0\nviscous = \"" + su.scheme + "\"\n";
}

class FftVersusHypre : public ::testing::TestWithParam<BoxSetup> {};

} // namespace

TEST_P(FftVersusHypre, StepsAgreeToRoundOff) {
    const BoxSetup& su = GetParam();
    Config fft_cfg, hypre_cfg;
    try {
        fft_cfg = case_from(case_text(su));
        hypre_cfg = case_from(case_text(su), {{"solver.pressure.method", "pcg_pfmg"},
                                              {"solver.pressure.tolerance", "1e-13"},
                                              {"solver.viscous.method", "pcg_pfmg"},
                                              {"solver.viscous.tolerance", "1e-13"}});
        Decomposition::choose_ranks(test::world_size(), fft_cfg.grid, fft_cfg.ranks);
    } catch (const InputError& e) {
        GTEST_SKIP() << e.what();
    }
    const LinearSolverChoice choice = choose_linear_solvers(fft_cfg);
    EXPECT_TRUE(choice.pressure_fft);
    EXPECT_TRUE(choice.viscous_fft);
    StepRun a(fft_cfg), b(hypre_cfg);
    EXPECT_THAT(a.stepper->solver_summary(), ::testing::HasSubstr("pressure FFT"));
    EXPECT_THAT(b.stepper->solver_summary(), ::testing::HasSubstr("pressure hypre pcg_pfmg"));
    a.steps(3);
    b.steps(3);
    // Each velocity component (its own viscous solve) and the pressure.
    real umax = 0, worst_relative = 0;
    for (int c = 0; c < a.s->u.dim; ++c) {
        real diff = 0, scale = 0;
        for_each_cell(a.dec->block().cells, [&](int i, int j, int k) {
            diff = std::max(diff, std::abs(a.s->u[c](i, j, k) - b.s->u[c](i, j, k)));
            scale = std::max(scale, std::abs(b.s->u[c](i, j, k)));
        });
        diff = a.dec->max(diff);
        umax = std::max(umax, a.dec->max(scale));
        EXPECT_LT(diff, 1e-10 * umax) << "velocity component "
                                      << "uvw"[c];
        worst_relative = std::max(worst_relative, diff / umax);
    }
    real pdiff = 0, pscale = 0;
    for_each_cell(a.dec->block().cells, [&](int i, int j, int k) {
        pdiff = std::max(pdiff, std::abs(a.s->p(i, j, k) - b.s->p(i, j, k)));
        pscale = std::max(pscale, std::abs(b.s->p(i, j, k)));
    });
    EXPECT_LT(a.dec->max(pdiff), 1e-10 * a.dec->max(pscale)) << "pressure";
    worst_relative = std::max(worst_relative, a.dec->max(pdiff) / a.dec->max(pscale));
    if (test::world_rank() == 0)
        std::cout << "  largest relative difference FFT vs hypre (u, v, w, p): " << worst_relative
                  << "\n";
}

namespace {

const std::string g3 = "cells = [8, 12, 6]\nlength = [0.8, 1.2, 0.6]";
const std::string g3w = "cells = [12, 6, 12]\nlength = [1.2, 0.6, 1.2]";
const std::string g2 = "cells = [8, 12, 1]\nlength = [0.8, 1.2, 0.1]";
const std::string g2w = "cells = [12, 12, 1]\nlength = [1.2, 1.2, 0.1]";

std::vector<BoxSetup> setups() {
    return {
        {"periodic_3d", "cells = [8, 16, 8]\nlength = [0.8, 1.6, 0.8]", ""},
        {"channel_3d", g3,
         "y_low = \"wall\"\ny_high = { type = \"wall\", velocity = [1.0, 0.0, 0.4] }\nz_low = "
         "\"free_slip\"\nz_high = \"free_slip\""},
        {"box_mixed_3d", g3w,
         "x_low = \"wall\"\nx_high = \"free_slip\"\ny_low = \"free_slip\"\ny_high = { type = "
         "\"wall\", velocity = [1.0, 0.0, 0.3] }\nz_low = \"wall\"\nz_high = \"wall\""},
        {"box_mixed_3d_euler", g3w,
         "x_low = \"free_slip\"\nx_high = \"wall\"\ny_low = \"wall\"\ny_high = \"wall\"\nz_low = "
         "{ type = \"wall\", velocity = [0.5, -0.2, 0.0] }\nz_high = \"free_slip\"",
         "backward_euler"},
        {"periodic_2d", "cells = [16, 8, 1]\nlength = [1.6, 0.8, 0.1]", ""},
        {"channel_2d", g2,
         "y_low = \"wall\"\ny_high = { type = \"wall\", velocity = [1.0, 0.0, 0.0] }"},
        {"free_slip_channel_2d", g2, "y_low = \"free_slip\"\ny_high = \"wall\""},
        {"cavity_2d", g2w,
         "x_low = \"wall\"\nx_high = \"wall\"\ny_low = \"wall\"\ny_high = { type = \"wall\", "
         "velocity = [1.0, 0.0, 0.0] }"},
        {"mixed_2d", g2w,
         "x_low = \"free_slip\"\nx_high = \"wall\"\ny_low = \"wall\"\ny_high = \"free_slip\""},
    };
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Boxes, FftVersusHypre, ::testing::ValuesIn(setups()),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(FftSelection, AutoFallsBackToHypreWhereCoefficientsVary) {
    const std::string base = R"(
[grid]
cells = [16, 16, 1]
length = [1.0, 1.0, 0.0625]
[fluid]
density = 1.0
viscosity = 0.1
[boundary]
y_low = "wall"
y_high = "wall"
[time]
end_time = 1.0
[[body]]
name = "disc"
kind = "solid"
shape = "cylinder"
centre = [0.5, 0.5, 0.0]
radius = 0.2
shear_modulus = 1.0
)";
    // Same viscosity inside: constant coefficients, FFT for both.
    LinearSolverChoice c = choose_linear_solvers(case_from(base));
    EXPECT_TRUE(c.pressure_fft);
    EXPECT_TRUE(c.viscous_fft);
    // A viscous solid: the pressure stays FFT, the viscous solve falls back to hypre.
    c = choose_linear_solvers(case_from(base, {{"body[0].solid_viscosity", "0.5"}}));
    EXPECT_TRUE(c.pressure_fft);
    EXPECT_FALSE(c.viscous_fft);
    EXPECT_THAT(c.viscous_reason, ::testing::HasSubstr("disc"));
    // A membrane enclosing a fluid of another viscosity: hypre, and the log says why.
    const std::string membrane = base.substr(0, base.find("[[body]]")) + R"(
[[body]]
name = "cell"
kind = "membrane"
shape = "cylinder"
centre = [0.5, 0.5, 0.0]
radius = 0.2
interface = "smoothed"
elastic_modulus = 1.0
)";
    EXPECT_TRUE(choose_linear_solvers(case_from(membrane)).viscous_fft);
    c = choose_linear_solvers(case_from(membrane, {{"body[0].viscosity_ratio", "5.0"}}));
    EXPECT_TRUE(c.pressure_fft);
    EXPECT_FALSE(c.viscous_fft);
    EXPECT_THAT(c.viscous_reason, ::testing::HasSubstr("viscosity_ratio"));
    // Asking for the FFT there is an error naming the key.
    const std::string msg = test::input_error_of([&] {
        case_from(base, {{"body[0].solid_viscosity", "0.5"}, {"solver.viscous.method", "fft"}});
    });
    EXPECT_THAT(msg, ::testing::HasSubstr("solver.viscous.method"));
    // A hypre method named explicitly is honoured.
    c = choose_linear_solvers(case_from(base, {{"solver.pressure.method", "pcg_smg"}}));
    EXPECT_FALSE(c.pressure_fft);
}

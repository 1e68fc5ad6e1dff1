// Case-file parsing and validation (config/config.cpp, config/reader.cpp): every bad input
// is an InputError naming the key, --set overrides apply before reading, impossible
// set-ups are caught before allocation, and the generated key table covers every key.
#include "config/config.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"
#include <cmath>

#include <filesystem>
#include <toml++/toml.h>

using namespace efsi;
using efsi::test::case_from;
using efsi::test::input_error_of;
using ::testing::HasSubstr;

namespace {

// An anisotropic box of cubic cells (dx = 1/8), periodic in x and z (powers of two for
// PFMG), walls in y with the top wall sliding in x and z.
const std::string base_case = R"(
[grid]
cells = [16, 8, 4]
length = [2.0, 1.0, 0.5]

[fluid]
density = 2.0
viscosity = 0.1

[boundary]
y_low = "wall"
y_high = { type = "wall", velocity = [1.5, 0.0, -0.5] }

[time]
end_time = 1.0
)";

// Every key the reader knows, set to a non-default value.
const std::string full_case = R"(
[case]
name = "full"
description = "every key set"

[grid]
cells = [16, 8, 4]
length = [2.0, 1.0, 0.5]
origin = [-1.0, 0.5, 0.25]

[fluid]
density = 2.0
viscosity = 0.1

[boundary]
x_low = "periodic"
x_high = { type = "periodic" }
y_low = { type = "free_slip" }
y_high = { type = "wall", velocity = [1.5, 0.0, -0.5], stop_time = 0.75 }
z_low = "periodic"
z_high = "periodic"

[forcing]
body_force = [0.5, 0.0, 0.0]

[initial]
type = "couette"
amplitude = 0.5

[time]
end_time = 1.0
max_steps = 100
dt = 0.01
cfl = 0.3
dt_max = 0.1
viscous = "backward_euler"

[solver.pressure]
method = "gmres_pfmg"
tolerance = 1e-9
max_iterations = 50

[solver.viscous]
method = "pcg_smg"
tolerance = 1e-11
max_iterations = 40

[output]
diagnostics_every = 5
progress_every = 7
fields_interval = 0.25
fields = false
checkpoint_every = 3

[stability]
max_cfl = 1.5
max_velocity = 100.0
max_tensor_trace = 50.0

[parallel]
ranks = [2, 1, 1]
)";

} // namespace

TEST(Config, BaseCaseReadsEveryValue) {
    const Config c = case_from(base_case);
    EXPECT_EQ(c.grid.cells, (Int3{16, 8, 4}));
    EXPECT_EQ(c.grid.dim, 3);
    EXPECT_DOUBLE_EQ(c.grid.dx(0), 0.125);
    EXPECT_DOUBLE_EQ(c.fluid.density, 2.0);
    EXPECT_DOUBLE_EQ(c.fluid.viscosity, 0.1);
    EXPECT_EQ(c.boundaries[0][0].type, BoundaryType::Periodic);
    EXPECT_EQ(c.boundaries[1][0].type, BoundaryType::Wall);
    EXPECT_EQ(c.boundaries[1][1].type, BoundaryType::Wall);
    EXPECT_DOUBLE_EQ(c.boundaries[1][1].velocity[0], 1.5);
    EXPECT_DOUBLE_EQ(c.boundaries[1][1].velocity[2], -0.5);
    EXPECT_EQ(c.time.viscous, ViscousScheme::CrankNicolson); // the default
    EXPECT_EQ(c.pressure_solver.method, "auto");             // FFT where it applies, else pcg_pfmg
    EXPECT_EQ(c.viscous_solver.method, "auto");
}

TEST(Config, FullCaseReadsEveryKey) {
    const Config c = case_from(full_case);
    EXPECT_EQ(c.name, "full");
    EXPECT_EQ(c.grid.origin, (Real3{-1.0, 0.5, 0.25}));
    EXPECT_EQ(c.boundaries[1][0].type, BoundaryType::FreeSlip);
    EXPECT_DOUBLE_EQ(c.boundaries[1][1].stop_time, 0.75);
    EXPECT_EQ(c.body_force, (Real3{0.5, 0, 0}));
    EXPECT_EQ(c.initial.type, "couette");
    EXPECT_EQ(c.time.max_steps, 100);
    EXPECT_DOUBLE_EQ(c.time.fixed_dt, 0.01);
    EXPECT_EQ(c.time.viscous, ViscousScheme::BackwardEuler);
    EXPECT_EQ(c.pressure_solver.method, "gmres_pfmg");
    EXPECT_EQ(c.pressure_solver.max_iterations, 50);
    EXPECT_EQ(c.viscous_solver.method, "pcg_smg");
    EXPECT_DOUBLE_EQ(c.viscous_solver.tolerance, 1e-11);
    EXPECT_FALSE(c.output.fields);
    EXPECT_EQ(c.output.checkpoint_every, 3);
    EXPECT_DOUBLE_EQ(c.stability.max_cfl, 1.5);
    EXPECT_DOUBLE_EQ(c.stability.max_tensor_trace, 50.0);
    EXPECT_EQ(c.ranks, (Int3{2, 1, 1}));
}

TEST(Config, ResolvedConfigurationReadsBackToTheSameCase) {
    const Config c = case_from(full_case);
    const Config again = case_from(c.resolved_toml);
    EXPECT_EQ(again.resolved_toml, c.resolved_toml);
    EXPECT_EQ(again.grid.cells, c.grid.cells);
    EXPECT_EQ(again.time.viscous, c.time.viscous);
    // Defaults are filled in too: the base case's resolved text names the default scheme
    // or at least re-parses to it.
    const Config b = case_from(base_case);
    EXPECT_EQ(case_from(b.resolved_toml).time.viscous, ViscousScheme::CrankNicolson);
}

TEST(Config, UnknownKeyIsNamed) {
    const std::string text = R"(
[grid]
cells = [16, 8, 4]
length = [2.0, 1.0, 0.5]
[fluid]
density = 1.0
viscosity = 0.1
viscossity = 0.2
[time]
end_time = 1.0
)";
    EXPECT_THAT(input_error_of([&] { case_from(text); }), HasSubstr("fluid.viscossity"));
    EXPECT_THAT(input_error_of([&] { case_from(text); }), HasSubstr("unknown key"));
}

TEST(Config, UnknownSectionAndNestedKeyAreNamed) {
    EXPECT_THAT(input_error_of([] { case_from(base_case + "[fluids]\nrho = 1\n"); }),
                HasSubstr("fluids"));
    EXPECT_THAT(
        input_error_of([] { case_from(base_case + "[solver.pressure]\ntolerence = 1e-8\n"); }),
        HasSubstr("solver.pressure.tolerence"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"boundary.y_low.speed", "[1.0, 0.0, 0.0]"}});
                }),
                HasSubstr("boundary.y_low.speed"));
}

TEST(Config, WrongTypeIsNamed) {
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"fluid.viscosity", "\"thick\""}});
    });
    EXPECT_THAT(msg, HasSubstr("fluid.viscosity"));
    EXPECT_THAT(msg, HasSubstr("expected a number"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"grid.cells", "[16, 8.5, 4]"}});
                }),
                HasSubstr("grid.cells[1]"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"time.max_steps", "1.5"}});
                }),
                HasSubstr("time.max_steps"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"output.fields", "1"}});
                }),
                HasSubstr("output.fields"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"grid.length", "[2.0, 1.0]"}});
                }),
                HasSubstr("grid.length"));
}

TEST(Config, OutOfRangeValueIsNamed) {
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"fluid.viscosity", "-1"}});
    });
    EXPECT_THAT(msg, HasSubstr("fluid.viscosity"));
    EXPECT_THAT(msg, HasSubstr("out of range"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"fluid.density", "0"}});
                }),
                HasSubstr("fluid.density"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"time.cfl", "1.5"}});
                }),
                HasSubstr("time.cfl"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"time.viscous", "\"implicit\""}});
                }),
                HasSubstr("time.viscous"));
    // An unstrained membrane's band has trace 2 (a solid's B 3): a bound at or below 2 would
    // stop every run.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"stability.max_tensor_trace", "2"}});
                }),
                HasSubstr("stability.max_tensor_trace"));
    // MTHINC's closed-form integral keeps its exponentials in range up to beta = 50.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"vof.beta_mthinc", "60"}});
                }),
                HasSubstr("vof.beta_mthinc"));
}

// The unit labels of the log: SI by default; a case in um and ms names them; an empty
// label is refused.
TEST(Config, UnitLabelsDefaultToSiAndAreChecked) {
    const Config si = case_from(base_case);
    EXPECT_EQ(si.length_unit, "m");
    EXPECT_EQ(si.time_unit, "s");
    const Config um =
        case_from(base_case, {{"case.length_unit", "\"um\""}, {"case.time_unit", "\"ms\""}});
    EXPECT_EQ(um.length_unit, "um");
    EXPECT_EQ(um.time_unit, "ms");
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"case.length_unit", "\"\""}});
                }),
                HasSubstr("case.length_unit"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"case.time_unit", "\"a label far too long\""}});
                }),
                HasSubstr("case.time_unit"));
}

TEST(Config, MissingRequiredKeyIsNamed) {
    const std::string text = "[grid]\ncells = [16, 8, 4]\nlength = [2.0, 1.0, 0.5]\n"
                             "[fluid]\ndensity = 1.0\n[time]\nend_time = 1.0\n";
    EXPECT_THAT(input_error_of([&] { case_from(text); }), HasSubstr("fluid.viscosity"));
}

TEST(Config, MalformedTomlNamesTheLine) {
    const std::string text = "[grid]\ncells = [16, 8, 4]\nlength = [2.0, 1.0\n[fluid]\n";
    const std::string msg = input_error_of([&] { case_from(text); });
    EXPECT_THAT(msg, HasSubstr("malformed TOML"));
    // toml++ reports the line where the array was found to be unterminated (3 or 4).
    EXPECT_TRUE(msg.find("case.toml:3:") != std::string::npos ||
                msg.find("case.toml:4:") != std::string::npos)
        << msg;
    const std::string bad_value = "[grid]\ncells = [16, 8, 4]\n\n\nlength = = 3\n";
    EXPECT_THAT(input_error_of([&] { case_from(bad_value); }), HasSubstr("case.toml:5:"));
}

TEST(Config, SetOverridesApplyBeforeReading) {
    const Config c = case_from(base_case, {{"fluid.viscosity", "0.5"},
                                           {"time.viscous", "explicit"}, // bare string
                                           {"time.dt", "0.001"},
                                           {"solver.pressure.method", "\"pcg_smg\""},
                                           {"grid.cells", "[32, 16, 8]"},
                                           {"boundary.z_low", "free_slip"},
                                           {"boundary.z_high", "free_slip"}});
    EXPECT_DOUBLE_EQ(c.fluid.viscosity, 0.5);
    EXPECT_EQ(c.time.viscous, ViscousScheme::Explicit);
    EXPECT_DOUBLE_EQ(c.time.fixed_dt, 0.001);
    EXPECT_EQ(c.pressure_solver.method, "pcg_smg");
    EXPECT_EQ(c.grid.cells, (Int3{32, 16, 8}));
    EXPECT_EQ(c.boundaries[2][0].type, BoundaryType::FreeSlip);
    // The override is part of the echoed configuration.
    EXPECT_THAT(c.resolved_toml, HasSubstr("0.5"));
    // A later override of the same key wins.
    EXPECT_DOUBLE_EQ(case_from(base_case, {{"fluid.viscosity", "0.5"}, {"fluid.viscosity", "0.25"}})
                         .fluid.viscosity,
                     0.25);
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"fluid..viscosity", "1"}});
                }),
                HasSubstr("malformed key"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"fluid.viscosity.x", "1"}});
                }),
                HasSubstr("not a table"));
}

TEST(Config, GridMustDivideAmongRanks) {
    GlobalGrid g;
    g.cells = {64, 64, 1};
    g.length = {1, 1, 1.0 / 64};
    g.dim = 2;
    const std::string msg = input_error_of([&] { Decomposition::choose_ranks(3, g, {0, 0, 0}); });
    EXPECT_THAT(msg, HasSubstr("cannot be divided"));
    EXPECT_THAT(msg, HasSubstr("64x64x1"));
    // A 2D run cannot be split in z.
    EXPECT_THAT(input_error_of([&] {
                    Decomposition::choose_ranks(2, g, {1, 1, 2});
                }),
                HasSubstr("parallel.ranks"));
    // Requested layouts that do not multiply to the rank count are named.
    EXPECT_THAT(input_error_of([&] {
                    Decomposition::choose_ranks(4, g, {3, 0, 0});
                }),
                HasSubstr("parallel.ranks"));
    const Int3 four = Decomposition::choose_ranks(4, g, {0, 0, 0});
    EXPECT_EQ(four[0] * four[1] * four[2], 4);
    EXPECT_EQ(four[2], 1);
}

TEST(Config, ChooseRanksFindsAWorkableFactorisation) {
    GlobalGrid g;
    g.cells = {12, 10, 8};
    // 6 ranks: MPI_Dims_create gives 3x2x1, which divides 12x10x8.
    const Int3 six = Decomposition::choose_ranks(6, g, {0, 0, 0});
    EXPECT_EQ(six[0] * six[1] * six[2], 6);
    for (int d = 0; d < 3; ++d)
        EXPECT_EQ(g.cells[d] % six[d], 0) << d;
    // 5 ranks: only 10 cells in y are divisible by 5.
    EXPECT_EQ(Decomposition::choose_ranks(5, g, {0, 0, 0}), (Int3{1, 5, 1}));
    // 7 ranks divide nothing.
    EXPECT_THAT(input_error_of([&] {
                    Decomposition::choose_ranks(7, g, {0, 0, 0});
                }),
                HasSubstr("cannot be divided"));
    // Each block needs at least two cells (the halo width): 16 ranks along z is too many.
    EXPECT_THAT(input_error_of([&] {
                    Decomposition::choose_ranks(8, g, {1, 1, 8});
                }),
                HasSubstr("cannot be divided"));
}

TEST(Config, PeriodicNonPowerOfTwoNeedsSmg) {
    // The default (auto) solves the pressure by FFT, which takes any cell count.
    EXPECT_NO_THROW(
        case_from(base_case, {{"grid.cells", "[12, 8, 4]"}, {"grid.length", "[1.5, 1.0, 0.5]"}}));
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"grid.cells", "[12, 8, 4]"},
                              {"grid.length", "[1.5, 1.0, 0.5]"},
                              {"solver.pressure.method", "pcg_pfmg"}});
    });
    EXPECT_THAT(msg, HasSubstr("grid.cells[0] = 12"));
    EXPECT_THAT(msg, HasSubstr("power of two"));
    // With SMG, or with walls in that direction, the grid is accepted.
    EXPECT_NO_THROW(case_from(base_case, {{"grid.cells", "[12, 8, 4]"},
                                          {"grid.length", "[1.5, 1.0, 0.5]"},
                                          {"solver.pressure.method", "pcg_smg"}}));
    EXPECT_NO_THROW(
        case_from(base_case, {{"grid.cells", "[16, 6, 4]"}, {"grid.length", "[2.0, 0.75, 0.5]"}}));
}

TEST(Config, PeriodicOnOneSideOnlyIsAnError) {
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"boundary.x_low", "wall"}});
    });
    EXPECT_THAT(msg, HasSubstr("x_low"));
    EXPECT_THAT(msg, HasSubstr("periodic"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"boundary.y_high", "periodic"}});
                }),
                HasSubstr("y_high"));
}

TEST(Config, WallMovingAlongItsNormalIsAnError) {
    const std::string msg = input_error_of([] {
        case_from(base_case,
                  {{"boundary.y_high", "{ type = \"wall\", velocity = [0.0, 1.0, 0.0] }"}});
    });
    EXPECT_THAT(msg, HasSubstr("boundary.y_high.velocity"));
    EXPECT_THAT(msg, HasSubstr("normal"));
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"boundary.y_low",
                                           "{ type = \"wall\", velocity = [0.0, -0.1, 0.0] }"}});
                }),
                HasSubstr("boundary.y_low.velocity"));
}

// A wall with stop_time moves until then and stands still from then on (the relaxation test
// of a sheared capsule, docs/method.md); it is absent from the fingerprint of a case without
// it, so checkpoints written before the key existed still restart.
TEST(Config, WallStopTimeStopsTheWallAndOnlyAWall) {
    const Config moving = case_from(base_case);
    EXPECT_FALSE(std::isfinite(moving.boundaries[1][1].stop_time));
    EXPECT_DOUBLE_EQ(moving.boundaries[1][1].velocity_at(0, 1e6), 1.5);
    const Config stops = case_from(
        base_case,
        {{"boundary.y_high", "{ type = \"wall\", velocity = [1.5, 0.0, -0.5], stop_time = 0.5 }"}});
    const FaceBoundary& f = stops.boundaries[1][1];
    EXPECT_DOUBLE_EQ(f.velocity_at(0, 0.49), 1.5);
    EXPECT_DOUBLE_EQ(f.velocity_at(2, 0.49), -0.5);
    EXPECT_EQ(f.velocity_at(0, 0.5), 0.0);
    EXPECT_EQ(f.velocity_at(2, 3.0), 0.0);
    EXPECT_NE(case_fingerprint(stops), case_fingerprint(moving));
    EXPECT_THAT(case_fingerprint(moving), ::testing::Not(HasSubstr("stop_time")));
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"boundary.x_low", "{ type = \"periodic\", stop_time = 1.0 }"},
                              {"boundary.x_high", "periodic"}});
    });
    EXPECT_THAT(msg, HasSubstr("boundary.x_low.stop_time"));
    EXPECT_THAT(msg, HasSubstr("only a wall"));
    EXPECT_THAT(
        input_error_of([] {
            case_from(base_case, {{"boundary.y_low", "{ type = \"wall\", stop_time = -1.0 }"}});
        }),
        HasSubstr("boundary.y_low.stop_time"));
}

TEST(Config, ImpossibleGeometriesAreErrors) {
    // 2D runs must be periodic in z.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"grid.cells", "[16, 8, 1]"},
                                          {"grid.length", "[2.0, 1.0, 0.125]"},
                                          {"boundary.z_low", "wall"},
                                          {"boundary.z_high", "wall"}});
                }),
                HasSubstr("2D"));
    // Cells must be cubes.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"grid.length", "[2.0, 1.5, 0.5]"}});
                }),
                HasSubstr("cubes"));
    // Too few cells.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case,
                              {{"grid.cells", "[16, 1, 4]"}, {"grid.length", "[2.0, 0.125, 0.5]"}});
                }),
                HasSubstr("grid.cells[1]"));
    // An explicit viscous term needs a safety factor below 0.9.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"time.viscous", "explicit"}, {"time.cfl", "0.95"}});
                }),
                HasSubstr("time.cfl"));
}

TEST(Config, ReferenceTableListsEveryKeyOfAFullCase) {
    const std::string md = case_reference_markdown();
    const Config c = case_from(full_case);
    // Walk the leaves of the resolved configuration (which holds every key of full_case).
    const toml::table root = toml::parse(c.resolved_toml);
    std::vector<std::string> keys;
    auto walk = [&](auto&& self, const toml::table& t, const std::string& prefix) -> void {
        for (auto&& [k, v] : t) {
            const std::string key = prefix + std::string(k.str());
            if (v.is_table())
                self(self, *v.as_table(), key + ".");
            else
                keys.push_back(key);
        }
    };
    walk(walk, root, "");
    // Boundary faces are tables {type, velocity}; the table lists their members.
    EXPECT_GE(keys.size(), 35u);
    for (const auto& k : keys)
        EXPECT_THAT(md, HasSubstr("`" + k + "`")) << "missing from the key table: " << k;
    for (const char* k : {"`fluid.viscosity`", "`time.viscous`", "`solver.pressure.method`",
                          "`boundary.y_high.velocity`", "`parallel.ranks`"})
        EXPECT_THAT(md, HasSubstr(k));
    // Building the table leaves the reader in its normal (validating) state.
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"fluid.viscosity", "-1"}});
                }),
                HasSubstr("fluid.viscosity"));
}

TEST(Config, ShippedCasesAreValid) {
    namespace fs = std::filesystem;
    int n = 0;
    for (const auto& entry : fs::directory_iterator(EFSI_CASES_DIR)) {
        if (!fs::exists(entry.path() / "case.toml")) continue;
        SCOPED_TRACE(entry.path().string());
        EXPECT_NO_THROW(load_case(entry.path()));
        ++n;
    }
    EXPECT_GE(n, 5);
    EXPECT_THAT(input_error_of([] { load_case("/nonexistent/case"); }), HasSubstr("no such case"));
}

TEST(Config, IncrementDampingNeedsAnImplicitViscousTermAndFAtLeastOne) {
    EXPECT_THAT(input_error_of([] {
                    case_from(base_case, {{"time.increment_damping", "0.5"}});
                }),
                HasSubstr("time.increment_damping"));
    const std::string msg = input_error_of([] {
        case_from(base_case, {{"time.increment_damping", "2.0"}, {"time.viscous", "\"explicit\""}});
    });
    EXPECT_THAT(msg, HasSubstr("time.increment_damping"));
    EXPECT_THAT(msg, HasSubstr("implicit viscous"));
    const Config c = case_from(base_case, {{"time.increment_damping", "3.0"}});
    EXPECT_DOUBLE_EQ(increment_viscosity(c), 2.0 * c.fluid.viscosity);
}

// The run loop (simulation/simulation.cpp) with bodies: the time step is chosen from the
// bodies' named limits, and summary.json names them and the one that set the last step.
#include "simulation/run_record.hpp"
#include "simulation/simulation.hpp"
#include "test_support.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace efsi;
using efsi::test::case_from;
namespace fs = std::filesystem;

namespace {

/// A stiff solid particle in a quiescent 2D box: its elastic limit is the smallest.
const std::string stiff_particle = R"(
[grid]
cells = [24, 20, 1]
length = [1.2, 1.0, 0.05]

[fluid]
density = 1.0
viscosity = 0.01

[forcing]
body_force = [0.1, 0.0, 0.0]

[time]
end_time = 1.0
max_steps = 3

[output]
fields = false

[[body]]
name = "particle"
kind = "solid"
shear_modulus = 1e4
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)";

nlohmann::json run_and_read_summary(const std::string& toml, const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("efsi_test_simulation_" + name);
    std::filesystem::remove_all(dir);
    RunOptions opt;
    opt.output_dir = dir;
    opt.quiet = true;
    Simulation sim(case_from(toml), opt, MPI_COMM_WORLD);
    EXPECT_EQ(sim.run(), 0);
    nlohmann::json j;
    std::ifstream(dir / "summary.json") >> j;
    std::filesystem::remove_all(dir);
    return j;
}

} // namespace

TEST(Simulation, SummaryNamesTheBodiesLimitsAndTheActiveOne) {
    const nlohmann::json j = run_and_read_summary(stiff_particle, "solid");
    EXPECT_EQ(j["status"], "max_steps");
    ASSERT_TRUE(j["time_step_limits"].contains("elastic"));
    EXPECT_NEAR(j["time_step_limits"]["elastic"].get<double>(), 0.5 * 0.05 / std::sqrt(1e4), 1e-15);
    EXPECT_EQ(j["time_step_limits"].size(), 1u);
    EXPECT_EQ(j["limited_by"], "elastic");
    EXPECT_NEAR(j["final"]["dt"].get<double>(), 0.5 * 0.5 * 0.05 / std::sqrt(1e4), 1e-15);
}

TEST(Simulation, NoBodyNoLimits) {
    // From rest, the body force's limit sqrt(h rho / |f|) = 0.71 s sets dt (end time far).
    std::string fluid_only = stiff_particle.substr(0, stiff_particle.find("[[body]]"));
    fluid_only.replace(fluid_only.find("end_time = 1.0"), 14, "end_time = 100");
    fluid_only.replace(fluid_only.find("max_steps = 3"), 13, "max_steps = 1"); // from rest
    const nlohmann::json j = run_and_read_summary(fluid_only, "fluid");
    EXPECT_TRUE(j["time_step_limits"].empty());
    EXPECT_EQ(j["limited_by"], "body force");
}

// A restart drops the rows past the checkpoint; a bodies.csv written before columns were
// added at the end gets the current header and `nan` in the added columns of its old rows.
TEST(RunRecord, RestartUpgradesAnOlderHeader) {
    const fs::path file = fs::temp_directory_path() / "efsi_test_drop_rows.csv";
    auto contents = [&] {
        std::ifstream in(file);
        std::stringstream all;
        all << in.rdbuf();
        return all.str();
    };
    std::ofstream(file) << "step,time,a\n0,0.0,1\n1,0.5,2\n2,1.0,3\n";
    drop_rows_after(file, 0.5, "step,time,a,b,c");
    EXPECT_EQ(contents(), "step,time,a,b,c\n0,0.0,1,nan,nan\n1,0.5,2,nan,nan\n");
    // The current header: rows dropped only.
    std::ofstream(file) << "step,time,a\n0,0.0,1\n1,0.5,2\n";
    drop_rows_after(file, 0.0, "step,time,a");
    EXPECT_EQ(contents(), "step,time,a\n0,0.0,1\n");
    fs::remove(file);
}

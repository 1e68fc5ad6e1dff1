// What a run records beside the flow's diagnostics.csv and the snapshots (docs/output.md):
// bodies.csv, one row per body at every diagnostics step, and summary.json, written once
// when the run ends (status, cost, machine load, the last diagnostics, the bodies, the
// time-step limits, the seeding report and the adhesion's totals). A restart continues the
// CSV files of the run it continues.
#pragma once

#include "bodies/body_system.hpp"
#include "config/config.hpp"
#include "parallel/decomposition.hpp"
#include "parallel/peak_memory.hpp"
#include "simulation/diagnostics.hpp"
#include "time/flow_state.hpp"
#include "time/time_step_control.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace efsi {

/// Keep the header and the rows up to time t (the second column) of a CSV an earlier run
/// wrote: a restart from a checkpoint older than the run's last step redoes the steps after
/// it, whose old rows would otherwise stay in the file next to the new ones. With `header`
/// (the line this version writes) and a file whose header is a shorter prefix of it (written
/// before columns were added at the end), the header becomes `header` and each kept row gets
/// `nan` for every added column, so the rows the restart appends match the header.
void drop_rows_after(const std::filesystem::path& file, double t, const std::string& header = {});

/// The first line of bodies.csv (without its newline).
const char* bodies_csv_header();
/// Appends one diagnostics step's rows to bodies.csv, one per body (call on one rank).
/// False if the append failed.
bool append_body_rows(const std::filesystem::path& file, long step, real time,
                      const std::vector<BodyDiagnostics>& bodies);

/// The machine load (1, 5 and 15 minute averages of /proc/loadavg); empty when unknown.
std::vector<double> machine_load();

/// What summary.json records of a run, gathered when it ends. The machine load at the end
/// is read when the summary is written.
/// Each stage's least and largest seconds over the ranks.
using StageSpread = std::map<std::string, std::array<double, 2>>;

/// StageSpread of this rank's stage times `mine` (collective; empty on one rank, or when the
/// ranks' stage names differ).
StageSpread stage_spread(const Decomposition& dec, const std::map<std::string, double>& mine);

struct RunSummary {
    const Config& cfg;
    const Decomposition& dec;
    const FlowState& state;
    std::string status; ///< "completed", "max_steps", "unstable" or "io_error"
    std::string message;
    long steps = 0; ///< steps taken by this run (after a restart: since the checkpoint)
    double wall_seconds = 0;
    std::vector<double> load_before; ///< machine_load() at the start of the run
    PeakMemory memory;
    /// The bytes of the bodies' copies across the periodic x seam, the largest over the
    /// ranks (part of memory; -1 when the ranks could not be reduced).
    double seam_copy_bytes_max_rank = 0;
    const std::map<std::string, double>& stage_seconds; ///< rank 0's
    /// Each stage's least and largest seconds over the ranks (empty on one rank, or when the
    /// ranks could not be reduced).
    StageSpread stage_spread;
    std::string linear_solvers;
    const std::vector<TimeStepLimit>& body_limits; ///< the bodies' named explicit limits
    /// The adhesion's limit changes with the bonds: its smallest value over the run
    /// (infinite when no bond was ever held, or without adhesion; then not recorded).
    real adhesion_limit = 0;
    std::string limited_by; ///< the limit that set the last step's dt
    const Diagnostics& last;
    const std::vector<BodyDiagnostics>& bodies; ///< at the last diagnostics step
    nlohmann::json adhesion;                    ///< the adhesion's totals; null without it
    std::filesystem::path restarted_from;       ///< empty: started from the initial condition
};

/// Writes summary.json (call on one rank). Written aside and renamed, so a failed write
/// never leaves a truncated summary; IoError if it failed.
void write_summary_json(const std::filesystem::path& file, const RunSummary& run);

} // namespace efsi

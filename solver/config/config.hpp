// The case configuration, parsed once into typed structs and checked before any
// allocation. See docs/case-reference.md (generated from the readers) for every key.
#pragma once

#include "boundary/boundary.hpp"
#include "config/adhesion_config.hpp"
#include "config/body_config.hpp"
#include "config/seeding_config.hpp"
#include "core/types.hpp"
#include "grid/grid.hpp"
#include "linear/structured_solver.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace efsi {

enum class ViscousScheme { Explicit, CrankNicolson, BackwardEuler };
/// Where time.increment_damping acts: the whole fluid, or only the membranes' bands.
enum class DampingRegion { Everywhere, Membranes };

struct FluidConfig {
    real density = 1;   ///< rho [kg/m^3]
    real viscosity = 1; ///< mu_f [Pa s]
};

struct TimeConfig {
    real end_time = 1;       ///< [s]
    int max_steps = 1000000; ///< hard cap on steps
    real fixed_dt = 0;       ///< [s]; 0 selects the adaptive step
    real cfl = 0.5;          ///< safety factor on every stability limit
    real dt_max = 0;         ///< [s]; 0 = no cap
    ViscousScheme viscous = ViscousScheme::CrankNicolson;
    /// F >= 1: the implicit viscous solve also damps the velocity increment with the extra
    /// viscosity (F - 1) mu_f, which relaxes the viscous time-step limits of explicit
    /// elastic forces (membrane, bending) by about F; 1 = off (SmacStepper, docs/method.md).
    real increment_damping = 1;
    /// Everywhere, or only on the membranes' bands, weighted by 4 phi (1 - phi) summed over
    /// the membranes (at most 1), the profile of their force density.
    DampingRegion increment_damping_on = DampingRegion::Everywhere;
};

struct InitialConfig {
    std::string type = "rest"; ///< rest | uniform | taylor_green | couette | poiseuille | shear
    real amplitude = 1;        ///< velocity scale [m/s]
    Real3 velocity{0, 0, 0};   ///< uniform: the velocity [m/s]
};

struct OutputConfig {
    int diagnostics_every = 10; ///< steps between diagnostics rows
    int progress_every = 100;   ///< steps between progress lines (rank 0)
    real fields_interval = 0;   ///< [s] between field snapshots; 0 = only the final state
    int checkpoint_every = 0;   ///< steps between checkpoints; 0 = only at the end
    bool fields = true;         ///< write field snapshots at all
};

struct StabilityConfig {
    real max_cfl = 2.0;      ///< a run whose CFL exceeds this is declared unstable
    real max_velocity = 1e6; ///< |u| above this [m/s] is declared a blow-up
    /// tr of a body's transported tensor (B of a solid, Gs of a membrane; 3 unstrained)
    /// above which the run is declared unstable (checked at each diagnostics step)
    real max_tensor_trace = 100;
};

/// Short-range repulsion between bodies (bodies/contact.hpp); stiffness 0: none.
struct ContactConfig {
    real stiffness = 0; ///< k [Pa] of F_ij = -k sum a_i grad a_j dV
};

struct Config {
    std::string name;
    std::string description;
    /// Labels of the case's length and time units in the log (the solver is unit-agnostic:
    /// a case written in um and ms sets "um" and "ms"; nothing is converted).
    std::string length_unit = "m", time_unit = "s";
    std::filesystem::path case_dir;
    GlobalGrid grid;
    FluidConfig fluid;
    BoxBoundaries boundaries;
    Real3 body_force{0, 0,
                     0}; ///< [N/m^3] uniform force density (= minus the mean pressure gradient)
    InitialConfig initial;
    TimeConfig time;
    LinearSolverSettings pressure_solver;
    LinearSolverSettings viscous_solver;
    OutputConfig output;
    StabilityConfig stability;
    Int3 ranks{0, 0, 0};
    std::vector<BodyConfig> bodies; ///< given by hand, then those [seeding] placed
    SeedingReport seeding;          ///< what [seeding] placed (used = false without it)
    ContactConfig contact;
    VofConfig vof;
    AdhesionConfig adhesion;   ///< [adhesion]; enabled = false (and empty) without the table
    std::string resolved_toml; ///< the configuration with every default filled in
};

/// Which linear solvers a case gets: the direct FFT solve where the operator has constant
/// coefficients and the method is "auto" or "fft", else hypre; with the reason, for the log.
struct LinearSolverChoice {
    bool pressure_fft = false;
    bool viscous_fft = false;
    std::string pressure_reason, viscous_reason;
};
LinearSolverChoice choose_linear_solvers(const Config& c);

/// The extra viscosity that damps the velocity increment, (F - 1) mu_f with F =
/// time.increment_damping [Pa s]; it adds to the viscosity of the membrane and bending
/// time-step limits.
inline real increment_viscosity(const Config& c) {
    return (c.time.increment_damping - 1) * c.fluid.viscosity;
}

/// `--set section.key=value` overrides, applied to the TOML before it is read.
using Overrides = std::vector<std::pair<std::string, std::string>>;

/// Parse and validate a case (a folder holding case.toml, or a .toml file).
/// Throws InputError naming the offending key.
Config load_case(const std::filesystem::path& case_path, const Overrides& overrides = {});

/// Parse from TOML text (tests and `efsi check`).
Config parse_case(const std::string& toml_text, const std::filesystem::path& case_dir,
                  const Overrides& overrides = {});

/// Markdown table of every case key (docs/case-reference.md).
std::string case_reference_markdown();

std::string to_string(ViscousScheme s);

/// The case a checkpoint belongs to, one `key = value` line per item: the grid, the
/// boundaries, the fluid, the forcing, the initial condition, and every body's keys (not
/// the time, output, solver, stability or parallel settings, which a restart may change).
/// A restart from a checkpoint whose fingerprint differs is refused, naming the lines.
std::string case_fingerprint(const Config& c);

} // namespace efsi

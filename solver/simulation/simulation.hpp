// A run: builds the grid, decomposition, fields and stepper from a Config, then steps
// to the end time writing diagnostics, snapshots, checkpoints and the summary.
#pragma once

#include "bodies/body_system.hpp"
#include "boundary/boundary.hpp"
#include "config/config.hpp"
#include "io/checkpoint.hpp"
#include "parallel/decomposition.hpp"
#include "simulation/adhesion_record.hpp"
#include "simulation/diagnostics.hpp"
#include "time/flow_state.hpp"
#include "time/smac.hpp"
#include "time/stage_timers.hpp"
#include "time/time_step_control.hpp"

#include <chrono>
#include <filesystem>
#include <memory>

namespace efsi {

struct RunOptions {
    std::filesystem::path output_dir;
    std::filesystem::path restart_file; ///< empty: start from the initial condition
    bool quiet = false;
};

class Simulation {
  public:
    Simulation(const Config& config, const RunOptions& options, MPI_Comm world);
    ~Simulation();
    /// Step to the end. Returns 0 on success (status "completed", or "max_steps" when
    /// time.max_steps stopped it before time.end_time), 3 when the run went unstable
    /// (status "unstable") or an output could not be written (status "io_error"); the
    /// message is printed and stored in summary.json, the last good checkpoint is kept.
    int run();

    const FlowState& state() const { return *state_; }
    const Decomposition& decomposition() const { return *dec_; }

  private:
    // The stages of run(), in the order they are called.
    void log_start();
    bool finished() const; ///< end time or time.max_steps reached
    /// Shorten an adaptive step to land on the next field snapshot time.
    void land_on_snapshot(TimeStepChoice& choice) const;
    void check_stability(const TimeStepChoice& choice);
    /// The bodies' stresses at the current state: mixture viscosity and force (with the
    /// bond forces of adhesion, which depend on dt through their stability check).
    void apply_body_stresses(real dt);
    /// Carry the bodies with (v^n + v^{n+1}) / 2 (u_mid_ holds v^n on entry), then the
    /// adhesion's kinetics and receptors with the same velocity.
    void advance_bodies(real dt);
    /// receptor_motions_[i]: the rigid motion of u_mid_ fitted over the body of the
    /// adhesion's i-th receptor group (receptor_motion = rigid).
    void fit_receptor_motions();
    /// The named explicit limits of this step: the bodies' (fixed) and the adhesion's (set
    /// by the bonds now held).
    std::vector<TimeStepLimit> time_step_limits();
    void record_step(const TimeStepChoice& choice, const StepReport& r);
    void write_outputs_if_due(bool final_step);
    void log_progress(const TimeStepChoice& choice, const StepReport& r) const;
    /// Write the summary and print the outcome; returns the exit code.
    int finish(const std::string& status, const std::string& message);

    /// "UNSTABLE at step ..., t = ...: why; where. The last good checkpoint ..."
    std::string unstable_message(const std::string& why) const;
    /// Gathers the run's record (run_record.hpp) and writes summary.json on rank 0.
    void write_summary(double wall_seconds, const std::string& status,
                       const std::string& message) const;
    void log(const std::string& line) const;
    double wall_seconds() const; ///< since log_start()
    std::vector<Body*> body_list() const;
    /// The checkpoint's records of state that is not a field: the adhesion's receptors,
    /// bonds and counters in `adhesion_state` (saved into it when `save`), none without
    /// [adhesion].
    std::vector<NamedRecord> checkpoint_records(StateRecord& adhesion_state, bool save) const;
    /// K = sum over fixed walls of phi_k / pin_tau_over_dt_k on the faces (or null).
    void build_pinning();

    Config cfg_;
    RunOptions opt_;
    std::unique_ptr<Decomposition> dec_;
    std::unique_ptr<HaloFiller> halos_;
    std::unique_ptr<FlowState> state_;
    std::unique_ptr<SmacStepper> stepper_;
    std::unique_ptr<class FieldOutput> fields_;
    std::unique_ptr<BodySystem> bodies_; ///< null when the case has no body
    std::vector<BodyDiagnostics> last_bodies_;
    std::vector<TimeStepLimit> body_limits_; ///< the bodies' named explicit limits
    std::unique_ptr<VelocityField> force_;   ///< body force density; only if a body adds one
    /// Platelet adhesion (receptors, ligands, bonds); null without [adhesion].
    std::unique_ptr<adhesion::Coupling> adhesion_;
    AdhesionRecord adhesion_record_;            ///< adhesion.csv and summary.json (with adhesion_)
    std::vector<RigidMotion> receptor_motions_; ///< per receptor group, this step's fit
    std::unique_ptr<VelocityField> u_mid_;      ///< (v^n + v^{n+1}) / 2 that carries the bodies
    std::unique_ptr<VelocityField> pinning_;    ///< K = dt chi / tau; only with fixed walls
    /// Where the increment damping acts (time.increment_damping_on = "membranes" only).
    std::unique_ptr<Field> damping_weight_;
    StageTimers timers_;
    RunClock clock_;
    Diagnostics last_;
    std::string last_limited_by_; ///< the limit that set the last step's dt
    long steps_this_run_ = 0;
    double time_at_start_ = 0;        ///< simulated time where this run began (> 0 after a restart)
    std::vector<double> load_before_; ///< /proc/loadavg at the start of run()
    std::chrono::steady_clock::time_point start_;
};

} // namespace efsi

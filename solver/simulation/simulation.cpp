#include "simulation/simulation.hpp"

#include "bodies/band_damping.hpp"
#include "bodies/rigid_fit.hpp"
#include "core/error.hpp"
#include "flow/initial_conditions.hpp"
#include "io/field_output.hpp"
#include "membrane/membrane_body.hpp"
#include "parallel/peak_memory.hpp"
#include "simulation/run_record.hpp"
#include "time/time_step_control.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

namespace efsi {

namespace fs = std::filesystem;

Simulation::Simulation(const Config& config, const RunOptions& options, MPI_Comm world)
    : cfg_(config), opt_(options) {
    // The decomposition checks the rank count against the grid before anything is allocated.
    dec_ = std::make_unique<Decomposition>(world, cfg_.grid, periodic_directions(cfg_.boundaries),
                                           cfg_.ranks);
    halos_ = std::make_unique<HaloFiller>(*dec_, cfg_.boundaries);
    state_ = std::make_unique<FlowState>(dec_->block(), dec_->dim());
    set_initial_condition(cfg_, *dec_, *state_);
    // Bodies exist only when the case has some: no body, no body fields, no body work.
    if (!cfg_.bodies.empty()) bodies_ = std::make_unique<BodySystem>(cfg_, *dec_, *halos_);
    // Adhesion (docs/method.md, "Coupling to the flow"): only with an [adhesion] table, whose
    // receptors sit on bodies, so bodies_ exists then. Made before a restart reads its
    // receptors and bonds back.
    if (cfg_.adhesion.enabled)
        adhesion_ = std::make_unique<adhesion::Coupling>(cfg_.adhesion, cfg_.bodies, *dec_,
                                                         cfg_.fluid.density, cfg_.fluid.viscosity);
    if (!opt_.restart_file.empty()) {
        StateRecord adhesion_state;
        read_checkpoint(opt_.restart_file, *dec_, *state_, clock_, body_list(),
                        case_fingerprint(cfg_), checkpoint_records(adhesion_state, false));
        if (adhesion_) {
            try {
                adhesion_->restore(adhesion_state);
                adhesion_record_.restore(adhesion_state);
            } catch (const InputError& e) {
                throw InputError(fmt::format("--restart {}: group 'adhesion': {}",
                                             opt_.restart_file.string(), e.what()));
            }
        }
        // Nothing is left to do: refuse before anything is written (a summary of an empty
        // run would replace the real one).
        if (!(state_->time < cfg_.time.end_time * (1 - 1e-12)))
            throw InputError(fmt::format(
                "--restart {}: the checkpoint is at t = {:.6g} s (step {}), at or after "
                "time.end_time = {:.6g} s; nothing to run (raise time.end_time to continue)",
                opt_.restart_file.string(), state_->time, state_->step, cfg_.time.end_time));
        if (state_->step >= cfg_.time.max_steps)
            throw InputError(fmt::format(
                "--restart {}: the checkpoint is at step {}, at or after time.max_steps = {}; "
                "nothing to run (raise time.max_steps to continue)",
                opt_.restart_file.string(), state_->step, cfg_.time.max_steps));
        for (Body* b : body_list())
            halos_->fill(b->phi(), b->patch());
        // The checkpoint's next snapshot time follows the fields_interval of the run that
        // wrote it; a restart may set another one (finer snapshots before a blow-up), which
        // the stored time would ignore until it is reached. So the schedule is rebuilt on
        // this run's interval: the first multiple of it after the restart time (same 1e-12
        // tolerance as write_output). The stored time is kept when it is that multiple up
        // to round-off (unchanged interval), so a restart stays bit for bit.
        // Without field output the schedule is never advanced, so it is left as stored.
        const real interval = cfg_.output.fields_interval;
        if (cfg_.output.fields && interval > 0) {
            const real next = interval * (std::floor(state_->time / interval + 1e-12) + 1);
            if (std::abs(clock_.next_fields_time - next) > 1e-9 * interval)
                clock_.next_fields_time = next;
        }
    } else if (bodies_) {
        bodies_->initialise();
    }
    // The bodies: their named time-step limits, whether they make the viscosity vary in
    // space, the velocity that carries them and the force field (only if some body adds one).
    if (bodies_) {
        body_limits_ = bodies_->time_step_limits();
        if (bodies_->viscosity_varies()) state_->viscosity_varies = true;
        u_mid_ = std::make_unique<VelocityField>("body_velocity", dec_->block(), dec_->dim());
    }
    if (bodies_ && (bodies_->adds_force() || adhesion_))
        force_ = std::make_unique<VelocityField>("body_force", dec_->block(), dec_->dim());
    halos_->fill(state_->p);
    halos_->fill(state_->mu);
    halos_->fill(state_->u);
    stepper_ = std::make_unique<SmacStepper>(cfg_, *dec_, *halos_);
    build_pinning();
    if (bodies_ && cfg_.time.increment_damping > 1 &&
        cfg_.time.increment_damping_on == DampingRegion::Membranes) {
        damping_weight_ =
            std::make_unique<Field>("damping_weight", Location::Cell, dec_->block(), dec_->dim());
        stepper_->set_damping_weight(damping_weight_.get());
    }
    // Each ligand's wall (docs/method.md, "The wall takes the reaction"): a no-slip wall of
    // the domain, or a pinned solid's held faces; a ligand on neither is an input error.
    if (adhesion_) {
        std::array<std::array<bool, 2>, 3> no_slip{};
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side)
                no_slip[a][side] = cfg_.boundaries[a][side].type == BoundaryType::Wall;
        adhesion_->anchor(no_slip, pinning_.get());
    }

    if (dec_->rank() == 0) {
        fs::create_directories(opt_.output_dir);
        std::ofstream(opt_.output_dir / "case.toml") << cfg_.resolved_toml << "\n";
        // Fresh files on a new run; a restart appends (after dropping the rows past the
        // checkpoint's time), but starts the files if absent.
        if (!opt_.restart_file.empty())
            for (const char* name : {"diagnostics.csv", "bodies.csv", "adhesion.csv"})
                drop_rows_after(opt_.output_dir / name, state_->time,
                                std::string(name) == "bodies.csv" ? bodies_csv_header() : "");
        if (opt_.restart_file.empty() || !fs::exists(opt_.output_dir / "diagnostics.csv")) {
            std::ofstream(opt_.output_dir / "diagnostics.csv") << Diagnostics::csv_header() << "\n";
            if (bodies_)
                std::ofstream(opt_.output_dir / "bodies.csv") << bodies_csv_header() << "\n";
            if (adhesion_)
                std::ofstream(opt_.output_dir / "adhesion.csv")
                    << AdhesionRecord::csv_header() << "\n";
        }
    }
    dec_->barrier();
    if (cfg_.output.fields) fields_ = std::make_unique<FieldOutput>(opt_.output_dir, *dec_);
}

Simulation::~Simulation() = default;

void Simulation::apply_body_stresses(real dt) {
    if (!bodies_) return;
    if (state_->viscosity_varies) bodies_->update_viscosity(state_->mu);
    if (damping_weight_) membrane_damping_weight(*bodies_, *halos_, *damping_weight_);
    if (!force_) return;
    if (bodies_->adds_force())
        bodies_->add_forces(*force_); // zeroes the field first
    else
        for (int c = 0; c < force_->dim; ++c)
            (*force_)[c].fill(0);
    if (!adhesion_) return;
    // The bonds' spring forces, from the positions at the start of the step: +F at the
    // receptor, -F to the ligand's wall (docs/method.md, "The wall takes the reaction").
    try {
        adhesion_->add_bond_forces(*force_, dt);
        // Receptors that move with their body's rigid motion load it as a rigid body: the
        // bonds' force and torque spread over the body (the fit's adjoint).
        const auto loads = adhesion_->rigid_loads();
        for (std::size_t i = 0; i < loads.size(); ++i) {
            if (loads[i].empty()) continue;
            Body& b = *bodies_->bodies()[adhesion_->bodies()[i].body];
            halos_->fill(b.phi(), b.patch());
            spread_rigid_load(b, loads[i], *dec_, *force_);
        }
    } catch (const RunError& e) {
        throw RunError(unstable_message(e.what()));
    }
    adhesion_record_.after_forces(*adhesion_, dt);
}

void Simulation::advance_bodies(real dt) {
    if (!bodies_) return;
    FlowState& s = *state_;
    // The bodies move with the time-centred velocity (v^n + v^{n+1})/2: second order in
    // time, and still discretely solenoidal (exact VOF conservation). u_mid_ holds v^n.
    for (int c = 0; c < s.u.dim; ++c) {
        auto& m = (*u_mid_)[c].data();
        const auto& v = s.u[c].data();
        for (std::size_t q = 0; q < m.size(); ++q)
            m[q] = 0.5 * (m[q] + v[q]);
    }
    timers_.time("halo", [&] { halos_->fill(*u_mid_); });
    try {
        // The receptors' bodies' rigid motions, fitted to u_mid over where they are now.
        if (adhesion_ && adhesion_->moves_rigidly())
            timers_.time("adhesion", [&] { fit_receptor_motions(); });
        bodies_->advance(*u_mid_, dt, s.step, timers_);
        // The bonds break and form (states at the start of the step, draws keyed by the
        // step's index at its start), then the receptors move with their bodies.
        if (adhesion_)
            timers_.time("adhesion",
                         [&] { adhesion_->advance(*u_mid_, dt, s.step - 1, receptor_motions_); });
    } catch (const RunError& e) {
        throw RunError(unstable_message(e.what()));
    }
    if (adhesion_) adhesion_record_.after_advance(*adhesion_, s.time);
}

void Simulation::fit_receptor_motions() {
    const auto groups = adhesion_->bodies();
    receptor_motions_.resize(groups.size());
    for (std::size_t i = 0; i < groups.size(); ++i) {
        const adhesion::BodyReceptors& r = groups[i];
        Real3 near;
        for (int a = 0; a < 3; ++a)
            near[a] = 0.5 * (r.lo[a] + r.hi[a]);
        receptor_motions_[i] = fit_rigid_motion(*bodies_->bodies()[r.body], *u_mid_, *dec_, near);
    }
}

std::vector<TimeStepLimit> Simulation::time_step_limits() {
    if (!adhesion_) return body_limits_;
    std::vector<TimeStepLimit> out = body_limits_;
    // The explicit bond springs (docs/method.md, "Time-step limits"): infinite without bonds,
    // so it is named only while bonds are held. choose_time_step multiplies it by time.cfl.
    const real dt = adhesion_->stable_time_step();
    if (std::isfinite(dt)) {
        out.push_back({"adhesion", dt});
        adhesion_record_.note_limit(dt);
    }
    return out;
}

void Simulation::build_pinning() {
    // Fixed walls never move, so K = dt chi / tau = sum_k phi_k / (tau_k / dt) is fixed:
    // built once, from the cell fractions averaged onto the faces.
    Field chi("pinned_fraction", Location::Cell, dec_->block(), dec_->dim());
    chi.fill(0);
    if (!bodies_ || !bodies_->add_pinning(chi)) return; // no term in the flow step
    halos_->fill(chi);
    pinning_ = std::make_unique<VelocityField>("pinning", dec_->block(), dec_->dim());
    for (int c = 0; c < pinning_->dim; ++c)
        for_each_cell(dec_->block().cells, [&](int i, int j, int l) {
            const Int3 p{i, j, l};
            (*pinning_)[c](p) = 0.5 * (chi(p - unit(c)) + chi(p));
        });
    stepper_->set_pinning(pinning_.get());
}

std::vector<NamedRecord> Simulation::checkpoint_records(StateRecord& adhesion_state,
                                                        bool save) const {
    if (!adhesion_) return {};
    adhesion_state.description = "the receptors, bonds and counters of [adhesion]";
    if (save) {
        adhesion_->save(adhesion_state);
        adhesion_record_.save(adhesion_state);
    }
    return {{"adhesion", &adhesion_state}};
}

std::vector<Body*> Simulation::body_list() const {
    std::vector<Body*> out;
    if (bodies_)
        for (auto& b : bodies_->bodies())
            out.push_back(b.get());
    return out;
}

void Simulation::log(const std::string& line) const {
    if (dec_->rank() == 0 && !opt_.quiet) std::cout << line << std::endl;
}

void Simulation::check_stability(const TimeStepChoice& choice) {
    const FlowState& s = *state_;
    std::string why;
    if (!std::isfinite(choice.max_speed))
        why = "the velocity is no longer finite";
    else if (choice.max_speed > cfg_.stability.max_velocity)
        why = fmt::format("|v| = {:.3e} {}/{} exceeds stability.max_velocity = {:.3e}",
                          choice.max_speed, cfg_.length_unit, cfg_.time_unit,
                          cfg_.stability.max_velocity);
    else if (choice.cfl > cfg_.stability.max_cfl)
        why = fmt::format("CFL = {:.3f} exceeds stability.max_cfl = {:.3f}", choice.cfl,
                          cfg_.stability.max_cfl);
    else if (choice.dt < 1e-14 * cfg_.time.end_time &&
             s.time < cfg_.time.end_time * (1 - 1e-12)) // not the round-off left at the end
        why = fmt::format("the time step collapsed to {:.3e} {}", choice.dt, cfg_.time_unit);
    // A membrane or solid whose strain tensor runs away (a principal stretch of ~10 at the
    // default bound) has left any physical regime well before the velocity shows it: the
    // stiff-membrane growth of Gs (docs/method.md) reached tr Gs 1e5 with |v| only 4x the
    // wall speed. Measured at the diagnostics steps (bodies.csv), so checked there.
    for (const auto& b : last_bodies_)
        if (why.empty() && !(b.tensor_trace_max <= cfg_.stability.max_tensor_trace))
            why = fmt::format("body '{}': max tr of its strain tensor = {:.3e} (bodies.csv "
                              "tensor_trace_max) exceeds stability.max_tensor_trace = {:.3g}",
                              b.name, b.tensor_trace_max, cfg_.stability.max_tensor_trace);
    if (why.empty()) return;
    throw RunError(unstable_message(why));
}

std::string Simulation::unstable_message(const std::string& why) const {
    const FlowState& s = *state_;
    return fmt::format("UNSTABLE at step {}, t = {:.6e} {}: {}; {}. The last good checkpoint "
                       "(if any) is kept in {}{}",
                       s.step, s.time, cfg_.time_unit, why,
                       locate_worst_velocity(*dec_, s, cfg_.length_unit + "/" + cfg_.time_unit),
                       (opt_.output_dir / "checkpoint.h5").string(),
                       membrane_instability_hint(cfg_));
}

void Simulation::write_outputs_if_due(bool final_step) {
    FlowState& s = *state_;
    const bool diag_due = s.step % cfg_.output.diagnostics_every == 0 || final_step;
    if (diag_due) {
        timers_.time("diagnostics", [&] {
            halos_->fill(s.u);
            measure_flow(*dec_, s, cfg_.fluid.density, last_);
            last_.step = s.step;
            last_.time = s.time;
            // Rank 0 appends the rows; a failed append (disk full) stops every rank.
            int failed = 0;
            if (dec_->rank() == 0) {
                std::ofstream out(opt_.output_dir / "diagnostics.csv", std::ios::app);
                out << last_.csv_row() << "\n";
                out.close();
                if (!out) failed = 1;
            }
            if (adhesion_ &&
                !adhesion_record_.append_row(opt_.output_dir / "adhesion.csv", *adhesion_, s.step,
                                             s.time, dec_->rank() == 0))
                failed = 3;
            if (bodies_) {
                last_bodies_ = bodies_->measure();
                if (dec_->rank() == 0 &&
                    !append_body_rows(opt_.output_dir / "bodies.csv", s.step, s.time, last_bodies_))
                    failed = 2;
            }
            MPI_Bcast(&failed, 1, MPI_INT, 0, dec_->comm());
            if (failed) {
                const fs::path cp = opt_.output_dir / "checkpoint.h5";
                std::error_code ec;
                throw IoError(fmt::format(
                    "appending to {} at step {} failed (disk full?); {}",
                    (opt_.output_dir / (failed == 1   ? "diagnostics.csv"
                                        : failed == 2 ? "bodies.csv"
                                                      : "adhesion.csv"))
                        .string(),
                    s.step,
                    fs::exists(cp, ec) ? fmt::format("the last good checkpoint is {}", cp.string())
                                       : std::string("there is no checkpoint of this run")));
            }
        });
    }
    if (fields_) {
        const real interval = cfg_.output.fields_interval;
        const bool due =
            final_step || (interval > 0 && s.time >= clock_.next_fields_time - 1e-12 * interval);
        if (due || (s.step == 0)) {
            timers_.time("output", [&] {
                std::vector<const Body*> bodies;
                for (Body* b : body_list())
                    bodies.push_back(b);
                try {
                    fields_->write(s, bodies);
                } catch (const IoError& e) {
                    const fs::path cp = opt_.output_dir / "checkpoint.h5";
                    std::error_code ec;
                    throw IoError(fmt::format(
                        "writing the snapshot at step {} (t = {:.6e} s) failed: {}. The "
                        "unfinished file was removed; {}",
                        s.step, s.time, e.what(),
                        fs::exists(cp, ec)
                            ? fmt::format("the last good checkpoint is {}", cp.string())
                            : std::string("there is no checkpoint of this run")));
                }
            });
            if (interval > 0)
                while (clock_.next_fields_time <= s.time + 1e-12 * interval)
                    clock_.next_fields_time += interval;
        }
    }
    const int every = cfg_.output.checkpoint_every;
    if (final_step || (every > 0 && s.step % every == 0 && s.step > 0))
        timers_.time("checkpoint", [&] {
            StateRecord adhesion_state;
            write_checkpoint(opt_.output_dir / "checkpoint.h5", *dec_, s, clock_, body_list(),
                             case_fingerprint(cfg_), checkpoint_records(adhesion_state, true));
        });
}

void Simulation::land_on_snapshot(TimeStepChoice& choice) const {
    // An adaptive step shortened so that the field snapshots fall on multiples of
    // fields_interval (comparisons at matching times need them there); when the snapshot
    // is less than two steps away, two equal steps reach it, so no step is much shorter
    // than the one before (the AB2 weights depend on their ratio). A fixed dt is kept.
    const real interval = cfg_.output.fields_interval;
    if (!fields_ || interval <= 0 || cfg_.time.fixed_dt > 0) return;
    const real left = clock_.next_fields_time - state_->time;
    if (!(left > 1e-12 * interval) || choice.dt <= 0) return;
    real dt = choice.dt;
    if (dt >= left)
        dt = left;
    else if (left < 2 * dt)
        dt = left / 2;
    else
        return;
    choice.cfl *= dt / choice.dt;
    choice.dt = dt;
    choice.limited_by = "output time";
}

int Simulation::run() {
    FlowState& s = *state_;
    log_start();
    std::string status = "completed";
    std::string message;
    try {
        if (s.step == 0) write_outputs_if_due(false);
        while (!finished()) {
            TimeStepChoice choice = choose_time_step(cfg_, *dec_, s, time_step_limits());
            check_stability(choice);
            land_on_snapshot(choice);
            timers_.time("body_stress", [&] { apply_body_stresses(choice.dt); });
            if (bodies_) *u_mid_ = s.u;
            const StepReport r = stepper_->step(s, choice.dt, timers_, force_.get());
            advance_bodies(choice.dt);
            record_step(choice, r);
            write_outputs_if_due(finished());
            log_progress(choice, r);
        }
        check_stability(choose_time_step(cfg_, *dec_, s, time_step_limits()));
        if (s.time < cfg_.time.end_time * (1 - 1e-12)) {
            status = "max_steps";
            message = fmt::format("stopped at time.max_steps = {} at t = {:.6g} {} of "
                                  "time.end_time = {:.6g} {}",
                                  cfg_.time.max_steps, s.time, cfg_.time_unit, cfg_.time.end_time,
                                  cfg_.time_unit);
        }
    } catch (const RunError& e) {
        status = "unstable";
        message = e.what();
    } catch (const IoError& e) {
        status = "io_error";
        message = e.what();
    }
    return finish(status, message);
}

bool Simulation::finished() const {
    return !(state_->time < cfg_.time.end_time * (1 - 1e-12)) ||
           state_->step >= cfg_.time.max_steps;
}

void Simulation::log_start() {
    start_ = std::chrono::steady_clock::now();
    time_at_start_ = state_->time;
    log(fmt::format("efsi: case '{}' on {} rank(s) ({}x{}x{}), grid {}x{}x{} ({}D), dx = {:.4g} {}",
                    cfg_.name, dec_->size(), dec_->ranks_per_dim()[0], dec_->ranks_per_dim()[1],
                    dec_->ranks_per_dim()[2], cfg_.grid.cells[0], cfg_.grid.cells[1],
                    cfg_.grid.cells[2], cfg_.grid.dim, cfg_.grid.dx(0), cfg_.length_unit));
    log(stepper_->solver_summary());
    if (const SeedingReport& sr = cfg_.seeding; sr.used)
        log(fmt::format("{}; haematocrit {:.4f} of the lumen of '{}' ({:.4g} {}^3), gap {:.3g} {}",
                        sr.message, sr.achieved, sr.vessel, sr.lumen_volume, cfg_.length_unit,
                        sr.gap, cfg_.length_unit));
    for (const BodyConfig& b : cfg_.bodies)
        if (!b.mask_mapping.empty()) log(fmt::format("body '{}': {}", b.name, b.mask_mapping));
    if (!body_limits_.empty()) {
        std::string limits;
        for (const TimeStepLimit& l : body_limits_)
            limits += fmt::format("{}{} {:.3e} {}", limits.empty() ? "" : ", ", l.name, l.dt,
                                  cfg_.time_unit);
        log("body time-step limits: " + limits);
    }
    if (adhesion_)
        log(fmt::format("adhesion: {} receptors on {} bodies, {} ligand sites; time-step limit "
                        "'adhesion' (the bond springs) applies while bonds are held",
                        adhesion_->receptors().size(), adhesion_->bodies().size(),
                        adhesion_->ligands().size()));
    load_before_ = machine_load();
}

double Simulation::wall_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Simulation::record_step(const TimeStepChoice& choice, const StepReport& r) {
    ++steps_this_run_;
    last_.dt = choice.dt;
    last_.cfl = choice.cfl;
    last_.pressure_iterations = r.pressure.iterations;
    last_.pressure_residual = r.pressure.relative_residual;
    last_.viscous_iterations = r.viscous.iterations;
    last_limited_by_ = choice.limited_by;
    if (!r.pressure.converged)
        log(fmt::format("warning: step {}: pressure solve stopped at {} iterations, relative "
                        "residual {:.2e}",
                        state_->step, r.pressure.iterations, r.pressure.relative_residual));
}

void Simulation::log_progress(const TimeStepChoice& choice, const StepReport& r) const {
    const FlowState& s = *state_;
    if (!(s.step % cfg_.output.progress_every == 0 || finished())) return;
    const double wall = wall_seconds();
    const double frac = s.time / cfg_.time.end_time;
    // The remaining wall time at this run's pace: a restarted run measures its progress from
    // the time it restarted at, not from t = 0.
    const double done = (s.time - time_at_start_) / (cfg_.time.end_time - time_at_start_);
    const double eta =
        steps_this_run_ > 0 && done > 0 ? wall * (1 - done) / std::max(1e-12, done) : 0.0;
    log(fmt::format("step {:7d}  t = {:.4e} {} ({:5.1f}%)  dt = {:.3e} [{}]  div = {:.1e}  "
                    "KE = {:.4e}  p-its {:3d}  ETA {:.0f} s (wall)",
                    s.step, s.time, cfg_.time_unit, 100 * frac, choice.dt, choice.limited_by,
                    last_.max_divergence, last_.kinetic_energy, r.pressure.iterations, eta));
}

int Simulation::finish(const std::string& status, const std::string& message) {
    const double wall = wall_seconds();
    try {
        write_summary(wall, status, message);
    } catch (const std::exception& e) {
        if (dec_->rank() == 0)
            std::cerr << "efsi: summary.json could not be written: " << e.what() << std::endl;
    }
    if (status != "completed" && status != "max_steps") {
        if (dec_->rank() == 0) std::cerr << "efsi: " << message << std::endl;
        return 3;
    }
    if (status == "max_steps") log("efsi: " + message);
    log(fmt::format("done: {} steps in {:.2f} s, {:.3e} cell updates/s; output in {}",
                    steps_this_run_, wall,
                    double(cfg_.grid.total_cells()) * steps_this_run_ / std::max(wall, 1e-9),
                    opt_.output_dir.string()));
    return 0;
}

void Simulation::write_summary(double wall_seconds, const std::string& status,
                               const std::string& message) const {
    // Reduced over the ranks only when every rank finished the run (docs/output.md).
    const bool all_finished = status == "completed" || status == "max_steps";
    const PeakMemory mem = peak_memory(dec_->comm(), all_finished);
    const auto spread = all_finished ? stage_spread(*dec_, timers_.seconds()) : StageSpread{};
    // The seam copies' bytes, the largest over the ranks (docs/performance.md, "Estimates
    // before a run"); -1 when the ranks could not be reduced.
    const double seam_bytes = !bodies_       ? 0.0
                              : all_finished ? dec_->max(real(bodies_->seam_copy_bytes()))
                                             : -1.0;
    if (dec_->rank() != 0) return;
    write_summary_json(
        opt_.output_dir / "summary.json",
        {.cfg = cfg_,
         .dec = *dec_,
         .state = *state_,
         .status = status,
         .message = message,
         .steps = steps_this_run_,
         .wall_seconds = wall_seconds,
         .load_before = load_before_,
         .memory = mem,
         .seam_copy_bytes_max_rank = seam_bytes,
         .stage_seconds = timers_.seconds(),
         .stage_spread = spread,
         .linear_solvers = stepper_->solver_summary(),
         .body_limits = body_limits_,
         .adhesion_limit = adhesion_record_.smallest_limit(),
         .limited_by = last_limited_by_,
         .last = last_,
         .bodies = last_bodies_,
         .adhesion = adhesion_ ? adhesion_record_.summary(*adhesion_) : nlohmann::json(),
         .restarted_from = opt_.restart_file});
}

} // namespace efsi

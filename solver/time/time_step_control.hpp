// The adaptive time step: the smallest of the stability limits times a safety factor.
//
//   advective   dt_a = 1 / max over faces of sum_d |u_d| / dx_d (wall speeds included)
//   viscous     dt_v = rho / (2 mu_max sum_d 1/dx_d^2)       (explicit viscous term only)
//   body force  dt_f = sqrt(dx_min rho / |f|)
//   dt = cfl * min(dt_a, dt_v, dt_f), capped by time.dt_max and by the end time; with
//   bodies, also by a face Courant number of 0.45 (the split VOF advection needs < 1/2).
// The bodies add their own named limits (elastic, membrane, bending: bodies/body_physics.hpp),
// and platelet adhesion its bond springs' (adhesion, while bonds are held: adhesion/coupling.hpp).
#pragma once

#include "config/config.hpp"
#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <string>
#include <vector>

namespace efsi {

/// An explicit time-step limit of some physics, by name ("elastic", "membrane", ...).
struct TimeStepLimit {
    std::string name;
    real dt = 0; ///< [s]
};

struct TimeStepChoice {
    real dt = 0;
    std::string limited_by; ///< which limit set dt
    real max_speed = 0;     ///< max |u_d| over faces [m/s], NaN if a value is not finite
    real cfl = 0;           ///< dt * max sum_d |u_d| / dx_d
};

/// Max over the owned faces of sum_d |u_d|/dx_d (cell-wise) and of |u_d|; NaN-aware.
void velocity_bounds(const Decomposition& dec, const FlowState& s, real& rate, real& speed);

/// dt from the flow's limits and `extra` (the bodies'); limited_by names the smallest.
TimeStepChoice choose_time_step(const Config& cfg, const Decomposition& dec, const FlowState& s,
                                const std::vector<TimeStepLimit>& extra = {});

} // namespace efsi

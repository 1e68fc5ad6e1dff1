// Global diagnostics of the flow, reduced over all ranks.
#pragma once

#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <string>

namespace efsi {

struct Diagnostics {
    long step = 0;
    real time = 0;
    real dt = 0;
    real max_divergence = 0; ///< max |div v| over cells [1/s]
    real kinetic_energy = 0; ///< integral of rho |v|^2 / 2 [J] (per unit z-length in 2D)
    real max_speed = 0;      ///< max |v_d| over faces [m/s]
    real cfl = 0;
    int pressure_iterations = 0;
    real pressure_residual = 0;
    int viscous_iterations = 0;

    static std::string csv_header();
    std::string csv_row() const;
};

/// Fill the flow diagnostics (halos of s.u must be current).
void measure_flow(const Decomposition& dec, const FlowState& s, real density, Diagnostics& d);

/// Where the fastest (or first non-finite) velocity of the run is, as a readable message.
/// `speed_unit`: the label of a velocity in the log ("m/s" for SI).
std::string locate_worst_velocity(const Decomposition& dec, const FlowState& s,
                                  const std::string& speed_unit = "m/s");

} // namespace efsi

// Everything that defines the flow at a time level (and is written to checkpoints).
#pragma once

#include "grid/field.hpp"

namespace efsi {

struct FlowState {
    VelocityField u;        ///< velocity v^n on the faces [m/s]
    Field p;                ///< pressure at cell centres [Pa]
    VelocityField adv_prev; ///< advective term of the previous step (Adams-Bashforth 2)
    Field mu;               ///< viscosity at cell centres [Pa s]
    real time = 0;          ///< [s]
    long step = 0;
    real dt_prev = 0;              ///< previous step's dt; 0 before the first step
    bool viscosity_varies = false; ///< true once bodies make mu(x) non-uniform

    FlowState(const LocalBlock& block, int dim)
        : u("velocity", block, dim), p("pressure", Location::Cell, block, dim),
          adv_prev("advection_previous", block, dim), mu("viscosity", Location::Cell, block, dim) {}
};

} // namespace efsi

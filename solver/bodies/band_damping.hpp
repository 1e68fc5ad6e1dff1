// Where the increment damping acts when it is confined to the membranes
// (time.increment_damping_on = "membranes"; docs/method.md, "Increment damping").
#pragma once

#include "boundary/boundary.hpp"
#include "grid/field.hpp"

namespace efsi {

class BodySystem;

/// w = min(1, sum over the membrane bodies of 4 phi (1 - phi)) on the owned cells: 1 on a
/// membrane's phi = 1/2 surface, falling off across its band as its force density does
/// (|grad phi| = 2 phi (1 - phi) / eps for the tanh profile), 0 away from every membrane.
/// Halos filled.
void membrane_damping_weight(const BodySystem& bodies, const HaloFiller& halos, Field& w);

} // namespace efsi

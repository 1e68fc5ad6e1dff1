// Force-dependent dissociation rate k_off(F) of a bond: the Bell model or the two-pathway
// catch-slip law (parameters.hpp). F is the magnitude of the bond's spring force: a
// compressed bond is as strained as a stretched one (Hammer & Apte 1992 use |F| the same way).
#pragma once

#include "adhesion/parameters.hpp"

namespace efsi::adhesion {

/// k_off [1/s] at bond force magnitude `force` [N] (its sign is ignored).
real off_rate(const AdhesionParameters& p, real force);

/// Probability that an event of rate `rate` [1/s] happens within `dt` [s]: 1 - exp(-rate dt),
/// computed without cancellation for small rate dt.
real event_probability(real rate, real dt);

} // namespace efsi::adhesion

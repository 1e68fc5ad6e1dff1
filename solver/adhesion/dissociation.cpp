#include "adhesion/dissociation.hpp"

#include <cmath>

namespace efsi::adhesion {

real off_rate(const AdhesionParameters& p, real force) {
    const real f = std::abs(force), kT = p.thermal_energy();
    switch (p.law) {
    case DissociationLaw::catch_slip:
        return p.catch_rate * std::exp(-p.catch_distance * f / kT) +
               p.slip_rate * std::exp(p.slip_distance * f / kT);
    case DissociationLaw::bell:
        break;
    }
    return p.k_off0 * std::exp(p.reactive_compliance * f / kT);
}

real event_probability(real rate, real dt) {
    return -std::expm1(-rate * dt);
}

} // namespace efsi::adhesion

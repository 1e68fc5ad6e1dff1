#include "adhesion/parameters.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <cmath>

namespace efsi::adhesion {

namespace {

void require(bool ok, const char* key, real value, const char* what) {
    if (!ok) throw InputError(fmt::format("adhesion.{} = {:g}: {}", key, value, what));
}

void non_negative(const char* key, real v) {
    require(std::isfinite(v), key, v, "must be a finite number");
    require(v >= 0, key, v, "must not be negative");
}

void positive(const char* key, real v) {
    require(std::isfinite(v), key, v, "must be a finite number");
    require(v > 0, key, v, "must be positive");
}

} // namespace

void AdhesionParameters::validate() const {
    non_negative("k_on", k_on);
    non_negative("k_off0", k_off0);
    non_negative("reactive_compliance", reactive_compliance);
    non_negative("bond_stiffness", bond_stiffness);
    non_negative("bond_rest_length", bond_rest_length);
    positive("reactive_distance", reactive_distance);
    non_negative("margin", margin);
    positive("temperature", temperature);
    require(!std::isnan(max_bond_force) && max_bond_force > 0, "max_bond_force", max_bond_force,
            "must be positive (infinite: no limit)");
    if (law == DissociationLaw::catch_slip) {
        non_negative("catch_rate", catch_rate);
        non_negative("catch_distance", catch_distance);
        non_negative("slip_rate", slip_rate);
        non_negative("slip_distance", slip_distance);
        require(catch_rate + slip_rate > 0, "catch_rate", catch_rate,
                "law = catch_slip needs catch_rate, catch_distance, slip_rate and "
                "slip_distance (fitted to Yago et al. 2008 or Ju et al. 2013; no defaults)");
    }
}

} // namespace efsi::adhesion

// Parameters of the GPIb-alpha / vWF adhesion kinetics, SI units throughout (docs/method.md,
// "Platelet adhesion (kinetic Monte Carlo)", lists each default with its source).
// The [adhesion] case table (config/adhesion_config.cpp) reads them under these names;
// `validate` names each value by its key (adhesion.k_on, ...).
#pragma once

#include "core/types.hpp"

#include <limits>

namespace efsi::adhesion {

/// Boltzmann constant [J/K] (exact, SI 2019).
inline constexpr real boltzmann = 1.380649e-23;

/// Force dependence of the dissociation rate.
enum class DissociationLaw {
    bell,       ///< k_off = k_off0 exp(gamma F / kB T)            (Bell 1978)
    catch_slip, ///< k_off = k_c0 exp(-x_c F / kB T) + k_s0 exp(x_s F / kB T)
                ///< (two-pathway model, Pereverzev et al. 2005; GPIb-alpha/vWF-A1 catch
                ///< bonds: Yago et al. 2008)
};

struct AdhesionParameters {
    /// Forward rate [1/s] of a free receptor with a free ligand within reach. Model choice
    /// (docs/method.md): no single measured value maps onto this per-receptor rate.
    real k_on = 10.0;
    /// Unstressed dissociation rate [1/s] of GPIb-alpha/vWF-A1 (Doggett et al. 2002: 3.45).
    real k_off0 = 3.45;
    /// Reactive compliance gamma [m] of the Bell model: kB T / gamma = 6.0 pN at 310 K
    /// (the force scale Mody & King 2008 report).
    real reactive_compliance = 0.71e-9;
    /// Bond spring constant sigma [N/m]: 1 pN/nm, inside the 0.1-10 pN/nm range of
    /// Mody & King 2008.
    real bond_stiffness = 1.0e-3;
    /// Bond rest length lambda [m] (model choice, GPIb-alpha extends tens of nm).
    real bond_rest_length = 50e-9;
    /// A free receptor may bind a free ligand at most this far away [m] (model choice).
    real reactive_distance = 70e-9;
    /// Extra distance of the cheap skip test [m]: a receptor (or a body's bounding box)
    /// farther than reactive_distance + margin from every ligand box gets no work at all.
    real margin = 100e-9;
    /// Absolute temperature [K] (body temperature).
    real temperature = 310.15;
    DissociationLaw law = DissociationLaw::bell;
    /// Two-pathway (catch-slip) parameters: rates [1/s] and distances [m]. No defaults are
    /// shipped: a fit to Yago et al. 2008 (or Ju et al. 2013) must be entered (validate
    /// refuses law = catch_slip with both rates zero).
    real catch_rate = 0;
    real catch_distance = 0;
    real slip_rate = 0;
    real slip_distance = 0;
    /// Largest bond force [N] the coupled time step can take (the flow coupling sets it from
    /// its stability limit); bond_forces() reports a bond above it. Infinite by default.
    real max_bond_force = std::numeric_limits<real>::infinity();

    /// kB T [J].
    real thermal_energy() const { return boltzmann * temperature; }

    /// Throws InputError naming the key (adhesion.<name>) of the first bad value: negative
    /// rates, stiffness, lengths or compliance, a non-positive temperature or reactive
    /// distance, non-finite values, a catch-slip law without its parameters.
    void validate() const;
};

} // namespace efsi::adhesion

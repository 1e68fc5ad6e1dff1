// Constitutive laws of a membrane: the strain energy per unit reference area Ws(Is, IIs)
// through its two derivatives, and the in-plane (Cauchy) tension it implies,
//   tau_s = (2 / J) [ dWs/dIs Bs + J^2 dWs/dIIs P ]                      (MODEL.md)
// A law is a small object implementing `energy_derivatives`; adding a law is one file
// (a class deriving from MembraneLaw, registered in make_membrane_law).
#pragma once

#include "config/body_config.hpp"
#include "membrane/kinematics.hpp"

#include <memory>
#include <string>

namespace efsi {

struct EnergyDerivatives {
    real dW_dIs = 0;
    real dW_dIIs = 0;
};

class MembraneLaw {
  public:
    virtual ~MembraneLaw() = default;
    virtual std::string name() const = 0;
    /// Strain energy per unit reference area.
    virtual real energy(real Is, real IIs) const = 0;
    virtual EnergyDerivatives energy_derivatives(real Is, real IIs) const = 0;
    /// The largest small-strain in-plane modulus [N/m] (for both laws the area-dilation
    /// modulus K, d^2 Ws / d(J - 1)^2 at rest): the stiffness the explicit time-step limit
    /// must hold.
    virtual real stiffest_modulus() const = 0;

    /// In-plane Cauchy tension tau_s (force per unit current length), a tangential tensor.
    Matrix3 tension(const MembraneKinematics& k) const {
        return tension_from(energy_derivatives(k.Is, k.IIs), k);
    }

    /// tau_s from the energy derivatives at k (the formula in the file header).
    static Matrix3 tension_from(const EnergyDerivatives& e, const MembraneKinematics& k) {
        const real a = 2 * e.dW_dIs / k.J, b = 2 * k.J * e.dW_dIIs;
        Matrix3 tau{};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                tau[i][j] = a * k.Bs[i][j] + b * k.P[i][j];
        return tau;
    }
};

/// The membrane law `law`; `alpha` is Skalak's area-dilation constant C
/// (ignored by the neo-Hookean law).
std::unique_ptr<MembraneLaw> make_membrane_law(MembraneLawKind law, real Es, real alpha = 1);
/// The same by the case-file name (neo_hookean, skalak); InputError for any other.
std::unique_ptr<MembraneLaw> make_membrane_law(const std::string& name, real Es, real alpha = 1);

} // namespace efsi

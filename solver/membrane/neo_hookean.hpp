// Neo-Hookean membrane (seed paper; Es = 3 Gs, Gs the small-strain shear modulus):
//   Ws = Es/6 (Is + 1/(IIs + 1) - 1)
//   dWs/dIs = Es/6,   dWs/dIIs = -Es/6 / (IIs + 1)^2 = -Es / (6 J^4)
//   => tau_s = Es / (3 J) (Bs - P / J^2).
// Uniaxial stretch (T2 = 0): lambda2 = lambda1^(-1/2), T1 = Gs (lambda1^3 - 1) / lambda1^(3/2).
#pragma once

#include "membrane/membrane_law.hpp"

namespace efsi {

class NeoHookeanLaw final : public MembraneLaw {
  public:
    explicit NeoHookeanLaw(real Es) : Es_(Es) {}
    std::string name() const override { return "neo_hookean"; }
    real energy(real Is, real IIs) const override { return Es_ / 6 * (Is + 1 / (IIs + 1) - 1); }
    real stiffest_modulus() const override { return Es_; } // K = Es, shear Es / 3
    EnergyDerivatives energy_derivatives(real /*Is*/, real IIs) const override {
        return {Es_ / 6, -Es_ / (6 * (IIs + 1) * (IIs + 1))};
    }

  private:
    real Es_;
};

} // namespace efsi

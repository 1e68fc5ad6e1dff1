// Skalak membrane in the seed's form (Es/6 plays the role of Gs/4 in Skalak's notation,
// i.e. Es = 3 Gs / 2; alpha is Skalak's area-dilation constant C):
//   Ws = Es/6 ((Is + 1)^2 + alpha IIs^2 - 2 IIs - 1)
//   dWs/dIs = Es/3 (Is + 1),   dWs/dIIs = Es/3 (alpha IIs - 1)
//   => tau_s = (2 Es / (3 J)) [ (Is + 1) Bs + J^2 (alpha IIs - 1) P ].
// Uniaxial stretch: lambda2^2 = (1 + C lambda1^2) / (1 + C lambda1^4),
// T1 = Gs / J [lambda1^2 (lambda1^2 - 1) + C J^2 (J^2 - 1)], J = lambda1 lambda2.
#pragma once

#include "membrane/membrane_law.hpp"

namespace efsi {

class SkalakLaw final : public MembraneLaw {
  public:
    SkalakLaw(real Es, real alpha) : Es_(Es), alpha_(alpha) {}
    std::string name() const override { return "skalak"; }
    real energy(real Is, real IIs) const override {
        return Es_ / 6 * ((Is + 1) * (Is + 1) + alpha_ * IIs * IIs - 2 * IIs - 1);
    }
    EnergyDerivatives energy_derivatives(real Is, real IIs) const override {
        return {Es_ / 3 * (Is + 1), Es_ / 3 * (alpha_ * IIs - 1)};
    }
    /// K = Gs (1 + 2 alpha) with Gs = 2 Es / 3 (14 Es for alpha = 10; alpha > 0 by the reader).
    real stiffest_modulus() const override { return 2 * Es_ / 3 * (1 + 2 * alpha_); }

  private:
    real Es_;
    real alpha_;
};

} // namespace efsi

// Solids as bodies (bodies/body_physics.hpp): a free visco-hyperelastic solid, which carries
// its left Cauchy-Green tensor B and adds div(phi G B') to the flow (solid_mechanics.hpp),
// and a fixed wall, a pinned solid held in place by penalisation (docs/method.md, Solids).
#pragma once

#include "bodies/body_physics.hpp"
#include "bodies/transport.hpp"
#include "solid/solid_mechanics.hpp"
#include "solid/tensor_extension.hpp"

#include <memory>

namespace efsi {

/// A free neo-Hookean solid: sigma_s' = 2 mu_s D' + G B'. Its time-step limit is "elastic",
/// elastic_time_step_limit (shear waves, or viscous relaxation where that is larger).
class SolidBody final : public BodyPhysics {
  public:
    SolidBody(const BodyConfig& body, const BodyContext& ctx);
    bool carries_tensor() const override { return true; }
    real viscosity() const override { return law_.viscosity; }
    bool adds_force() const override { return law_.shear_modulus != 0; }
    BodyWork prepare_force(Body& body) override;
    void add_force(Body& body, VelocityField& force) override;
    const SolidLaw& law() const { return law_; }

  protected:
    BodyWork carry_tensor(Body& body, const BodyStep& step) override;
    BodyWork extend_tensor(Body& body, const BodyStep& step) override;

  private:
    SolidLaw law_;
    std::unique_ptr<BodyTransport> transport_;
    std::unique_ptr<TensorExtension> extension_; ///< null: B not extended
};

/// A pinned solid (e.g. a vessel wall): never moves, so B stays the identity and is not
/// stored; no elastic force and no time-step limit. Its velocity is penalised to zero by
/// -(phi / tau) v, tau = pin_tau_over_dt dt (implicit in the flow step).
class FixedWall final : public BodyPhysics {
  public:
    FixedWall(const BodyConfig& body, const BodyContext& ctx);
    bool carries_tensor() const override { return false; }
    bool moves() const override { return false; }
    real viscosity() const override { return viscosity_; }
    bool add_pinning(const Body& body, Field& chi) const override;

  private:
    real viscosity_;
};

} // namespace efsi

// A membrane as a body (bodies/body_physics.hpp): a smoothed band carrying the surface
// tensor Gs (and kappa_R with bending), the force of its law |grad phi| f (membrane_force.hpp),
// Gs carried by the surface's velocity (surface_velocity.hpp) or the local one, and rebuilt
// off the band's core after each step (normal_extension.hpp or the layered TensorExtension).
// Its time-step limits are "membrane" (in-plane, membrane_time_step_limit) and, with
// bending, "bending" (bending_time_step_limit).
#pragma once

#include "bodies/body_physics.hpp"
#include "bodies/transport.hpp"
#include "membrane/membrane_force.hpp"
#include "membrane/membrane_law.hpp"
#include "membrane/normal_extension.hpp"
#include "solid/tensor_extension.hpp"

#include <memory>

namespace efsi {

class MembraneBody final : public BodyPhysics {
  public:
    MembraneBody(const BodyConfig& body, const BodyContext& ctx);
    ~MembraneBody() override;
    bool carries_tensor() const override { return true; }
    /// Gs = P_R = I - n_R n_R and kappa_R from the shape's level sets (kept for a mask).
    void initialise(Body& body, const Shape* shape) override;
    bool adds_force() const override { return true; }
    void add_force(Body& body, VelocityField& force) override;
    const MembraneLaw& law() const { return *law_; }

  protected:
    void carry_tensor(Body& body, const BodyStep& step) override;
    void extend_tensor(Body& body, const BodyStep& step) override;

  private:
    std::unique_ptr<MembraneLaw> law_;
    std::unique_ptr<MembraneForce> force_;
    std::unique_ptr<BodyTransport> transport_;
    std::unique_ptr<TensorExtension> extension_;        ///< strain_extension = layers
    std::unique_ptr<NormalExtension> normal_extension_; ///< strain_extension = normal
};

} // namespace efsi

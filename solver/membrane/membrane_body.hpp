// A membrane as a body (bodies/body_physics.hpp): a smoothed band carrying the surface
// tensor Gs (and kappa_R with bending), the force of its law |grad phi| f (membrane_force.hpp),
// Gs carried by the surface's velocity (surface_velocity.hpp) or the local one, and rebuilt
// off the band's core after each step (normal_extension.hpp or the layered TensorExtension);
// or, with strain_model = reference_map, the reference map X carried instead and Gs rebuilt
// from its gradient (reference_map.hpp),
// phi's tanh profile restored after each VOF step (interface/conservative_reinit.hpp).
// Its time-step limits are "membrane" (in-plane, membrane_time_step_limit) and, with
// bending, "bending" (bending_time_step_limit).
#pragma once

#include "bodies/body_physics.hpp"
#include "bodies/transport.hpp"
#include "interface/conservative_reinit.hpp"
#include "interface/shapes.hpp"
#include "membrane/membrane_force.hpp"
#include "membrane/membrane_law.hpp"
#include "membrane/normal_extension.hpp"
#include "solid/tensor_extension.hpp"

#include <memory>
#include <string>

namespace efsi {

/// Explicit membrane force limit (0 without membranes): the larger of the viscous and the
/// inertial capillary-type limits, c mu h / K (c = kMembraneViscousFactor) and
/// sqrt(rho h^3 / (2 pi K)), K the stiffest small-strain modulus of the laws in the scene
/// (MembraneLaw::stiffest_modulus; Es for the neo-Hookean law). Galusinski & Vigneaux 2008
/// show the stable step follows the viscous one at low Re and the inertial one, Brackbill et
/// al. 1992, at high Re. The factor is measured, as the solids' limit is (docs/method.md,
/// "Membranes in the time step"): with a fixed step the explicit force ran stably at or
/// above 10 mu h / K in every case tried (capsules, neo-Hookean and Skalak C = 10 and 100, d/8 to
/// d/32; the red cell of rbc_in_tube at C = 10 and 100), and 12 mu h / K stopped the C = 100
/// red cell; with time.cfl = 0.5 the automatic step keeps a margin of 2 below it.
inline constexpr real kMembraneViscousFactor = 10;

real membrane_time_step_limit(const GlobalGrid& grid, real density, real viscosity, real es_max);

/// The reference curvature a cell holds: the curvature of the shape's level set through it,
/// clamped to [-4/h, 4/h], and 0 where it is not a number. Near a focal point of the surface
/// the level sets curve without bound, and at the focal point itself they have no curvature
/// (the distance is not differentiable there): on a red cell's axis, about a dimple curvature
/// radius outside the dimple, rbc_in_tube on 70 x 35 x 35 cells had kappa_R = -1e15 and NaN
/// in cells on the axis, which the transport carried into the band in four steps. No
/// curvature sampled on the grid (central differences of psi, a distance, over cells of size
/// h) exceeds about 4/h: a level set that curves more is not resolved (docs/method.md,
/// "Membrane bending").
real resolvable_reference_curvature(real kappa, real h);

class MembraneBody final : public BodyPhysics {
  public:
    MembraneBody(const BodyConfig& body, const BodyContext& ctx);
    ~MembraneBody() override;
    bool carries_tensor() const override { return true; }
    /// Gs = P_R = I - n_R n_R and kappa_R from the shape's level sets (kept for a mask).
    void initialise(Body& body, const Shape* shape) override;
    bool adds_force() const override { return true; }
    BodyWork prepare_force(Body& body) override;
    void add_force(Body& body, VelocityField& force) override;
    /// The enclosed fluid's viscosity, viscosity_ratio x the fluid's.
    real viscosity() const override { return cfg_.viscosity_ratio * ctx_.run.fluid.viscosity; }
    const MembraneLaw& law() const { return *law_; }

  protected:
    BodyWork carry_tensor(Body& body, const BodyStep& step) override;
    real restore_profile(Body& body, const BodyStep& step) override;
    BodyWork extend_tensor(Body& body, const BodyStep& step) override;

  private:
    void initialise_tensor(Body& body, const Shape& shape);
    void initialise_reference_curvature(Body& body, const Shape& shape);

    std::unique_ptr<MembraneLaw> law_;
    std::unique_ptr<MembraneForce> force_;
    std::unique_ptr<BodyTransport> transport_;
    std::unique_ptr<TensorExtension> extension_;        ///< strain_extension = layers
    std::unique_ptr<NormalExtension> normal_extension_; ///< strain_extension = normal
    std::unique_ptr<ConservativeReinit> reinit_;        ///< profile_iterations > 0
    /// The reference surface the map is projected onto (map_projection; none for a mask).
    std::unique_ptr<Shape> reference_shape_;
};

/// A possible cause worth naming when a run with membranes blows up (appended to the
/// UNSTABLE message): with the layered extension of Gs, Gs carried by the surface velocity
/// over a wide reach is unstable for stiff membranes; with the reference map (the default), a
/// body a few cells thick; with Gs carried by the surface velocity, a body thinner than its
/// band. Empty when no body qualifies.
std::string membrane_instability_hint(const Config& cfg);

} // namespace efsi

// One body's physics behind one interface: each kind of body (passive tracer, solid, fixed
// wall, membrane) is one implementation, so a new kind or a new force term touches one place.
//
// A run calls, per body and in this order (docs/method.md, "Bodies"):
//   initialise    the tensor's initial state once phi is set (B = I, Gs = P_R, kappa_R)
//   add_force     its force density on the velocity faces, before the flow step
//   advance       its state after the flow step: tensor, then phi (VOF), then extension
//   time_step_limits   its named explicit limits ("elastic", "membrane", "bending")
// and asks viscosity() for the mixture mu(x) and add_pinning() for the penalisation of
// fixed walls. Every method that touches fields is collective over the ranks.
#pragma once

#include "bodies/body.hpp"
#include "bodies/body_work.hpp"
#include "boundary/boundary.hpp"
#include "config/config.hpp"
#include "interface/vof_advection.hpp"
#include "time/stage_timers.hpp"
#include "time/time_step_control.hpp"

#include <memory>
#include <vector>

namespace efsi {

class Shape;
class SurfaceVelocity;

/// What a body's advance needs from the flow step.
struct BodyStep {
    const VelocityField& u; ///< (v^n + v^{n+1}) / 2 on the faces, halos filled
    real dt;
    long step;
    StageTimers& timers;
    /// Loaded with u for this step when some membrane carries Gs with its surface's
    /// velocity (one instance shared by all bodies); null otherwise.
    SurfaceVelocity* surface_velocity = nullptr;
};

/// The grid, ranks and halos a body's physics works with (outlive it).
struct BodyContext {
    const Config& run;
    const Decomposition& dec;
    const HaloFiller& halos;
};

class BodyPhysics {
  public:
    BodyPhysics(const BodyConfig& body, const BodyContext& ctx);
    virtual ~BodyPhysics();
    BodyPhysics(const BodyPhysics&) = delete;
    BodyPhysics& operator=(const BodyPhysics&) = delete;

    const BodyConfig& config() const { return cfg_; }

    /// Whether the body carries a tensor (B or Gs) beside phi.
    virtual bool carries_tensor() const = 0;
    /// False for a body held in place: never advanced, its patch never re-fitted.
    virtual bool moves() const { return true; }
    /// Set the tensor's initial state once phi is set (the body was allocated with the
    /// identity). `shape` is the body's initial shape, null for a voxel mask.
    virtual void initialise(Body& body, const Shape* shape);

    /// Viscosity of the body's material in mu(x) = mu_f + sum_k phi_k (mu_k - mu_f).
    virtual real viscosity() const { return ctx_.run.fluid.viscosity; }
    /// Whether add_force adds anything (the force field exists only if some body does).
    virtual bool adds_force() const { return false; }
    /// The body's force, in two parts that the caller runs for every body in turn
    /// (BodySystem::add_forces): prepare_force, the work on the body's own fields (a
    /// BodyWork, bodies/body_work.hpp, run for all bodies in rounds of halo fills; nothing by
    /// default), then add_force, which adds the force density [N/m^3] to the face field
    /// `force`, body after body, so that the sums are those of one body at a time.
    virtual BodyWork prepare_force(Body& body);
    virtual void add_force(Body& body, VelocityField& force);
    /// Add phi / (tau / dt) of a body held by penalisation to the cell field `chi`; returns
    /// whether the body is so held.
    virtual bool add_pinning(const Body& body, Field& chi) const;

    /// Carry the body over one flow step, in three parts that the caller runs for every body
    /// in turn (BodySystem::advance): the tensor with the velocity gradient of the step
    /// (advance_tensor); then phi, by vof()'s sweeps; then phi's profile restoration and the
    /// tensor's extension (finish_advance, which adds to `clipped` the volume this rank
    /// clipped). The first and the last are BodyWork (bodies/body_work.hpp), which the caller
    /// runs for all bodies in rounds of halo fills.
    BodyWork advance_tensor(Body& body, const BodyStep& step);
    VofAdvection& vof() { return *vof_; }
    BodyWork finish_advance(Body& body, const BodyStep& step, real& clipped);

    /// The body's explicit time-step limits, each named (empty: none).
    const std::vector<TimeStepLimit>& time_step_limits() const { return limits_; }

  protected:
    /// D T/Dt = L T + T L^T of the body's tensor over the step (nothing by default).
    virtual BodyWork carry_tensor(Body& body, const BodyStep& step);
    /// Restore the shape of phi's profile after the VOF step (nothing by default); returns
    /// the volume this rank clipped doing so [m^3].
    virtual real restore_profile(Body& body, const BodyStep& step);
    /// Rebuild the tensor outside the cells where it is known (nothing by default).
    virtual BodyWork extend_tensor(Body& body, const BodyStep& step);

    const BodyConfig& cfg_;
    BodyContext ctx_;
    std::vector<TimeStepLimit> limits_;

  private:
    std::unique_ptr<VofAdvection> vof_;
};

/// A passive body: phi only, carried by the flow (a tracer; no force, no limit).
class PassiveBody final : public BodyPhysics {
  public:
    using BodyPhysics::BodyPhysics;
    bool carries_tensor() const override { return false; }
};

/// The implementation of the body's kind (a pinned solid is a FixedWall).
std::unique_ptr<BodyPhysics> make_body_physics(const BodyConfig& body, const BodyContext& ctx);

} // namespace efsi

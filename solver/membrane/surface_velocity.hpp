// The membrane's velocity carried off its surface along the normals, for the transport of Gs.
//
// Every level set of a smoothed band is a material surface, and the transport of Gs with
// the local velocity makes each one carry its own strain. The tangential velocity has a
// kink across the membrane (the jump of the shear stress the membrane supports), so the
// layers at s = +-eps tank-tread at different rates and their strains drift apart by
// ~eps x shear rate x t, whatever the capillary number; relative to the membrane's strain
// (~Ca) that is an error growing like 1/Ca (docs/verification.md, "Where the rest comes
// from"). Transporting Gs with the velocity of the surface instead,
//
//   u_e(x) = u(y) + s dn/dt = u(y) - s P (grad u(y))^T n,   y = x - s n,
//   s = psi(x) = eps atanh(1 - 2 phi),   n = grad psi / |grad psi|,
//
// (y the foot point of x on phi = 1/2; u_e is the velocity of the point at fixed distance s
// along the moving normal, the parallel surfaces of a Kirchhoff-Love shell) gives every
// layer the surface's stretching. At the surface u_e = u, and because a tangential Gs only
// sees the tangential derivatives of the velocity, the membrane's own kinematics are
// unchanged; only tangential derivatives of u at the surface enter, and those do not see
// the kink; a rigid motion is reproduced exactly. Off the surface a layer's strain differs
// from the surface's by s x (change of curvature): bounded, ~(eps/R) x the deformation,
// and of opposite sign on the two sides. (u(y) alone, without s dn/dt, makes the layers
// rotate at different angular velocities, omega R/(R + s), and was worse than u itself.)
//
// Numerics: each velocity component is interpolated at the foot point from its own
// staggered grid by tensor-product Catmull-Rom cubics (C1, exact for quadratics), so the
// velocity gradient of u_e that stretches Gs is continuous. u_e replaces u on the faces
// within reach - 1 cells of the surface (default reach 5: enough for the extension core,
// |psi| <= 2.3 eps at eps <= 1 cell, and the transport's two-cell stencil), blends
// linearly into u between reach - 1 and reach cells (no switch: round-off must not decide
// which velocity a face gets), and u is kept beyond; the tensor extension overwrites the
// cells there. The foot-point stencil reaches reach + 3 cells, so the interpolated copy
// of u carries ceil(reach) + 3 halo layers.
//
// The reach is a body key (surface_velocity_reach) because the default is unstable for
// stiff membranes: the band's outer layers then take their strain from the surface but
// push on their own fluid, and the exchange of energy between Gs and the flow is no longer
// balanced. Measured (2D, d/16, docs/method.md): neo-Hookean Es = 160 mu shear_rate a and
// Skalak C = 10 at Ca 0.025 blow up with reach 5 and run stably with reach 1.5.
#pragma once

#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

#include <span>
#include <string>

namespace efsi {

class SurfaceVelocity {
  public:
    /// The default reach (cells), and the one that keeps stiff membranes stable.
    static constexpr real default_reach = 5.0;
    static constexpr real stiff_membrane_reach = 1.5;

    /// One instance serves every membrane body of a run (the interpolation source, a copy
    /// of u with wide halos, is made once per step and shared). Throws InputError (naming
    /// `body_name`, the first body that uses it) when a rank's block is too thin for the
    /// interpolation's halo.
    /// `max_reach` (cells): the largest reach any body will ask compute() for.
    SurfaceVelocity(const HaloFiller& halos, const std::string& body_name = "",
                    real max_reach = default_reach);

    /// Once per step, before compute(): u (halos filled) into the interpolation source.
    /// Collective.
    void load(const VelocityField& u);
    /// The same, copying u only where compute() can read it for bodies whose patches have
    /// the global boxes `patches` (each widened by the wide halo, and its periodic images);
    /// the source keeps stale values elsewhere, which no later compute() for those bodies
    /// reads. Collective; every rank passes the same boxes.
    void load(const VelocityField& u, std::span<const Box> patches);

    /// u_e for `body` (smoothing width `eps_cells` cells): u carried off the surface along
    /// the normals near its band, u elsewhere on the body's patch and within three cells of
    /// it (what the body's transport reads; faces farther away hold whatever an earlier
    /// call left); halos filled. Faces within `reach_cells` - 1 cells of the surface get
    /// u_e, those beyond `reach_cells` keep u, and between the two the weight of u_e falls
    /// linearly (reach_cells <= the constructor's max_reach). Collective: every rank calls it
    /// for every body, in the same order; each sets u on its part of the body's region
    /// first, so the result for one body never carries another's band there.
    const VelocityField& compute(const Body& body, real eps_cells,
                                 real reach_cells = default_reach);

  private:
    /// The rest of load(): the source's halos and the result's layout.
    void finish_load(const VelocityField& u);

    const HaloFiller& halos_;
    real max_reach_ = default_reach;
    int wide_halo_ = 8;  ///< ceil(max_reach) + 3
    VelocityField wide_; ///< u with wide halos, the interpolation source
    VelocityField out_;  ///< u_e of the last body, u around it
    Field psi_;          ///< signed distance on the last body's patch
};

} // namespace efsi

// Conservative restoration of a smoothed interface's tanh profile.
//
// A membrane's phi is the profile (1 - tanh(L / eps)) / 2 across its surface, and the
// membrane force, its normals (psi = eps atanh(1 - 2 phi) must be a distance) and the
// strain's extension along the normals all rely on that shape. Advection keeps the volume
// but not the shape: the flow's normal strain thins and thickens the band (measured in the
// 3D capsule in shear, d/16, Ca 0.05: |grad psi| in 0.01 < phi < 0.99 spreads from 1 to
// 0.67-1.25 by shear-rate x t = 1). This operator relaxes phi towards the profile in
// pseudo-time tau with the accurate conservative diffuse-interface flux (Jain, J. Comput.
// Phys. 469 (2022) 111529; after Olsson & Kreiss 2005 and Chiu & Lin 2011):
//
//   d phi / d tau = div( e grad phi - (1/4) (1 - tanh^2(psi_a / 2e)) n ),
//   e = eps / 2,  psi_a = e ln(phi / (1 - phi)) = -psi,  n = grad psi_a / |grad psi_a|,
//
// whose steady state is exactly phi = (1 + tanh(psi_a / 2e)) / 2, i.e. our profile.
// Discretely both terms are written with psi_a, using e grad phi = (1/4)(1 - tanh^2) grad
// psi_a for the profile, and n_d = g_d / |g|: the flux through a face normal to d is
//   (1/4) (1 - tanh^2(psi_f / 2e)) g_d (1 - 1 / |g|),
// with g the gradient of psi_a AT THE FACE, to fourth order: g_d from the four cells along
// d, (27 (psi_1 - psi_0) - (psi_2 - psi_-1)) / 24h, the tangential components from the
// cells' fourth-order central gradients interpolated to the face, (9 (g_0 + g_1) - (g_-1 +
// g_2)) / 16. Any planar tanh profile of width eps, at any angle to the grid, is an exact
// discrete steady state, and a curved exact profile is one to O(h^4 kappa^4): the
// restoration no longer rounds the surface. (The second-order form, face difference minus
// the average of the two cells' normalised central gradients, moves a curved surface
// towards lower curvature at a rate ~h^4 kappa^3: on an ellipsoid with D = 0.25 at 16
// cells per diameter, 64 pseudo-steps lowered D by 1.2e-3, against 4e-6 with this form,
// enough to bend the D(t) of a capsule at Ca 0.2 by ~0.015 per pseudo-step per time step
// by t = 6. The phi-difference form e (phi_hi - phi_lo) / h of Jain's paper settles at
// eps = 1 cell to a profile whose |grad psi| is 7.5 % off 1 in 0.05 < phi < 0.95.)
// Each pseudo-step is a flux
// difference on the faces: the volume sum phi dV changes only by round-off (the fluxes
// telescope; a face between two empty or two full cells carries none, so nothing leaves
// the patch). Where a pseudo-step would carry a cell past 0 or 1 the face changes are
// limited (Zalesak's limiter with the bounds 0 and 1) rather than the cell clipped, so the
// volume holds at any width. Pseudo-step dtau = h^2 / (4 dim e) (half the explicit diffusion
// limit); the number of pseudo-steps per time step is the body key `profile_iterations`.
#pragma once

#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

#include <array>

namespace efsi {

struct ReinitStats {
    real clipped_volume = 0; ///< sum of |phi clipped to [0,1] - phi| dV (this rank)
};

class ConservativeReinit {
  public:
    /// `eps_cells`: the smoothing width eps of the profile in cells; `iterations`:
    /// pseudo-steps per call.
    ConservativeReinit(const HaloFiller& halos, real eps_cells, int iterations);

    /// Relax the body's phi on its patch; fills phi's halos. Collective over the ranks the
    /// patch spans.
    ReinitStats apply(Body& body);

  private:
    const HaloFiller& halos_;
    real eps_cells_;
    int iterations_;
    Field work_;                    ///< phi with 2 halo layers
    Field psi_a_;                   ///< e ln(phi / (1 - phi)), 2 halo layers
    Field expo_;                    ///< exp(psi_a / 2e) = sqrt(phi / (1 - phi)), 2 halo layers
    std::array<Field, 3> grad_;     ///< fourth-order central gradient of psi_a, per component
    std::array<Field, 3> change_;   ///< the change of phi by the face p + 1/2 e_d, at p
    Field gain_limit_, loss_limit_; ///< per cell, the factors that keep phi in [0, 1]
};

} // namespace efsi

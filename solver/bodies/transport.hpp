// Transport of a body's cell fields by the flow, on the body's patch only.
//
//   scalars (kappa_R):      D s/Dt = 0
//   tensors (B, Gs):        D T/Dt = L T + T L^T,   L_ij = d v_i / d x_j
//
// Space: the advective term u.grad s is written as div(u s) - s div(u), with face values
// of s from a MUSCL reconstruction limited by van Leer's limiter (second order where the
// field is smooth, no new extrema at the body edge), times the face velocity. L is
// evaluated at cell centres: diagonal terms from the two faces of the cell, off-diagonal
// terms as central differences averaged over the cell's two faces (exact for linear v).
// Time: Heun's method (RK2) with the velocity of the end of the flow step held fixed.
#pragma once

#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

#include <array>
#include <vector>

namespace efsi {

/// Velocity gradient L_ij = dv_i/dx_j at the centre of cell p (zero rows/columns past dim).
Matrix3 velocity_gradient_at(const VelocityField& u, const GlobalGrid& g, const Int3& p);

/// -u.grad s at the centre of cell p (MUSCL / van Leer, flux form with divergence correction).
real advection_rate_at(const Field& s, const VelocityField& u, const GlobalGrid& g, const Int3& p);

class BodyTransport {
  public:
    explicit BodyTransport(const HaloFiller& halos) : halos_(halos) {}
    /// Advance the body's tensor (and kappa_R) by dt with the face velocity u (halos filled).
    void advance(Body& body, const VelocityField& u, real dt);

  private:
    void rates(const Body& body, const SymmetricTensorField& t, const Field* kappa,
               const VelocityField& u, std::vector<Field>& out);
    const HaloFiller& halos_;
    std::vector<Field> k1_, k2_;
    SymmetricTensorField stage_; ///< T^n + dt k1
    Field stage_kappa_;
};

} // namespace efsi

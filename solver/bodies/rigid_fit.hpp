// A body seen as rigid: the rigid-body motion that best fits the flow over it, and the
// force density that puts a rigid load on it (the fit's adjoint).
//
// The fit: the velocity V and spin omega
// minimising sum_cells phi |u - V - omega x (x - c)|^2 dV about the body's centroid c (the
// phi-weighted least squares of fictitious-domain methods). V is the mean of u over phi
// (the velocity of the centroid under the body's own transport); omega solves
// I omega = sum phi r x u, I = sum phi (|r|^2 1 - r r^T) the body's inertia tensor per unit
// density.
//
// The load: F and T (about the centroid) spread over the body as the force density
// f = phi (F / V + Omega x r), V = sum phi dV, I Omega = T: its sum is F and its moment T,
// and its power against any u is F . V_fit + T . omega_fit, the power of the point forces
// on receptors that move with the fitted motion (energy-consistent pairing). A force density
// over the whole body moves it without straining it, as a rigid body's load would.
// docs/method.md, "Receptors move with the platelet".
#pragma once

#include "bodies/body.hpp"
#include "core/rigid_motion.hpp"
#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

namespace efsi {

/// The fit of the face velocity `u` over body `b` (its phi on its patch, cell-centred u as the
/// mean of the two faces). Positions along periodic directions are taken by the minimum image
/// about `near` (a point within half a box of the body, e.g. its last centroid), and the
/// centroid is returned in that image. Throws RunError naming the body when it holds no
/// volume. Collective: two sums over the ranks.
RigidMotion fit_rigid_motion(const Body& b, const VelocityField& u, const Decomposition& dec,
                             const Real3& near);

/// Adds the force density of `load` on body b to the face field `force` [N/m^3]: each cell's
/// phi (F / V + Omega x r) dV (r from the centroid, in the image of load.point) goes half to
/// each of its two faces along each component, all of it to the inner one next to a no-slip
/// wall (a face on a wall takes no force), so that the faces' sum is F and their moment
/// about the centroid T exactly (a force moved along its own line keeps its moment). Writes
/// owned faces only; b's phi halos must be filled. Collective: two sums over the ranks.
/// Returns the face values written on this rank.
std::size_t spread_rigid_load(const Body& b, const RigidLoad& load, const Decomposition& dec,
                              VelocityField& force);

} // namespace efsi

// Between points (receptors, ligand anchors) and the staggered grid, for the adhesion
// coupling (docs/method.md, "Platelet adhesion", "Coupling to the flow"):
//
//  - interpolation of the face velocity at a point: TRILINEAR (two faces per direction).
//    It reproduces a linear velocity field exactly (so a receptor in a uniform flow moves
//    exactly with it, and in a linear shear exactly too), is second order for smooth
//    fields, which matches the second-order staggered flow solver (a wider kernel would
//    add cost, not accuracy), and needs only the first halo layer, where the boundary
//    conditions put the wall values (the point between a wall and the first cell centre
//    sees the wall's velocity through the mirrored ghost).
//  - spreading of a point force onto the faces: Peskin's 4-point kernel (Peskin, Acta
//    Numerica 11 (2002) 479), phi(r) = (3 - 2|r| + sqrt(1 + 4|r| - 4r^2)) / 8 for |r| <= 1,
//    (5 - 2|r| - sqrt(-7 + 12|r| - 4r^2)) / 8 for 1 <= |r| <= 2, 0 beyond, per direction.
//    Its weights sum to one and have zero first moment for any position (the spread force
//    integrates to F and is centred on the point), their squares sum to 3/8 for any
//    position (the self-interaction does not depend on where the point sits in its cell),
//    and it is C^1, so a moving receptor's force slides over the faces without the kinks
//    the 3-point kernel (Roma, Peskin & Berger, J Comput Phys 153 (1999) 509; C^0) would
//    put in it at every half cell. Support 4 cells: 64 faces per component.
//
// Walls: along a wall-bounded direction the faces where the velocity is fixed (the wall's
// own normal face) and the points beyond the wall take no force; the remaining weights of
// that direction are rescaled to sum to one, so the spread force still integrates to F
// exactly (momentum is conserved to round-off), its centre moving at most two cells into
// the fluid. Periodic directions wrap.
//
// Ranks: a face value is written only by the rank that owns the face (no reverse halo
// exchange), so a caller that holds every point on every rank (the coupling does) gets
// every face written once, with contributions added in the caller's point order: the
// force field is the same bits for any rank count. Interpolation reads each of the 8 values
// per component on the one rank that holds it (an owned face, or a wall ghost on the rank
// at that wall), every other rank contributes an exact zero, one element-wise sum over the
// ranks (Decomposition::sum_in_place; no MPI here) gives every rank all of them, and every
// rank combines them in the same order: the interpolated velocity is the same bits on
// every rank and for every rank count.
#pragma once

#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

#include <span>
#include <vector>

namespace efsi::adhesion {

/// Peskin's 4-point kernel phi(r), r in cells.
real peskin4(real r);

/// Adds the force F [N] acting at x [m] to `force` as the force density
/// F_c delta_h(x - x_face) [N/m^3] on the faces of component c this rank owns. Returns the
/// number of face values written on this rank (a work counter). Throws RunError when x is
/// not inside the domain along a wall-bounded direction (or not finite).
std::size_t spread_force(VelocityField& force, const Decomposition& dec, const Real3& x,
                         const Real3& F);

/// Spreading onto a held (pinned) wall body: the reaction of a bond whose ligand sits on a
/// fixed solid goes onto that solid's faces, where the pinning removes it, not into the
/// fluid next to it (docs/method.md, "The wall takes the reaction"). The weight of face f is
/// phi4(x - x_f) * held_f, held_f = K_f / (1 + K_f) the fraction of a face's velocity the
/// pinning K = dt chi / tau removes each step, renormalised over the kernel to sum to one:
/// the force still integrates to F exactly. Faces beyond a wall (or a wall's own normal
/// face) take nothing, as in spread_force.
///
/// Ranks: the 64 weights per point and component are gathered (each written by the rank
/// that owns the face, exact zeros elsewhere, one element-wise sum) and every rank
/// normalises them in the same order, so the field is the same bits for any rank count.
/// Collective: every rank calls with the same points.
class HeldSpreader {
  public:
    /// share[p] = the smallest over the components of sum_f phi4 * held_f at x[p]: 1 deep
    /// inside a held body, about 1/2 on its surface, 0 in the fluid.
    void held_share(const VelocityField& pinning, const Decomposition& dec,
                    std::span<const Real3> x, std::vector<real>& share);
    /// Adds F[p] at x[p] onto the held faces (weights above). Throws RunError naming the point
    /// when some component's held share is below `min_share` (nowhere to put it). Returns
    /// the number of face values written on this rank.
    std::size_t spread(VelocityField& force, const VelocityField& pinning, const Decomposition& dec,
                       std::span<const Real3> x, std::span<const Real3> F, real min_share);

  private:
    void gather(const VelocityField& pinning, const Decomposition& dec, std::span<const Real3> x);
    std::vector<real> w_; ///< 64 weights per point and component, summed over ranks
};

class VelocityInterpolator {
  public:
    /// out[p] = the trilinear interpolation of the staggered velocity `u` at x[p], the same
    /// bits on every rank. `u` must have its halos filled (HaloFiller::fill), as the
    /// velocity the bodies are moved with has. One collective call (every rank must call it
    /// with the same points). Throws RunError naming the point's index when a point is not
    /// inside the domain along a wall-bounded direction.
    void interpolate(const VelocityField& u, const Decomposition& dec, std::span<const Real3> x,
                     std::span<Real3> out);

  private:
    std::vector<real> corners_; ///< 8 values per point and component, summed over ranks
    std::vector<Real3> frac_;   ///< per point and component: position within its cell
};

} // namespace efsi::adhesion

// Extension of a solid's left Cauchy-Green tensor B from the cells that are mostly solid
// into the interface cells and the fluid around them (docs/method.md, Solids).
//
// With a sharp interface (cell volume fractions), B stands for the deformation of the solid
// material in a cell, but the transport D B/Dt = L B + B L^T uses the velocity gradient of
// the whole cell, which in a cut cell is mostly the fluid's shear. Carried with that
// gradient, B in the interface cells grows without bound as the fluid keeps shearing past a
// rotating or tank-treading solid, and the elastic stress phi G B' of those cells stiffens
// the interface until the run blows up. Instead, after each step, B in every cell with
// phi < threshold is replaced by a constant extension of B from the cells with
// phi >= threshold, marched outwards layer by layer (as the reference map is extrapolated
// across the interface in Rycroft et al. 2020 / Valkov et al. 2015): each new cell takes
// the mean of its already known 3^dim neighbours. (Weights along the normal of phi were
// tried: in the VOF's tails, phi ~ 1e-7, the normal is noise, and round-off differences
// between decompositions then changed B there by 1e-6 relative; the plain mean depends on
// the set of known cells only.)
// Each layer reads only cells known before it and then exchanges halos, so the result is
// the same on any number of ranks. Cells still unreached after `layers` layers are reset to
// the identity: they hold at most VOF residues, and a fragment with no cell above the
// threshold is not a resolved solid (it keeps no elastic memory).
#pragma once

#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

namespace efsi {

//
// Membranes (two_sided): the same extension from the core of the band, threshold <= phi
// <= 1 - threshold, to both sides. Gs stands for the stretch of the membrane, a surface,
// but is transported with the velocity gradient of every band cell; in the outer band,
// where the fluid outside shears past the capsule (and inside it tank-treads), Gs grows
// without bound and loses positive definiteness (tr Gs ~ 300, det < 0 in the tails of the
// d/8 Ca 0.2 shear run by t = 8.8, which then blew up). Extended from the core, Gs is
// (nearly) constant across the band, as the surface tensor of a membrane is.
class TensorExtension {
  public:
    TensorExtension(const HaloFiller& halos, real threshold, int layers = 4, bool two_sided = false)
        : halos_(halos), threshold_(threshold), layers_(layers), two_sided_(two_sided) {}

    /// Replace the body's tensor outside the known cells (phi >= threshold, and
    /// phi <= 1 - threshold if two-sided; phi's halos filled); fills the tensor's halos.
    /// Collective.
    void apply(Body& body);

    real threshold() const { return threshold_; }
    int layers() const { return layers_; }

  private:
    const HaloFiller& halos_;
    real threshold_;
    int layers_;
    bool two_sided_;
    Field level_; ///< 0: known from the start (phi >= threshold), k: set in layer k, -1: unknown
};

} // namespace efsi

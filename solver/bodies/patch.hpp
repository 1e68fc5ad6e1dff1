// A body's patch: the part of the grid where its fields are stored and its kernels run.
//
// The patch is one box in GLOBAL cell indices, identical on every rank (it is reduced
// over ranks), intersected with each rank's block. Because Cartesian neighbours share
// their transverse index ranges, two neighbours always agree on the size of the slab they
// exchange, and on whether to exchange at all: they do exactly when the global box
// continues across their common boundary. A box that would wrap around a periodic
// direction covers that whole direction instead, except along x when the caller lets it
// cross the seam (`cross_seam`) and x is not split over ranks (the default layouts keep x
// whole up to 4 ranks, parallel/decomposition.cpp): such a box stays one unwrapped box of
// indices (lo < 0 or hi > n), its centre in
// [0, n); whoever reads or writes the flow's fields on it maps those indices across the
// seam (BodySystem's seam views: docs/method.md, "The periodic seam").
#pragma once

#include "grid/box.hpp"
#include "parallel/decomposition.hpp"

#include <array>

namespace efsi {

struct Patch {
    /// The asked box, wrapped and clipped but not widened: the same on every rank AND for
    /// every rank layout (decisions about moving a patch are made on it, and a checkpoint
    /// stores it).
    Box fitted;
    Box global; ///< global cell indices (fitted, widened for the layout), the same on every rank
    Box local;  ///< block-local indices of the part this rank owns (may be empty)
    /// Exchange halos with the neighbour on [direction][side].
    std::array<std::array<bool, 2>, 3> exchange{};
    /// The period along x (its cells) when the box crosses the periodic x seam (its indices
    /// run past [0, n)), else 0.
    int seam_period = 0;

    bool empty() const { return local.empty(); }
    bool crosses_seam() const { return seam_period > 0; }
};

/// The patch of a global box on this rank. `box` may extend past the grid (a margin):
/// along periodic directions it is wrapped (becoming the whole direction if it would wrap),
/// along walled directions it is clipped.
/// The box is widened where needed so that every rank it touches owns at least
/// `halo_width` layers of it. `cross_seam`: along a periodic x a box narrower than the grid
/// that would wrap stays unwrapped, shifted by a multiple of the period so that its centre
/// lies in [0, n) (the same box for every shift of its input by periods).
Patch make_patch(const Box& box, const Decomposition& dec, int halo_width = 2,
                 bool cross_seam = false);

} // namespace efsi

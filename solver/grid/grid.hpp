// The uniform Cartesian grid, globally and as the block this rank owns.
//
// Cells are numbered 0..n-1 in each direction. A staggered face field stores, at
// index i along its normal direction, the face on the LOW side of cell i (at x_i - dx/2),
// so every location has exactly n entries per direction on a periodic or walled box and
// all locations share one index box per rank.
#pragma once

#include <cmath>

#include "core/types.hpp"

namespace efsi {

/// Where a field's values live: cell centres or the faces normal to x, y or z.
enum class Location { Cell, FaceX, FaceY, FaceZ };

constexpr Location face_location(int d) {
    return static_cast<Location>(1 + d);
}
/// Direction normal to a face location, -1 for cell centres.
constexpr int face_normal(Location loc) {
    return static_cast<int>(loc) - 1;
}

struct GlobalGrid {
    Int3 cells{1, 1, 1};   ///< number of cells per direction
    Real3 length{1, 1, 1}; ///< box size [m]
    Real3 origin{0, 0, 0}; ///< low corner [m]
    int dim = 3;           ///< 2 for a one-cell z slab (no z work is done), else 3

    real dx(int d) const { return length[d] / cells[d]; }
    std::int64_t total_cells() const { return std::int64_t(cells[0]) * cells[1] * cells[2]; }
    real cell_volume() const { return dx(0) * dx(1) * dx(2); }
};

/// The block of cells one rank owns, in global indices [offset, offset + cells).
struct LocalBlock {
    Int3 cells{1, 1, 1};
    Int3 offset{0, 0, 0};
    std::int64_t count() const { return std::int64_t(cells[0]) * cells[1] * cells[2]; }
};

/// Position of the point of a location at local index (i,j,k) of a block.
inline Real3 position(const GlobalGrid& g, const LocalBlock& b, Location loc, int i, int j, int k) {
    const Int3 idx{i, j, k};
    Real3 x{};
    for (int d = 0; d < 3; ++d) {
        const real shift = (face_normal(loc) == d) ? 0.0 : 0.5;
        x[d] = g.origin[d] + (b.offset[d] + idx[d] + shift) * g.dx(d);
    }
    return x;
}

/// The image of x nearest `about` along the periodic directions (x itself elsewhere): where
/// a body's shape is evaluated at a cell across the periodic seam from its centre.
inline Real3 image_near(Real3 x, const Real3& about, const GlobalGrid& g, const Bool3& periodic) {
    for (int d = 0; d < g.dim; ++d)
        if (periodic[d]) x[d] -= g.length[d] * std::round((x[d] - about[d]) / g.length[d]);
    return x;
}

} // namespace efsi

// A voxel mask (a segmented image) read from HDF5 and mapped onto the grid as a volume
// fraction, the way a vessel wall arrives from medical imaging.
//
// The file holds a 3D dataset [nz][ny][nx] (x fastest) of 0/1 labels or volume fractions in
// [0, 1] (any integer or float type; read as double) with two attributes on the dataset:
// `spacing` (3 doubles, voxel size in x, y, z [m]) and `origin` (3 doubles, the low corner
// of voxel (0,0,0) [m]). A voxel is a piecewise-constant cell of the image.
//
// Mapping: the volume fraction of a grid cell is the mean of the voxel values at
// `subsamples`^3 points of the cell (cell-centred sub-cells). When the mask's voxels are
// the grid's cells (same spacing, origin on a grid corner) this is an exact copy; otherwise
// the mask is resampled and the log says so. A grid cell that reaches outside the mask is
// refused with a message naming the extents, never padded or shifted silently.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace efsi {

struct VoxelMask {
    Int3 voxels{0, 0, 0};     ///< nx, ny, nz
    Real3 spacing{};          ///< [m]
    Real3 origin{};           ///< low corner [m]
    std::vector<real> values; ///< x fastest, in [0, 1]
    std::string source;       ///< "file:dataset", for messages

    real at(int i, int j, int k) const {
        return values[std::size_t(i) +
                      std::size_t(voxels[0]) * (std::size_t(j) + std::size_t(voxels[1]) * k)];
    }
    real upper(int d) const { return origin[d] + spacing[d] * voxels[d]; }
};

/// Read and validate a mask. Throws InputError naming the file, the dataset or the
/// attribute and the problem (missing, wrong shape, non-finite or out-of-range values, more
/// than `max_voxels` voxels) before allocating the voxels.
VoxelMask read_voxel_mask(const std::filesystem::path& file, const std::string& dataset,
                          std::int64_t max_voxels = std::int64_t(1) << 31);

/// How a mask maps onto a grid.
struct MaskMapping {
    bool aligned = false; ///< voxels are the grid's cells (exact copy)
    std::string description;
};

/// Check that the mask covers the grid's box (throws InputError with both extents when it
/// does not) and say whether it is aligned with the grid.
MaskMapping check_mask_against_grid(const VoxelMask& mask, const GlobalGrid& grid);

/// Volume fraction of the mask on the owned cells of phi (its block or patch).
void mask_volume_fraction(const VoxelMask& mask, const GlobalGrid& grid, const LocalBlock& block,
                          Field& phi, int subsamples = 4);

} // namespace efsi

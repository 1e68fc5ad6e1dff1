// A voxel mask (a segmented image) read from HDF5 and mapped onto the grid as a volume
// fraction, the way a vessel wall arrives from medical imaging.
//
// The file holds a 3D dataset [nz][ny][nx] (x fastest) of 0/1 labels or volume fractions in
// [0, 1] (any integer or float type; read as double) with two attributes on the dataset:
// `spacing` (3 doubles, voxel size in x, y, z) and `origin` (3 doubles, the low corner of
// voxel (0,0,0)), in the case's length unit. A voxel is a piecewise-constant cell of the
// image. A dataset with neither attribute is taken to be on the grid's own cells, and is
// refused unless it has exactly the grid's number of cells in each direction.
//
// Mapping: the volume fraction of a grid cell is the mean of the voxel values at
// `subsamples`^3 points of the cell (cell-centred sub-cells). When the mask's voxels are
// the grid's cells (same spacing, origin on a grid corner) the values are copied; otherwise
// the mask is resampled and the log says so. A grid cell that reaches outside the mask is
// refused with a message naming the extents, never padded or shifted silently.
//
// A run reads the header when it reads the case (so a misplaced mask is refused before
// anything is allocated), and each rank later reads only the voxels its cells cover.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace efsi {

struct VoxelMask {
    Int3 voxels{0, 0, 0}; ///< nx, ny, nz of the whole image
    Real3 spacing{};      ///< voxel size [length unit]
    Real3 origin{};       ///< low corner of voxel (0,0,0) [length unit]
    /// false: the dataset has no spacing/origin attributes (place_on_grid sets them)
    bool placed = true;
    Box held{};               ///< the voxels whose values are held (all, or one rank's part)
    std::vector<real> values; ///< the held voxels, x fastest, in [0, 1]
    std::filesystem::path file;
    std::string dataset;
    std::string source; ///< "file:dataset", for messages

    real at(int i, int j, int k) const {
        const Int3 n = held.size();
        return values[std::size_t(i - held.lo[0]) +
                      std::size_t(n[0]) * (std::size_t(j - held.lo[1]) +
                                           std::size_t(n[1]) * std::size_t(k - held.lo[2]))];
    }
    real upper(int d) const { return origin[d] + spacing[d] * voxels[d]; }
};

/// Read and validate a mask's header: its size, spacing and origin, no values. Throws
/// InputError naming the file, the dataset or the attribute and the problem (not HDF5, no
/// such dataset, not 3D, not numeric, one of spacing/origin without the other, spacing not
/// positive, more than `max_voxels` voxels).
VoxelMask read_voxel_mask_header(const std::filesystem::path& file, const std::string& dataset,
                                 std::int64_t max_voxels = std::int64_t(1) << 31);

/// Read the values of the voxels in `part` (within the image) from the mask's file into
/// `mask.held` and `mask.values`. Returns the flat index (x fastest, over the whole image)
/// of the first value that is not in [0, 1], or -1 when every value is; the caller reports
/// it (collectively, when each rank reads its own part). Throws InputError when the file
/// cannot be read.
std::int64_t read_voxel_values(VoxelMask& mask, const Box& part);

/// Header and every value; throws InputError for a value not in [0, 1] as well.
VoxelMask read_voxel_mask(const std::filesystem::path& file, const std::string& dataset,
                          std::int64_t max_voxels = std::int64_t(1) << 31);

/// Give a mask without spacing/origin attributes the grid's cells (spacing dx, origin the
/// grid's origin); refuses one whose voxel count differs from the grid's cell count.
/// Does nothing to a placed mask.
void place_on_grid(VoxelMask& mask, const GlobalGrid& grid, std::string_view length_unit = "m");

/// How a mask maps onto a grid.
struct MaskMapping {
    bool aligned = false; ///< voxels are the grid's cells (exact copy)
    std::string description;
};

/// Check that the mask covers the grid's box (throws InputError with both extents when it
/// does not) and say whether it is aligned with the grid.
MaskMapping check_mask_against_grid(const VoxelMask& mask, const GlobalGrid& grid,
                                    std::string_view length_unit = "m");

/// What a case's mask body needs before any voxel is read: the header, placed on the grid
/// (place_on_grid) and checked against it (check_mask_against_grid); `mapping`, if given,
/// receives how it maps.
VoxelMask read_voxel_mask_for_grid(const std::filesystem::path& file, const std::string& dataset,
                                   const GlobalGrid& grid, std::string_view length_unit,
                                   MaskMapping* mapping = nullptr);

/// The voxels that the mapping of `cells` (block-local indices of `block`) reads: what a rank
/// passes to read_voxel_values. Empty for an empty box.
Box mask_voxels_for(const VoxelMask& mask, const GlobalGrid& grid, const LocalBlock& block,
                    const Box& cells, int subsamples = 4);

/// Volume fraction of the mask on the owned cells of phi (its block or patch); the mask must
/// hold the voxels mask_voxels_for names for them. Aligned: a copy of the voxel values.
void mask_volume_fraction(const VoxelMask& mask, const GlobalGrid& grid, const LocalBlock& block,
                          Field& phi, int subsamples = 4);

} // namespace efsi

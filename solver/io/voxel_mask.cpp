#include "io/voxel_mask.hpp"

#include "core/error.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cmath>

namespace efsi {

namespace {

/// Closes an HDF5 handle when it goes out of scope.
struct Handle {
    hid_t id;
    herr_t (*close)(hid_t);
    ~Handle() {
        if (id >= 0) close(id);
    }
};

Real3 read_triple(hid_t dset, const char* name, const std::string& where) {
    Handle a{H5Aopen(dset, name, H5P_DEFAULT), H5Aclose};
    Handle space{H5Aget_space(a.id), H5Sclose};
    if (H5Sget_simple_extent_npoints(space.id) != 3)
        throw InputError(fmt::format("voxel mask {}: attribute '{}' must hold 3 numbers (x, y, z)",
                                     where, name));
    Real3 v{};
    if (H5Aread(a.id, H5T_NATIVE_DOUBLE, v.data()) < 0)
        throw InputError(fmt::format("voxel mask {}: attribute '{}' is not numeric", where, name));
    for (real x : v)
        if (!std::isfinite(x))
            throw InputError(
                fmt::format("voxel mask {}: attribute '{}' is not finite", where, name));
    return v;
}

/// HDF5's own error stack printing off while in scope (our messages, not its stack).
struct QuietHdf5 {
    H5E_auto2_t func;
    void* data;
    QuietHdf5() {
        H5Eget_auto2(H5E_DEFAULT, &func, &data);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func, data); }
    QuietHdf5(const QuietHdf5&) = delete;
    QuietHdf5& operator=(const QuietHdf5&) = delete;
};

/// The file and its dataset, open, or an InputError naming what is wrong.
struct OpenMask {
    Handle file, dataset;
};

OpenMask open_mask(const std::filesystem::path& file, const std::string& dataset,
                   const std::string& where) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(
            fmt::format("voxel mask {}: '{}' is not a readable file", where, file.string()));
    OpenMask m{{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose}, {-1, H5Dclose}};
    if (m.file.id < 0) throw InputError(fmt::format("voxel mask {}: not an HDF5 file", where));
    if (H5Lexists(m.file.id, dataset.c_str(), H5P_DEFAULT) <= 0)
        throw InputError(fmt::format("voxel mask {}: no dataset '{}' in the file", where, dataset));
    m.dataset.id = H5Dopen2(m.file.id, dataset.c_str(), H5P_DEFAULT);
    if (m.dataset.id < 0)
        throw InputError(fmt::format("voxel mask {}: '{}' is not a dataset", where, dataset));
    return m;
}

} // namespace

VoxelMask read_voxel_mask_header(const std::filesystem::path& file, const std::string& dataset,
                                 std::int64_t max_voxels) {
    const std::string where = file.string() + ":" + dataset;
    QuietHdf5 quiet;
    const OpenMask f = open_mask(file, dataset, where);
    const hid_t d = f.dataset.id;
    Handle space{H5Dget_space(d), H5Sclose};
    if (H5Sget_simple_extent_ndims(space.id) != 3)
        throw InputError(fmt::format("voxel mask {}: the dataset must be 3D [nz][ny][nx]", where));
    hsize_t dims[3];
    H5Sget_simple_extent_dims(space.id, dims, nullptr);
    const H5T_class_t cls = H5Tget_class(Handle{H5Dget_type(d), H5Tclose}.id);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT)
        throw InputError(fmt::format("voxel mask {}: values must be integers (0/1) or floats "
                                     "(volume fractions)",
                                     where));
    VoxelMask m;
    m.file = file;
    m.dataset = dataset;
    m.source = where;
    m.voxels = {int(dims[2]), int(dims[1]), int(dims[0])};
    const double count = double(dims[0]) * double(dims[1]) * double(dims[2]);
    if (count < 1 || count > double(max_voxels))
        throw InputError(fmt::format("voxel mask {}: {} x {} x {} voxels (limit {})", where,
                                     dims[2], dims[1], dims[0], max_voxels));
    const bool has_spacing = H5Aexists(d, "spacing") > 0, has_origin = H5Aexists(d, "origin") > 0;
    if (has_spacing != has_origin)
        throw InputError(fmt::format("voxel mask {}: attribute '{}' (3 numbers) is missing; give "
                                     "both spacing and origin, or neither for a mask on the "
                                     "grid's own cells",
                                     where, has_spacing ? "origin" : "spacing"));
    m.placed = has_spacing;
    if (m.placed) {
        m.spacing = read_triple(d, "spacing", where);
        m.origin = read_triple(d, "origin", where);
        for (int a = 0; a < 3; ++a)
            if (!(m.spacing[a] > 0))
                throw InputError(
                    fmt::format("voxel mask {}: spacing must be > 0 in x, y and z", where));
    }
    return m;
}

std::int64_t read_voxel_values(VoxelMask& m, const Box& part) {
    const Box whole{{0, 0, 0}, m.voxels};
    if (!whole.contains(part))
        throw InputError(fmt::format("voxel mask {}: voxels [{}, {}) x [{}, {}) x [{}, {}) asked "
                                     "for, outside the image",
                                     m.source, part.lo[0], part.hi[0], part.lo[1], part.hi[1],
                                     part.lo[2], part.hi[2]));
    m.held = part;
    m.values.assign(std::size_t(part.count()), 0.0);
    if (part.empty()) return -1;
    QuietHdf5 quiet;
    const OpenMask f = open_mask(m.file, m.dataset, m.source);
    Handle space{H5Dget_space(f.dataset.id), H5Sclose};
    const Int3 n = part.size();
    const hsize_t start[3] = {hsize_t(part.lo[2]), hsize_t(part.lo[1]), hsize_t(part.lo[0])};
    const hsize_t count[3] = {hsize_t(n[2]), hsize_t(n[1]), hsize_t(n[0])};
    Handle memory{H5Screate_simple(3, count, nullptr), H5Sclose};
    if (H5Sselect_hyperslab(space.id, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
        H5Dread(f.dataset.id, H5T_NATIVE_DOUBLE, memory.id, space.id, H5P_DEFAULT,
                m.values.data()) < 0)
        throw InputError(fmt::format("voxel mask {}: the values could not be read", m.source));
    for (int k = part.lo[2]; k < part.hi[2]; ++k)
        for (int j = part.lo[1]; j < part.hi[1]; ++j)
            for (int i = part.lo[0]; i < part.hi[0]; ++i) {
                const real v = m.at(i, j, k);
                if (!(v >= 0 && v <= 1))
                    return std::int64_t(i) +
                           std::int64_t(m.voxels[0]) * (j + std::int64_t(m.voxels[1]) * k);
            }
    return -1;
}

VoxelMask read_voxel_mask(const std::filesystem::path& file, const std::string& dataset,
                          std::int64_t max_voxels) {
    VoxelMask m = read_voxel_mask_header(file, dataset, max_voxels);
    const std::int64_t bad = read_voxel_values(m, Box{{0, 0, 0}, m.voxels});
    if (bad >= 0)
        throw InputError(fmt::format("voxel mask {}: value {} at voxel {} is not in [0, 1]",
                                     m.source, m.values[std::size_t(bad)], bad));
    return m;
}

void place_on_grid(VoxelMask& m, const GlobalGrid& g, std::string_view unit) {
    if (m.placed) return;
    if (m.voxels != g.cells)
        throw InputError(fmt::format(
            "voxel mask {}: {} x {} x {} voxels and no spacing/origin attributes; a mask "
            "without them must have the grid's {} x {} x {} cells (give spacing and origin in "
            "{} to have it resampled)",
            m.source, m.voxels[0], m.voxels[1], m.voxels[2], g.cells[0], g.cells[1], g.cells[2],
            unit));
    for (int a = 0; a < 3; ++a) {
        m.spacing[a] = g.dx(a);
        m.origin[a] = g.origin[a];
    }
    m.placed = true;
}

namespace {

/// The voxels are the grid's cells: the same spacing, the origin on a grid corner.
bool aligned_with(const VoxelMask& m, const GlobalGrid& g) {
    for (int a = 0; a < g.dim; ++a) {
        const real h = g.dx(a);
        const real shift = (g.origin[a] - m.origin[a]) / h;
        if (std::abs(m.spacing[a] - h) > 1e-9 * h || std::abs(shift - std::round(shift)) > 1e-9)
            return false;
    }
    return true;
}

/// How a grid cell's sub-cells are placed, and which voxel holds each.
struct Sampling {
    const VoxelMask& m;
    const GlobalGrid& g;
    Int3 n; ///< sub-cells per cell and direction (1 in z in 2D)
    Sampling(const VoxelMask& mask, const GlobalGrid& grid, int subsamples)
        : m(mask), g(grid), n{std::max(1, subsamples), std::max(1, subsamples),
                              grid.dim == 3 ? std::max(1, subsamples) : 1} {}
    /// The voxel along a that holds sub-cell `sub` of global cell `c`.
    int voxel(int a, int c, int sub) const {
        const real x = g.origin[a] + (c + (sub + 0.5) / n[a]) * g.dx(a);
        return std::clamp(int(std::floor((x - m.origin[a]) / m.spacing[a])), 0, m.voxels[a] - 1);
    }
};

} // namespace

MaskMapping check_mask_against_grid(const VoxelMask& m, const GlobalGrid& g,
                                    std::string_view unit) {
    const char* axes = "xyz";
    for (int a = 0; a < g.dim; ++a) {
        const real lo = g.origin[a], hi = g.origin[a] + g.length[a];
        const real tol = 1e-9 * g.dx(a);
        if (m.origin[a] > lo + tol || m.upper(a) < hi - tol)
            throw InputError(fmt::format(
                "voxel mask {}: it covers [{:.6g}, {:.6g}] {} in {} but the grid spans [{:.6g}, "
                "{:.6g}] {}; give a mask that covers the box (it is never padded or shifted)",
                m.source, m.origin[a], m.upper(a), unit, axes[a], lo, hi, unit));
    }
    MaskMapping map;
    map.aligned = aligned_with(m, g);
    map.description =
        map.aligned ? fmt::format("voxel mask {}: aligned with the grid, copied", m.source)
                    : fmt::format("voxel mask {}: voxels {:.4g} x {:.4g} x {:.4g} {} against "
                                  "cells {:.4g} x {:.4g} x {:.4g} {}, resampled (cell means of "
                                  "the voxel values)",
                                  m.source, m.spacing[0], m.spacing[1], m.spacing[2], unit, g.dx(0),
                                  g.dx(1), g.dx(2), unit);
    return map;
}

VoxelMask read_voxel_mask_for_grid(const std::filesystem::path& file, const std::string& dataset,
                                   const GlobalGrid& grid, std::string_view unit,
                                   MaskMapping* mapping) {
    VoxelMask m = read_voxel_mask_header(file, dataset);
    place_on_grid(m, grid, unit);
    const MaskMapping map = check_mask_against_grid(m, grid, unit);
    if (mapping) *mapping = map;
    return m;
}

Box mask_voxels_for(const VoxelMask& m, const GlobalGrid& g, const LocalBlock& block,
                    const Box& cells, int subsamples) {
    if (cells.empty()) return Box{};
    const Sampling sample(m, g, subsamples);
    Box v;
    for (int a = 0; a < 3; ++a) {
        v.lo[a] = sample.voxel(a, block.offset[a] + cells.lo[a], 0);
        v.hi[a] = sample.voxel(a, block.offset[a] + cells.hi[a] - 1, sample.n[a] - 1) + 1;
    }
    return v;
}

void mask_volume_fraction(const VoxelMask& m, const GlobalGrid& g, const LocalBlock& block,
                          Field& phi, int subsamples) {
    const bool copy = aligned_with(m, g);
    const Sampling sample(m, g, copy ? 1 : subsamples);
    const Int3 n = sample.n;
    const real weight = 1.0 / (real(n[0]) * n[1] * n[2]);
    const Box own = phi.owned();
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j)
            for (int i = own.lo[0]; i < own.hi[0]; ++i) {
                const Int3 c{block.offset[0] + i, block.offset[1] + j, block.offset[2] + k};
                if (copy) {
                    phi(i, j, k) = m.at(sample.voxel(0, c[0], 0), sample.voxel(1, c[1], 0),
                                        sample.voxel(2, c[2], 0));
                    continue;
                }
                real sum = 0;
                for (int c2 = 0; c2 < n[2]; ++c2)
                    for (int c1 = 0; c1 < n[1]; ++c1)
                        for (int c0 = 0; c0 < n[0]; ++c0)
                            sum += m.at(sample.voxel(0, c[0], c0), sample.voxel(1, c[1], c1),
                                        sample.voxel(2, c[2], c2));
                phi(i, j, k) = sum * weight;
            }
}

} // namespace efsi

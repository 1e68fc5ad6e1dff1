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
    if (H5Aexists(dset, name) <= 0)
        throw InputError(
            fmt::format("voxel mask {}: attribute '{}' (3 numbers, [m]) is missing", where, name));
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

} // namespace

VoxelMask read_voxel_mask(const std::filesystem::path& file, const std::string& dataset,
                          std::int64_t max_voxels) {
    const std::string where = file.string() + ":" + dataset;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(
            fmt::format("voxel mask {}: '{}' is not a readable file", where, file.string()));
    H5E_auto2_t old_func;
    void* old_data;
    H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // our messages, not HDF5's stack
    struct Restore {
        H5E_auto2_t f;
        void* d;
        ~Restore() { H5Eset_auto2(H5E_DEFAULT, f, d); }
    } restore{old_func, old_data};

    Handle f{H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    if (f.id < 0) throw InputError(fmt::format("voxel mask {}: not an HDF5 file", where));
    if (H5Lexists(f.id, dataset.c_str(), H5P_DEFAULT) <= 0)
        throw InputError(fmt::format("voxel mask {}: no dataset '{}' in the file", where, dataset));
    Handle d{H5Dopen2(f.id, dataset.c_str(), H5P_DEFAULT), H5Dclose};
    if (d.id < 0)
        throw InputError(fmt::format("voxel mask {}: '{}' is not a dataset", where, dataset));
    Handle space{H5Dget_space(d.id), H5Sclose};
    if (H5Sget_simple_extent_ndims(space.id) != 3)
        throw InputError(fmt::format("voxel mask {}: the dataset must be 3D [nz][ny][nx]", where));
    hsize_t dims[3];
    H5Sget_simple_extent_dims(space.id, dims, nullptr);
    const H5T_class_t cls = H5Tget_class(Handle{H5Dget_type(d.id), H5Tclose}.id);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT)
        throw InputError(fmt::format("voxel mask {}: values must be integers (0/1) or floats "
                                     "(volume fractions)",
                                     where));
    VoxelMask m;
    m.source = where;
    m.voxels = {int(dims[2]), int(dims[1]), int(dims[0])};
    const double count = double(dims[0]) * double(dims[1]) * double(dims[2]);
    if (count < 1 || count > double(max_voxels))
        throw InputError(fmt::format("voxel mask {}: {} x {} x {} voxels (limit {})", where,
                                     dims[2], dims[1], dims[0], max_voxels));
    m.spacing = read_triple(d.id, "spacing", where);
    m.origin = read_triple(d.id, "origin", where);
    for (int a = 0; a < 3; ++a)
        if (!(m.spacing[a] > 0))
            throw InputError(
                fmt::format("voxel mask {}: spacing must be > 0 in x, y and z", where));
    m.values.resize(std::size_t(count));
    if (H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.values.data()) < 0)
        throw InputError(fmt::format("voxel mask {}: the values could not be read", where));
    for (std::size_t n = 0; n < m.values.size(); ++n)
        if (!(m.values[n] >= 0 && m.values[n] <= 1))
            throw InputError(fmt::format("voxel mask {}: value {} at voxel {} is not in [0, 1]",
                                         where, m.values[n], n));
    return m;
}

MaskMapping check_mask_against_grid(const VoxelMask& m, const GlobalGrid& g) {
    const char* axes = "xyz";
    const int dims = g.dim;
    for (int a = 0; a < dims; ++a) {
        const real lo = g.origin[a], hi = g.origin[a] + g.length[a];
        const real tol = 1e-9 * g.dx(a);
        if (m.origin[a] > lo + tol || m.upper(a) < hi - tol)
            throw InputError(fmt::format(
                "voxel mask {}: it covers [{:.6g}, {:.6g}] m in {} but the grid spans [{:.6g}, "
                "{:.6g}] m; give a mask that covers the box (it is never padded or shifted)",
                m.source, m.origin[a], m.upper(a), axes[a], lo, hi));
    }
    MaskMapping map;
    map.aligned = true;
    for (int a = 0; a < dims; ++a) {
        const real h = g.dx(a);
        const real shift = (g.origin[a] - m.origin[a]) / h;
        if (std::abs(m.spacing[a] - h) > 1e-9 * h || std::abs(shift - std::round(shift)) > 1e-9)
            map.aligned = false;
    }
    map.description =
        map.aligned ? fmt::format("voxel mask {}: aligned with the grid, copied", m.source)
                    : fmt::format("voxel mask {}: voxels {:.4g} x {:.4g} x {:.4g} m against cells "
                                  "{:.4g} x {:.4g} x {:.4g} m, resampled (cell means of the "
                                  "voxel values)",
                                  m.source, m.spacing[0], m.spacing[1], m.spacing[2], g.dx(0),
                                  g.dx(1), g.dx(2));
    return map;
}

void mask_volume_fraction(const VoxelMask& m, const GlobalGrid& g, const LocalBlock& block,
                          Field& phi, int subsamples) {
    const int s = std::max(1, subsamples);
    const int sz = g.dim == 3 ? s : 1;
    const Box own = phi.owned();
    auto voxel = [&](int a, real x) {
        const int v = int(std::floor((x - m.origin[a]) / m.spacing[a]));
        return std::clamp(v, 0, m.voxels[a] - 1);
    };
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j)
            for (int i = own.lo[0]; i < own.hi[0]; ++i) {
                const Int3 c{block.offset[0] + i, block.offset[1] + j, block.offset[2] + k};
                real sum = 0;
                for (int c2 = 0; c2 < sz; ++c2)
                    for (int c1 = 0; c1 < s; ++c1)
                        for (int c0 = 0; c0 < s; ++c0) {
                            const int sub[3] = {c0, c1, c2};
                            int v[3];
                            for (int a = 0; a < 3; ++a) {
                                const int n = a < 2 || g.dim == 3 ? s : 1;
                                const real x = g.origin[a] + (c[a] + (sub[a] + 0.5) / n) * g.dx(a);
                                v[a] = voxel(a, x);
                            }
                            sum += m.at(v[0], v[1], v[2]);
                        }
                phi(i, j, k) = sum / (real(s) * s * sz);
            }
}

} // namespace efsi

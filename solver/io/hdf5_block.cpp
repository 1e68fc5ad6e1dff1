// Hdf5File's fields (write_block, read_block, read_checksum): a field's owned values into and
// out of a 3D dataset that holds the whole grid or one box of it (a body's patch).
#include "io/hdf5_detail.hpp"
#include "io/hdf5_file.hpp"

#include "core/error.hpp"

#include <fmt/core.h>
#include <mpi.h>

#include <algorithm>
#include <cerrno>

namespace efsi {

using hdf5_detail::Creation;
using hdf5_detail::Storage;

namespace {
/// Selection of the global cells `sel` (its part inside `stored`) in a dataset [nz][ny][nx]
/// that holds the global box `stored`, and a memory space of `sel`'s size.
struct BoxSpace {
    hid_t fspace, mspace;
    BoxSpace(const Box& stored, const Box& sel) {
        const Int3 n = stored.size();
        const hsize_t dims[3] = {hsize_t(n[2]), hsize_t(n[1]), hsize_t(n[0])};
        fspace = H5Screate_simple(3, dims, nullptr);
        const Box part = intersect(sel, stored);
        if (part.empty()) {
            H5Sselect_none(fspace);
        } else {
            const hsize_t start[3] = {hsize_t(part.lo[2] - stored.lo[2]),
                                      hsize_t(part.lo[1] - stored.lo[1]),
                                      hsize_t(part.lo[0] - stored.lo[0])};
            const Int3 c = part.size();
            const hsize_t count[3] = {hsize_t(c[2]), hsize_t(c[1]), hsize_t(c[0])};
            H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
        }
        const hsize_t local = hsize_t(std::max<std::int64_t>(0, part.count()));
        mspace = H5Screate_simple(1, &local, nullptr);
    }
    ~BoxSpace() {
        H5Sclose(mspace);
        H5Sclose(fspace);
    }
};

/// The global cells of `f`'s owned box (its block, or its part of a patch).
Box owned_global(const Decomposition& dec, const Field& f) {
    const Int3 off = dec.block().offset;
    Box b = f.owned();
    for (int d = 0; d < 3; ++d) {
        b.lo[d] += off[d];
        b.hi[d] += off[d];
    }
    return b;
}

Box whole_grid(const GlobalGrid& g) {
    Box b;
    for (int d = 0; d < 3; ++d) {
        b.lo[d] = 0;
        b.hi[d] = g.cells[d];
    }
    return b;
}
} // namespace

namespace {
/// The owned values of `f` in storage order (x fastest), row by row.
void gather_owned(const Field& f, std::vector<double>& buf) {
    const Box own = f.owned();
    const int n0 = own.hi[0] - own.lo[0];
    buf.resize(std::size_t(std::max<std::int64_t>(0, own.count())));
    if (n0 <= 0) return;
    double* to = buf.data();
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j) {
            const double* from = f.data().data() + f.index(own.lo[0], j, k);
            std::copy(from, from + n0, to);
            to += n0;
        }
}

} // namespace

std::uint64_t Hdf5File::write_block(const std::string& name, const Field& f, const Box* box) {
    const GlobalGrid& g = dec_.grid();
    const Box stored = box ? *box : whole_grid(g);
    const Box own = owned_global(dec_, f);
    agree(own.empty() || intersect(own, stored).count() == own.count(),
          fmt::format("writing dataset '{}': a rank's part lies outside its box", name));
    BoxSpace s(stored, own);
    std::vector<double>& buf = scratch_;
    gather_owned(f, buf);
    const Creation dcpl(H5T_NATIVE_DOUBLE, Storage::Contiguous, 3, nullptr);
    errno = 0;
    hid_t dset = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, s.fspace, H5P_DEFAULT, dcpl,
                            H5P_DEFAULT);
    try {
        agree(dset >= 0, fmt::format("creating dataset '{}'", name));
    } catch (...) {
        if (dset >= 0) H5Dclose(dset);
        throw;
    }
    if (box) {
        // Where the box starts in the grid (x, y, z): a reader places the values with it.
        const hsize_t three = 3;
        const std::int64_t lo[3] = {box->lo[0], box->lo[1], box->lo[2]};
        hid_t space = H5Screate_simple(1, &three, nullptr);
        hid_t attr = H5Acreate2(dset, "box_lo", H5T_NATIVE_INT64, space, H5P_DEFAULT, H5P_DEFAULT);
        const herr_t wl = attr >= 0 ? H5Awrite(attr, H5T_NATIVE_INT64, lo) : -1;
        if (attr >= 0) H5Aclose(attr);
        H5Sclose(space);
        if (wl < 0) {
            H5Dclose(dset);
            agree(false, fmt::format("writing the box of dataset '{}'", name));
        }
    }
    errno = 0;
    const herr_t w = H5Dwrite(dset, H5T_NATIVE_DOUBLE, s.mspace, s.fspace, xfer_, buf.data());
    const int e = errno;
    return seal(dset, w, e, block_checksum(dec_, f, buf), name);
}

std::uint64_t Hdf5File::stored_checksum(const std::string& name) const {
    if (!has(name)) return 0;
    hid_t dset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
    std::uint64_t value = 0;
    if (dset >= 0 && H5Aexists(dset, "checksum") > 0) {
        hid_t attr = H5Aopen(dset, "checksum", H5P_DEFAULT);
        if (attr >= 0) {
            if (H5Aread(attr, H5T_NATIVE_UINT64, &value) < 0) value = 0;
            H5Aclose(attr);
        }
    }
    if (dset >= 0) H5Dclose(dset);
    return value;
}

namespace {
/// Read the owned box of `f`'s layout from `dset` into `buf`; false on a failed read.
bool read_owned(const Decomposition& dec, hid_t file, hid_t xfer, const std::string& name,
                const Field& f, std::vector<double>& buf, std::string& why) {
    hid_t dset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    if (dset < 0) {
        why = fmt::format("dataset '{}' cannot be opened", name);
        return false;
    }
    hid_t space = H5Dget_space(dset);
    hsize_t dims[3] = {0, 0, 0};
    const int nd = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
    if (nd == 3) H5Sget_simple_extent_dims(space, dims, nullptr);
    if (space >= 0) H5Sclose(space);
    const GlobalGrid& g = dec.grid();
    // The dataset holds the whole grid, or (attribute "box_lo") a box of it.
    Box stored = whole_grid(g);
    bool fits = nd == 3;
    if (fits && H5Aexists(dset, "box_lo") > 0) {
        std::int64_t lo[3] = {0, 0, 0};
        hid_t attr = H5Aopen(dset, "box_lo", H5P_DEFAULT);
        fits = attr >= 0 && H5Aread(attr, H5T_NATIVE_INT64, lo) >= 0;
        if (attr >= 0) H5Aclose(attr);
        for (int d = 0; d < 3 && fits; ++d) {
            stored.lo[d] = int(lo[d]);
            stored.hi[d] = int(lo[d] + std::int64_t(dims[2 - d]));
            // Along a periodic x a patch's box may cross the seam (bodies/patch.hpp): its
            // indices then run past [0, n), but it is never wider than the grid.
            const bool across = d == 0 && dec.periodic()[0] && stored.lo[0] > -g.cells[0] &&
                                stored.hi[0] < 2 * g.cells[0] &&
                                stored.hi[0] - stored.lo[0] < g.cells[0];
            fits = across || (stored.lo[d] >= 0 && stored.hi[d] <= g.cells[d]);
        }
    } else {
        fits = fits && dims[0] == hsize_t(g.cells[2]) && dims[1] == hsize_t(g.cells[1]) &&
               dims[2] == hsize_t(g.cells[0]);
    }
    if (!fits) {
        H5Dclose(dset);
        why = fmt::format("dataset '{}' is {}x{}x{} but the case grid is {}x{}x{}", name, dims[2],
                          dims[1], dims[0], g.cells[0], g.cells[1], g.cells[2]);
        return false;
    }
    // The owned box's part inside the stored box is read; the rest of it is 0 (nothing was
    // written there).
    const Box own = owned_global(dec, f);
    const Box part = intersect(own, stored);
    BoxSpace s(stored, own);
    buf.assign(std::size_t(std::max<std::int64_t>(0, own.count())), 0.0);
    std::vector<double> part_values;
    const bool direct = part.count() == own.count();
    if (!direct) part_values.resize(std::size_t(std::max<std::int64_t>(0, part.count())));
    const herr_t r = H5Dread(dset, H5T_NATIVE_DOUBLE, s.mspace, s.fspace, xfer,
                             direct ? buf.data() : part_values.data());
    H5Dclose(dset);
    if (r < 0) {
        why = fmt::format("dataset '{}' cannot be read (truncated file?)", name);
        return false;
    }
    if (!direct && !part.empty()) {
        const Int3 on = own.size(), pn = part.size();
        std::size_t q = 0;
        for (int k = part.lo[2]; k < part.hi[2]; ++k)
            for (int j = part.lo[1]; j < part.hi[1]; ++j) {
                const std::size_t at =
                    (std::size_t(k - own.lo[2]) * std::size_t(on[1]) + std::size_t(j - own.lo[1])) *
                        std::size_t(on[0]) +
                    std::size_t(part.lo[0] - own.lo[0]);
                std::copy(part_values.begin() + std::ptrdiff_t(q),
                          part_values.begin() + std::ptrdiff_t(q + std::size_t(pn[0])),
                          buf.begin() + std::ptrdiff_t(at));
                q += std::size_t(pn[0]);
            }
    }
    return true;
}
} // namespace

std::uint64_t Hdf5File::read_checksum(const std::string& name, const Field& f) {
    agree(has(name), fmt::format("finding dataset '{}'", name));
    std::vector<double>& buf = scratch_;
    std::string why;
    const bool ok = read_owned(dec_, file_, xfer_, name, f, buf, why);
    agree(ok, ok ? "" : why);
    return block_checksum(dec_, f, buf);
}

void Hdf5File::read_block(const std::string& name, Field& f, bool require_checksum,
                          const Box* written) {
    if (!has(name)) throw InputError(fmt::format("{}: has no dataset '{}'", path_.string(), name));
    std::vector<double>& buf = scratch_;
    std::string why;
    const bool ok = read_owned(dec_, file_, xfer_, name, f, buf, why);
    int bad = ok ? 0 : 1, any = 0;
    MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, dec_.comm());
    if (any)
        throw InputError(fmt::format("{}: {}", path_.string(),
                                     why.empty() ? "dataset '" + name + "' cannot be read" : why));
    const std::uint64_t stored = stored_checksum(name);
    if (stored != 0 || require_checksum) {
        const std::uint64_t sum = block_checksum(dec_, f, buf, written);
        if (stored == 0)
            throw InputError(fmt::format("{}: dataset '{}' has no checksum", path_.string(), name));
        if (sum != stored)
            throw InputError(fmt::format("{}: dataset '{}' does not match its checksum (stored "
                                         "{:016x}, data {:016x}): the file is corrupted",
                                         path_.string(), name, stored, sum));
    }
    // Points outside `written` keep the values `f` holds (the dataset has its fill value 0
    // there: nothing was written).
    const Box own = f.owned();
    const Int3 off = dec_.block().offset;
    const int n0 = own.hi[0] - own.lo[0];
    const double* from = buf.data();
    for (int k = own.lo[2]; k < own.hi[2] && n0 > 0; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j) {
            int a = 0, b = n0;
            if (written) {
                const bool in = off[1] + j >= written->lo[1] && off[1] + j < written->hi[1] &&
                                off[2] + k >= written->lo[2] && off[2] + k < written->hi[2];
                a = in ? std::clamp(written->lo[0] - off[0] - own.lo[0], 0, n0) : 0;
                b = in ? std::clamp(written->hi[0] - off[0] - own.lo[0], 0, n0) : 0;
            }
            if (a < b)
                std::copy(from + a, from + b, f.data().data() + f.index(own.lo[0] + a, j, k));
            from += n0;
        }
}

} // namespace efsi

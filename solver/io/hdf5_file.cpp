#include "io/hdf5_file.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace efsi {

bool hdf5_state_broken = false;

namespace {
/// Writes the scalar attribute `name` of HDF5 type `type` on `owner` (a file, group or
/// dataset); the HDF5 status of the write, negative when any call failed.
herr_t write_scalar_attribute(hid_t owner, const char* name, hid_t type, const void* value) {
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = owner >= 0 ? H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT) : -1;
    const herr_t w = attr >= 0 ? H5Awrite(attr, type, value) : -1;
    if (attr >= 0) H5Aclose(attr);
    H5Sclose(space);
    return w;
}

/// How a dataset is laid out in the file.
enum class Storage {
    Contiguous, ///< zeros written at allocation, then the values
    Chunked,    ///< deflated chunks, zero the fill value
};

/// Dataset creation properties for `storage`. Parallel HDF5 leaves regions that no rank
/// writes undefined, so every dataset gets zeros written at allocation; for a dataset every
/// point of which is written this costs less than it saves (with no fill at all, the 128^3
/// Taylor-Green checkpoint took 0.46-0.63 s against 0.27-0.31 s, session 50). A dataset
/// written in part (a body's fields in a snapshot, on the whole grid) is stored in chunks of
/// `chunk` points, deflated (level 1): a chunk of zeros takes a few bytes, so the file holds
/// the patches, not (number of bodies) x (grid). HDF5 1.10 then reads, merges and deflates
/// again every chunk a patch covers in part; the checkpoint, which also reads its file back,
/// stores a body's fields on its patch box instead (write_block's `box`).
class Creation {
  public:
    Creation(hid_t type, Storage storage, int rank, const hsize_t* chunk)
        : plist_(H5Pcreate(H5P_DATASET_CREATE)) {
        const double zero_d = 0;
        const std::int64_t zero_i = 0;
        H5Pset_fill_value(plist_, type,
                          type == H5T_NATIVE_DOUBLE ? static_cast<const void*>(&zero_d)
                                                    : static_cast<const void*>(&zero_i));
        if (storage == Storage::Chunked) {
            H5Pset_chunk(plist_, rank, chunk);
            H5Pset_deflate(plist_, 1);
        }
        H5Pset_fill_time(plist_, H5D_FILL_TIME_ALLOC);
        H5Pset_alloc_time(plist_, H5D_ALLOC_TIME_EARLY);
    }
    ~Creation() { H5Pclose(plist_); }
    Creation(const Creation&) = delete;
    Creation& operator=(const Creation&) = delete;
    operator hid_t() const { return plist_; }

  private:
    hid_t plist_;
};

/// A fixed-length string type of n bytes (n >= 1).
hid_t string_type(std::size_t n) {
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, std::max<std::size_t>(1, n));
    H5Tset_strpad(t, H5T_STR_NULLPAD);
    return t;
}

/// Rank 0 reserves `bytes` for a new file (posix_fallocate): on a full disk or under a
/// file-size limit the write is refused before HDF5 starts it (HDF5 cannot close a file
/// whose metadata it failed to write). Returns 0 or the errno.
int reserve(const std::filesystem::path& path, std::uint64_t bytes) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return errno;
    const int rc = bytes > 0 ? posix_fallocate(fd, 0, off_t(bytes)) : 0;
    ::close(fd);
    if (rc != 0) ::unlink(path.c_str());
    return rc;
}

int saved_errno(bool ok) {
    return ok ? 0 : (errno != 0 ? errno : -1);
}
} // namespace

Hdf5File::Hdf5File(const std::filesystem::path& path, Mode mode, const Decomposition& dec,
                   std::uint64_t expected_bytes)
    : path_(path), dec_(dec) {
    // Failures are reported by the checks below, once, with the file named; HDF5's own
    // error stacks (thousands of lines on a full disk) are not printed.
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    if (mode == Mode::Create && expected_bytes > 0) {
        int err = dec.rank() == 0 ? reserve(path, expected_bytes + expected_bytes / 50 + 65536) : 0;
        MPI_Bcast(&err, 1, MPI_INT, 0, dec.comm());
        if (err != 0)
            throw IoError(fmt::format("{}: no room for its {:.3g} MB ({})", path.string(),
                                      double(expected_bytes) / 1e6, std::strerror(err)));
    }
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_fapl_mpio(fapl, dec.comm(), MPI_INFO_NULL);
    errno = 0;
    if (mode == Mode::Create)
        file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    else
        file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
    H5Pclose(fapl);
    xfer_ = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(xfer_, H5FD_MPIO_COLLECTIVE);
    try {
        agree(file_ >= 0, mode == Mode::Create ? "creating the file"
                                               : "opening the file (not a readable HDF5 "
                                                 "file, or truncated)");
    } catch (...) {
        H5Pclose(xfer_);
        xfer_ = -1;
        if (file_ >= 0) H5Fclose(file_);
        file_ = -1;
        throw;
    }
}

Hdf5File::~Hdf5File() {
    if (xfer_ >= 0) H5Pclose(xfer_);
    if (file_ >= 0) {
        // After a failed write some objects may still be open: close them first, so that
        // the file itself can close (HDF5 would otherwise try again at MPI_Finalize).
        const ssize_t n = H5Fget_obj_count(file_, H5F_OBJ_ALL & ~H5F_OBJ_FILE);
        if (n > 0) {
            std::vector<hid_t> ids(static_cast<std::size_t>(n));
            H5Fget_obj_ids(file_, H5F_OBJ_ALL & ~H5F_OBJ_FILE, std::size_t(n), ids.data());
            for (hid_t id : ids)
                while (H5Iis_valid(id) > 0 && H5Idec_ref(id) > 0) {
                }
        }
        if (H5Fclose(file_) < 0) hdf5_state_broken = true;
    }
}

void Hdf5File::agree(bool ok, const std::string& what) const {
    int local = saved_errno(ok), worst = 0, any = local != 0 ? 1 : 0, failed = 0;
    MPI_Allreduce(&any, &failed, 1, MPI_INT, MPI_MAX, dec_.comm());
    if (!failed) return;
    MPI_Allreduce(&local, &worst, 1, MPI_INT, MPI_MAX, dec_.comm());
    throw IoError(fmt::format("{}: {} failed{}", path_.string(), what,
                              worst > 0 ? std::string(" (") + std::strerror(worst) + ")" : ""));
}

void Hdf5File::close() {
    if (file_ < 0) return;
    errno = 0;
    const herr_t flushed = H5Fflush(file_, H5F_SCOPE_GLOBAL);
    const int e = errno;
    const herr_t closed = H5Fclose(file_);
    file_ = -1;
    errno = e;
    agree(flushed >= 0 && closed >= 0, "closing the file (writing its last blocks)");
}

void Hdf5File::write_flat_any(const std::string& name, const Int3& n, const Int3& o, const Int3& c,
                              int ncomp, const void* values, hid_t type) {
    const hsize_t total = hsize_t(n[0]) * n[1] * n[2];
    const int rank = ncomp > 1 ? 2 : 1;
    const hsize_t dims[2] = {total, hsize_t(ncomp)};
    hid_t fspace = H5Screate_simple(rank, dims, nullptr);
    const std::int64_t written = std::int64_t(c[0]) * c[1] * c[2];
    const bool whole = dec_.sum(written) >= std::int64_t(total);
    // Chunks of 4096 points with all their components (at most the dataset).
    const hsize_t chunk[2] = {std::min<hsize_t>(total, 4096), hsize_t(ncomp)};
    const Creation dcpl(type, whole ? Storage::Contiguous : Storage::Chunked, rank, chunk);
    errno = 0;
    hid_t dset = H5Dcreate2(file_, name.c_str(), type, fspace, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    try {
        agree(dset >= 0, fmt::format("creating dataset '{}'", name));
    } catch (...) {
        if (dset >= 0) H5Dclose(dset);
        H5Sclose(fspace);
        throw;
    }
    // The block is one strided hyperslab per z plane: rows of c[0] points, stride n[0].
    H5Sselect_none(fspace);
    for (int k = 0; k < c[2]; ++k) {
        const hsize_t start[2] = {(hsize_t(o[2] + k) * n[1] + o[1]) * n[0] + o[0], 0};
        const hsize_t stride[2] = {hsize_t(n[0]), 1};
        const hsize_t count[2] = {hsize_t(c[1]), 1};
        const hsize_t block[2] = {hsize_t(c[0]), hsize_t(ncomp)};
        H5Sselect_hyperslab(fspace, H5S_SELECT_OR, start, stride, count, block);
    }
    const hsize_t local = hsize_t(c[0]) * c[1] * c[2] * ncomp;
    hid_t mspace = H5Screate_simple(1, &local, nullptr);
    errno = 0;
    const herr_t w = H5Dwrite(dset, type, mspace, fspace, xfer_, values);
    const int e = errno;
    H5Sclose(mspace);
    H5Sclose(fspace);
    const herr_t cl = H5Dclose(dset);
    errno = e;
    agree(w >= 0 && cl >= 0, fmt::format("writing dataset '{}'", name));
}

void Hdf5File::write_flat(const std::string& name, const Int3& n, const Int3& o, const Int3& c,
                          int ncomp, const std::vector<double>& values) {
    write_flat_any(name, n, o, c, ncomp, values.data(), H5T_NATIVE_DOUBLE);
}

void Hdf5File::write_flat(const std::string& name, const Int3& n, const Int3& o, const Int3& c,
                          int ncomp, const std::vector<std::int64_t>& values) {
    write_flat_any(name, n, o, c, ncomp, values.data(), H5T_NATIVE_INT64);
}

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
    int e = errno;
    const std::uint64_t sum = block_checksum(dec_, f, buf);
    const herr_t wa = write_scalar_attribute(dset, "checksum", H5T_NATIVE_UINT64, &sum);
    if (e == 0) e = errno;
    const herr_t cl = H5Dclose(dset);
    errno = e;
    agree(w >= 0 && wa >= 0 && cl >= 0, fmt::format("writing dataset '{}'", name));
    return sum;
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
            fits = stored.lo[d] >= 0 && stored.hi[d] <= g.cells[d];
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

std::uint64_t Hdf5File::write_array_any(const std::string& name, std::size_t n, const void* values,
                                        hid_t type) {
    const hsize_t dims = n;
    hid_t fspace = H5Screate_simple(1, &dims, nullptr);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    errno = 0;
    hid_t dset = H5Dcreate2(file_, name.c_str(), type, fspace, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Pclose(lcpl);
    try {
        agree(dset >= 0, fmt::format("creating dataset '{}'", name));
    } catch (...) {
        if (dset >= 0) H5Dclose(dset);
        H5Sclose(fspace);
        throw;
    }
    // Every rank holds the same values: rank 0 writes them all, the others nothing (the
    // transfer is collective).
    const bool writer = dec_.rank() == 0 && n > 0;
    if (!writer) H5Sselect_none(fspace);
    const hsize_t local = writer ? n : 0;
    hid_t mspace = H5Screate_simple(1, &local, nullptr);
    errno = 0;
    const herr_t w = n > 0 ? H5Dwrite(dset, type, mspace, fspace, xfer_, values) : 0;
    int e = errno;
    H5Sclose(mspace);
    H5Sclose(fspace);
    const std::uint64_t sum = array_checksum(values, n);
    const herr_t wa = write_scalar_attribute(dset, "checksum", H5T_NATIVE_UINT64, &sum);
    if (e == 0) e = errno;
    const herr_t cl = H5Dclose(dset);
    errno = e;
    agree(w >= 0 && wa >= 0 && cl >= 0, fmt::format("writing dataset '{}'", name));
    return sum;
}

std::uint64_t Hdf5File::write_array(const std::string& name, const std::vector<double>& values) {
    return write_array_any(name, values.size(), values.data(), H5T_NATIVE_DOUBLE);
}

std::uint64_t Hdf5File::write_array(const std::string& name,
                                    const std::vector<std::uint64_t>& values) {
    return write_array_any(name, values.size(), values.data(), H5T_NATIVE_UINT64);
}

std::vector<std::uint64_t> Hdf5File::read_array_any(const std::string& name, hid_t type) const {
    const bool integer = type != H5T_NATIVE_DOUBLE;
    if (!has(name)) throw InputError(fmt::format("{}: has no dataset '{}'", path_.string(), name));
    hid_t dset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
    hid_t space = dset >= 0 ? H5Dget_space(dset) : -1;
    hid_t stored = dset >= 0 ? H5Dget_type(dset) : -1;
    hsize_t n = 0;
    const bool shape_ok = space >= 0 && H5Sget_simple_extent_ndims(space) == 1 &&
                          H5Sget_simple_extent_dims(space, &n, nullptr) == 1;
    const bool type_ok = stored >= 0 && H5Tget_size(stored) == 8 &&
                         H5Tget_class(stored) == (integer ? H5T_INTEGER : H5T_FLOAT);
    if (stored >= 0) H5Tclose(stored);
    if (space >= 0) H5Sclose(space);
    std::vector<std::uint64_t> words(shape_ok && type_ok ? std::size_t(n) : 0);
    const herr_t r = shape_ok && type_ok && n > 0
                         ? H5Dread(dset, type, H5S_ALL, H5S_ALL, xfer_, words.data())
                         : 0;
    if (dset >= 0) H5Dclose(dset);
    if (!shape_ok || !type_ok)
        throw InputError(fmt::format("{}: dataset '{}' is not a 1D array of 8-byte {}",
                                     path_.string(), name, integer ? "integers" : "reals"));
    agree(r >= 0, fmt::format("reading dataset '{}'", name));
    const std::uint64_t want = stored_checksum(name);
    if (want == 0)
        throw InputError(fmt::format("{}: dataset '{}' has no checksum", path_.string(), name));
    const std::uint64_t sum = array_checksum(words.data(), words.size());
    if (sum != want)
        throw InputError(fmt::format("{}: dataset '{}' does not match its checksum (stored "
                                     "{:016x}, data {:016x}): the file is corrupted",
                                     path_.string(), name, want, sum));
    return words;
}

std::vector<double> Hdf5File::read_real_array(const std::string& name) const {
    const std::vector<std::uint64_t> words = read_array_any(name, H5T_NATIVE_DOUBLE);
    std::vector<double> out(words.size());
    if (!words.empty()) std::memcpy(out.data(), words.data(), 8 * words.size());
    return out;
}

std::vector<std::uint64_t> Hdf5File::read_integer_array(const std::string& name) const {
    return read_array_any(name, H5T_NATIVE_UINT64);
}

std::vector<std::string> Hdf5File::members(const std::string& group, bool groups) const {
    std::vector<std::string> out;
    const std::string where = group.empty() ? "/" : group;
    if (H5Lexists(file_, where.c_str(), H5P_DEFAULT) <= 0 && where != "/") return out;
    hid_t g = H5Gopen2(file_, where.c_str(), H5P_DEFAULT);
    if (g < 0) return out;
    H5G_info_t info;
    if (H5Gget_info(g, &info) >= 0)
        for (hsize_t i = 0; i < info.nlinks; ++i) {
            const ssize_t len =
                H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
            if (len < 0) continue;
            std::string name(std::size_t(len) + 1, '\0');
            H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                               H5P_DEFAULT);
            name.resize(std::size_t(len));
            hid_t o = H5Oopen(g, name.c_str(), H5P_DEFAULT);
            if (o < 0) continue;
            const H5I_type_t t = H5Iget_type(o);
            H5Oclose(o);
            if ((groups && t == H5I_GROUP) || (!groups && t == H5I_DATASET)) out.push_back(name);
        }
    H5Gclose(g);
    std::sort(out.begin(), out.end());
    return out;
}

bool Hdf5File::is_integer(const std::string& name) const {
    if (!has(name)) return false;
    hid_t dset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
    if (dset < 0) return false;
    hid_t type = H5Dget_type(dset);
    const bool integer = type >= 0 && H5Tget_class(type) == H5T_INTEGER;
    if (type >= 0) H5Tclose(type);
    H5Dclose(dset);
    return integer;
}

bool Hdf5File::has(const std::string& name) const {
    return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0;
}

bool Hdf5File::has_attribute(const std::string& name) const {
    return H5Aexists(file_, name.c_str()) > 0;
}

void Hdf5File::write_attribute(const std::string& name, double value) {
    errno = 0;
    const herr_t w = write_scalar_attribute(file_, name.c_str(), H5T_NATIVE_DOUBLE, &value);
    agree(w >= 0, fmt::format("writing attribute '{}'", name));
}

void Hdf5File::write_integer_attribute(const std::string& name, std::int64_t value) {
    errno = 0;
    const herr_t w = write_scalar_attribute(file_, name.c_str(), H5T_NATIVE_INT64, &value);
    agree(w >= 0, fmt::format("writing attribute '{}'", name));
}

namespace {
/// The object a string attribute goes on: the root, or group `group` (created if absent).
hid_t attribute_owner(hid_t file, const std::string& group) {
    if (group.empty()) return H5Oopen(file, "/", H5P_DEFAULT);
    if (H5Lexists(file, group.c_str(), H5P_DEFAULT) > 0)
        return H5Gopen2(file, group.c_str(), H5P_DEFAULT);
    return H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
}
} // namespace

void Hdf5File::write_string_attribute(const std::string& name, const std::string& value,
                                      const std::string& group) {
    hid_t type = string_type(value.size());
    errno = 0;
    hid_t owner = attribute_owner(file_, group);
    std::string padded = value;
    padded.resize(std::max<std::size_t>(1, value.size()), '\0');
    const herr_t w = write_scalar_attribute(owner, name.c_str(), type, padded.data());
    if (owner >= 0) H5Oclose(owner);
    H5Tclose(type);
    agree(w >= 0, fmt::format("writing attribute '{}'", name));
}

void Hdf5File::write_dataset_attributes(
    const std::string& dataset, const std::vector<std::pair<std::string, std::string>>& attrs) {
    errno = 0;
    hid_t dset = H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT);
    bool ok = dset >= 0;
    for (const auto& [key, value] : attrs) {
        if (!ok) break;
        hid_t type = string_type(value.size());
        std::string padded = value;
        padded.resize(std::max<std::size_t>(1, value.size()), '\0');
        ok = write_scalar_attribute(dset, key.c_str(), type, padded.data()) >= 0;
        H5Tclose(type);
    }
    if (dset >= 0) H5Dclose(dset);
    agree(ok, fmt::format("writing the attributes of dataset '{}'", dataset));
}

bool Hdf5File::has_string_attribute(const std::string& name, const std::string& group) const {
    if (!group.empty() && H5Lexists(file_, group.c_str(), H5P_DEFAULT) <= 0) return false;
    return H5Aexists_by_name(file_, group.empty() ? "/" : group.c_str(), name.c_str(),
                             H5P_DEFAULT) > 0;
}

std::string Hdf5File::read_string_attribute(const std::string& name,
                                            const std::string& group) const {
    if (!has_string_attribute(name, group))
        throw InputError(fmt::format("{}: has no attribute '{}'", path_.string(), name));
    hid_t attr = H5Aopen_by_name(file_, group.empty() ? "/" : group.c_str(), name.c_str(),
                                 H5P_DEFAULT, H5P_DEFAULT);
    hid_t type = H5Aget_type(attr);
    std::string value;
    if (H5Tget_class(type) == H5T_STRING && !H5Tis_variable_str(type)) {
        value.assign(H5Tget_size(type), '\0');
        hid_t mem = string_type(value.size());
        if (H5Aread(attr, mem, value.data()) < 0) value.clear();
        H5Tclose(mem);
    }
    H5Tclose(type);
    H5Aclose(attr);
    value.erase(std::find(value.begin(), value.end(), '\0'), value.end());
    return value;
}

double Hdf5File::read_attribute(const std::string& name) const {
    if (H5Aexists(file_, name.c_str()) <= 0)
        throw InputError(fmt::format("{}: has no attribute '{}'", path_.string(), name));
    double value = 0;
    hid_t attr = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
    const herr_t r = H5Aread(attr, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(attr);
    if (r < 0)
        throw InputError(fmt::format("{}: attribute '{}' cannot be read", path_.string(), name));
    return value;
}

} // namespace efsi

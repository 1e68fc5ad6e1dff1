#include "io/hdf5_file.hpp"

#include "io/hdf5_detail.hpp"

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

using hdf5_detail::Creation;
using hdf5_detail::Storage;
using hdf5_detail::write_scalar_attribute;

namespace {
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
    return seal(dset, w, e, array_checksum(values, n), name);
}

std::uint64_t Hdf5File::seal(hid_t dset, herr_t written, int err, std::uint64_t sum,
                             const std::string& name) {
    const herr_t wa = write_scalar_attribute(dset, "checksum", H5T_NATIVE_UINT64, &sum);
    if (err == 0) err = errno;
    const herr_t cl = H5Dclose(dset);
    errno = err;
    agree(written >= 0 && wa >= 0 && cl >= 0, fmt::format("writing dataset '{}'", name));
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

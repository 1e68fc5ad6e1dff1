#include "io/hdf5_file.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace efsi {

namespace {
/// Dataset creation properties that write zeros where no rank writes (parallel HDF5 leaves
/// such regions undefined otherwise): a body's fields cover only its patch.
class ZeroFill {
  public:
    explicit ZeroFill(hid_t type) : plist_(H5Pcreate(H5P_DATASET_CREATE)) {
        const double zero_d = 0;
        const std::int64_t zero_i = 0;
        H5Pset_fill_value(plist_, type,
                          type == H5T_NATIVE_DOUBLE ? static_cast<const void*>(&zero_d)
                                                    : static_cast<const void*>(&zero_i));
        H5Pset_fill_time(plist_, H5D_FILL_TIME_ALLOC);
        H5Pset_alloc_time(plist_, H5D_ALLOC_TIME_EARLY);
    }
    ~ZeroFill() { H5Pclose(plist_); }
    operator hid_t() const { return plist_; }

  private:
    hid_t plist_;
};
ZeroFill zero_fill(hid_t type) {
    return ZeroFill(type);
}
} // namespace

Hdf5File::Hdf5File(const std::filesystem::path& path, Mode mode, const Decomposition& dec)
    : dec_(dec) {
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_fapl_mpio(fapl, dec.comm(), MPI_INFO_NULL);
    if (mode == Mode::Create)
        file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    else
        file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
    H5Pclose(fapl);
    if (file_ < 0)
        throw RunError(fmt::format("{}: cannot {} HDF5 file", path.string(),
                                   mode == Mode::Create ? "create" : "open"));
    xfer_ = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(xfer_, H5FD_MPIO_COLLECTIVE);
}

Hdf5File::~Hdf5File() {
    if (xfer_ >= 0) H5Pclose(xfer_);
    if (file_ >= 0) H5Fclose(file_);
}

void Hdf5File::write_flat_any(const std::string& name, const Int3& n, const Int3& o, const Int3& c,
                              int ncomp, const void* values, hid_t type) {
    const hsize_t total = hsize_t(n[0]) * n[1] * n[2];
    const int rank = ncomp > 1 ? 2 : 1;
    const hsize_t dims[2] = {total, hsize_t(ncomp)};
    hid_t fspace = H5Screate_simple(rank, dims, nullptr);
    hid_t dset =
        H5Dcreate2(file_, name.c_str(), type, fspace, H5P_DEFAULT, zero_fill(type), H5P_DEFAULT);
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
    H5Dwrite(dset, type, mspace, fspace, xfer_, values);
    H5Sclose(mspace);
    H5Sclose(fspace);
    H5Dclose(dset);
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
/// Selection of a field's owned box (whole block or patch) in the global [nz][ny][nx] array.
struct BoxSpace {
    hid_t fspace, mspace;
    BoxSpace(const Decomposition& dec, const Field& f) {
        const GlobalGrid& g = dec.grid();
        const LocalBlock& b = dec.block();
        const Int3 o = f.begin(), n = f.cells();
        const hsize_t dims[3] = {hsize_t(g.cells[2]), hsize_t(g.cells[1]), hsize_t(g.cells[0])};
        const hsize_t start[3] = {hsize_t(b.offset[2] + o[2]), hsize_t(b.offset[1] + o[1]),
                                  hsize_t(b.offset[0] + o[0])};
        const hsize_t count[3] = {hsize_t(n[2]), hsize_t(n[1]), hsize_t(n[0])};
        fspace = H5Screate_simple(3, dims, nullptr);
        const bool empty = n[0] <= 0 || n[1] <= 0 || n[2] <= 0;
        if (empty)
            H5Sselect_none(fspace);
        else
            H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
        const hsize_t local = empty ? 0 : count[0] * count[1] * count[2];
        mspace = H5Screate_simple(1, &local, nullptr);
    }
    ~BoxSpace() {
        H5Sclose(mspace);
        H5Sclose(fspace);
    }
};
} // namespace

void Hdf5File::write_block(const std::string& name, const Field& f) {
    BoxSpace s(dec_, f);
    std::vector<double> buf;
    buf.reserve(std::size_t(std::max<std::int64_t>(0, f.owned().count())));
    for_each_in(f.owned(), [&](int i, int j, int k) { buf.push_back(f(i, j, k)); });
    hid_t dset = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, s.fspace, H5P_DEFAULT,
                            zero_fill(H5T_NATIVE_DOUBLE), H5P_DEFAULT);
    H5Dwrite(dset, H5T_NATIVE_DOUBLE, s.mspace, s.fspace, xfer_, buf.data());
    H5Dclose(dset);
}

void Hdf5File::read_block(const std::string& name, Field& f) {
    if (!has(name)) throw RunError(fmt::format("checkpoint has no dataset '{}'", name));
    hid_t dset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
    hid_t space = H5Dget_space(dset);
    hsize_t dims[3] = {0, 0, 0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    const GlobalGrid& g = dec_.grid();
    if (dims[0] != hsize_t(g.cells[2]) || dims[1] != hsize_t(g.cells[1]) ||
        dims[2] != hsize_t(g.cells[0])) {
        H5Dclose(dset);
        throw InputError(fmt::format("dataset '{}' is {}x{}x{} but the case grid is {}x{}x{}", name,
                                     dims[2], dims[1], dims[0], g.cells[0], g.cells[1],
                                     g.cells[2]));
    }
    BoxSpace s(dec_, f);
    std::vector<double> buf(std::size_t(std::max<std::int64_t>(0, f.owned().count())));
    H5Dread(dset, H5T_NATIVE_DOUBLE, s.mspace, s.fspace, xfer_, buf.data());
    H5Dclose(dset);
    std::size_t c = 0;
    for_each_in(f.owned(), [&](int i, int j, int k) { f(i, j, k) = buf[c++]; });
}

bool Hdf5File::has(const std::string& name) const {
    return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0;
}

void Hdf5File::write_attribute(const std::string& name, double value) {
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr =
        H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(attr);
    H5Sclose(space);
}

double Hdf5File::read_attribute(const std::string& name) const {
    if (H5Aexists(file_, name.c_str()) <= 0)
        throw RunError(fmt::format("checkpoint has no attribute '{}'", name));
    double value = 0;
    hid_t attr = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
    H5Aread(attr, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(attr);
    return value;
}

} // namespace efsi

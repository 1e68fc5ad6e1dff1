// A parallel HDF5 file (MPI-IO, collective transfers) and block-wise dataset access:
// each rank writes or reads the part of a global array that its block owns.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

#include <hdf5.h>

#include <filesystem>
#include <string>
#include <vector>

namespace efsi {

class Hdf5File {
  public:
    enum class Mode { Create, Read };
    Hdf5File(const std::filesystem::path& path, Mode mode, const Decomposition& dec);
    ~Hdf5File();
    Hdf5File(const Hdf5File&) = delete;
    Hdf5File& operator=(const Hdf5File&) = delete;

    /// Flat array of `global_points` (x fastest) with `ncomp` values per point, of which
    /// this rank owns the box [offset, offset + count). `values` is in the same order.
    void write_flat(const std::string& name, const Int3& global_points, const Int3& offset,
                    const Int3& count, int ncomp, const std::vector<double>& values);
    void write_flat(const std::string& name, const Int3& global_points, const Int3& offset,
                    const Int3& count, int ncomp, const std::vector<std::int64_t>& values);
    /// The owned values of a field (its block, or its patch) into a global 3D dataset
    /// [nz][ny][nx]; points outside every rank's box read back as 0 (the fill value).
    void write_block(const std::string& name, const Field& f);
    void read_block(const std::string& name, Field& f);
    bool has(const std::string& name) const;

    void write_attribute(const std::string& name, double value);
    double read_attribute(const std::string& name) const;

  private:
    void write_flat_any(const std::string& name, const Int3& global_points, const Int3& offset,
                        const Int3& count, int ncomp, const void* values, hid_t type);
    hid_t file_ = -1;
    hid_t xfer_ = -1;
    const Decomposition& dec_;
};

} // namespace efsi

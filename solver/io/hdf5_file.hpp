// A parallel HDF5 file (MPI-IO, collective transfers) and block-wise dataset access:
// each rank writes or reads the part of a global array that its block owns.
//
// Every call that writes or reads is checked, and its outcome agreed on by all ranks (one
// small allreduce), so that a failure on any rank (a full disk, a file-size limit, a
// truncated file) throws the same IoError on every rank instead of a hang, an abort, or a
// silently incomplete file. HDF5's own error printing is turned off.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace efsi {

/// Set when HDF5 failed to close a file after a write error: its library state is then
/// unsafe to tear down at MPI_Finalize (main exits without it).
extern bool hdf5_state_broken;

class Hdf5File {
  public:
    enum class Mode { Create, Read };
    /// With `expected_bytes` (Create), rank 0 first reserves that much room for the file
    /// (plus 2% and 64 kB of metadata): on a full disk or under a file-size limit the
    /// write fails cleanly with IoError before HDF5 starts.
    Hdf5File(const std::filesystem::path& path, Mode mode, const Decomposition& dec,
             std::uint64_t expected_bytes = 0);
    ~Hdf5File();
    Hdf5File(const Hdf5File&) = delete;
    Hdf5File& operator=(const Hdf5File&) = delete;

    /// Flat array of `global_points` (x fastest) with `ncomp` values per point, of which
    /// this rank owns the box [offset, offset + count). `values` is in the same order.
    void write_flat(const std::string& name, const Int3& global_points, const Int3& offset,
                    const Int3& count, int ncomp, const std::vector<double>& values);
    void write_flat(const std::string& name, const Int3& global_points, const Int3& offset,
                    const Int3& count, int ncomp, const std::vector<std::int64_t>& values);
    /// The owned values of a field (its block, or its patch) into a 3D dataset [nz][ny][nx]
    /// that holds the whole grid, or with `box` (global cell indices, containing every
    /// rank's part) only that box, whose start (x, y, z) goes into the attribute "box_lo";
    /// points outside every rank's part read back as 0 (the fill value). Stores the checksum
    /// of the values written (block_checksum) as the dataset's attribute "checksum" and
    /// returns it.
    std::uint64_t write_block(const std::string& name, const Field& f, const Box* box = nullptr);
    /// Read a field's owned values; when the dataset has a "checksum" attribute (or
    /// `require_checksum`), the values read must match it, else InputError. `written` (global
    /// cell indices, may be null): the box the dataset was written from, the only points the
    /// checksum covers (a patch read on another rank layout may be wider than the one written).
    void read_block(const std::string& name, Field& f, bool require_checksum = false,
                    const Box* written = nullptr);
    /// Read back the owned values of `f`'s layout from dataset `name` and return their
    /// checksum (collective), without touching `f`.
    std::uint64_t read_checksum(const std::string& name, const Field& f);
    /// The checksum stored on a dataset (0 when it has none).
    std::uint64_t stored_checksum(const std::string& name) const;
    bool has(const std::string& name) const;

    /// A 1D dataset `name` ("group/array": the group is created when absent) of values that
    /// every rank holds alike: rank 0 writes them. Stores array_checksum of the values as
    /// the dataset's attribute "checksum" and returns it.
    std::uint64_t write_array(const std::string& name, const std::vector<double>& values);
    std::uint64_t write_array(const std::string& name, const std::vector<std::uint64_t>& values);
    /// Every rank reads the whole 1D dataset `name`, which must match its checksum
    /// (InputError naming the dataset otherwise, or when it is not a 1D array of that type).
    std::vector<double> read_real_array(const std::string& name) const;
    std::vector<std::uint64_t> read_integer_array(const std::string& name) const;
    /// Checksum of an array of n 8-byte values: a 64-bit mix of (index, value bits) summed
    /// over the values, and of n. The same on every rank.
    static std::uint64_t array_checksum(const void* values, std::size_t n);
    /// The names directly under group `group` ("" for the root), sorted: its groups when
    /// `groups`, else its datasets.
    std::vector<std::string> members(const std::string& group, bool groups) const;
    /// Is dataset `name` of an integer type?
    bool is_integer(const std::string& name) const;

    void write_attribute(const std::string& name, double value);
    double read_attribute(const std::string& name) const;
    /// String attributes on the root, or on group `group` (created when absent).
    void write_string_attribute(const std::string& name, const std::string& value,
                                const std::string& group = "");
    std::string read_string_attribute(const std::string& name, const std::string& group = "") const;
    bool has_string_attribute(const std::string& name, const std::string& group = "") const;
    bool has_attribute(const std::string& name) const;
    /// String attributes (units, centring, ...) on an existing dataset.
    void write_dataset_attributes(const std::string& dataset,
                                  const std::vector<std::pair<std::string, std::string>>& attrs);
    void write_integer_attribute(const std::string& name, std::int64_t value);

    /// Close the file, checking that everything reached it (collective). The destructor
    /// closes without checking.
    void close();
    const std::filesystem::path& path() const { return path_; }

    /// Rank-count independent checksum of a field's owned values: the sum over points of a
    /// 64-bit mix of (global index, value bits), summed over ranks. A flipped bit or a
    /// changed value changes it; so does a zeroed dataset. `only` (global cell indices, may be
    /// null): the points outside it are left out.
    static std::uint64_t block_checksum(const Decomposition& dec, const Field& f,
                                        const std::vector<double>& owned_values,
                                        const Box* only = nullptr);

  private:
    void write_flat_any(const std::string& name, const Int3& global_points, const Int3& offset,
                        const Int3& count, int ncomp, const void* values, hid_t type);
    std::uint64_t write_array_any(const std::string& name, std::size_t n, const void* values,
                                  hid_t type);
    /// The values of 1D dataset `name` as 8-byte words, read as `type` (checked: InputError).
    std::vector<std::uint64_t> read_array_any(const std::string& name, hid_t type) const;
    /// All ranks agree on the outcome of `what`: throws IoError everywhere if it failed
    /// anywhere (with the errno of a failing rank when it is known).
    void agree(bool ok, const std::string& what) const;
    /// Finish writing dataset `dset` (`written`: the status of its H5Dwrite, errno saved
    /// right after it in `err`): store `sum` as its "checksum" attribute, close it, and
    /// agree over the ranks that all of it succeeded. Returns `sum`.
    std::uint64_t seal(hid_t dset, herr_t written, int err, std::uint64_t sum,
                       const std::string& name);
    std::filesystem::path path_;
    hid_t file_ = -1;
    hid_t xfer_ = -1;
    const Decomposition& dec_;
    /// The owned values of the dataset being written or read, kept between datasets so a
    /// checkpoint of many fields allocates (and the kernel zeroes) one buffer, not one each.
    std::vector<double> scratch_;
};

} // namespace efsi

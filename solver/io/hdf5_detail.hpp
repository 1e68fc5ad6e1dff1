// Internals shared by the files of Hdf5File (hdf5_file.cpp, hdf5_block.cpp): a scalar
// attribute's write and the dataset creation properties. Not part of the interface.
#pragma once

#include <hdf5.h>

#include <cstdint>

namespace efsi::hdf5_detail {

/// Writes the scalar attribute `name` of HDF5 type `type` on `owner` (a file, group or
/// dataset); the HDF5 status of the write, negative when any call failed.
inline herr_t write_scalar_attribute(hid_t owner, const char* name, hid_t type, const void* value) {
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

} // namespace efsi::hdf5_detail

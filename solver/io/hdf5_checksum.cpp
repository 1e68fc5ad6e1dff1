// The checksums of datasets (Hdf5File::block_checksum, Hdf5File::array_checksum): sums of a
// 64-bit mix of (index, value bits), so that they do not depend on the rank count or on the
// order in which the ranks add their parts.
#include "io/hdf5_file.hpp"

#include "core/splitmix64.hpp"

#include <mpi.h>

#include <cstring>

namespace efsi {

std::uint64_t Hdf5File::block_checksum(const Decomposition& dec, const Field& f,
                                       const std::vector<double>& values, const Box* only) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    const Box own = f.owned();
    const int n0 = own.hi[0] - own.lo[0];
    std::uint64_t sum = 0;
    const double* v = values.data();
    // Row by row (x fastest, as the values are stored): the same terms as point by point.
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1] && n0 > 0; ++j) {
            const std::uint64_t row = (std::uint64_t(b.offset[2] + k) * std::uint64_t(g.cells[1]) +
                                       std::uint64_t(b.offset[1] + j)) *
                                          std::uint64_t(g.cells[0]) +
                                      std::uint64_t(b.offset[0] + own.lo[0]);
            const bool row_in =
                !only || (b.offset[1] + j >= only->lo[1] && b.offset[1] + j < only->hi[1] &&
                          b.offset[2] + k >= only->lo[2] && b.offset[2] + k < only->hi[2]);
            for (int i = 0; i < n0 && row_in; ++i) {
                const int gi = b.offset[0] + own.lo[0] + i;
                if (only && (gi < only->lo[0] || gi >= only->hi[0])) continue;
                std::uint64_t bits = 0;
                std::memcpy(&bits, v + i, sizeof bits);
                sum += splitmix64(splitmix64(row + std::uint64_t(i)) ^ bits);
            }
            v += n0;
        }
    std::uint64_t total = 0;
    MPI_Allreduce(&sum, &total, 1, MPI_UINT64_T, MPI_SUM, dec.comm());
    return total;
}

std::uint64_t Hdf5File::array_checksum(const void* values, std::size_t n) {
    std::uint64_t sum = splitmix64(n);
    const auto* b = static_cast<const unsigned char*>(values);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, b + 8 * i, sizeof bits);
        sum += splitmix64(splitmix64(i) ^ bits);
    }
    return sum;
}

} // namespace efsi

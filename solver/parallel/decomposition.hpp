// MPI Cartesian domain decomposition: who owns which block, who the neighbours are,
// halo exchange and global reductions. The only MPI the physics ever sees is through
// this class's methods (sum, max, exchange), never MPI calls of its own.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

#include <mpi.h>

#include <array>
#include <span>
#include <string>
#include <vector>

namespace efsi {

/// MPI datatype of `real`.
inline MPI_Datatype mpi_real() {
    return MPI_DOUBLE;
}

class Decomposition {
  public:
    /// `ranks_per_dim` entries of 0 are chosen by MPI_Dims_create. Throws InputError when
    /// the grid cannot be divided among the ranks (before any field is allocated).
    Decomposition(MPI_Comm world, const GlobalGrid& grid, Bool3 periodic,
                  Int3 ranks_per_dim = {0, 0, 0});
    ~Decomposition();
    Decomposition(const Decomposition&) = delete;
    Decomposition& operator=(const Decomposition&) = delete;

    /// Check that `ranks` can split `grid` (the same rule the constructor applies);
    /// returns the per-direction rank counts or throws InputError.
    static Int3 choose_ranks(int ranks, const GlobalGrid& grid, Int3 requested);

    const GlobalGrid& grid() const { return grid_; }
    const LocalBlock& block() const { return block_; }
    int dim() const { return grid_.dim; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    const Int3& ranks_per_dim() const { return dims_; }
    const Int3& coords() const { return coords_; }
    const Bool3& periodic() const { return periodic_; }
    MPI_Comm comm() const { return cart_; }

    /// True when this rank's block touches the low (side 0) or high (side 1) box face
    /// of direction d.
    bool at_boundary(int d, int side) const {
        return side == 0 ? coords_[d] == 0 : coords_[d] == dims_[d] - 1;
    }

    /// Fill the halo layers of `f` in direction d from the neighbouring ranks (periodic
    /// wrap included). Physical-boundary halos are left for the boundary conditions.
    void exchange(Field& f, int d) const;
    /// The same for a field on a patch (a sub-box of the block): exchange only with the
    /// neighbours asked for. Both sides of a rank boundary must agree (see bodies/patch.hpp).
    void exchange(Field& f, int d, bool with_low, bool with_high) const;
    /// exchange(fields[q], d, with[q][0], with[q][1]) for several fields at once: every
    /// message is posted before any is waited for, so a rank that shares several patches
    /// with its neighbours waits once, not patch by patch. Every rank must list the fields
    /// it shares with a neighbour in the same order (the bodies' order, say).
    void exchange_all(std::span<Field* const> fields, std::span<const std::array<bool, 2>> with,
                      int d) const;
    /// Rank of the neighbour on side 0 (low) or 1 (high) of direction d (or MPI_PROC_NULL).
    int neighbour(int d, int side) const { return neighbour_[d][side]; }
    /// Whether there is a neighbouring rank on that side (a wall has none).
    bool has_neighbour(int d, int side) const { return neighbour_[d][side] != MPI_PROC_NULL; }

    real sum(real x) const;
    real max(real x) const;
    /// Element-wise max over the ranks of a few values, in one reduction.
    std::array<real, 3> max(const std::array<real, 3>& x) const;
    real min(real x) const;
    std::int64_t sum(std::int64_t x) const;
    /// Element-wise sum over the ranks of a whole array, in place (one collective).
    void sum_in_place(std::span<real> values) const;
    /// Element-wise max over the ranks of a whole array, in place (one collective).
    void max_in_place(std::span<real> values) const;
    void barrier() const;
    /// Abort every rank with a message (used when one rank finds a fatal error).
    [[noreturn]] void abort(const std::string& message) const;

  private:
    GlobalGrid grid_;
    LocalBlock block_;
    Bool3 periodic_{};
    Int3 dims_{1, 1, 1};
    Int3 coords_{0, 0, 0};
    std::array<std::array<int, 2>, 3> neighbour_{};
    int rank_ = 0;
    int size_ = 1;
    MPI_Comm cart_ = MPI_COMM_NULL;
    mutable std::vector<std::vector<real>> buffers_; ///< exchange_all's, 4 per field
};

} // namespace efsi

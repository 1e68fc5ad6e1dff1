#include "parallel/decomposition.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <vector>

#include <iostream>

namespace efsi {

Int3 Decomposition::choose_ranks(int ranks, const GlobalGrid& grid, Int3 requested) {
    Int3 dims = requested;
    if (grid.dim == 2) {
        if (dims[2] > 1)
            throw InputError("parallel.ranks: a 2D run cannot be split in z (ranks[2] must be 1)");
        dims[2] = 1;
    }
    int fixed = 1;
    for (int d = 0; d < 3; ++d)
        if (dims[d] > 0) fixed *= dims[d];
    if (ranks % fixed != 0)
        throw InputError(fmt::format("parallel.ranks: {}x{}x{} does not divide {} MPI ranks",
                                     dims[0], dims[1], dims[2], ranks));
    // MPI_Dims_create balances the remaining factors; then check divisibility and, if it
    // fails, try every factorisation before giving up so any workable count is accepted.
    Int3 trial = dims;
    MPI_Dims_create(ranks, 3, trial.data());
    // MPI_Dims_create puts the largest factors first (x); they go to the last directions
    // instead (z in 3D, y in 2D): x rows stay whole (unit-stride sweeps, halos of whole
    // planes or rows), and with ranks only along the last direction the blocks are the FFT
    // solver's slabs, so it skips two of its four all-to-all redistributions
    // (docs/method.md, "Parallel layout").
    {
        std::vector<int> free_values;
        for (int d = 0; d < 3; ++d)
            if (dims[d] <= 0) free_values.push_back(trial[d]);
        std::sort(free_values.begin(), free_values.end());
        std::size_t q = 0;
        for (int d = 0; d < 3; ++d)
            if (dims[d] <= 0) trial[d] = free_values[q++];
    }
    auto divides = [&](const Int3& t) {
        for (int d = 0; d < 3; ++d)
            if (grid.cells[d] % t[d] != 0 || (t[d] > 1 && grid.cells[d] / t[d] < 2))
                return false; // each block needs at least two cells (the halo width)
        return true;
    };
    if (divides(trial)) return trial;
    for (int a = 1; a <= ranks; ++a) {
        if (ranks % a || (dims[0] > 0 && dims[0] != a)) continue;
        for (int b = 1; b <= ranks / a; ++b) {
            if ((ranks / a) % b || (dims[1] > 0 && dims[1] != b)) continue;
            const int c = ranks / a / b;
            if (dims[2] > 0 && dims[2] != c) continue;
            if (grid.dim == 2 && c != 1) continue;
            if (divides({a, b, c})) return {a, b, c};
        }
    }
    throw InputError(fmt::format(
        "grid.cells: {}x{}x{} cells cannot be divided among {} MPI ranks (every direction's "
        "cell count must be a multiple of the ranks along it); choose a rank count whose "
        "factors divide the grid",
        grid.cells[0], grid.cells[1], grid.cells[2], ranks));
}

Decomposition::Decomposition(MPI_Comm world, const GlobalGrid& grid, Bool3 periodic,
                             Int3 ranks_per_dim)
    : grid_(grid), periodic_(periodic) {
    int world_size = 1;
    MPI_Comm_size(world, &world_size);
    dims_ = choose_ranks(world_size, grid, ranks_per_dim);
    // MPI dims are ordered (x, y, z) here; reorder=0 keeps ranks predictable in tests.
    std::array<int, 3> per{int(periodic[0]), int(periodic[1]), int(periodic[2])};
    MPI_Cart_create(world, 3, dims_.data(), per.data(), 0, &cart_);
    MPI_Comm_rank(cart_, &rank_);
    MPI_Comm_size(cart_, &size_);
    MPI_Cart_coords(cart_, rank_, 3, coords_.data());
    for (int d = 0; d < 3; ++d) {
        MPI_Cart_shift(cart_, d, 1, &neighbour_[d][0], &neighbour_[d][1]);
        block_.cells[d] = grid.cells[d] / dims_[d];
        block_.offset[d] = coords_[d] * block_.cells[d];
    }
}

Decomposition::~Decomposition() {
    if (cart_ != MPI_COMM_NULL) MPI_Comm_free(&cart_);
}

void Decomposition::exchange(Field& f, int d) const {
    exchange(f, d, neighbour_[d][0] != MPI_PROC_NULL, neighbour_[d][1] != MPI_PROC_NULL);
}

namespace {

/// The halo slabs of a field along d: g layers spanning the full extent (halos included)
/// of the other directions, so that exchanging x, then y, then z also fills edge and
/// corner halos. Its rows along x are contiguous in memory and copied whole.
struct HaloSlabs {
    Field& f;
    int d, g;
    Int3 lo, hi;
    std::size_t count = 0, row = 0;
    int first = 0, last = 0; ///< owned range [first, last) along d

    HaloSlabs(Field& field, int dir) : f(field), d(dir), g(field.halo()[dir]) {
        const Int3 b = f.begin(), n = f.cells(), h = f.halo();
        // A patch owns at least g layers wherever it exists (bodies/patch.cpp sees to it).
        lo = {b[0] - h[0], b[1] - h[1], b[2] - h[2]};
        hi = {b[0] + n[0] + h[0], b[1] + n[1] + h[1], b[2] + n[2] + h[2]};
        lo[d] = 0;
        hi[d] = g;
        count = std::size_t(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
        row = std::size_t(hi[0] - lo[0]);
        first = b[d];
        last = b[d] + n[d];
    }
    real* row_at(int start, int j, int k) const {
        Int3 p{lo[0], j, k};
        p[d] += start;
        return f.data().data() + f.index(p[0], p[1], p[2]);
    }
    /// Copy the slab starting at layer `start` along d to (pack) or from (unpack) a buffer.
    void transfer(int start, bool pack, real* buffer) const {
        std::size_t c = 0;
        for (int k = lo[2]; k < hi[2]; ++k)
            for (int j = lo[1]; j < hi[1]; ++j, c += row) {
                real* r = row_at(start, j, k);
                if (pack)
                    std::copy(r, r + row, buffer + c);
                else
                    std::copy(buffer + c, buffer + c + row, r);
            }
    }
    /// Periodic with one rank along d: the halos are copies of the own far layers (the
    /// values MPI would carry to this same rank), with no message.
    void wrap() const {
        for (int k = lo[2]; k < hi[2]; ++k)
            for (int j = lo[1]; j < hi[1]; ++j) {
                const real* a = row_at(first, j, k);
                std::copy(a, a + row, row_at(last, j, k));
            }
        for (int k = lo[2]; k < hi[2]; ++k)
            for (int j = lo[1]; j < hi[1]; ++j) {
                const real* a = row_at(last - g, j, k);
                std::copy(a, a + row, row_at(first - g, j, k));
            }
    }
};

} // namespace

void Decomposition::exchange(Field& f, int d, bool with_low, bool with_high) const {
    Field* one[] = {&f};
    const std::array<bool, 2> with[] = {{with_low, with_high}};
    exchange_all(one, with, d);
}

void Decomposition::exchange_all(std::span<Field* const> fields,
                                 std::span<const std::array<bool, 2>> with, int d) const {
    // Every message of every field is posted before any is waited for. Between two ranks
    // the messages of one tag arrive in the order they were sent, and both ranks list the
    // fields they share in the same order (the caller's), so each receive meets its send.
    struct Pending {
        HaloSlabs slabs;
        int low, high;
        std::vector<real>* buf; ///< 4 buffers: down send, up send, from high, from low
    };
    std::vector<Pending> pending;
    pending.reserve(fields.size());
    for (std::size_t q = 0; q < fields.size(); ++q) {
        HaloSlabs slabs(*fields[q], d);
        if (slabs.g == 0) continue;
        const int low = with[q][0] ? neighbour_[d][0] : MPI_PROC_NULL;
        const int high = with[q][1] ? neighbour_[d][1] : MPI_PROC_NULL;
        if (low == rank_ && high == rank_) {
            slabs.wrap();
            continue;
        }
        // No neighbour on either side (a wall, or the edge of a body's patch): nothing to
        // send or receive.
        if (low == MPI_PROC_NULL && high == MPI_PROC_NULL) continue;
        pending.push_back({slabs, low, high, nullptr});
    }
    if (pending.empty()) return;
    if (buffers_.size() < 4 * pending.size()) buffers_.resize(4 * pending.size());
    for (std::size_t q = 0; q < pending.size(); ++q) {
        pending[q].buf = &buffers_[4 * q];
        for (int b = 0; b < 4; ++b)
            pending[q].buf[b].resize(pending[q].slabs.count);
    }
    std::vector<MPI_Request> req;
    req.reserve(4 * pending.size());
    // Both directions at once: my first g layers go down (and my high halo comes from
    // above), my last g layers go up (and my low halo comes from below).
    for (Pending& p : pending) {
        const int count = int(p.slabs.count);
        req.emplace_back();
        MPI_Irecv(p.buf[2].data(), count, mpi_real(), p.high, 10 + d, cart_, &req.back());
        req.emplace_back();
        MPI_Irecv(p.buf[3].data(), count, mpi_real(), p.low, 20 + d, cart_, &req.back());
    }
    for (Pending& p : pending) {
        const int count = int(p.slabs.count);
        if (p.low != MPI_PROC_NULL) p.slabs.transfer(p.slabs.first, true, p.buf[0].data());
        req.emplace_back();
        MPI_Isend(p.buf[0].data(), count, mpi_real(), p.low, 10 + d, cart_, &req.back());
        if (p.high != MPI_PROC_NULL)
            p.slabs.transfer(p.slabs.last - p.slabs.g, true, p.buf[1].data());
        req.emplace_back();
        MPI_Isend(p.buf[1].data(), count, mpi_real(), p.high, 20 + d, cart_, &req.back());
    }
    MPI_Waitall(int(req.size()), req.data(), MPI_STATUSES_IGNORE);
    for (Pending& p : pending) {
        if (p.high != MPI_PROC_NULL) p.slabs.transfer(p.slabs.last, false, p.buf[2].data());
        if (p.low != MPI_PROC_NULL)
            p.slabs.transfer(p.slabs.first - p.slabs.g, false, p.buf[3].data());
    }
}

real Decomposition::sum(real x) const {
    real r = 0;
    MPI_Allreduce(&x, &r, 1, mpi_real(), MPI_SUM, cart_);
    return r;
}
real Decomposition::max(real x) const {
    real r = 0;
    MPI_Allreduce(&x, &r, 1, mpi_real(), MPI_MAX, cart_);
    return r;
}
std::array<real, 3> Decomposition::max(const std::array<real, 3>& x) const {
    std::array<real, 3> r{};
    MPI_Allreduce(x.data(), r.data(), 3, mpi_real(), MPI_MAX, cart_);
    return r;
}
real Decomposition::min(real x) const {
    real r = 0;
    MPI_Allreduce(&x, &r, 1, mpi_real(), MPI_MIN, cart_);
    return r;
}
std::int64_t Decomposition::sum(std::int64_t x) const {
    std::int64_t r = 0;
    MPI_Allreduce(&x, &r, 1, MPI_INT64_T, MPI_SUM, cart_);
    return r;
}
void Decomposition::sum_in_place(std::span<real> values) const {
    if (values.empty()) return;
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), mpi_real(), MPI_SUM,
                  cart_);
}
void Decomposition::max_in_place(std::span<real> values) const {
    if (values.empty()) return;
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), mpi_real(), MPI_MAX,
                  cart_);
}
void Decomposition::barrier() const {
    MPI_Barrier(cart_);
}

void Decomposition::abort(const std::string& message) const {
    std::cerr << message << std::endl;
    MPI_Abort(cart_, 1);
    std::abort();
}

} // namespace efsi

// Moving a global array between two distributions over the ranks: each rank owns one box
// of global indices in the source layout and one in the target layout (empty boxes are
// allowed), stored with x fastest (contiguously, or with padded rows and planes: Storage).
// Every rank sends each other rank the
// intersection of its source box with that rank's target box (one MPI_Alltoallv); the
// part a rank keeps is copied directly. Used by the FFT solver (linear/fft_poisson.cpp)
// to go between the Cartesian blocks of the Decomposition and its slabs.
#pragma once

#include "core/types.hpp"
#include "grid/box.hpp"

#include <mpi.h>

#include <vector>

namespace efsi {

/// How one rank's box is stored: x fastest, rows `row` values apart, planes `plane` values
/// apart (row >= the box's width, plane >= row x its height). Padding the rows and planes
/// keeps the strides of the transforms off powers of two (cache-set conflicts; see
/// linear/fft_poisson.cpp). `dense(box)`: no padding.
struct Storage {
    std::ptrdiff_t row = 0, plane = 0;
    static Storage dense(const Box& b) {
        const Int3 n = b.size();
        return {n[0], std::ptrdiff_t(n[0]) * n[1]};
    }
    std::ptrdiff_t index(const Box& b, int i, int j, int k) const {
        return std::ptrdiff_t(i - b.lo[0]) + row * (j - b.lo[1]) + plane * (k - b.lo[2]);
    }
};

/// Copy the points of `part` from an array laid out over box `from` to one over box `to`
/// (both x fastest, dense; `part` lies inside both).
void copy_box(const Box& part, const real* src, const Box& from, real* dst, const Box& to);
/// The same with the arrays' storage given.
void copy_box(const Box& part, const real* src, const Box& from, const Storage& sfrom, real* dst,
              const Box& to, const Storage& sto);

class Redistribution {
  public:
    /// `from[r]` and `to[r]`: the boxes of rank r (ranks of `comm`) in the two layouts;
    /// this rank's arrays are stored as `sfrom` / `sto` (dense when not given).
    Redistribution(MPI_Comm comm, std::vector<Box> from, std::vector<Box> to,
                   const Storage* sfrom = nullptr, const Storage* sto = nullptr);

    /// `src` holds this rank's `from` box, `dst` receives its `to` box.
    void run(const real* src, real* dst);

    /// True when the two layouts are the same (run is then a copy of the own box).
    bool identity() const { return identity_; }

  private:
    MPI_Comm comm_;
    int rank_ = 0;
    std::vector<Box> from_, to_;
    Storage sfrom_, sto_;
    std::vector<int> send_count_, send_offset_, recv_count_, recv_offset_;
    std::vector<real> send_, recv_;
    bool identity_ = true;
};

} // namespace efsi

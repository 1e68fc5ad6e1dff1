// Moving a global array between two distributions over the ranks: each rank owns one box
// of global indices in the source layout and one in the target layout (empty boxes are
// allowed), stored contiguously with x fastest. Every rank sends each other rank the
// intersection of its source box with that rank's target box (one MPI_Alltoallv); the
// part a rank keeps is copied directly. Used by the FFT solver (linear/fft_poisson.cpp)
// to go between the Cartesian blocks of the Decomposition and its slabs.
#pragma once

#include "core/types.hpp"
#include "grid/box.hpp"

#include <mpi.h>

#include <vector>

namespace efsi {

/// Copy the points of `part` from an array laid out over box `from` to one over box `to`
/// (both x fastest; `part` lies inside both).
void copy_box(const Box& part, const real* src, const Box& from, real* dst, const Box& to);

class Redistribution {
  public:
    /// `from[r]` and `to[r]`: the boxes of rank r (ranks of `comm`) in the two layouts.
    Redistribution(MPI_Comm comm, std::vector<Box> from, std::vector<Box> to);

    /// `src` holds this rank's `from` box, `dst` receives its `to` box.
    void run(const real* src, real* dst);

    /// True when the two layouts are the same (run is then a copy of the own box).
    bool identity() const { return identity_; }

  private:
    MPI_Comm comm_;
    int rank_ = 0;
    std::vector<Box> from_, to_;
    std::vector<int> send_count_, send_offset_, recv_count_, recv_offset_;
    std::vector<real> send_, recv_;
    bool identity_ = true;
};

} // namespace efsi

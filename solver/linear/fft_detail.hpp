// Private to the FFT solver (fft_poisson.cpp, fft_tridiagonal.cpp): not part of the public API.
#pragma once

#include "linear/fft_poisson.hpp"

#include "core/error.hpp"
#include "parallel/redistribution.hpp"

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace efsi {

class FftWorkspace {
  public:
    explicit FftWorkspace(const Decomposition& d) : dec(d) {
        const GlobalGrid& g = dec.grid();
        dim = dec.dim();
        n = g.cells;
        // With x periodic the x transform is real-to-complex: each row of n reals becomes
        // n/2 + 1 complex numbers (2 (n/2 + 1) reals, re and im interleaved), and every other
        // direction transforms complex data (complex FFTs where periodic: FFTW's SIMD
        // codelets, 2-2.5x faster along a strided direction than its scalar R2HC), or re and
        // im alike (the real transforms of a wall direction).
        complex_x = dec.periodic()[0];
        spectral = n;
        if (complex_x) spectral[0] = 2 * (n[0] / 2 + 1);
        // With a complex x and a wall direction, that direction is not transformed but
        // solved as a tridiagonal system per wavenumber of the others (as CaNS does): y if
        // it has walls, else z. Its slab must hold it whole.
        if (complex_x) {
            if (dim >= 2 && !dec.periodic()[1])
                tri = 1;
            else if (dim == 3 && !dec.periodic()[2])
                tri = 2;
        }
        // Periodic in every direction on several ranks (3D): z, the direction slab A is split
        // along, is not transformed but solved as cyclic tridiagonal systems distributed over
        // the ranks (a reduced system of one unknown per rank and line), so the solve needs
        // no transpose at all: slab B is slab A. Each rank needs two z cells or more.
        const int size = dec.size();
        if (complex_x && dim == 3 && size > 1 && dec.periodic()[1] && dec.periodic()[2] &&
            n[2] >= 2 * size) {
            tri = 2;
            distributed_tri = true;
        }
        // Slab A is split along the last direction (z in 3D, y in 2D); slab B along the one
        // before it, or along x when a direction is solved as tridiagonal systems (slab A
        // then transforms x alone, slab B everything else); each keeps the other directions
        // whole.
        split_a = dim - 1;
        split_b = distributed_tri ? split_a : tri >= 0 ? 0 : dim - 2;
        std::vector<Box> cart_boxes(size), a_boxes(size), a_spectral(size), b_boxes(size);
        const LocalBlock& blk = dec.block();
        std::array<int, 6> mine{blk.offset[0],
                                blk.offset[1],
                                blk.offset[2],
                                blk.offset[0] + blk.cells[0],
                                blk.offset[1] + blk.cells[1],
                                blk.offset[2] + blk.cells[2]};
        std::vector<int> all(6 * std::size_t(size));
        MPI_Allgather(mine.data(), 6, MPI_INT, all.data(), 6, MPI_INT, dec.comm());
        for (int r = 0; r < size; ++r) {
            for (int e = 0; e < 3; ++e) {
                cart_boxes[r].lo[e] = all[6 * r + e];
                cart_boxes[r].hi[e] = all[6 * r + 3 + e];
            }
            a_boxes[r] = slab(n, split_a, r, size);
            a_spectral[r] = slab(spectral, split_a, r, size);
            b_boxes[r] = slab(spectral, split_b, r, size);
        }
        const int me = dec.rank();
        cart = cart_boxes[me];
        box_a = a_spectral[me];
        box_b = b_boxes[me];
        sa = padded(box_a);
        sb = padded(box_b);
        // The block's n reals per row go to slab A's rows, which have room for the
        // spectral row; slab A to B moves whole spectral rows.
        cart_to_a = std::make_unique<Redistribution>(dec.comm(), cart_boxes, a_boxes, nullptr, &sa);
        a_to_cart = std::make_unique<Redistribution>(dec.comm(), a_boxes, cart_boxes, &sa, nullptr);
        a_to_b = std::make_unique<Redistribution>(dec.comm(), a_spectral, b_boxes, &sa, &sb);
        b_to_a = std::make_unique<Redistribution>(dec.comm(), b_boxes, a_spectral, &sb, &sa);
        a = allocate(sa.plane * box_a.size()[2]);
        b = a_to_b->identity() ? a : allocate(sb.plane * box_b.size()[2]);
        c = cart_to_a->identity() ? nullptr : allocate(cart.count());
    }
    ~FftWorkspace() {
        if (c) fftw_free(c);
        if (b != a) fftw_free(b);
        fftw_free(a);
    }
    FftWorkspace(const FftWorkspace&) = delete;
    FftWorkspace& operator=(const FftWorkspace&) = delete;

    const Decomposition& dec;
    int dim = 3;
    Int3 n{1, 1, 1};
    bool complex_x = false;       ///< x periodic: real-to-complex along x, complex data after it
    int tri = -1;                 ///< the direction solved as tridiagonal systems (-1: none)
    bool distributed_tri = false; ///< tri (z) is split over the ranks: slab B is slab A
    Int3 spectral{1, 1, 1};       ///< points per direction after the x transform (reals)
    int split_a = 2, split_b = 1;
    Box cart, box_a, box_b; ///< this rank's boxes (global indices; A and B spectral)
    Storage sa, sb;         ///< how slabs A and B are stored (padded)
    std::unique_ptr<Redistribution> cart_to_a, a_to_cart, a_to_b, b_to_a;
    real* a = nullptr; ///< slab A
    real* b = nullptr; ///< slab B (the same array as a when the layouts coincide)
    real* c = nullptr; ///< the Cartesian block (none when it coincides with slab A)

    /// Rank r's share of `extent` split along `split`. Along a complex x the split falls
    /// between complex numbers.
    Box slab(const Int3& extent, int split, int r, int size) const {
        Box s{{0, 0, 0}, extent};
        const int unit = split == 0 && complex_x && extent[0] == spectral[0] ? 2 : 1;
        const std::int64_t count = extent[split] / unit;
        s.lo[split] = unit * int(std::int64_t(r) * count / size);
        s.hi[split] = unit * int(std::int64_t(r + 1) * count / size);
        return s;
    }

  private:
    /// Rows of an odd number of values and planes one cache line longer than their rows:
    /// the transforms along y and z then stride by no power of two. With power-of-two
    /// strides every point of a z transform falls in the same few cache sets (128^3,
    /// FFTW_ESTIMATE, one core: x + y + z R2HC 37 -> 21 ms, DCT-II 55 -> 33 ms). Complex
    /// rows (x periodic) hold an even number of reals (a complex number must not straddle
    /// two rows; a slab's share of x is whole complex numbers), two more where that number
    /// is a multiple of 8; their planes are even too.
    Storage padded(const Box& box) const {
        const Int3 s = box.size();
        Storage st;
        if (complex_x)
            st.row = s[0] + (s[0] % 8 == 0 ? 2 : 0);
        else
            st.row = s[0] + (s[0] % 2 == 0 ? 1 : 0);
        st.plane = st.row * s[1] + (dim == 3 ? 8 : 0);
        return st;
    }
    static real* allocate(std::int64_t count) {
        auto* p = static_cast<real*>(
            fftw_malloc(sizeof(real) * std::size_t(std::max<std::int64_t>(count, 1))));
        if (!p) throw RunError("FFT solver: out of memory for its buffers");
        return p;
    }
};

namespace fft_detail {

/// Transform pair, normalisation and eigenvalues of -h^2 L along one direction.
struct Transform {
    /// real-to-real (FFTW's r2r kinds), real-to-complex (x, periodic) or complex (a periodic
    /// y or z after a complex x)
    enum class How { R2R, R2C, C2C } how = How::R2R;
    /// R2C of even length done as a complex DFT of half the length (HalfLengthReal).
    bool half_length = false;
    fftw_r2r_kind forward = FFTW_R2HC, backward = FFTW_HC2R;
    int first = 0;            ///< first transformed index (1 for wall faces)
    int length = 1;           ///< points transformed
    real norm = 1;            ///< backward(forward(x)) = norm x
    std::vector<real> lambda; ///< eigenvalue of -L at each index (size N)
    std::vector<char> live;   ///< false at the fixed wall face
    std::string name;
};

} // namespace fft_detail

/// The real-to-complex transform of even length n along rows, done as a complex DFT of
/// length m = n/2 and one pass in each row: the row's n reals read as m complex numbers
/// (even entries real parts, odd ones imaginary) hold the DFTs of the even and the odd
/// samples at once, which `separate` turns into the n/2 + 1 complex values of the real
/// row's DFT (in place; a row has room for them), and `join` back before the backward
/// complex DFT (whose output is then n times the row, as FFTW's complex-to-real). FFTW's
/// own real-to-complex codelets are scalar, its complex ones SIMD.
class HalfLengthReal {
  public:
    explicit HalfLengthReal(int n);
    /// Forward: row holds Z (m complex, after the complex DFT); it then holds X[0..m].
    void separate(real* row);
    /// Backward: row holds X[0..m] (the imaginary parts of X[0] and X[m] are ignored); it
    /// then holds 2 Z, ready for the backward complex DFT of length m.
    void join(real* row);

  private:
    /// ar_, ai_ from the row's first `values` complex numbers (m: the m-th is the 0-th,
    /// m + 1: all of X[0..m]), and br_, bi_ their conjugates mirrored (index k <- m - k).
    void load(const real* row, int values);
    int m_;
    std::vector<real> wr_, wi_;           ///< exp(-2 pi i k / n), k = 0..m
    std::vector<real> ar_, ai_, br_, bi_; ///< one row: a value, its mirror (scratch)
};

struct FftSolver::Impl {
    std::shared_ptr<FftWorkspace> ws;
    std::array<FftDirection, 3> dirs;
    std::array<fft_detail::Transform, 3> t;
    std::array<fftw_plan, 3> forward{}, backward{};
    real norm = 1;
    real alpha = 0, beta = 1;
    PhaseSeconds seconds;
    std::array<bool, 3> in_b{};             ///< transformed in slab B (else in slab A)
    std::unique_ptr<HalfLengthReal> x_half; ///< x: R2C as a half-length complex DFT
    /// Each row of slab A through x_half's separate (forward) or join (backward).
    void x_half_pass(bool separate);
    std::vector<real> work;     ///< the tridiagonal solve's modified upper diagonal
    std::vector<real> wall_rhs; ///< right-hand side of the fixed wall faces (identity rows)
    std::vector<real> zero;     ///< a zero row (the one before the first)
    /// the distributed solve's per-plane coupling table, exchanged line ends and the
    /// reduced system's answers (distributed_tridiagonal)
    std::vector<real> coupling, ends, all_ends, v_low, v_high, diag, one;

    void tridiagonal();
    void distributed_tridiagonal();
    void shift_singular_lines_to_zero_mean();

    ~Impl() {
        for (int d = 0; d < 3; ++d) {
            if (forward[d]) fftw_destroy_plan(forward[d]);
            if (backward[d]) fftw_destroy_plan(backward[d]);
        }
    }
};

} // namespace efsi

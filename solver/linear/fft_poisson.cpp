#include "linear/fft_poisson.hpp"

#include "core/error.hpp"
#include "parallel/redistribution.hpp"

#include <fftw3.h>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <type_traits>
#include <vector>

namespace efsi {

static_assert(std::is_same_v<real, double>, "the FFT solver uses FFTW's double interface");

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

std::shared_ptr<FftWorkspace> make_fft_workspace(const Decomposition& dec) {
    return std::make_shared<FftWorkspace>(dec);
}

namespace {

/// Transform pair, normalisation and eigenvalues of -h^2 L along one direction.
struct Transform {
    /// real-to-real (FFTW's r2r kinds), real-to-complex (x, periodic) or complex (a periodic
    /// y or z after a complex x)
    enum class How { R2R, R2C, C2C } how = How::R2R;
    fftw_r2r_kind forward = FFTW_R2HC, backward = FFTW_HC2R;
    int first = 0;            ///< first transformed index (1 for wall faces)
    int length = 1;           ///< points transformed
    real norm = 1;            ///< backward(forward(x)) = norm x
    std::vector<real> lambda; ///< eigenvalue of -L at each index (size N)
    std::vector<char> live;   ///< false at the fixed wall face
    std::string name;
};

/// `complex_x`: x is transformed real-to-complex (the workspace's complex mode); direction
/// `axis` of `cells` cells.
Transform transform_for(const FftDirection& d, int axis, bool complex_x, int cells, real h) {
    Transform t;
    const int N = cells;
    const real pi = std::numbers::pi;
    const real w = 4.0 / (h * h);
    t.lambda.assign(N, 0.0);
    t.live.assign(N, 1);
    t.length = N;
    t.norm = 2.0 * N;
    auto sin2 = [](real x) { return std::sin(x) * std::sin(x); };
    if (d.periodic && complex_x) {
        t.norm = N;
        if (axis == 0) {
            // Complex index k (reals 2k and 2k + 1) holds wavenumber k, k = 0 .. N/2.
            t.how = Transform::How::R2C;
            const int m = 2 * (N / 2 + 1);
            t.lambda.assign(m, 0.0);
            t.live.assign(m, 1);
            for (int i = 0; i < m; ++i)
                t.lambda[i] = w * sin2(pi * (i / 2) / N);
            t.name = "periodic (R2C)";
        } else {
            t.how = Transform::How::C2C;
            for (int k = 0; k < N; ++k)
                t.lambda[k] = w * sin2(pi * k / N);
            t.name = "periodic (complex DFT)";
        }
    } else if (d.periodic) {
        // Half-complex order: index k holds Re or Im of wavenumber min(k, N - k), whose
        // eigenvalue is the same sin^2(pi k / N).
        t.forward = FFTW_R2HC;
        t.backward = FFTW_HC2R;
        t.norm = N;
        for (int k = 0; k < N; ++k)
            t.lambda[k] = w * sin2(pi * k / N);
        t.name = "periodic (R2HC)";
    } else if (d.wall_faces) {
        t.forward = t.backward = FFTW_RODFT00;
        t.first = 1;
        t.length = N - 1;
        t.live[0] = 0;
        for (int k = 0; k + 1 < N; ++k)
            t.lambda[k + 1] = w * sin2(pi * (k + 1) / (2.0 * N));
        t.name = "wall faces (DST-I)";
    } else if (d.low == FftSide::ZeroGradient && d.high == FftSide::ZeroGradient) {
        t.forward = FFTW_REDFT10;
        t.backward = FFTW_REDFT01;
        for (int k = 0; k < N; ++k)
            t.lambda[k] = w * sin2(pi * k / (2.0 * N));
        t.name = "Neumann (DCT-II)";
    } else if (d.low == FftSide::ZeroValue && d.high == FftSide::ZeroValue) {
        t.forward = FFTW_RODFT10;
        t.backward = FFTW_RODFT01;
        for (int k = 0; k < N; ++k)
            t.lambda[k] = w * sin2(pi * (k + 1) / (2.0 * N));
        t.name = "Dirichlet (DST-II)";
    } else {
        const bool dn = d.low == FftSide::ZeroValue;
        t.forward = t.backward = dn ? FFTW_RODFT11 : FFTW_REDFT11;
        for (int k = 0; k < N; ++k)
            t.lambda[k] = w * sin2(pi * (2 * k + 1) / (4.0 * N));
        t.name = dn ? "Dirichlet-Neumann (DST-IV)" : "Neumann-Dirichlet (DCT-IV)";
    }
    return t;
}

/// In-place plan of `kind` along direction d of an array over `box` (x fastest).
fftw_plan plan_along(real* data, const Box& box, const Storage& st, int d, const Transform& t,
                     fftw_r2r_kind kind) {
    const Int3 n = box.size();
    const std::array<int, 3> stride{1, int(st.row), int(st.plane)};
    fftw_iodim along{t.length, stride[d], stride[d]};
    std::array<fftw_iodim, 2> many{};
    int h = 0;
    for (int e = 2; e >= 0; --e)
        if (e != d) many[h++] = fftw_iodim{n[e], stride[e], stride[e]};
    real* p = data + std::size_t(t.first) * stride[d];
    fftw_plan plan = fftw_plan_guru_r2r(1, &along, 2, many.data(), p, p, &kind, FFTW_ESTIMATE);
    if (!plan)
        throw RunError(
            fmt::format("FFT solver: FFTW could not plan the transform along {}", "xyz"[d]));
    return plan;
}

/// Strides of the complex view of a real array stored as `st` (x periodic: even rows and
/// planes), in complex numbers.
std::array<int, 3> complex_strides(const Storage& st) {
    return {1, int(st.row / 2), int(st.plane / 2)};
}

/// In-place real-to-complex (forward) or complex-to-real (backward) plan along x of the
/// spectral array over `box` (x extent 2 (n/2 + 1) reals; n real points in, n/2 + 1
/// complex out).
fftw_plan plan_x_real_complex(real* data, const Box& box, const Storage& st, int n, bool forward) {
    const Int3 s = box.size();
    const std::array<int, 3> cs = complex_strides(st);
    fftw_iodim along{n, 1, 1};
    std::array<fftw_iodim, 2> many{};
    // reals in, complex out (forward); complex in, reals out (backward)
    many[0] =
        forward ? fftw_iodim{s[2], int(st.plane), cs[2]} : fftw_iodim{s[2], cs[2], int(st.plane)};
    many[1] = forward ? fftw_iodim{s[1], int(st.row), cs[1]} : fftw_iodim{s[1], cs[1], int(st.row)};
    auto* z = reinterpret_cast<fftw_complex*>(data);
    fftw_plan plan =
        forward ? fftw_plan_guru_dft_r2c(1, &along, 2, many.data(), data, z, FFTW_ESTIMATE)
                : fftw_plan_guru_dft_c2r(1, &along, 2, many.data(), z, data, FFTW_ESTIMATE);
    if (!plan)
        throw RunError("FFT solver: FFTW could not plan the real-to-complex transform along x");
    return plan;
}

/// In-place complex plan along direction d (1 or 2) of the spectral array over `box`.
fftw_plan plan_complex_along(real* data, const Box& box, const Storage& st, int d, int sign) {
    const Int3 s = box.size();
    const std::array<int, 3> cs = complex_strides(st);
    const std::array<int, 3> count{s[0] / 2, s[1], s[2]};
    fftw_iodim along{count[d], cs[d], cs[d]};
    std::array<fftw_iodim, 2> many{};
    int h = 0;
    for (int e = 2; e >= 0; --e)
        if (e != d) many[h++] = fftw_iodim{count[e], cs[e], cs[e]};
    auto* z = reinterpret_cast<fftw_complex*>(data);
    fftw_plan plan = fftw_plan_guru_dft(1, &along, 2, many.data(), z, z, sign, FFTW_ESTIMATE);
    if (!plan)
        throw RunError(fmt::format("FFT solver: FFTW could not plan the complex transform along {}",
                                   "xyz"[d]));
    return plan;
}

} // namespace

struct FftSolver::Impl {
    std::shared_ptr<FftWorkspace> ws;
    std::array<FftDirection, 3> dirs;
    std::array<Transform, 3> t;
    std::array<fftw_plan, 3> forward{}, backward{};
    real norm = 1;
    real alpha = 0, beta = 1;
    PhaseSeconds seconds;
    std::array<bool, 3> in_b{}; ///< transformed in slab B (else in slab A)
    std::vector<real> work;     ///< the tridiagonal solve's modified upper diagonal
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

FftSolver::FftSolver(const Decomposition& dec, const std::array<FftDirection, 3>& directions,
                     std::shared_ptr<FftWorkspace> workspace)
    : impl_(std::make_unique<Impl>()) {
    Impl& I = *impl_;
    I.ws = workspace ? std::move(workspace) : make_fft_workspace(dec);
    if (&I.ws->dec != &dec) throw RunError("FFT solver: workspace of another decomposition");
    I.dirs = directions;
    FftWorkspace& ws = *I.ws;
    for (int d = 0; d < ws.dim; ++d) {
        if (I.dirs[d].periodic != dec.periodic()[d])
            throw RunError(
                fmt::format("FFT solver: direction {} periodic in one place only", "xyz"[d]));
        I.t[d] = transform_for(I.dirs[d], d, ws.complex_x, ws.n[d], dec.grid().dx(d));
        const bool in_b = ws.tri >= 0 ? d != 0 : d == ws.split_a;
        I.in_b[d] = in_b;
        if (d == ws.tri) {
            I.t[d].name =
                ws.distributed_tri
                    ? fmt::format("periodic, cyclic tridiagonal over {} ranks", ws.dec.size())
                    : fmt::format("{}, tridiagonal", I.t[d].name);
            continue; // solved, not transformed
        }
        I.norm *= I.t[d].norm;
        const Box& box = in_b ? ws.box_b : ws.box_a;
        if (box.empty()) continue;
        real* data = in_b ? ws.b : ws.a;
        const Storage& st = in_b ? ws.sb : ws.sa;
        switch (I.t[d].how) {
        case Transform::How::R2C:
            I.forward[d] = plan_x_real_complex(data, box, st, ws.n[0], true);
            I.backward[d] = plan_x_real_complex(data, box, st, ws.n[0], false);
            break;
        case Transform::How::C2C:
            I.forward[d] = plan_complex_along(data, box, st, d, FFTW_FORWARD);
            I.backward[d] = plan_complex_along(data, box, st, d, FFTW_BACKWARD);
            break;
        case Transform::How::R2R:
            I.forward[d] = plan_along(data, box, st, d, I.t[d], I.t[d].forward);
            I.backward[d] = plan_along(data, box, st, d, I.t[d], I.t[d].backward);
            break;
        }
    }
    for (int d = ws.dim; d < 3; ++d) { // the one-cell z of a 2D run: nothing to transform
        I.t[d].lambda.assign(1, 0.0);
        I.t[d].live.assign(1, 1);
    }
}

FftSolver::~FftSolver() = default;

void FftSolver::set_coefficients(real alpha, real beta) {
    if (!(alpha >= 0) || !(beta >= 0) || (alpha == 0 && beta == 0))
        throw RunError(
            fmt::format("FFT solver: bad coefficients alpha = {}, beta = {}", alpha, beta));
    impl_->alpha = alpha;
    impl_->beta = beta;
}

std::string FftSolver::describe() const {
    std::string s;
    for (int d = 0; d < impl_->ws->dim; ++d)
        s += fmt::format("{}{}: {}", d ? ", " : "", "xyz"[d], impl_ -> t[d].name);
    return s;
}

const FftSolver::PhaseSeconds& FftSolver::phase_seconds() const {
    return impl_->seconds;
}

namespace {
/// Adds the seconds since the last lap to one of the phase accumulators.
class PhaseClock {
  public:
    void lap(double& into) {
        const auto now = std::chrono::steady_clock::now();
        into += std::chrono::duration<double>(now - last_).count();
        last_ = now;
    }

  private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};
} // namespace

// Along the tridiagonal direction T (held whole by slab B) each wavenumber pair of the
// other directions leaves (alpha + beta lambda) u_j - beta (u_{j+1} - 2 u_j + u_{j-1}) / h^2
// = f_j, lambda the other directions' eigenvalue, closed at each end by its ghost rule
// (ghost = s u at the end cell: s = 1 zero gradient, -1 zero value; wall faces: the unknowns
// are the faces 1 .. N-1 between the fixed faces 0 and N, whose values are zero here). The
// Thomas algorithm runs along T with the x index innermost (unit stride). The operator is
// singular only for alpha = 0, lambda = 0 and zero gradient at both ends: that line is
// solved with its last value set to zero and then shifted to zero mean, which is the
// transforms' zero mode set to zero.
void FftSolver::Impl::tridiagonal() {
    FftWorkspace& W = *ws;
    const Box& bb = W.box_b;
    if (bb.empty()) return;
    const int T = W.tri;
    const int q = T == 1 ? 2 : 1; // the other direction besides x
    const Int3 sz = bb.size();
    const std::array<std::ptrdiff_t, 3> stride{1, W.sb.row, W.sb.plane};
    const int N = sz[T], nx = sz[0];
    const FftDirection& dir = dirs[T];
    const real hT = W.dec.grid().dx(T);
    const real g = beta / (hT * hT);
    const int first = dir.wall_faces ? 1 : 0;
    auto side = [&](FftSide sd) {
        return dir.wall_faces ? 0.0 : sd == FftSide::ZeroGradient ? 1.0 : -1.0;
    };
    const real s_lo = side(dir.low), s_hi = side(dir.high);
    const bool neumann = s_lo == 1.0 && s_hi == 1.0;
    const real inv_norm = 1.0 / norm;
    const auto& l0 = t[0].lambda;
    work.resize(std::size_t(N) * std::size_t(nx));
    zero.resize(std::size_t(nx));
    for (int kq = bb.lo[q]; kq < bb.hi[q]; ++kq) {
        real* base = W.b + std::ptrdiff_t(kq - bb.lo[q]) * stride[q];
        if (!t[q].live[kq] || N <= first) {
            for (int j = 0; j < N; ++j)
                std::fill(base + j * stride[T], base + j * stride[T] + nx, 0.0);
            continue;
        }
        const real lq = t[q].lambda[kq];
        if (first == 1) std::fill(base, base + nx, 0.0); // the fixed wall face
        // The singular line (alpha = 0, both other wavenumbers zero, zero gradient at both
        // ends) to zero mean along T: its right-hand side before the sweep (the zero mode is
        // dropped), its answer after it (the last pivot is zero: the value there came out 0).
        const bool singular = neumann && alpha == 0 && lq == 0;
        auto zero_mean_of_singular_line = [&] {
            for (int i = 0; i < nx; ++i) {
                if (l0[bb.lo[0] + i] != 0) continue;
                real mean = 0;
                for (int j = 0; j < N; ++j)
                    mean += base[j * stride[T] + i];
                mean /= N;
                for (int j = 0; j < N; ++j)
                    base[j * stride[T] + i] -= mean;
            }
        };
        if (singular) zero_mean_of_singular_line();
        // forward elimination (the row before the first is zero: no coupling there)
        for (int j = first; j < N; ++j) {
            real* row = base + j * stride[T];
            const real e = g * (2.0 - (j == first ? s_lo : 0.0) - (j == N - 1 ? s_hi : 0.0));
            real* cp = work.data() + std::size_t(j) * nx;
            const real* prev = j == first ? zero.data() : row - stride[T];
            const real* cprev = j == first ? zero.data() : cp - nx;
            for (int i = 0; i < nx; ++i) {
                const real den = alpha + beta * (l0[bb.lo[0] + i] + lq) + e + g * cprev[i];
                cp[i] = den != 0 ? -g / den : 0.0;
                row[i] = den != 0 ? (row[i] * inv_norm + g * prev[i]) / den : 0.0;
            }
        }
        // back substitution
        for (int j = N - 2; j >= first; --j) {
            real* row = base + j * stride[T];
            const real* next = row + stride[T];
            const real* cp = work.data() + std::size_t(j) * nx;
            for (int i = 0; i < nx; ++i)
                row[i] -= cp[i] * next[i];
        }
        if (singular) zero_mean_of_singular_line();
    }
}

namespace {
/// Solves the cyclic tridiagonal system a_r x_{r-1} + d_r x_r + c_r x_{r+1} = b_r, r = 0 ..
/// P - 1 (indices modulo P, P >= 3), by the Thomas algorithm and a Sherman-Morrison
/// correction; w needs 3 P values.
void solve_cyclic(int P, const real* a, const real* d, const real* c, const real* b, real* x,
                  real* w) {
    real* diag = w;
    real* z = w + P;
    real* cp = w + 2 * P;
    const real gamma = -d[0];
    const real corner_low = c[P - 1], corner_high = a[0]; // x_0 in row P-1, x_{P-1} in row 0
    for (int r = 0; r < P; ++r)
        diag[r] = d[r];
    diag[0] -= gamma;
    diag[P - 1] -= corner_low * corner_high / gamma;
    // Thomas for the two right-hand sides b and u = (gamma, 0, .., 0, corner_low)
    real den = diag[0];
    cp[0] = c[0] / den;
    x[0] = b[0] / den;
    z[0] = gamma / den;
    for (int r = 1; r < P; ++r) {
        den = diag[r] - a[r] * cp[r - 1];
        cp[r] = c[r] / den;
        x[r] = (b[r] - a[r] * x[r - 1]) / den;
        z[r] = ((r == P - 1 ? corner_low : 0.0) - a[r] * z[r - 1]) / den;
    }
    for (int r = P - 2; r >= 0; --r) {
        x[r] -= cp[r] * x[r + 1];
        z[r] -= cp[r] * z[r + 1];
    }
    const real f =
        (x[0] + corner_high * x[P - 1] / gamma) / (1.0 + z[0] + corner_high * z[P - 1] / gamma);
    for (int r = 0; r < P; ++r)
        x[r] -= f * z[r];
}
} // namespace

// With alpha = 0 the lines whose other wavenumbers are both zero are singular along z: each
// is shifted to zero mean over all its rows (all ranks).
void FftSolver::Impl::shift_singular_lines_to_zero_mean() {
    FftWorkspace& W = *ws;
    const Box& bb = W.box_b;
    const Int3 sz = bb.size();
    std::vector<std::ptrdiff_t> lines; // offsets of the singular lines' first rows
    for (int j = 0; j < sz[1]; ++j)
        for (int i = 0; i < sz[0]; ++i)
            if (t[0].lambda[bb.lo[0] + i] + t[1].lambda[bb.lo[1] + j] == 0)
                lines.push_back(j * W.sb.row + i);
    std::vector<real> sums(lines.size(), 0.0);
    for (std::size_t s = 0; s < lines.size(); ++s)
        for (int k = 0; k < sz[2]; ++k)
            sums[s] += W.b[lines[s] + k * W.sb.plane];
    MPI_Allreduce(MPI_IN_PLACE, sums.data(), int(sums.size()), mpi_real(), MPI_SUM, W.dec.comm());
    for (std::size_t s = 0; s < lines.size(); ++s)
        for (int k = 0; k < sz[2]; ++k)
            W.b[lines[s] + k * W.sb.plane] -= sums[s] / real(W.n[2]);
}

// z periodic and split over the ranks (slab B is slab A: x and y whole on every rank). Each
// line (a wavenumber of x and of y) is a cyclic tridiagonal system along z,
//   D u_k - g (u_{k-1} + u_{k+1}) = f_k,   D = alpha + beta (lambda_x + lambda_y) + 2 g,
//   g = beta / h_z^2,
// of which rank r holds m_r consecutive rows. Call V_r the value at rank r's last row. Given
// V_{r-1} and V_r, rank r's other n = m_r - 1 rows solve the local system T' (diagonal D,
// off-diagonal -g, n rows, no wrap) with the couplings g V_{r-1} into its first row and
// g V_r into its last: u_k = y_k + p_k V_{r-1} + p_{n-1-k} V_r, where y = T'^-1 f and
// p = T'^-1 (g e_0) (T' is symmetric and persymmetric, so the last row's response is p
// reversed). The Thomas algorithm gives p's two ends for free: p_0 = -c'_{n-1} and
// p_{n-1} = prod_k (-c'_k), c' its modified upper diagonal. The rows left, each rank's last,
// couple the V of neighbouring ranks (indices of ranks modulo P):
//   -g p^(r)_{n_r-1} V_{r-1} + (D - g p^(r)_0 - g p^(r+1)_0) V_r - g p^(r+1)_{n_{r+1}-1} V_{r+1}
//     = f^(r)_last + g y^(r)_{n_r-1} + g y^(r+1)_0,
// a cyclic tridiagonal system with one unknown per rank. Each rank sends every other the two
// numbers per line that system needs (f_last + g y_{n-1} and g y_0: one MPI_Allgather of
// 2 x lines values, where the transforms along z needed two transposes of the whole array),
// solves the reduced systems of all lines, and finishes its rows. The singular line (alpha
// = 0 and both other wavenumbers zero) is solved with V_{P-1} = 0 and shifted to zero mean.
void FftSolver::Impl::distributed_tridiagonal() {
    FftWorkspace& W = *ws;
    const Box& bb = W.box_b;
    const Int3 sz = bb.size();
    const int nx = sz[0], ny = sz[1], m = sz[2], n = m - 1;
    const std::ptrdiff_t row = W.sb.row, plane = W.sb.plane;
    const real hz = W.dec.grid().dx(2);
    const real g = beta / (hz * hz);
    const real inv_norm = 1.0 / norm;
    const auto& l0 = t[0].lambda;
    const auto& l1 = t[1].lambda;
    const int P = W.dec.size(), me = W.dec.rank();
    const std::size_t L = std::size_t(nx) * std::size_t(ny);
    // local rows of every rank (at most two different counts: n_min and n_min + 1)
    std::vector<int> nr(P);
    int n_min = n, n_max = n;
    for (int r = 0; r < P; ++r) {
        nr[r] = W.slab(W.spectral, 2, r, P).size()[2] - 1;
        n_min = std::min(n_min, nr[r]);
        n_max = std::max(n_max, nr[r]);
    }
    const int kinds = n_max - n_min + 1;
    work.resize(std::size_t(n_max) * nx);
    coupling.resize(std::size_t(n_max) * nx);
    zero.assign(std::size_t(nx), 0.0);
    one.assign(std::size_t(nx), 1.0);
    ends.resize(2 * L);
    std::vector<real> p_first(kinds * L), p_last(kinds * L); // p_0, p_{n-1} per count, line
    diag.resize(std::size_t(nx));
    auto set_diagonal = [&](int gj) { // D of the lines of one y index
        for (int i = 0; i < nx; ++i)
            diag[i] = alpha + beta * (l0[bb.lo[0] + i] + l1[gj]) + 2 * g;
    };
    // The singular line(s): the right-hand side's mean over all ranks (the zero mode) is
    // dropped, so that the reduced system is consistent.
    if (alpha == 0) shift_singular_lines_to_zero_mean();
    // 1. y = T'^-1 f on rows 0 .. n-1 (Thomas), the line ends to send, p's ends. One y index
    // at a time: its lines (n x nx values) stay in cache between the two sweeps.
    for (int j = 0; j < ny; ++j) {
        real* base = W.b + j * row;
        set_diagonal(bb.lo[1] + j);
        const real* __restrict D = diag.data();
        for (int k = 0; k < n_max; ++k) {
            real* __restrict cp = work.data() + std::size_t(k) * nx;
            const real* __restrict cprev = k == 0 ? zero.data() : cp - nx;
            real* __restrict pr = coupling.data() + std::size_t(k) * nx; // prod of -c'
            const real* __restrict prprev = k == 0 ? one.data() : pr - nx;
            if (k < n) {
                real* __restrict r = base + k * plane;
                const real* __restrict prev = k == 0 ? zero.data() : r - plane;
                for (int i = 0; i < nx; ++i) {
                    const real inv = 1.0 / (D[i] + g * cprev[i]);
                    cp[i] = -g * inv;
                    pr[i] = g * inv * prprev[i];
                    r[i] = (r[i] * inv_norm + g * prev[i]) * inv;
                }
            } else {
                for (int i = 0; i < nx; ++i) {
                    const real inv = 1.0 / (D[i] + g * cprev[i]);
                    cp[i] = -g * inv;
                    pr[i] = g * inv * prprev[i];
                }
            }
        }
        for (int k = n - 2; k >= 0; --k) {
            real* __restrict r = base + k * plane;
            const real* __restrict next = r + plane;
            const real* __restrict cp = work.data() + std::size_t(k) * nx;
            for (int i = 0; i < nx; ++i)
                r[i] -= cp[i] * next[i];
        }
        const real* last = base + n * plane;
        const real* y_first = base;
        const real* y_last = base + (n - 1) * plane;
        for (int i = 0; i < nx; ++i) {
            const std::size_t l = std::size_t(j) * nx + i;
            ends[l] = last[i] * inv_norm + g * y_last[i];
            ends[L + l] = g * y_first[i];
        }
        for (int q = 0; q < kinds; ++q) {
            const int nq = n_min + q;
            for (int i = 0; i < nx; ++i) {
                const std::size_t l = std::size_t(j) * nx + i;
                p_first[q * L + l] = -work[std::size_t(nq - 1) * nx + i];
                p_last[q * L + l] = coupling[std::size_t(nq - 1) * nx + i];
            }
        }
    }
    // 2. Every rank's line ends, and the reduced systems of all lines.
    all_ends.resize(2 * L * P);
    MPI_Allgather(ends.data(), int(2 * L), mpi_real(), all_ends.data(), int(2 * L), mpi_real(),
                  W.dec.comm());
    v_low.resize(L);
    v_high.resize(L);
    std::vector<real> ra(P), rd(P), rc(P), rb(P), rv(P), rw(3 * P);
    const int prev_rank = (me + P - 1) % P;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::size_t l = std::size_t(j) * nx + i;
            const real D = alpha + beta * (l0[bb.lo[0] + i] + l1[bb.lo[1] + j]) + 2 * g;
            for (int r = 0; r < P; ++r) {
                const int s = (r + 1) % P;
                const std::size_t qr = std::size_t(nr[r] - n_min) * L + l;
                const std::size_t qs = std::size_t(nr[s] - n_min) * L + l;
                ra[r] = -g * p_last[qr];
                rd[r] = D - g * p_first[qr] - g * p_first[qs];
                rc[r] = -g * p_last[qs];
                rb[r] =
                    all_ends[std::size_t(r) * 2 * L + l] + all_ends[std::size_t(s) * 2 * L + L + l];
            }
            const bool is_singular = alpha == 0 && l0[bb.lo[0] + i] + l1[bb.lo[1] + j] == 0;
            if (is_singular) {
                // V_{P-1} = 0; rows 0 .. P-2 without their couplings to it (Thomas)
                rv[P - 1] = 0;
                real den = rd[0];
                rw[0] = rc[0] / den;
                rv[0] = rb[0] / den;
                for (int r = 1; r < P - 1; ++r) {
                    den = rd[r] - ra[r] * rw[r - 1];
                    rw[r] = rc[r] / den;
                    rv[r] = (rb[r] - ra[r] * rv[r - 1]) / den;
                }
                for (int r = P - 3; r >= 0; --r)
                    rv[r] -= rw[r] * rv[r + 1];
            } else if (P == 2) {
                const real a00 = rd[0], a01 = ra[0] + rc[0], a10 = ra[1] + rc[1], a11 = rd[1];
                const real det = a00 * a11 - a01 * a10;
                rv[0] = (rb[0] * a11 - a01 * rb[1]) / det;
                rv[1] = (a00 * rb[1] - a10 * rb[0]) / det;
            } else {
                solve_cyclic(P, ra.data(), rd.data(), rc.data(), rb.data(), rv.data(), rw.data());
            }
            v_low[l] = rv[prev_rank];
            v_high[l] = rv[me];
        }
    // 3. u_k = y_k + p_k V_{r-1} + p_{n-1-k} V_r, and the last row V_r.
    for (int j = 0; j < ny; ++j) {
        real* base = W.b + j * row;
        set_diagonal(bb.lo[1] + j);
        const real* __restrict D = diag.data();
        // p = T'^-1 (g e_0) on this y index's lines: forward (prod of -c'), then back
        for (int k = 0; k < n; ++k) {
            real* __restrict cp = work.data() + std::size_t(k) * nx;
            const real* __restrict cprev = k == 0 ? zero.data() : cp - nx;
            real* __restrict p = coupling.data() + std::size_t(k) * nx;
            const real* __restrict pprev = k == 0 ? one.data() : p - nx;
            for (int i = 0; i < nx; ++i) {
                const real inv = 1.0 / (D[i] + g * cprev[i]);
                cp[i] = -g * inv;
                p[i] = g * inv * pprev[i];
            }
        }
        for (int k = n - 2; k >= 0; --k) {
            real* __restrict p = coupling.data() + std::size_t(k) * nx;
            const real* __restrict pnext = p + nx;
            const real* __restrict cp = work.data() + std::size_t(k) * nx;
            for (int i = 0; i < nx; ++i)
                p[i] -= cp[i] * pnext[i];
        }
        const real* __restrict lo = v_low.data() + std::size_t(j) * nx;
        const real* __restrict hi = v_high.data() + std::size_t(j) * nx;
        for (int k = 0; k < n; ++k) {
            real* __restrict r = base + k * plane;
            const real* __restrict pk = coupling.data() + std::size_t(k) * nx;
            const real* __restrict pm = coupling.data() + std::size_t(n - 1 - k) * nx;
            for (int i = 0; i < nx; ++i)
                r[i] += pk[i] * lo[i] + pm[i] * hi[i];
        }
        std::copy(hi, hi + nx, base + n * plane);
    }
    // 4. The singular line's answer to zero mean.
    if (alpha == 0) shift_singular_lines_to_zero_mean();
}

SolveReport FftSolver::solve(const Field& rhs, Field& x) {
    Impl& I = *impl_;
    FftWorkspace& ws = *I.ws;
    PhaseSeconds& sec = I.seconds;
    PhaseClock clock;
    const Int3 nb = ws.cart.size();
    // Owned values to the Cartesian buffer (or straight to slab A when they coincide).
    real* block = ws.c ? ws.c : ws.a;
    const Storage sblock = ws.c ? Storage::dense(ws.cart) : ws.sa;
    for (int k = 0; k < nb[2]; ++k)
        for (int j = 0; j < nb[1]; ++j) {
            real* row = block + sblock.row * j + sblock.plane * k;
            const real* from = rhs.data().data() + rhs.index(0, j, k);
            std::copy(from, from + nb[0], row);
        }
    clock.lap(sec.copy);
    if (ws.c) ws.cart_to_a->run(ws.c, ws.a);
    clock.lap(sec.redistribution);
    for (int d = 0; d < ws.dim; ++d)
        if (!I.in_b[d] && I.forward[d]) fftw_execute(I.forward[d]);
    clock.lap(sec.transforms);
    if (ws.b != ws.a) ws.a_to_b->run(ws.a, ws.b);
    clock.lap(sec.redistribution);
    for (int d = 0; d < ws.dim; ++d)
        if (I.in_b[d] && I.forward[d]) fftw_execute(I.forward[d]);
    clock.lap(sec.transforms);
    if (ws.distributed_tri)
        I.distributed_tridiagonal();
    else if (ws.tri >= 0)
        I.tridiagonal();
    else {
        // Divide by the eigenvalues (and the transforms' normalisation); the zero mode of
        // a singular operator and the fixed wall faces are set to zero.
        const Box& bb = ws.box_b;
        const auto& l0 = I.t[0].lambda;
        const auto& l1 = I.t[1].lambda;
        const auto& l2 = I.t[2].lambda;
        for (int k = bb.lo[2]; k < bb.hi[2]; ++k)
            for (int j = bb.lo[1]; j < bb.hi[1]; ++j) {
                const bool live_jk = I.t[1].live[j] && I.t[2].live[k];
                const real ljk = l1[j] + l2[k];
                real* row = ws.b + ws.sb.index(bb, bb.lo[0], j, k) - bb.lo[0];
                for (int i = bb.lo[0]; i < bb.hi[0]; ++i) {
                    const real den = I.alpha + I.beta * (l0[i] + ljk);
                    row[i] =
                        (live_jk && I.t[0].live[i] && den != 0) ? row[i] / (den * I.norm) : 0.0;
                }
            }
    }
    clock.lap(sec.divide);
    for (int d = ws.dim - 1; d >= 0; --d)
        if (I.in_b[d] && I.backward[d]) fftw_execute(I.backward[d]);
    clock.lap(sec.transforms);
    if (ws.b != ws.a) ws.b_to_a->run(ws.b, ws.a);
    clock.lap(sec.redistribution);
    for (int d = ws.dim - 1; d >= 0; --d)
        if (!I.in_b[d] && I.backward[d]) fftw_execute(I.backward[d]);
    clock.lap(sec.transforms);
    if (ws.c) ws.a_to_cart->run(ws.a, ws.c);
    clock.lap(sec.redistribution);
    for (int k = 0; k < nb[2]; ++k)
        for (int j = 0; j < nb[1]; ++j) {
            const real* row = block + sblock.row * j + sblock.plane * k;
            std::copy(row, row + nb[0], x.data().data() + x.index(0, j, k));
        }
    // The fixed wall faces are identity rows.
    for (int d = 0; d < ws.dim; ++d)
        if (I.dirs[d].wall_faces && !I.dirs[d].periodic && ws.cart.lo[d] == 0) {
            Box plane{{0, 0, 0}, nb};
            plane.hi[d] = 1;
            for_each_in(plane, [&](int i, int j, int k) { x(i, j, k) = rhs(i, j, k); });
        }
    clock.lap(sec.copy);
    SolveReport r;
    r.iterations = 1;
    r.relative_residual = 0;
    r.converged = true;
    return r;
}

} // namespace efsi

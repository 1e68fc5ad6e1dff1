#include "linear/fft_detail.hpp"

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

std::shared_ptr<FftWorkspace> make_fft_workspace(const Decomposition& dec) {
    return std::make_shared<FftWorkspace>(dec);
}

using fft_detail::Transform;

namespace {

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
            // Even n: as a complex DFT of n/2 (HalfLengthReal): 128^3 on one core, the x
            // pass 5.2 ms with FFTW's (scalar) real-to-complex codelet, 2.7-3.6 ms so.
            t.half_length = N % 2 == 0;
            t.name = t.half_length ? "periodic (R2C by a complex DFT of n/2)" : "periodic (R2C)";
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

/// In-place complex plan of length n/2 along x (the rows' n reals read as n/2 complex
/// numbers) of the spectral array over `box`: HalfLengthReal's complex DFT.
fftw_plan plan_x_half_length(real* data, const Box& box, const Storage& st, int n, int sign) {
    const Int3 s = box.size();
    const std::array<int, 3> cs = complex_strides(st);
    fftw_iodim along{n / 2, 1, 1};
    std::array<fftw_iodim, 2> many{fftw_iodim{s[2], cs[2], cs[2]}, fftw_iodim{s[1], cs[1], cs[1]}};
    auto* z = reinterpret_cast<fftw_complex*>(data);
    fftw_plan plan = fftw_plan_guru_dft(1, &along, 2, many.data(), z, z, sign, FFTW_ESTIMATE);
    if (!plan) throw RunError("FFT solver: FFTW could not plan the half-length transform along x");
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
            if (I.t[d].half_length) {
                if (in_b) throw RunError("FFT solver: the x transform must run in slab A");
                I.forward[d] = plan_x_half_length(data, box, st, ws.n[0], FFTW_FORWARD);
                I.backward[d] = plan_x_half_length(data, box, st, ws.n[0], FFTW_BACKWARD);
                I.x_half = std::make_unique<HalfLengthReal>(ws.n[0]);
                break;
            }
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

HalfLengthReal::HalfLengthReal(int n)
    : m_(n / 2), wr_(m_ + 1), wi_(m_ + 1), ar_(m_ + 1), ai_(m_ + 1), br_(m_ + 1), bi_(m_ + 1) {
    for (int k = 0; k <= m_; ++k) {
        const real angle = 2.0 * std::numbers::pi * k / n;
        wr_[k] = std::cos(angle);
        wi_[k] = -std::sin(angle);
    }
}

// With A = Z[k] and B = conj(Z[m - k]) (Z[m] = Z[0]), the DFTs of the even and odd samples
// are E = (A + B) / 2 and O = -i (A - B) / 2, and X[k] = E + W^k O. The loops run over
// plain arrays (a row's values and their mirror) so that they vectorise.
void HalfLengthReal::load(const real* row, int values) {
    const int m = m_;
    for (int k = 0; k < values; ++k) {
        ar_[k] = row[2 * k];
        ai_[k] = row[2 * k + 1];
    }
    if (values == m) { // the m-th value is the 0-th (periodic)
        ar_[m] = ar_[0];
        ai_[m] = ai_[0];
    }
    for (int k = 0; k <= m; ++k) {
        br_[k] = ar_[m - k];
        bi_[k] = -ai_[m - k];
    }
}

void HalfLengthReal::separate(real* row) {
    const int m = m_;
    load(row, m);
    for (int k = 0; k <= m; ++k) {
        const real er = 0.5 * (ar_[k] + br_[k]), ei = 0.5 * (ai_[k] + bi_[k]);
        const real orr = 0.5 * (ai_[k] - bi_[k]), oi = -0.5 * (ar_[k] - br_[k]);
        row[2 * k] = er + (wr_[k] * orr - wi_[k] * oi);
        row[2 * k + 1] = ei + (wr_[k] * oi + wi_[k] * orr);
    }
}

// The inverse: with A = X[k] and B = conj(X[m - k]), 2 E = A + B and 2 O = W^-k (A - B),
// and 2 Z = 2 E + i 2 O.
void HalfLengthReal::join(real* row) {
    const int m = m_;
    row[1] = 0.0; // a real row's X[0] and X[m] are real: their imaginary parts are ignored
    row[2 * m + 1] = 0.0;
    load(row, m + 1);
    for (int k = 0; k < m; ++k) {
        const real er = ar_[k] + br_[k], ei = ai_[k] + bi_[k];
        const real dr = ar_[k] - br_[k], di = ai_[k] - bi_[k];
        // 2 O = conj(W^k) (dr + i di)
        const real orr = wr_[k] * dr + wi_[k] * di, oi = wr_[k] * di - wi_[k] * dr;
        row[2 * k] = er - oi;
        row[2 * k + 1] = ei + orr;
    }
}

void FftSolver::Impl::x_half_pass(bool separate) {
    const FftWorkspace& w = *ws;
    const Int3 s = w.box_a.size();
    if (w.box_a.empty()) return;
    for (int k = 0; k < s[2]; ++k)
        for (int j = 0; j < s[1]; ++j) {
            real* row = w.a + w.sa.row * j + w.sa.plane * k;
            if (separate)
                x_half->separate(row);
            else
                x_half->join(row);
        }
}

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

real* FftSolver::input_row(int j, int k) {
    FftWorkspace& ws = *impl_->ws;
    real* block = ws.c ? ws.c : ws.a;
    const Storage sblock = ws.c ? Storage::dense(ws.cart) : ws.sa;
    return block + sblock.row * j + sblock.plane * k;
}

SolveReport FftSolver::solve(const Field& rhs, Field& x) {
    const Int3 nb = impl_->ws->cart.size();
    PhaseClock clock;
    // Owned values to the Cartesian buffer (or straight to slab A when they coincide).
    for (int k = 0; k < nb[2]; ++k)
        for (int j = 0; j < nb[1]; ++j) {
            const real* from = rhs.data().data() + rhs.index(0, j, k);
            std::copy(from, from + nb[0], input_row(j, k));
        }
    clock.lap(impl_->seconds.copy);
    return solve_in_place(x);
}

SolveReport FftSolver::solve_in_place(Field& x) {
    Impl& I = *impl_;
    FftWorkspace& ws = *I.ws;
    PhaseSeconds& sec = I.seconds;
    PhaseClock clock;
    const Int3 nb = ws.cart.size();
    real* block = ws.c ? ws.c : ws.a;
    const Storage sblock = ws.c ? Storage::dense(ws.cart) : ws.sa;
    // The fixed wall faces are identity rows: their right-hand side, kept before the
    // transforms overwrite the buffer.
    I.wall_rhs.clear();
    for (int d = 0; d < ws.dim; ++d)
        if (I.dirs[d].wall_faces && !I.dirs[d].periodic && ws.cart.lo[d] == 0) {
            Box plane{{0, 0, 0}, nb};
            plane.hi[d] = 1;
            for_each_in(plane,
                        [&](int i, int j, int k) { I.wall_rhs.push_back(input_row(j, k)[i]); });
        }
    if (ws.c) ws.cart_to_a->run(ws.c, ws.a);
    clock.lap(sec.redistribution);
    for (int d = 0; d < ws.dim; ++d)
        if (!I.in_b[d] && I.forward[d]) {
            fftw_execute(I.forward[d]);
            if (d == 0 && I.x_half) I.x_half_pass(true);
        }
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
        const char* live0 = I.t[0].live.data();
        const real alpha = I.alpha, beta = I.beta, norm = I.norm;
        for (int k = bb.lo[2]; k < bb.hi[2]; ++k)
            for (int j = bb.lo[1]; j < bb.hi[1]; ++j) {
                real* row = ws.b + ws.sb.index(bb, bb.lo[0], j, k) - bb.lo[0];
                if (!(I.t[1].live[j] && I.t[2].live[k])) {
                    std::fill(row + bb.lo[0], row + bb.hi[0], 0.0);
                    continue;
                }
                const real ljk = l1[j] + l2[k];
                // Branch-free, so that it vectorises (with -fno-trapping-math: the file's
                // flag, solver/CMakeLists.txt): a dead entry divides by 1 and is then set to
                // zero (a live one is divided exactly as before).
                for (int i = bb.lo[0]; i < bb.hi[0]; ++i) {
                    const real den = alpha + beta * (l0[i] + ljk);
                    const bool ok = (live0[i] != 0) & (den != 0);
                    const real v = row[i] / (ok ? den * norm : 1.0);
                    row[i] = ok ? v : 0.0;
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
        if (!I.in_b[d] && I.backward[d]) {
            if (d == 0 && I.x_half) I.x_half_pass(false);
            fftw_execute(I.backward[d]);
        }
    clock.lap(sec.transforms);
    if (ws.c) ws.a_to_cart->run(ws.a, ws.c);
    clock.lap(sec.redistribution);
    for (int k = 0; k < nb[2]; ++k)
        for (int j = 0; j < nb[1]; ++j) {
            const real* row = block + sblock.row * j + sblock.plane * k;
            std::copy(row, row + nb[0], x.data().data() + x.index(0, j, k));
        }
    // The fixed wall faces are identity rows.
    std::size_t q = 0;
    for (int d = 0; d < ws.dim; ++d)
        if (I.dirs[d].wall_faces && !I.dirs[d].periodic && ws.cart.lo[d] == 0) {
            Box plane{{0, 0, 0}, nb};
            plane.hi[d] = 1;
            for_each_in(plane, [&](int i, int j, int k) { x(i, j, k) = I.wall_rhs[q++]; });
        }
    clock.lap(sec.copy);
    SolveReport r;
    r.iterations = 1;
    r.relative_residual = 0;
    r.converged = true;
    return r;
}

} // namespace efsi

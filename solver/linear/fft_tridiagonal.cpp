// The FFT solver's tridiagonal solves (linear/fft_poisson.hpp): along a wall direction held
// whole by slab B, and the cyclic one along z split over the ranks.
#include "linear/fft_detail.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace efsi {

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
    const real a = alpha, b = beta;
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
            real* __restrict row = base + j * stride[T];
            const real e = g * (2.0 - (j == first ? s_lo : 0.0) - (j == N - 1 ? s_hi : 0.0));
            real* __restrict cp = work.data() + std::size_t(j) * nx;
            const real* __restrict prev = j == first ? zero.data() : row - stride[T];
            const real* __restrict cprev = j == first ? zero.data() : cp - nx;
            const real* __restrict lx = l0.data() + bb.lo[0];
            // Branch-free, with arithmetic masks rather than selects and on locals only (the
            // members could alias the rows), so that GCC vectorises it: a zero pivot divides
            // by 1 and its results are multiplied by 0; a nonzero one divides and is
            // multiplied by 1, exactly as a plain division.
            for (int i = 0; i < nx; ++i) {
                const real den = a + b * (lx[i] + lq) + e + g * cprev[i];
                const real singular_pivot = den == 0 ? 1.0 : 0.0;
                const real d = den + singular_pivot, keep = 1.0 - singular_pivot;
                cp[i] = (-g / d) * keep;
                row[i] = ((row[i] * inv_norm + g * prev[i]) / d) * keep;
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

/// One row of the distributed solve's forward elimination (Thomas on T'): the pivots' c'
/// (cp), the running product of -c' (pr) and the eliminated right-hand side (r, in place).
/// A function of its own so that the restrict-qualified arguments let GCC vectorise it (the
/// same loop inline stays scalar: "no vectype for stmt").
void eliminate_row(int nx, real g, real inv_norm, const real* __restrict D,
                   const real* __restrict cprev, const real* __restrict prprev,
                   const real* __restrict prev, real* __restrict cp, real* __restrict pr,
                   real* __restrict r) {
    for (int i = 0; i < nx; ++i) {
        const real inv = 1.0 / (D[i] + g * cprev[i]);
        cp[i] = -g * inv;
        pr[i] = g * inv * prprev[i];
        r[i] = (r[i] * inv_norm + g * prev[i]) * inv;
    }
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
                real* r = base + k * plane;
                eliminate_row(nx, g, inv_norm, D, cprev, prprev, k == 0 ? zero.data() : r - plane,
                              cp, pr, r);
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

} // namespace efsi

// Whole-block sweeps of the flow step, written for the memory system: unit-stride inner
// loops over raw rows, neighbours as constant offsets, directions unrolled at compile time
// (templates on the component and the dimension), one pass per output field.
//
// They compute exactly the stencils of operators/flow_operators.hpp (the pointwise kernels
// stay the reference and serve variable viscosity, patches and tests); divisions by h are
// multiplications by 1/h, so results agree with the pointwise kernels to round-off, not bit
// for bit. Every field of a block has the same layout (owned cells plus the same halo), which
// is checked once per sweep, so one index serves all fields of a sweep.
#pragma once

#include "core/error.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace efsi::sweep {

/// Offsets of the ±1 neighbours in each direction and the index of a row's first cell.
struct Layout {
    std::ptrdiff_t s[3];
    Int3 n; ///< owned cells
    explicit Layout(const Field& f) : n(f.cells()) {
        s[0] = 1;
        s[1] = std::ptrdiff_t(f.extent()[0]);
        s[2] = std::ptrdiff_t(f.extent()[0]) * std::ptrdiff_t(f.extent()[1]);
    }
    std::ptrdiff_t row(const Field& f, int j, int k) const {
        return std::ptrdiff_t(f.index(0, j, k));
    }
};

inline void require_same_layout(const Field& a, const Field& b) {
    if (a.extent() != b.extent() || a.begin() != b.begin())
        throw std::logic_error("sweep: fields " + a.name() + " and " + b.name() +
                               " differ in layout");
}

/// Rows of the owned block: f(j, k).
template <class F>
inline void for_each_row(const Int3& n, F&& f) {
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            f(j, k);
}

/// The fixed wall faces of component C in row (j, k) (the low c-face on a wall) are set to
/// zero; returns the first point of the row left to compute (n0 when the whole row is wall).
template <int C>
inline int zero_wall_faces(bool wall_at_low_c, int j, int k, int n0, real* row) {
    if (!wall_at_low_c) return 0;
    if (C == 0) {
        row[0] = 0;
        return 1;
    }
    if ((C == 1 && j == 0) || (C == 2 && k == 0)) {
        std::fill(row, row + n0, real(0));
        return n0;
    }
    return 0;
}

/// adv_c = -div(u u_c) at the c-faces (Harlow & Welch conservative central form).
///
/// Row by row over unit-stride restrict pointers (one per neighbour row, so the inner loop is
/// plain streams the compiler vectorises without alias checks). The momentum flux through a
/// face is shared by the two cells on either side of it, so it is computed once: along x
/// into a row buffer that is then differenced, along y and z kept from the previous row and
/// plane (the rows run with y, then z, increasing), which halves the arithmetic and loads.
/// Every flux is the same expression, evaluated in the same order, as before, so the result
/// is bit for bit that of the direct two-flux form (and of flow_operators.hpp to round-off).
template <int C, int Dim>
void advection(const VelocityField& u, const GlobalGrid& g, Field& adv) {
    const Layout L(u[C]);
    real inv[3];
    for (int e = 0; e < 3; ++e)
        inv[e] = e < Dim ? 1.0 / g.dx(e) : 0.0;
    const real* uc = u[C].data().data();
    const real* ue[3] = {u[0].data().data(), u[1].data().data(),
                         Dim > 2 ? u[2].data().data() : nullptr};
    real* out = adv.data().data();
    const std::ptrdiff_t sc = L.s[C];
    const int n0 = L.n[0];
    // x fluxes of the row at faces i - 1/2 (C != 0: the (c,x) edges; C == 0: cell centres),
    // i = 0..n0, stored at fx[i].
    std::vector<real> fx_buf(std::size_t(n0) + 1);
    real* __restrict fx = fx_buf.data();
    // y and z fluxes through the high edges of the previous row / plane (see below).
    std::vector<real> fy_buf(C != 1 ? std::size_t(n0) : 0);
    std::vector<real> fz_buf(Dim > 2 && C != 2 ? std::size_t(n0) * std::size_t(L.n[1]) : 0);
    real* fy = fy_buf.data();
    real* fz = fz_buf.data();
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u[C], j, k);
        const real* __restrict c0 = uc + r;
        real* __restrict o = out + r;
        if constexpr (C == 0) {
            // (u u) at cell centres i - 1 + 1/2: hi of point i - 1 = lo of point i.
            for (int i = 0; i <= n0; ++i) {
                const real h = 0.5 * (c0[i - 1] + c0[i]);
                fx[i] = h * h;
            }
        } else {
            // flux u_x u_c on the (c,x) edge between points i - 1 and i
            const real* __restrict w0 = ue[0] + r;
            for (int i = 0; i <= n0; ++i)
                fx[i] = 0.25 * (w0[i] + w0[i - sc]) * (c0[i] + c0[i - 1]);
        }
        const real ix = inv[0];
        if constexpr (C == 0) {
            for (int i = 0; i < n0; ++i)
                o[i] = (fx[i + 1] - fx[i]) * ix;
        } else {
            // the c-direction term
            const real* __restrict cp = c0 + sc;
            const real* __restrict cm = c0 - sc;
            const real icc = inv[C];
            for (int i = 0; i < n0; ++i) {
                const real hi = 0.5 * (c0[i] + cp[i]);
                const real lo = 0.5 * (cm[i] + c0[i]);
                o[i] = (hi * hi - lo * lo) * icc + (fx[i + 1] - fx[i]) * ix;
            }
        }
#pragma GCC unroll 3
        for (int e = 1; e < Dim; ++e) {
            if (e == C) continue;
            const std::ptrdiff_t se = L.s[e];
            const real* __restrict wp = ue[e] + r + se;
            const real* __restrict wpm = ue[e] + r + se - sc;
            const real* __restrict cp = c0 + se;
            const real ie = inv[e];
            // The flux through the low (c,e) edge is the previous row's (y) or plane's (z)
            // high one, kept in a buffer; computed afresh on the block's first row / plane.
            real* __restrict prev = e == 1 ? fy : fz + std::ptrdiff_t(j) * n0;
            if ((e == 1 ? j : k) == 0) {
                const real* __restrict w0 = ue[e] + r;      // w at m
                const real* __restrict wm = ue[e] + r - sc; // w at m - sc
                const real* __restrict cm = c0 - se;
                for (int i = 0; i < n0; ++i)
                    prev[i] = 0.25 * (w0[i] + wm[i]) * (c0[i] + cm[i]);
            }
            for (int i = 0; i < n0; ++i) {
                // flux u_e u_c on the (c,e) edges of cells m + e_e and m
                const real fh = 0.25 * (wp[i] + wpm[i]) * (cp[i] + c0[i]);
                o[i] += (fh - prev[i]) * ie;
                prev[i] = fh;
            }
        }
        for (int i = 0; i < n0; ++i)
            o[i] = -o[i];
    });
}

/// What the predictor adds to v^n, per unit time, at the c-faces, for uniform viscosity:
///   v* = v^n + dt [a1 (A + F/rho) + a0 A_prev + (b_c - grad p) / rho + nu_expl lap(v_c)]
/// `force` may be null; when given, F/rho is added into `adv` too (it joins the history).
/// The first `skip_low` rows/points of the c-faces on a wall are left to the caller.
struct PredictorCoefficients {
    real a1, a0, dt, inv_rho, body_force, nu_explicit; ///< nu_explicit = (1-theta) mu / rho
};

template <int C, int Dim>
void predictor(const VelocityField& u, const Field& p, Field& adv, const Field& adv_prev,
               const Field* force, const GlobalGrid& g, const PredictorCoefficients& k_,
               bool wall_at_low_c, Field& ustar) {
    const Layout L(u[C]);
    real inv[3], inv2[3];
    for (int e = 0; e < 3; ++e) {
        inv[e] = e < Dim ? 1.0 / g.dx(e) : 0.0;
        inv2[e] = inv[e] * inv[e];
    }
    const real* uc = u[C].data().data();
    const real* pp = p.data().data();
    real* a = adv.data().data();
    const real* ap = adv_prev.data().data();
    const real* f = force ? force->data().data() : nullptr;
    real* out = ustar.data().data();
    const std::ptrdiff_t sc = L.s[C];
    const real gp = inv[C] * k_.inv_rho, bf = k_.body_force * k_.inv_rho;
    const bool viscous = k_.nu_explicit != 0;
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u[C], j, k);
        const int i0 = zero_wall_faces<C>(wall_at_low_c, j, k, L.n[0], out + r);
        if (i0 == L.n[0]) return;
        if (f)
            for (int i = i0; i < L.n[0]; ++i)
                a[r + i] += f[r + i] * k_.inv_rho;
        for (int i = i0; i < L.n[0]; ++i) {
            const std::ptrdiff_t m = r + i;
            real rate = k_.a1 * a[m] + k_.a0 * ap[m] - (pp[m] - pp[m - sc]) * gp + bf;
            if (viscous) {
                real lap = 0;
#pragma GCC unroll 3
                for (int e = 0; e < Dim; ++e)
                    lap += (uc[m - L.s[e]] + uc[m + L.s[e]] - 2 * uc[m]) * inv2[e];
                rate += k_.nu_explicit * lap;
            }
            out[m] = uc[m] + k_.dt * rate;
        }
    });
}

/// The predictor for a viscosity field mu whose transpose term is not needed (mu uniform in
/// value, as with pinned solids of the fluid's viscosity) and for pinned solids (`pin`, may be
/// null: K = dt chi / tau, dividing v* when the viscous term is all explicit): the expressions
/// of SmacStepper's pointwise form (gradient_at, viscous_laplacian_at with its edge
/// viscosities, / rho), in the same order, so the same values bit for bit, row by row.
struct PredictorFieldCoefficients {
    real a1, a0, dt, rho, body_force, explicit_share;
};

template <int C, int Dim>
void predictor_viscosity_field(const VelocityField& u, const Field& p, const Field& mu, Field& adv,
                               const Field& adv_prev, const Field* force, const Field* pin,
                               const GlobalGrid& g, const PredictorFieldCoefficients& k_,
                               bool wall_at_low_c, Field& ustar) {
    const Layout L(u[C]);
    real h2[3] = {1, 1, 1};
    for (int e = 0; e < Dim; ++e)
        h2[e] = g.dx(e) * g.dx(e);
    const real hc = g.dx(C);
    const real* uc = u[C].data().data();
    const real* pp = p.data().data();
    const real* m_ = mu.data().data();
    real* a = adv.data().data();
    const real* ap = adv_prev.data().data();
    const real* f = force ? force->data().data() : nullptr;
    const real* kp = pin && k_.explicit_share == 1.0 ? pin->data().data() : nullptr;
    real* out = ustar.data().data();
    const std::ptrdiff_t sc = L.s[C];
    const real rho = k_.rho;
    const bool viscous = k_.explicit_share > 0;
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u[C], j, k);
        const int i0 = zero_wall_faces<C>(wall_at_low_c, j, k, L.n[0], out + r);
        if (i0 == L.n[0]) return;
        if (f)
            for (int i = i0; i < L.n[0]; ++i)
                a[r + i] += f[r + i] / rho;
        for (int i = i0; i < L.n[0]; ++i) {
            const std::ptrdiff_t m = r + i;
            real rate = k_.a1 * a[m] + k_.a0 * ap[m];
            rate += (-((pp[m] - pp[m - sc]) / hc) + k_.body_force) / rho;
            if (viscous) {
                const real u0 = uc[m];
                real acc = 0;
#pragma GCC unroll 3
                for (int e = 0; e < Dim; ++e) {
                    const std::ptrdiff_t se = L.s[e];
                    real w0, w1;
                    if (e == C) {
                        w0 = m_[m - sc] / h2[e];
                        w1 = m_[m] / h2[e];
                    } else {
                        w0 = 0.25 * (m_[m] + m_[m - sc] + m_[m - se] + m_[m - sc - se]) / h2[e];
                        w1 = 0.25 * (m_[m + se] + m_[m + se - sc] + m_[m] + m_[m - sc]) / h2[e];
                    }
                    acc += w0 * (uc[m - se] - u0) + w1 * (uc[m + se] - u0);
                }
                rate += k_.explicit_share * acc / rho;
            }
            out[m] = uc[m] + k_.dt * rate;
            if (kp) out[m] /= 1.0 + kp[m];
        }
    });
}

/// max(m, |x_i|) over a row; exact whatever the order, so vectorised (SSE2 max on two lanes)
/// where the compiler will not vectorise a floating-point max reduction itself. NaNs are
/// skipped as std::max(m, x) skips them (max_pd returns its second operand, m, then).
inline real max_abs(const real* __restrict x, int n, real m) {
    int i = 0;
#if defined(__SSE2__)
    const __m128d sign = _mm_set1_pd(-0.0);
    __m128d a = _mm_set1_pd(m), b = a;
    for (; i + 4 <= n; i += 4) {
        a = _mm_max_pd(_mm_andnot_pd(sign, _mm_loadu_pd(x + i)), a);
        b = _mm_max_pd(_mm_andnot_pd(sign, _mm_loadu_pd(x + i + 2)), b);
    }
    a = _mm_max_pd(a, b);
    double lanes[2];
    _mm_storeu_pd(lanes, a);
    m = std::max(lanes[0], lanes[1]);
#endif
    for (; i < n; ++i)
        m = std::max(m, std::abs(x[i]));
    return m;
}

/// -scale div(v) at the cell centres of row (j, k) of the owned block, written to
/// out_row(j, k) (a pointer to the row's first owned point: a field's row, or a solver's
/// buffer); returns max |v| over the owned faces swept when Speed (the iterative solve's
/// stopping floor needs it; the direct solve does not).
template <int Dim, bool Speed, class OutRow>
real divergence_rows(const VelocityField& u, const GlobalGrid& g, real scale, OutRow&& out_row) {
    const Layout L(u[0]);
    real inv[3];
    for (int e = 0; e < 3; ++e)
        inv[e] = e < Dim ? scale / g.dx(e) : 0.0;
    const real* v[3] = {u[0].data().data(), u[1].data().data(),
                        Dim > 2 ? u[2].data().data() : nullptr};
    const int n0 = L.n[0];
    real speed = 0;
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u[0], j, k);
        const real* __restrict x0 = v[0] + r;
        const real* __restrict y0 = v[1] + r;
        const real* __restrict y1 = v[1] + r + L.s[1];
        real* __restrict o = out_row(j, k);
        if constexpr (Dim == 2) {
            for (int i = 0; i < n0; ++i)
                o[i] = -((x0[i + 1] - x0[i]) * inv[0] + (y1[i] - y0[i]) * inv[1]);
        } else {
            const real* __restrict z0 = v[2] + r;
            const real* __restrict z1 = v[2] + r + L.s[2];
            for (int i = 0; i < n0; ++i)
                o[i] = -(((x0[i + 1] - x0[i]) * inv[0] + (y1[i] - y0[i]) * inv[1]) +
                         (z1[i] - z0[i]) * inv[2]);
        }
        if constexpr (Speed)
            for (int e = 0; e < Dim; ++e)
                speed = max_abs(v[e] + r, n0, speed);
    });
    return speed;
}

/// rhs = -scale div(v) at the cell centres (divergence_rows into a field of u's layout).
template <int Dim, bool Speed = true>
real divergence(const VelocityField& u, const GlobalGrid& g, real scale, Field& rhs) {
    require_same_layout(u[0], rhs);
    const Layout L(rhs);
    real* out = rhs.data().data();
    return divergence_rows<Dim, Speed>(u, g, scale,
                                       [&](int j, int k) { return out + L.row(rhs, j, k); });
}

/// v_c = v*_c - scale grad_c phi at the c-faces (0 on a fixed wall face).
template <int C, int Dim>
void correction(const Field& ustar, const Field& phi, const GlobalGrid& g, real scale,
                bool wall_at_low_c, Field& u) {
    const Layout L(u);
    const real gs = scale / g.dx(C);
    const real* us = ustar.data().data();
    const real* ph = phi.data().data();
    real* out = u.data().data();
    const std::ptrdiff_t sc = L.s[C];
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u, j, k);
        const int i0 = zero_wall_faces<C>(wall_at_low_c, j, k, L.n[0], out + r);
        if (i0 == L.n[0]) return;
        for (int i = i0; i < L.n[0]; ++i) {
            const std::ptrdiff_t m = r + i;
            out[m] = us[m] - (ph[m] - ph[m - sc]) * gs;
        }
    });
}

/// Call f.template operator()<C, Dim>() for each component C < dim (Dim = dim).
template <class F>
inline void for_each_component(int dim, F&& f) {
    if (dim == 2) {
        f.template operator()<0, 2>();
        f.template operator()<1, 2>();
    } else {
        f.template operator()<0, 3>();
        f.template operator()<1, 3>();
        f.template operator()<2, 3>();
    }
}

} // namespace efsi::sweep

// THINC reconstructions of a volume fraction inside one cell, and the integrals of the
// reconstruction over a sub-box of the cell: the pointwise kernels of VOF advection.
//
// All geometry here is in unit-cell coordinates (cell widths scaled to 1), so the kernels
// know nothing about the grid; the loop drivers in vof_advection.cpp map to physical space.
//
// 1D THINC (Xiao, Honma & Kono 2005), cell coordinate X in [0, 1]:
//     H(X) = (1/2) (1 + gamma tanh(beta (X - Xc))),
// gamma = +-1 the orientation of the jump (sign of phi_{i+1} - phi_{i-1}), beta its
// sharpness (transition ~ 2/beta cells), Xc the jump position fixed by int_0^1 H = phi.
//
// Multidimensional THINC (MTHINC, Ii, Sugiyama, Takeuchi, Takagi & Matsumoto, JCP 231
// (2012) 2328), X in [-1/2, 1/2]^dim:
//     H(X) = (1/2) (1 + tanh(beta (n . X + d))),
// n the unit normal pointing into the body (up grad phi), d fixed by the cell average.
// As in Ii et al., volume integrals of H are taken exactly along the direction m of the
// largest |n_m| (where H has a closed-form primitive, ln cosh) and by Gauss-Legendre
// quadrature (2 points) in the other directions; the same rule defines d and the fluxes, so
// a flux never exceeds what the reconstruction puts in the cell. We keep the linear
// (planar) level n . X; Ii et al. also add a quadratic curvature term, not done here.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace efsi {

/// ln cosh(z) without overflow: |z| + ln(1 + e^{-2|z|}) - ln 2.
inline real log_cosh(real z) {
    const real a = std::abs(z);
    return a + std::log1p(std::exp(-2 * a)) - std::numbers::ln2;
}

// ---------------------------------------------------------------- 1D THINC

struct Thinc1D {
    real gamma = 1; ///< +1: phi increases with X; -1: decreases
    real beta = 3.5;
    real centre = 0.5; ///< jump position Xc in cell units
};

/// Jump position for cell average phi in (0, 1). From int_0^1 H dX = phi:
///   ln cosh(beta (1 - Xc)) - ln cosh(beta Xc) = beta s,  s = gamma (2 phi - 1),
/// and cosh(beta - y) = cosh(beta) cosh(y) - sinh(beta) sinh(y) with y = beta Xc gives
///   tanh(beta Xc) = (cosh(beta) - e^{beta s}) / sinh(beta).
inline Thinc1D thinc1d_reconstruct(real phi, real gamma, real beta) {
    const real s = gamma * (2 * phi - 1);
    const real t = (std::cosh(beta) - std::exp(beta * s)) / std::sinh(beta);
    return {gamma, beta, std::atanh(t) / beta};
}

/// int_a^b H(X) dX for 0 <= a <= b <= 1.
inline real thinc1d_integral(const Thinc1D& h, real a, real b) {
    return 0.5 *
           ((b - a) + h.gamma / h.beta *
                          (log_cosh(h.beta * (b - h.centre)) - log_cosh(h.beta * (a - h.centre))));
}

// ---------------------------------------------------------------- MTHINC

struct Mthinc {
    Real3 n{0, 0, 0}; ///< unit normal in unit-cell coordinates, into the body
    real beta = 1;
    real d = 0; ///< level offset
    int m = 0;  ///< direction integrated exactly (largest |n_m|)
    int dim = 3;
};

/// int over the box [lo, hi] (unit-cell coordinates, only the first dim entries used) of
/// H = (1/2)(1 + tanh(beta (n.X + d))); exact along m, 2-point Gauss in the others.
/// With q = n.X - n_m X_m + d,
///   int_lo^hi H dX_m = (1/2) [ (hi - lo) + (ln cosh(beta(n_m hi + q)) -
///                                            ln cosh(beta(n_m lo + q))) / (beta n_m) ].
/// `dd` receives the derivative of the integral with respect to d (for Newton).
inline real mthinc_box_integral(const Mthinc& r, const Real3& lo, const Real3& hi,
                                real* dd = nullptr) {
    constexpr real g = 0.5773502691896257645; // 1/sqrt(3): Gauss points at +-g on [-1, 1]
    int others[2] = {0, 0};
    int no = 0;
    real weight = 1; // product of the half-lengths of the Gauss directions (weights 1 each)
    for (int e = 0; e < r.dim; ++e)
        if (e != r.m) {
            others[no++] = e;
            weight *= 0.5 * (hi[e] - lo[e]);
        }
    const real nm = r.n[r.m];
    const real len = hi[r.m] - lo[r.m];
    real sum = 0, dsum = 0;
    for (int q = 0; q < (1 << no); ++q) {
        real level = r.d;
        for (int a = 0; a < no; ++a) {
            const int e = others[a];
            const real mid = 0.5 * (lo[e] + hi[e]), half = 0.5 * (hi[e] - lo[e]);
            level += r.n[e] * (mid + ((q >> a) & 1 ? g : -g) * half);
        }
        const real zh = r.beta * (nm * hi[r.m] + level), zl = r.beta * (nm * lo[r.m] + level);
        sum += 0.5 * (len + (log_cosh(zh) - log_cosh(zl)) / (r.beta * nm));
        dsum += 0.5 * (std::tanh(zh) - std::tanh(zl)) / nm;
    }
    if (dd) *dd = weight * dsum;
    return weight * sum;
}

/// Reconstruction of a cell with average phi in (0, 1) and normal direction `grad`
/// (any length > 0, unit-cell coordinates): finds d with int_cell H = phi by Newton's
/// method safeguarded by bisection (the integral increases monotonically with d).
inline Mthinc mthinc_reconstruct(real phi, const Real3& grad, real beta, int dim) {
    Mthinc r;
    r.beta = beta;
    r.dim = dim;
    real len2 = 0;
    for (int e = 0; e < dim; ++e)
        len2 += grad[e] * grad[e];
    const real len = std::sqrt(len2);
    for (int e = 0; e < dim; ++e) {
        r.n[e] = grad[e] / len;
        if (std::abs(r.n[e]) > std::abs(r.n[r.m])) r.m = e;
    }
    const Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
    // |n.X| <= sqrt(dim)/2 in the cell; 20/beta more makes tanh = +-1 to round-off.
    real a = -std::sqrt(real(dim)) / 2 - 20 / beta, b = -a;
    // Start from the closed form that ignores the transverse components of n (the 1D
    // profile along m with slope n_m):  tanh(beta d) = tanh(beta n_m (phi - 1/2)) /
    // tanh(beta n_m / 2) (even in n_m); Newton then needs a few iterations, not ~10.
    const real bn = beta * std::abs(r.n[r.m]);
    const real t = std::tanh(bn * (phi - 0.5)) / std::tanh(0.5 * bn);
    r.d = std::clamp(std::atanh(std::clamp(t, -1 + 1e-15, 1 - 1e-15)) / beta, a, b);
    for (int it = 0; it < 100; ++it) {
        real slope = 0;
        const real f = mthinc_box_integral(r, lo, hi, &slope) - phi;
        if (std::abs(f) < 1e-15) break;
        (f > 0 ? b : a) = r.d;
        real next = slope > 0 ? r.d - f / slope : 0.5 * (a + b);
        if (!(next > a && next < b)) next = 0.5 * (a + b);
        if (b - a < 1e-15) break;
        r.d = next;
    }
    return r;
}

/// The flux of one face in one call: mthinc_reconstruct(phi, grad, beta, dim) followed by
/// mthinc_box_integral over the slab of width `a` at the high (`positive`) or low end of
/// the cell along d, bit-identical to the two calls but with fewer transcendental calls:
/// Newton takes tanh (the slope) only in the iterations that use it, not in the one that
/// finds it has converged; and when d is the exact direction m, the slab shares its face on
/// the cell boundary with the whole cell, so ln cosh there comes from the last Newton
/// evaluation (when that was at the final d: always, unless Newton hit its iteration
/// limit). The values are computed with the same expressions in the same order as there.
inline real mthinc_slab_integral(real phi, const Real3& grad, real beta, int dim, int d, real a,
                                 bool positive) {
    constexpr real g = 0.5773502691896257645;
    Mthinc r;
    r.beta = beta;
    r.dim = dim;
    real len2 = 0;
    for (int e = 0; e < dim; ++e)
        len2 += grad[e] * grad[e];
    const real len = std::sqrt(len2);
    for (int e = 0; e < dim; ++e) {
        r.n[e] = grad[e] / len;
        if (std::abs(r.n[e]) > std::abs(r.n[r.m])) r.m = e;
    }
    // The Gauss points of the whole cell, as mthinc_box_integral takes them for lo = -1/2,
    // hi = 1/2: mid = 0 and half = 1/2 in the transverse directions.
    int others[2] = {0, 0};
    int no = 0;
    real weight = 1;
    for (int e = 0; e < dim; ++e)
        if (e != r.m) {
            others[no++] = e;
            weight *= 0.5 * (0.5 - -0.5);
        }
    const int nq = 1 << no;
    real term[4][2] = {}; // n_e (mid + (+-g) half): Gauss point q, transverse direction ax
    for (int q = 0; q < nq; ++q)
        for (int ax = 0; ax < no; ++ax) {
            const real mid = 0.5 * (-0.5 + 0.5), half = 0.5 * (0.5 - -0.5);
            term[q][ax] = r.n[others[ax]] * (mid + ((q >> ax) & 1 ? g : -g) * half);
        }
    const real nm = r.n[r.m];
    real level[4], zh[4], zl[4], lch[4], lcl[4];
    real d_eval = 0;
    bool evaluated = false;
    // int_cell H at r.d, keeping the levels, the arguments and ln cosh of each Gauss point.
    auto cell_integral = [&]() {
        real sum = 0;
        for (int q = 0; q < nq; ++q) {
            level[q] = r.d;
            for (int ax = 0; ax < no; ++ax)
                level[q] += term[q][ax];
            zh[q] = r.beta * (nm * 0.5 + level[q]);
            zl[q] = r.beta * (nm * -0.5 + level[q]);
            lch[q] = log_cosh(zh[q]);
            lcl[q] = log_cosh(zl[q]);
            sum += 0.5 * ((0.5 - -0.5) + (lch[q] - lcl[q]) / (r.beta * nm));
        }
        d_eval = r.d;
        evaluated = true;
        return weight * sum;
    };
    auto cell_slope = [&]() {
        real dsum = 0;
        for (int q = 0; q < nq; ++q)
            dsum += 0.5 * (std::tanh(zh[q]) - std::tanh(zl[q])) / nm;
        return weight * dsum;
    };
    // mthinc_reconstruct's Newton iteration (see there), bracket [lo_d, hi_d].
    real lo_d = -std::sqrt(real(dim)) / 2 - 20 / beta, hi_d = -lo_d;
    const real bn = beta * std::abs(r.n[r.m]);
    const real t = std::tanh(bn * (phi - 0.5)) / std::tanh(0.5 * bn);
    r.d = std::clamp(std::atanh(std::clamp(t, -1 + 1e-15, 1 - 1e-15)) / beta, lo_d, hi_d);
    for (int it = 0; it < 100; ++it) {
        const real f = cell_integral() - phi;
        if (std::abs(f) < 1e-15) break;
        (f > 0 ? hi_d : lo_d) = r.d;
        const real slope = cell_slope();
        real next = slope > 0 ? r.d - f / slope : 0.5 * (lo_d + hi_d);
        if (!(next > lo_d && next < hi_d)) next = 0.5 * (lo_d + hi_d);
        if (hi_d - lo_d < 1e-15) break;
        r.d = next;
    }
    Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
    if (positive)
        lo[d] = 0.5 - a;
    else
        hi[d] = -0.5 + a;
    if (d != r.m || !evaluated || r.d != d_eval) return mthinc_box_integral(r, lo, hi);
    // d = m: the slab spans the cell transversely, so its Gauss levels are the cell's.
    const real slab = hi[r.m] - lo[r.m];
    real sum = 0;
    for (int q = 0; q < nq; ++q) {
        const real ch = positive ? lch[q] : log_cosh(r.beta * (nm * hi[r.m] + level[q]));
        const real cl = positive ? log_cosh(r.beta * (nm * lo[r.m] + level[q])) : lcl[q];
        sum += 0.5 * (slab + (ch - cl) / (r.beta * nm));
    }
    return weight * sum;
}

} // namespace efsi

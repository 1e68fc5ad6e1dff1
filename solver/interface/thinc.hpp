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
// largest |n_m| (where H has a closed-form primitive: ln cosh up to a linear term, written
// here as ln(1 + e^{2z})/2 so that an iteration for d costs one exp and one log, see
// MthincBoxRule) and by Gauss-Legendre quadrature (2 points) in the other directions; the
// same rule defines d and the fluxes, so a flux never exceeds what the reconstruction puts
// in the cell. We keep the linear (planar) level n . X; Ii et al. also add a quadratic
// curvature term, not done here.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
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

/// Largest MTHINC beta the closed form below takes. Over the bracket of the iteration for d
/// |d| <= sqrt(dim)/2 + 20/beta, so |z_q| <= beta (sqrt(3)/2 + 1/2 + 1/3) + 20: at
/// beta = 50, x_q <= e^{210}, (x_q + 1)(x_q + G) <= e^{420} and the product of the ratios
/// <= G^4 <= e^{400}, so nothing overflows. Such a beta already makes H a step (jump
/// 2/beta = 0.04 cells wide).
inline constexpr real mthinc_beta_max = 50;

/// The MTHINC integral over one box [lo, hi] as a function of the level offset d, for a
/// fixed normal: exact along m, 2-point Gauss in the other directions (mthinc_box_integral).
///
/// Along m, (1 + tanh z)/2 has the primitive ln(1 + e^{2z})/2, so at the Gauss point q
/// (transverse level t_q = sum_{e != m} n_e X_e) the line integral is
///     int_lo^hi H dX_m = ln[(x_q + G) / (x_q + 1)] / (2 beta n_m),
///     x_q = e^{-2 z_q},  z_q = beta (n_m lo_m + t_q + d),  G = e^{2 beta n_m (hi_m - lo_m)},
/// (z_q the argument at the low end of the line), and its derivative with respect to d is
///     (H(z_hi) - H(z_lo)) / n_m = x_q (G - 1) / ((x_q + 1)(x_q + G) n_m).
/// x_q = e^{-2 beta (n_m lo_m + d)} F_q with F_q = e^{-2 beta t_q} fixed by the box, so
/// an evaluation at a new d (an iteration) takes one exp for all the Gauss points,
/// and their sum of logarithms is the log of one product: one exp and one log, where the
/// sum of ln cosh differences took 2^dim exp and 2^dim log1p (and as many tanh for the
/// slope). F_q is a product over the transverse directions of e^{-2 beta n_e X_e}, so a
/// box that spans the cell in one of them shares that direction's factors with the cell.
/// Nothing overflows for beta <= mthinc_beta_max (see there), and the absolute
/// round-off of a ratio (1e-16, ratios between 1 and G) is that of phi itself.
class MthincBoxRule {
  public:
    MthincBoxRule() = default;
    /// The rule of r's normal over [lo, hi]. `cell` (optional) is the rule of the same
    /// normal over the whole cell: its Gauss-point factors are reused in each transverse
    /// direction the box spans, its G when the box spans it along m (same values: the
    /// same expressions of the same numbers).
    MthincBoxRule(const Mthinc& r, const Real3& lo, const Real3& hi,
                  const MthincBoxRule* cell = nullptr)
        : beta_(r.beta), nm_(r.n[r.m]) {
        constexpr real g = 0.5773502691896257645; // 1/sqrt(3): Gauss points at +-g on [-1, 1]
        real weight = 1; // Gauss weights 1 times the transverse half-lengths
        int no = 0;
        for (int e = 0; e < r.dim; ++e) {
            if (e == r.m) continue;
            const int a = no++;
            weight *= 0.5 * (hi[e] - lo[e]);
            if (cell && lo[e] == -0.5 && hi[e] == 0.5) {
                pair_[a][0] = cell->pair_[a][0];
                pair_[a][1] = cell->pair_[a][1];
                continue;
            }
            // e^{-2 beta n_e X_e} at the two Gauss points X_e = mid -+ g half, as M / Q and
            // M Q: one exp for a direction centred in the cell (M = 1), two otherwise.
            const real mid = 0.5 * (lo[e] + hi[e]), half = 0.5 * (hi[e] - lo[e]);
            const real m = mid == 0 ? 1 : std::exp(-2 * beta_ * r.n[e] * mid);
            const real q = std::exp(-2 * beta_ * r.n[e] * g * half);
            pair_[a][0] = m / q;
            pair_[a][1] = m * q;
        }
        nq_ = 1 << no;
        for (int q = 0; q < nq_; ++q) {
            real f = 1;
            for (int a = 0; a < no; ++a)
                f *= pair_[a][(q >> a) & 1];
            factor_[q] = f;
        }
        low_ = nm_ * lo[r.m];
        growth_ = cell && lo[r.m] == -0.5 && hi[r.m] == 0.5
                      ? cell->growth_
                      : std::exp(2 * beta_ * nm_ * (hi[r.m] - lo[r.m]));
        scale_ = weight / (2 * beta_ * nm_);
        slope_scale_ = weight * (growth_ - 1) / nm_;
    }

    /// int_box H at level offset d; `dd` (if given) receives its derivative in d and `d2`
    /// (if given) its second derivative, (x_q (G - x_q^2) / ((x_q + 1)(x_q + G))^2) summed,
    /// times -2 beta (G - 1) weight / n_m.
    real integral(real d, real* dd = nullptr, real* d2 = nullptr) const {
        const real e = std::exp(-2 * beta_ * (low_ + d));
        real ratio = 1, slope = 0, bend = 0;
        for (int q = 0; q < nq_; ++q) {
            const real x = e * factor_[q], xl = x + 1, xh = x + growth_;
            const real inv = 1 / (xl * xh); // one division for the ratio and the slopes
            ratio *= xh * xh * inv;
            slope += x * inv;
            bend += x * (growth_ - x * x) * inv * inv;
        }
        if (dd) *dd = slope_scale_ * slope;
        if (d2) *d2 = -2 * beta_ * slope_scale_ * bend;
        return scale_ * std::log(ratio);
    }

    /// The level offset d of the cell's 1D profile along m alone (transverse components of
    /// n left out) with cell average phi: for the whole cell (lo_m = -1/2, one Gauss point)
    /// ln[(x + G)/(x + 1)] = 2 beta n_m phi gives x = (G - P)/(P - 1), P = e^{2 beta n_m phi}.
    /// The iteration's starting point (the closed form tanh(beta d) = tanh(beta n_m (phi - 1/2)) /
    /// tanh(beta n_m / 2) in other terms). Only for a rule over the whole cell.
    real profile_level(real phi) const {
        const real p = std::exp(2 * beta_ * nm_ * phi);
        return 0.5 * nm_ - std::log((growth_ - p) / (p - 1)) / (2 * beta_);
    }

  private:
    real beta_;
    real nm_;
    real low_ = 0;         ///< n_m lo_m: the level of the low end of the lines, less t_q and d
    real growth_ = 1;      ///< G
    real scale_ = 1;       ///< weight / (2 beta n_m)
    real slope_scale_ = 1; ///< weight (G - 1) / n_m
    real factor_[4] = {1, 1, 1, 1};      ///< F_q
    real pair_[2][2] = {{1, 1}, {1, 1}}; ///< e^{-2 beta n_e X_e} at the Gauss points, per direction
    int nq_ = 1;
};

/// int over the box [lo, hi] (unit-cell coordinates, only the first dim entries used) of
/// H = (1/2)(1 + tanh(beta (n.X + d))); exact along m, 2-point Gauss in the others
/// (MthincBoxRule). `dd` receives the derivative of the integral with respect to d.
inline real mthinc_box_integral(const Mthinc& r, const Real3& lo, const Real3& hi,
                                real* dd = nullptr) {
    return MthincBoxRule(r, lo, hi).integral(r.d, dd);
}

/// The reconstruction's normal: n = grad / |grad| (grad any length > 0, unit-cell
/// coordinates) and m the direction of its largest component; d left at 0.
inline Mthinc mthinc_normal(const Real3& grad, real beta, int dim) {
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
    return r;
}

/// The iteration for the level offset d of one cell (int_cell H = phi in (0, 1), `cell`
/// the rule of r's normal over the whole cell): Halley's method (third order; the rule
/// gives the second derivative at no extra exp or log) on a bracket [a, b] that each
/// evaluation narrows (the integral increases monotonically with d), a step leaving the
/// bracket replaced by bisection. It starts from the 1D profile along m
/// (MthincBoxRule::profile_level) and takes mthinc_level_steps steps with no test in
/// between, so that the steps of several cells interleave (mthinc_slab_integrals) with no
/// branch the processor could mispredict. When the residual of the last of them is below
/// 1e-6 of min(phi, 1 - phi), that step left it at round-off (cubic convergence); else
/// `finish` goes on, testing after each step, to a residual of 1e-15 or a bracket of that
/// width.
struct MthincLevel {
    real a = 0, b = 0; ///< bracket
    real d = 0;        ///< current level
    real phi = 0;
    real close = 0;      ///< 1e-6 min(phi, 1 - phi)
    real f = 1;          ///< residual at the last evaluation
    bool halley = false; ///< the last step was Halley's (or Newton's), not a bisection

    void start(const Mthinc& r, const MthincBoxRule& cell, real phi_) {
        phi = phi_;
        // |n.X| <= sqrt(dim)/2 in the cell; 20/beta more makes tanh = +-1 to round-off.
        a = -std::sqrt(real(r.dim)) / 2 - 20 / r.beta;
        b = -a;
        close = 1e-6 * std::min(phi, 1 - phi);
        // A start lost to round-off (P = 1 or G) is NaN or infinite.
        const real s = cell.profile_level(phi);
        d = std::isnan(s) ? 0 : std::clamp(s, a, b);
    }

    /// One evaluation and one step, written with selects only. A step that lands on the
    /// bracket's end is kept (at a root, f = 0, the step is zero and d stays); one outside
    /// it (or not a number: a zero slope) is a bisection.
    void step(const MthincBoxRule& cell) {
        real slope = 0, bend = 0;
        f = cell.integral(d, &slope, &bend) - phi;
        const bool above = f > 0;
        b = pick(above, d, b);
        a = pick(above, a, d);
        // Halley: d - f f' / (f'^2 - f f'' / 2), one division; Newton (d - f f' / f'^2)
        // where the correction is more than half of f'^2 (far from the root).
        const real s2 = slope * slope, halley_den = s2 - 0.5 * f * bend;
        const real tried = d - f * slope / pick(halley_den > 0.5 * s2, halley_den, s2);
        halley = (tried >= a) & (tried <= b);
        d = pick(halley, tried, 0.5 * (a + b));
    }

    /// `yes ? x : y` by bit masks: the compiler turns a plain conditional into a branch,
    /// which here goes either way at random and costs a pipeline flush when mispredicted.
    static real pick(bool yes, real x, real y) {
        const std::uint64_t mask = -std::uint64_t(yes);
        return std::bit_cast<real>((std::bit_cast<std::uint64_t>(x) & mask) |
                                   (std::bit_cast<std::uint64_t>(y) & ~mask));
    }

    bool converged() const { return halley && std::abs(f) < close; }

    void finish(const MthincBoxRule& cell) {
        for (int it = 0; it < 100 && !converged(); ++it) {
            if (std::abs(f) < 1e-15 || b - a < 1e-15) return;
            step(cell);
        }
    }
};

/// Steps MthincLevel takes before it tests: from the profile's start two or three reach
/// round-off at the betas the schemes use (a smoothed body's 1/smoothing_width, the sharp
/// default 2), so three make the test pass almost always.
inline constexpr int mthinc_level_steps = 3;

/// The level offset d with int_cell H = phi in (0, 1) (MthincLevel).
inline real mthinc_level(const Mthinc& r, const MthincBoxRule& cell, real phi) {
    MthincLevel l;
    l.start(r, cell, phi);
    for (int it = 0; it < mthinc_level_steps; ++it)
        l.step(cell);
    if (!l.converged()) l.finish(cell);
    return l.d;
}

/// Reconstruction of a cell with average phi in (0, 1) and normal direction `grad`
/// (any length > 0, unit-cell coordinates). beta <= mthinc_beta_max.
inline Mthinc mthinc_reconstruct(real phi, const Real3& grad, real beta, int dim) {
    Mthinc r = mthinc_normal(grad, beta, dim);
    r.d = mthinc_level(r, MthincBoxRule(r, {-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}), phi);
    return r;
}

/// The slab integrals of n faces along direction d, one per cell: out[f] =
/// mthinc_slab_integral(phi[f], grad[f], beta, dim, d, |c|, c > 0) with c = courant[f],
/// bit for bit (the same operations in
/// the same order for each face), the cells taken four at a time with their steps
/// interleaved: one cell's iteration is a chain of dependent exp, log and divisions,
/// and four independent chains keep the processor busy where one leaves it waiting.
inline void mthinc_slab_integrals(int n, const real* phi, const Real3* grad, real beta, int dim,
                                  int d, const real* courant, real* out) {
    constexpr int L = 4;
    for (int f0 = 0; f0 < n; f0 += L) {
        const int nl = std::min(L, n - f0);
        Mthinc r[L];
        MthincBoxRule cell[L];
        MthincLevel level[L];
        for (int l = 0; l < nl; ++l) {
            r[l] = mthinc_normal(grad[f0 + l], beta, dim);
            cell[l] = MthincBoxRule(r[l], {-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
        }
        for (int l = 0; l < nl; ++l)
            level[l].start(r[l], cell[l], phi[f0 + l]);
        for (int it = 0; it < mthinc_level_steps; ++it)
            for (int l = 0; l < nl; ++l)
                level[l].step(cell[l]);
        for (int l = 0; l < nl; ++l) {
            if (!level[l].converged()) level[l].finish(cell[l]);
            r[l].d = level[l].d;
        }
        for (int l = 0; l < nl; ++l) {
            Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
            const real c = courant[f0 + l];
            if (c > 0)
                lo[d] = 0.5 - std::abs(c);
            else
                hi[d] = -0.5 + std::abs(c);
            out[f0 + l] = MthincBoxRule(r[l], lo, hi, &cell[l]).integral(r[l].d);
        }
    }
}

/// The flux of one face in one call: mthinc_reconstruct(phi, grad, beta, dim) followed by
/// mthinc_box_integral over the slab of width `a` at the high (`positive`) or low end of
/// the cell along d, bit for bit the same value, the slab's rule reusing the cell's
/// Gauss-point factors (d = m) or G (d != m): mthinc_slab_integrals for one face.
inline real mthinc_slab_integral(real phi, const Real3& grad, real beta, int dim, int d, real a,
                                 bool positive) {
    const real c = positive ? a : -a;
    real v = 0;
    mthinc_slab_integrals(1, &phi, &grad, beta, dim, d, &c, &v);
    return v;
}

} // namespace efsi

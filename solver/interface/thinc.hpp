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

#include "core/lanes.hpp"
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

/// Largest MTHINC beta the closed form below takes. Over the bracket of the iteration for d
/// |d| <= sqrt(dim)/2 + 20/beta, so |z_q| <= beta (sqrt(3)/2 + 1/2 + 1/3) + 20: at
/// beta = 50, x_q <= e^{210}, (x_q + 1)(x_q + G) <= e^{420} and the product of the ratios
/// <= G^4 <= e^{400}, so nothing overflows. Such a beta already makes H a step (jump
/// 2/beta = 0.04 cells wide).
inline constexpr real mthinc_beta_max = 50;

/// The normal of MthincBoxRuleT: n and, per direction e, whether e is m (a mask, so that
/// each lane of a real4 has its own m).
template <class V>
struct MthincNormalT {
    V n[3]{};
    lane_mask<V> is_m[3]{};

    MthincNormalT() = default;
    explicit MthincNormalT(const Mthinc& r) requires(lane_count<V> == 1)
        : n{r.n[0], r.n[1], r.n[2]}, is_m{r.m == 0, r.m == 1, r.m == 2} {}

    /// x[m] in each lane.
    V along_m(const V* x) const { return select(is_m[0], x[0], select(is_m[1], x[1], x[2])); }
};

/// mthinc_normal (below) for `lane_count<V>` gradients at once (grad[e] the components
/// along e): the same operations lane by lane, m the first direction of largest |n_e|.
template <class V>
MthincNormalT<V> mthinc_normal_lanes(const V* grad, int dim) {
    V len2 = splat<V>(0);
    for (int e = 0; e < dim; ++e)
        len2 += grad[e] * grad[e];
    const V len = lane_sqrt(len2);
    MthincNormalT<V> r;
    V m = splat<V>(0), largest{};
    for (int e = 0; e < dim; ++e) {
        r.n[e] = grad[e] / len;
        const V size = lane_abs(r.n[e]);
        if (e == 0) {
            largest = size;
            continue;
        }
        const lane_mask<V> larger = size > largest;
        m = select(larger, splat<V>(e), m);
        largest = select(larger, size, largest);
    }
    for (int e = 0; e < 3; ++e)
        r.is_m[e] = m == e;
    return r;
}

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
///
/// V is real (one box) or real4 (four boxes, one per lane, each with its own normal,
/// direction m and box; beta and dim shared). Lane l of a real4 rule holds bit for bit the
/// values of the real rule of lane l's normal and box: the same operations on the same
/// numbers, lane by lane, and lane_exp, lane_log agree between the two (core/lanes.hpp).
template <class V>
class MthincBoxRuleT {
  public:
    using Mask = lane_mask<V>;
    static constexpr int lanes = lane_count<V>;

    /// The rule of r's normal over [lo, hi]. `cell` (optional) is the rule of the same
    /// normal over the whole cell: its Gauss-point factors are reused in each transverse
    /// direction the box spans, its G when the box spans it along m (same values: the
    /// same expressions of the same numbers).
    MthincBoxRuleT(const Mthinc& r, const Real3& lo, const Real3& hi,
                   const MthincBoxRuleT* cell = nullptr) requires(lanes == 1)
        : MthincBoxRuleT(r.beta, r.dim, MthincNormalT<real>(r), lo.data(), hi.data(), cell) {}

    /// The same for `lanes` normals and boxes at once (lo[e], hi[e] the box's bounds along
    /// e in each lane). Written with selects only: the directions of a lane's Gauss points
    /// (the transverse ones, slot a being direction a below m and a + 1 from m on) are
    /// picked by its masks, and an exp is taken only where some lane needs it.
    MthincBoxRuleT(real beta, int dim, const MthincNormalT<V>& nrm, const V* lo, const V* hi,
                   const MthincBoxRuleT* cell = nullptr)
        : beta_(beta) {
        constexpr real g = 0.5773502691896257645; // 1/sqrt(3): Gauss points at +-g on [-1, 1]
        const V one = splat<V>(1);
        const int no = dim - 1;
        V weight = one; // Gauss weights 1 times the transverse half-lengths
        Mask after_m = nrm.is_m[0];
        for (int a = 0; a < no; ++a) {
            const V n_a = select(after_m, nrm.n[a + 1], nrm.n[a]);
            const V lo_a = select(after_m, lo[a + 1], lo[a]);
            const V hi_a = select(after_m, hi[a + 1], hi[a]);
            after_m = after_m | nrm.is_m[a + 1];
            weight *= 0.5 * (hi_a - lo_a);
            const Mask same = (lo_a == -0.5) & (hi_a == 0.5);
            if (!cell || !all_lanes(same)) {
                // e^{-2 beta n_e X_e} at the two Gauss points X_e = mid -+ g half, as M / Q
                // and M Q: one exp for a direction centred in the cell (M = 1), two otherwise.
                const V mid = 0.5 * (lo_a + hi_a), half = 0.5 * (hi_a - lo_a);
                const Mask centred = mid == 0;
                const V m = all_lanes(centred)
                                ? one
                                : select(centred, one, lane_exp(-2 * beta_ * n_a * mid));
                const V q = lane_exp(-2 * beta_ * n_a * g * half);
                pair_[a][0] = m / q;
                pair_[a][1] = m * q;
            }
            if (cell)
                for (int k = 0; k < 2; ++k)
                    pair_[a][k] = select(same, cell->pair_[a][k], pair_[a][k]);
        }
        nq_ = 1 << no;
        for (int q = 0; q < nq_; ++q) {
            V f = one;
            for (int a = 0; a < no; ++a)
                f *= pair_[a][(q >> a) & 1];
            factor_[q] = f;
        }
        const V lo_m = nrm.along_m(lo), hi_m = nrm.along_m(hi);
        nm_ = nrm.along_m(nrm.n);
        low_ = nm_ * lo_m;
        const Mask same = (lo_m == -0.5) & (hi_m == 0.5);
        if (!cell || !all_lanes(same)) growth_ = lane_exp(2 * beta_ * nm_ * (hi_m - lo_m));
        if (cell) growth_ = select(same, cell->growth_, growth_);
        scale_ = weight / (2 * beta_ * nm_);
        slope_scale_ = weight * (growth_ - 1) / nm_;
    }

    /// int_box H at level offset d; `dd` (if given) receives its derivative in d and `d2`
    /// (if given) its second derivative, (x_q (G - x_q^2) / ((x_q + 1)(x_q + G))^2) summed,
    /// times -2 beta (G - 1) weight / n_m.
    V integral(V d, V* dd = nullptr, V* d2 = nullptr) const {
        const V e = lane_exp(-2 * beta_ * (low_ + d));
        V ratio = splat<V>(1), slope = splat<V>(0), bend = splat<V>(0);
        for (int q = 0; q < nq_; ++q) {
            const V x = e * factor_[q], xl = x + 1, xh = x + growth_;
            const V inv = 1 / (xl * xh); // one division for the ratio and the slopes
            ratio *= xh * xh * inv;
            slope += x * inv;
            bend += x * (growth_ - x * x) * inv * inv;
        }
        if (dd) *dd = slope_scale_ * slope;
        if (d2) *d2 = -2 * beta_ * slope_scale_ * bend;
        return scale_ * lane_log(ratio);
    }

    /// The level offset d of the cell's 1D profile along m alone (transverse components of
    /// n left out) with cell average phi: for the whole cell (lo_m = -1/2, one Gauss point)
    /// ln[(x + G)/(x + 1)] = 2 beta n_m phi gives x = (G - P)/(P - 1), P = e^{2 beta n_m phi}.
    /// The iteration's starting point (the closed form tanh(beta d) = tanh(beta n_m (phi - 1/2)) /
    /// tanh(beta n_m / 2) in other terms). Only for a rule over the whole cell.
    V profile_level(V phi) const {
        const V p = lane_exp(2 * beta_ * nm_ * phi);
        return 0.5 * nm_ - lane_log((growth_ - p) / (p - 1)) / (2 * beta_);
    }

    /// The one-box rule of lane l (the same values).
    MthincBoxRuleT<real> single(int l) const {
        MthincBoxRuleT<real> s;
        s.beta_ = beta_;
        s.nm_ = lane(nm_, l);
        s.low_ = lane(low_, l);
        s.growth_ = lane(growth_, l);
        s.scale_ = lane(scale_, l);
        s.slope_scale_ = lane(slope_scale_, l);
        for (int q = 0; q < 4; ++q)
            s.factor_[q] = lane(factor_[q], l);
        for (int a = 0; a < 2; ++a)
            for (int k = 0; k < 2; ++k)
                s.pair_[a][k] = lane(pair_[a][k], l);
        s.nq_ = nq_;
        return s;
    }

  private:
    template <class>
    friend class MthincBoxRuleT;
    MthincBoxRuleT() = default;

    real beta_ = 1;
    V nm_{};
    /// n_m lo_m: the level of the low end of the lines, less t_q and d
    V low_{};
    V growth_ = splat<V>(1);      ///< G
    V scale_ = splat<V>(1);       ///< weight / (2 beta n_m)
    V slope_scale_ = splat<V>(1); ///< weight (G - 1) / n_m
    /// F_q
    V factor_[4] = {splat<V>(1), splat<V>(1), splat<V>(1), splat<V>(1)};
    /// e^{-2 beta n_e X_e} at the Gauss points, per direction
    V pair_[2][2] = {{splat<V>(1), splat<V>(1)}, {splat<V>(1), splat<V>(1)}};
    int nq_ = 1;
};

using MthincBoxRule = MthincBoxRuleT<real>;

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
    const MthincNormalT<real> nrm = mthinc_normal_lanes<real>(grad.data(), dim);
    Mthinc r;
    r.beta = beta;
    r.dim = dim;
    for (int e = 0; e < 3; ++e) {
        r.n[e] = nrm.n[e];
        if (nrm.is_m[e]) r.m = e;
    }
    return r;
}

/// The iteration for the level offset d of one cell (int_cell H = phi in (0, 1), `cell`
/// the rule of the normal over the whole cell): Halley's method (third order; the rule
/// gives the second derivative at no extra exp or log) on a bracket [a, b] that each
/// evaluation narrows (the integral increases monotonically with d), a step leaving the
/// bracket replaced by bisection. It starts from the 1D profile along m
/// (MthincBoxRule::profile_level) and takes mthinc_level_steps steps with no test in
/// between, written with selects only, so that four cells step together in the lanes of
/// a real4 (V = real4, mthinc_slab_integrals) as one cell does (V = real). When the
/// residual of the last of them is below 1e-6 of min(phi, 1 - phi), that step left it at
/// round-off (cubic convergence); else `finish` goes on for that cell alone, testing after
/// each step, to a residual of 1e-15 or a bracket of that width.
template <class V>
struct MthincLevelT {
    using Mask = lane_mask<V>;

    V a{}, b{}; ///< bracket
    V d{};      ///< current level
    V phi{};
    V close{};         ///< 1e-6 min(phi, 1 - phi)
    V f = splat<V>(1); ///< residual at the last evaluation
    Mask halley{};     ///< the last step was Halley's (or Newton's), not a bisection

    void start(real beta, int dim, const MthincBoxRuleT<V>& cell, V phi_) {
        phi = phi_;
        // |n.X| <= sqrt(dim)/2 in the cell; 20/beta more makes tanh = +-1 to round-off.
        const real low = -std::sqrt(real(dim)) / 2 - 20 / beta;
        a = splat<V>(low);
        b = splat<V>(-low);
        close = 1e-6 * lane_min(phi, 1 - phi);
        // A start lost to round-off (P = 1 or G) is NaN or infinite: 0 if NaN, else
        // clamped to the bracket (std::clamp's comparisons).
        const V s = cell.profile_level(phi);
        d = select(s != s, splat<V>(0), select(s < a, a, select(b < s, b, s)));
    }

    /// One evaluation and one step, written with selects only. A step that lands on the
    /// bracket's end is kept (at a root, f = 0, the step is zero and d stays); one outside
    /// it (or not a number: a zero slope) is a bisection.
    void step(const MthincBoxRuleT<V>& cell) {
        V slope{}, bend{};
        f = cell.integral(d, &slope, &bend) - phi;
        const Mask above = f > 0;
        b = select(above, d, b);
        a = select(above, a, d);
        // Halley: d - f f' / (f'^2 - f f'' / 2), one division; Newton (d - f f' / f'^2)
        // where the correction is more than half of f'^2 (far from the root).
        const V s2 = slope * slope, halley_den = s2 - 0.5 * f * bend;
        const V tried = d - f * slope / select(halley_den > 0.5 * s2, halley_den, s2);
        halley = (tried >= a) & (tried <= b);
        d = select(halley, tried, 0.5 * (a + b));
    }

    bool converged() const requires(lane_count<V> == 1) { return halley && std::abs(f) < close; }

    void finish(const MthincBoxRuleT<V>& cell) requires(lane_count<V> == 1) {
        for (int it = 0; it < 100 && !converged(); ++it) {
            if (std::abs(f) < 1e-15 || b - a < 1e-15) return;
            step(cell);
        }
    }

    /// The one-cell iteration of lane l (the same values).
    MthincLevelT<real> single(int l) const {
        MthincLevelT<real> s;
        s.a = lane(a, l);
        s.b = lane(b, l);
        s.d = lane(d, l);
        s.phi = lane(phi, l);
        s.close = lane(close, l);
        s.f = lane(f, l);
        s.halley = lane(halley, l);
        return s;
    }
};

using MthincLevel = MthincLevelT<real>;

/// Steps MthincLevel takes before it tests: from the profile's start two or three reach
/// round-off at the betas the schemes use (a smoothed body's 1/smoothing_width, the sharp
/// default 2), so three make the test pass almost always.
inline constexpr int mthinc_level_steps = 3;

/// The level offset d with int_cell H = phi in (0, 1) (MthincLevel).
inline real mthinc_level(const Mthinc& r, const MthincBoxRule& cell, real phi) {
    MthincLevel l;
    l.start(r.beta, r.dim, cell, phi);
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
/// bit for bit (the same operations in the same order for each face). The faces go four
/// at a time through the lanes of real4: one face's iteration is a chain of dependent exp,
/// log and divisions, and four chains in one vector take one vector exp or log (libmvec's
/// on AVX2 builds: core/lanes.hpp) and one division instruction where four faces took
/// four scalar calls and four divisions (docs/method.md, "MTHINC in four lanes"). Everything is
/// written with selects, so that each lane has its own direction m and slab side; a lane whose
/// iteration has not passed its test after mthinc_level_steps finishes alone.
inline void mthinc_slab_integrals(int n, const real* phi, const Real3* grad, real beta, int dim,
                                  int d, const real* courant, real* out) {
    constexpr int L = lane_count<real4>;
    const real4 cube_lo[3] = {splat<real4>(-0.5), splat<real4>(-0.5), splat<real4>(-0.5)};
    const real4 cube_hi[3] = {splat<real4>(0.5), splat<real4>(0.5), splat<real4>(0.5)};
    for (int f0 = 0; f0 < n; f0 += L) {
        const int nl = std::min(L, n - f0);
        real4 g[3]{}, ph{}, c{};
        for (int l = 0; l < L; ++l) {
            const int f = f0 + std::min(l, nl - 1); // lanes past the end repeat the last face
            for (int e = 0; e < 3; ++e)
                g[e][l] = grad[f][e];
            ph[l] = phi[f];
            c[l] = courant[f];
        }
        const MthincNormalT<real4> nrm = mthinc_normal_lanes(g, dim);
        const MthincBoxRuleT<real4> cell(beta, dim, nrm, cube_lo, cube_hi);
        MthincLevelT<real4> level;
        level.start(beta, dim, cell, ph);
        for (int it = 0; it < mthinc_level_steps; ++it)
            level.step(cell);
        real4 level_d = level.d;
        for (int l = 0; l < nl; ++l) {
            MthincLevel one = level.single(l);
            if (one.converged()) continue;
            one.finish(cell.single(l));
            level_d[l] = one.d;
        }
        // The slab of width |c| at the cell's high end (c > 0) or low end along d.
        real4 lo[3] = {cube_lo[0], cube_lo[1], cube_lo[2]};
        real4 hi[3] = {cube_hi[0], cube_hi[1], cube_hi[2]};
        const mask4 positive = c > 0;
        lo[d] = select(positive, 0.5 - lane_abs(c), lo[d]);
        hi[d] = select(positive, hi[d], -0.5 + lane_abs(c));
        const real4 v = MthincBoxRuleT<real4>(beta, dim, nrm, lo, hi, &cell).integral(level_d);
        for (int l = 0; l < nl; ++l)
            out[f0 + l] = v[l];
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

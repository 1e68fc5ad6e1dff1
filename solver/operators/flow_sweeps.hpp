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
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(u[C], j, k);
        for (int i = 0; i < L.n[0]; ++i) {
            const std::ptrdiff_t m = r + i;
            const real hi = 0.5 * (uc[m] + uc[m + sc]);
            const real lo = 0.5 * (uc[m - sc] + uc[m]);
            real acc = (hi * hi - lo * lo) * inv[C];
#pragma GCC unroll 3
            for (int e = 0; e < Dim; ++e) {
                if (e == C) continue;
                const std::ptrdiff_t se = L.s[e];
                const real* w = ue[e];
                // flux u_e u_c on the (c,e) edges of cells m + e_e and m
                const real fh = 0.25 * (w[m + se] + w[m + se - sc]) * (uc[m + se] + uc[m]);
                const real fl = 0.25 * (w[m] + w[m - sc]) * (uc[m] + uc[m - se]);
                acc += (fh - fl) * inv[e];
            }
            out[m] = -acc;
        }
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

/// rhs = -scale div(v) at the cell centres; returns max |v| over the owned faces swept.
template <int Dim>
real divergence(const VelocityField& u, const GlobalGrid& g, real scale, Field& rhs) {
    const Layout L(rhs);
    real inv[3];
    for (int e = 0; e < 3; ++e)
        inv[e] = e < Dim ? scale / g.dx(e) : 0.0;
    const real* v[3] = {u[0].data().data(), u[1].data().data(),
                        Dim > 2 ? u[2].data().data() : nullptr};
    real* out = rhs.data().data();
    real speed = 0;
    for_each_row(L.n, [&](int j, int k) {
        const std::ptrdiff_t r = L.row(rhs, j, k);
        for (int i = 0; i < L.n[0]; ++i) {
            const std::ptrdiff_t m = r + i;
            real div = 0;
#pragma GCC unroll 3
            for (int e = 0; e < Dim; ++e)
                div += (v[e][m + L.s[e]] - v[e][m]) * inv[e];
            out[m] = -div;
        }
        for (int e = 0; e < Dim; ++e)
            for (int i = 0; i < L.n[0]; ++i)
                speed = std::max(speed, std::abs(v[e][r + i]));
    });
    return speed;
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

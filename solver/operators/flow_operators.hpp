// Second-order finite differences on the staggered (MAC) grid.
//
// Pointwise kernels take the point as a signed index p = (i,j,k) of the owned block and
// read only neighbours within one halo layer, so the same kernel serves a dense sweep
// and a sweep over part of the grid. Directions are loop variables (c: velocity
// component, e: derivative direction), never written out three times.
//
// Conventions: component c lives on the low c-face of cell p; the (c,e) edge of cell p
// is its low-c, low-e edge.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

namespace efsi {

inline Int3 shifted(Int3 p, int d, int by) {
    p[d] += by;
    return p;
}

/// Divergence of the face velocity at cell centre p.
inline real divergence_at(const VelocityField& u, const GlobalGrid& g, const Int3& p) {
    real div = 0;
    for (int d = 0; d < u.dim; ++d)
        div += (u[d](shifted(p, d, 1)) - u[d](p)) / g.dx(d);
    return div;
}

/// Gradient (direction d) of a cell scalar at the low d-face of cell p.
inline real gradient_at(const Field& s, const GlobalGrid& g, int d, const Int3& p) {
    return (s(p) - s(shifted(p, d, -1))) / g.dx(d);
}

/// Viscosity on the (c,e) edge of cell p: mean of the four cells around the edge.
inline real edge_viscosity(const Field& mu, int c, int e, const Int3& p) {
    const Int3 pc = shifted(p, c, -1);
    return 0.25 * (mu(p) + mu(pc) + mu(shifted(p, e, -1)) + mu(shifted(pc, e, -1)));
}

/// Advective term -(div (u u_c)) at the c-face of cell p, conservative central form
/// (Harlow & Welch): fluxes are products of two-point averages, which conserves momentum
/// and, for a discretely solenoidal u, kinetic energy.
inline real advection_at(const VelocityField& u, const GlobalGrid& g, int c, const Int3& p) {
    real acc = 0;
    for (int e = 0; e < u.dim; ++e) {
        if (e == c) {
            // Flux u_c u_c at the cell centres p and p - e_c.
            const real hi = 0.5 * (u[c](p) + u[c](shifted(p, c, 1)));
            const real lo = 0.5 * (u[c](shifted(p, c, -1)) + u[c](p));
            acc += (hi * hi - lo * lo) / g.dx(c);
        } else {
            // Flux u_e u_c at the (c,e) edges of cells p + e_e and p.
            auto flux = [&](const Int3& q) {
                const real ue = 0.5 * (u[e](q) + u[e](shifted(q, c, -1)));
                const real uc = 0.5 * (u[c](q) + u[c](shifted(q, e, -1)));
                return ue * uc;
            };
            acc += (flux(shifted(p, e, 1)) - flux(p)) / g.dx(e);
        }
    }
    return -acc;
}

/// Weights of the variable-viscosity Laplacian div(mu grad u_c) at the c-face of cell p:
/// the value is sum over e, side of w[e][side] * (u_c(neighbour) - u_c(p)).
inline std::array<std::array<real, 2>, 3> viscous_weights(const Field& mu, const GlobalGrid& g,
                                                          int dim, int c, const Int3& p) {
    std::array<std::array<real, 2>, 3> w{};
    for (int e = 0; e < dim; ++e) {
        const real h2 = g.dx(e) * g.dx(e);
        if (e == c) {
            w[e][0] = mu(shifted(p, c, -1)) / h2;
            w[e][1] = mu(p) / h2;
        } else {
            w[e][0] = edge_viscosity(mu, c, e, p) / h2;
            w[e][1] = edge_viscosity(mu, c, e, shifted(p, e, 1)) / h2;
        }
    }
    return w;
}

/// div(mu grad u_c) at the c-face of cell p.
inline real viscous_laplacian_at(const VelocityField& u, const Field& mu, const GlobalGrid& g,
                                 int c, const Int3& p) {
    const auto w = viscous_weights(mu, g, u.dim, c, p);
    const real uc = u[c](p);
    real acc = 0;
    for (int e = 0; e < u.dim; ++e)
        acc += w[e][0] * (u[c](shifted(p, e, -1)) - uc) + w[e][1] * (u[c](shifted(p, e, 1)) - uc);
    return acc;
}

/// The rest of the viscous stress divergence, sum_e d/dx_e (mu du_e/dx_c), at the c-face
/// of cell p. It vanishes for uniform mu and solenoidal u, so it is only evaluated when
/// the viscosity varies in space (bodies), and always explicitly.
inline real viscous_transpose_at(const VelocityField& u, const Field& mu, const GlobalGrid& g,
                                 int c, const Int3& p) {
    real acc = 0;
    for (int e = 0; e < u.dim; ++e) {
        if (e == c) {
            const real hi = mu(p) * (u[c](shifted(p, c, 1)) - u[c](p));
            const real lo = mu(shifted(p, c, -1)) * (u[c](p) - u[c](shifted(p, c, -1)));
            acc += (hi - lo) / (g.dx(c) * g.dx(c));
        } else {
            auto flux = [&](const Int3& q) { // mu du_e/dx_c on the (c,e) edge of cell q
                return edge_viscosity(mu, c, e, q) * (u[e](q) - u[e](shifted(q, c, -1))) / g.dx(c);
            };
            acc += (flux(shifted(p, e, 1)) - flux(p)) / g.dx(e);
        }
    }
    return acc;
}

/// Velocity interpolated to the centre of cell p (for output and diagnostics).
inline real cell_centre_velocity(const VelocityField& u, int c, const Int3& p) {
    return 0.5 * (u[c](p) + u[c](shifted(p, c, 1)));
}

} // namespace efsi

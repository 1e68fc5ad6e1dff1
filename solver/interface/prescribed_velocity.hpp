// Face velocities of a prescribed solenoidal flow, discretely divergence-free.
//
// The flow is given by a vector potential A (u = curl A). The flux through each face is
// taken as the circulation of A round the face divided by its area (Stokes), with A
// sampled at the midpoints of the face's edges:
//     u_d = (A_b(+a) - A_b(-a)) / dx_a - (A_a(+b) - A_a(-b)) / dx_b,  (d, a, b) cyclic,
// where A_b(+-a) is A_b on the edges of the face at +-dx_a/2. The discrete divergence of a
// discrete curl cancels term by term, so sum_d (u_d(i+1) - u_d(i)) / dx_d = 0 to
// round-off and VOF volume is conserved exactly. In 2D (dim == 2) only A_z matters
// (A_z is the stream function psi: u = dpsi/dy, v = -dpsi/dx) and z-derivatives are
// dropped. Every face of the field, halos included, is set directly from the formula,
// so no halo exchange is needed and ranks agree bit for bit on shared faces.
#pragma once

#include "grid/field.hpp"
#include "grid/grid.hpp"

namespace efsi {

/// Fill u from the vector potential `potential(x) -> Real3` (lab coordinates).
template <class Potential>
void set_velocity_from_potential(VelocityField& u, const GlobalGrid& g, const LocalBlock& b,
                                 Potential&& potential) {
    for (int d = 0; d < u.dim; ++d) {
        Field& f = u[d];
        const Int3 h = f.halo(), n = f.cells();
        const Int3 lo{-h[0], -h[1], -h[2]};
        const Int3 ext{n[0] + 2 * h[0], n[1] + 2 * h[1], n[2] + 2 * h[2]};
        for_each_cell(ext, [&](int i0, int j0, int k0) {
            const Int3 p{i0 + lo[0], j0 + lo[1], k0 + lo[2]};
            const Real3 xf = position(g, b, face_location(d), p[0], p[1], p[2]);
            real v = 0;
            // Two terms: (a, b) = (d+1, d+2) with sign +, contributing +dA_b/dx_a, and
            // the same with a and b swapped and sign -; together the cyclic curl.
            for (int t = 0; t < 2; ++t) {
                const int a = (d + 1 + t) % 3, bb = (d + 2 - t) % 3;
                if (a >= g.dim) continue; // no derivative along a missing direction
                const real sign = t == 0 ? 1.0 : -1.0;
                Real3 xp = xf, xm = xf;
                xp[a] += 0.5 * g.dx(a);
                xm[a] -= 0.5 * g.dx(a);
                v += sign * (potential(xp)[bb] - potential(xm)[bb]) / g.dx(a);
            }
            f(p) = v;
        });
    }
}

} // namespace efsi

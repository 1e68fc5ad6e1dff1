#include "bodies/rigid_fit.hpp"

#include "core/error.hpp"
#include "core/matrix3.hpp"
#include "operators/flow_operators.hpp"

#include <fmt/core.h>

#include <array>
#include <cmath>

namespace efsi {

namespace {

/// x along the periodic directions by the minimum image about `near`.
Real3 image(const Decomposition& dec, const Real3& x, const Real3& near) {
    const GlobalGrid& g = dec.grid();
    Real3 r = x;
    for (int k = 0; k < g.dim; ++k)
        if (dec.periodic()[k])
            r[k] = x[k] - g.length[k] * std::round((x[k] - near[k]) / g.length[k]);
    return r;
}

/// Sums over b's owned cells with phi != 0 of f(phi, cell index, position by the minimum image
/// about `near`) into `s`, then over the ranks.
template <std::size_t N, class F>
std::array<real, N> body_sums(const Body& b, const Decomposition& dec, const Real3& near, F&& f) {
    std::array<real, N> s{};
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) {
            const real p = b.phi()(i, j, k);
            if (p == 0) return;
            f(s, p, Int3{i, j, k},
              image(dec, position(dec.grid(), dec.block(), Location::Cell, i, j, k), near));
        });
    dec.sum_in_place(s);
    return s;
}

/// Adds phi (|r|^2 1 - r r^T) to the upper triangle Ixx Iyy Izz Ixy Ixz Iyz in s[0..6).
template <std::size_t N>
void add_inertia(std::array<real, N>& s, real p, const Real3& r) {
    const real rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    s[0] += p * (rr - r[0] * r[0]);
    s[1] += p * (rr - r[1] * r[1]);
    s[2] += p * (rr - r[2] * r[2]);
    s[3] -= p * r[0] * r[1];
    s[4] -= p * r[0] * r[2];
    s[5] -= p * r[1] * r[2];
}

/// The centroid of b (sum phi x / sum phi, in the image of `near`) and sum phi; throws
/// RunError naming the body when it holds no volume.
std::pair<Real3, real> centroid(const Body& b, const Decomposition& dec, const Real3& near) {
    const auto s = body_sums<4>(b, dec, near, [](auto& acc, real p, const Int3&, const Real3& x) {
        acc[0] += p;
        for (int a = 0; a < 3; ++a)
            acc[1 + a] += p * x[a];
    });
    if (!(s[0] > 0)) throw RunError(fmt::format("body '{}' holds no volume", b.name()));
    return {{s[1] / s[0], s[2] / s[0], s[3] / s[0]}, s[0]};
}

/// Omega with I Omega = L (I from its upper triangle t[0..6)); about z only in 2D; zero when
/// I is singular (a point or a line of cells: no rotation to fit).
Real3 solve_spin(const real* t, const Real3& L, int dim) {
    if (dim == 2) return {0, 0, t[2] > 0 ? L[2] / t[2] : 0.0};
    const Matrix3 I{{{t[0], t[3], t[4]}, {t[3], t[1], t[5]}, {t[4], t[5], t[2]}}};
    if (!(determinant(I) > 0)) return {0, 0, 0};
    return mat_vec(inverse(I), L);
}

} // namespace

RigidMotion fit_rigid_motion(const Body& b, const VelocityField& u, const Decomposition& dec,
                             const Real3& near) {
    // A patch across the periodic x seam indexes x past [0, n): the velocity there is its
    // image's (x is whole on the rank).
    const int period = b.patch().seam_period;
    auto velocity = [&](Int3 q) {
        if (period > 0) q[0] = (q[0] % period + period) % period;
        Real3 v{0, 0, 0};
        for (int c = 0; c < u.dim; ++c)
            v[c] = cell_centre_velocity(u, c, q);
        return v;
    };
    RigidMotion m;
    try {
        const auto [c, volume] = centroid(b, dec, near);
        m.centre = c;
        // The mean velocity, then the inertia and the angular momentum of the velocity
        // relative to it about the centroid (one pass, one collective).
        const auto s =
            body_sums<3>(b, dec, near, [&](auto& acc, real p, const Int3& q, const Real3&) {
                const Real3 v = velocity(q);
                for (int a = 0; a < 3; ++a)
                    acc[a] += p * v[a];
            });
        for (int a = 0; a < 3; ++a)
            m.velocity[a] = s[a] / volume;
        const auto t =
            body_sums<9>(b, dec, near, [&](auto& acc, real p, const Int3& q, const Real3& x) {
                const Real3 v = velocity(q);
                Real3 r, w;
                for (int a = 0; a < 3; ++a) {
                    r[a] = x[a] - m.centre[a];
                    w[a] = v[a] - m.velocity[a];
                }
                add_inertia(acc, p, r);
                const Real3 l = cross(r, w);
                for (int a = 0; a < 3; ++a)
                    acc[6 + a] += p * l[a];
            });
        m.spin = solve_spin(t.data(), {t[6], t[7], t[8]}, dec.grid().dim);
    } catch (const RunError& e) {
        throw RunError(fmt::format("{}: no rigid motion to fit", e.what()));
    }
    return m;
}

std::size_t spread_rigid_load(const Body& b, const RigidLoad& load, const Decomposition& dec,
                              VelocityField& force) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& blk = dec.block();
    const auto [c, volume] = centroid(b, dec, load.point);
    const auto t =
        body_sums<6>(b, dec, load.point, [&](auto& acc, real p, const Int3&, const Real3& x) {
            add_inertia(acc, p, {x[0] - c[0], x[1] - c[1], x[2] - c[2]});
        });
    // The torque about the centroid; sums of phi are per cell, so V and I carry dV.
    const real dV = g.cell_volume();
    Real3 T = cross({load.point[0] - c[0], load.point[1] - c[1], load.point[2] - c[2]}, load.force);
    for (int a = 0; a < 3; ++a)
        T[a] += load.torque[a];
    Real3 omega = solve_spin(t.data(), T, g.dim);
    for (real& w : omega)
        w /= dV;
    const real inv_volume = 1 / (volume * dV);
    if (b.patch().empty()) return 0;
    // The density phi (F / V + Omega x r) at the centre of local cell q.
    auto density = [&](int comp, const Int3& q) {
        const real p = b.phi()(q[0], q[1], q[2]);
        if (p == 0) return 0.0;
        const Real3 x = image(dec, position(g, blk, Location::Cell, q[0], q[1], q[2]), load.point);
        const Real3 spin = cross(omega, {x[0] - c[0], x[1] - c[1], x[2] - c[2]});
        return p * (load.force[comp] * inv_volume + spin[comp]);
    };
    std::size_t written = 0;
    for (int comp = 0; comp < force.dim; ++comp) {
        const bool walled = !dec.periodic()[comp];
        const int n = g.cells[comp];
        // Share of a cell's value on its low and high faces (global index gi along comp).
        auto low_share = [&](int gi) {
            return walled && gi == 0 ? 0.0 : walled && gi == n - 1 ? 1.0 : 0.5;
        };
        auto high_share = [&](int gi) {
            return walled && gi == n - 1 ? 0.0 : walled && gi == 0 ? 1.0 : 0.5;
        };
        // The owned faces touching the patch: low faces of its cells and the high face of
        // its last cell along comp.
        Box faces = b.patch().local;
        faces.hi[comp] += 1;
        // Across the periodic x seam the patch's x indices run past [0, n): each face is
        // written at its image (x is whole on the rank).
        const int period = b.patch().seam_period;
        Box own{{0, 0, 0}, blk.cells};
        if (period > 0) {
            own.lo[0] = faces.lo[0];
            own.hi[0] = faces.hi[0];
        }
        faces = intersect(faces, own);
        // The cell below the patch's first local cell is the patch's (filled halo) when the
        // patch goes on below this rank's part, or wraps (it then covers the direction).
        const Patch& pa = b.patch();
        const bool below_in_patch = pa.local.lo[comp] + blk.offset[comp] > pa.global.lo[comp] ||
                                    (!walled && pa.global.lo[comp] == 0 && pa.global.hi[comp] == n);
        Field& f = force[comp];
        for_each_in(faces, [&](int i, int j, int k) {
            const Int3 q{i, j, k};
            const int gi = q[comp] + blk.offset[comp];
            if (walled && gi == 0) return; // a wall face takes no force
            Int3 below = q;
            below[comp] -= 1;
            real v = 0;
            if (q[comp] < b.patch().local.hi[comp]) v += low_share(gi) * density(comp, q);
            if (below[comp] >= b.patch().local.lo[comp] || below_in_patch)
                v += high_share(gi - 1) * density(comp, below);
            if (v == 0) return;
            f(period > 0 ? (i % period + period) % period : i, j, k) += v;
            ++written;
        });
    }
    return written;
}

} // namespace efsi

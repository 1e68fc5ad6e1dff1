#include "adhesion/grid_transfer.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <limits>

namespace efsi::adhesion {

real peskin4(real r) {
    const real a = std::abs(r);
    if (a <= 1) return (3 - 2 * a + std::sqrt(1 + 4 * a - 4 * a * a)) / 8;
    if (a < 2) return (5 - 2 * a - std::sqrt(std::max(real(0), -7 + 12 * a - 4 * a * a))) / 8;
    return 0;
}

namespace {

/// Position of point x along axis a in units of cells, relative to the index origin of
/// component c (faces normal to a sit at integer indices, cell centres at half indices).
real grid_coordinate(const GlobalGrid& g, const Real3& x, int c, int a) {
    return (x[a] - g.origin[a]) / g.dx(a) - (a == c ? 0.0 : 0.5);
}

int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}

std::string point_text(const Real3& x) {
    return fmt::format("({:.6g}, {:.6g}, {:.6g}) m", x[0], x[1], x[2]);
}

/// Is x inside the domain along every wall-bounded direction (and finite)?
bool inside_walls(const Decomposition& dec, const Real3& x) {
    const GlobalGrid& g = dec.grid();
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(x[a])) return false;
        if (dec.periodic()[a]) continue;
        if (x[a] < g.origin[a] || x[a] > g.origin[a] + g.length[a]) return false;
    }
    return true;
}

/// The rank-local index of global index `i` along axis a when this rank holds that value
/// for reading: an owned point, or a ghost beyond a wall on the rank at that wall.
bool holds_for_reading(const Decomposition& dec, int a, int i, int& local) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    if (dec.periodic()[a]) i = wrap(i, g.cells[a]);
    local = i - b.offset[a];
    if (local >= 0 && local < b.cells[a]) return true;
    if (dec.periodic()[a]) return false;
    return (i < 0 && dec.at_boundary(a, 0)) || (i >= g.cells[a] && dec.at_boundary(a, 1));
}

/// One direction of the spreading stencil: up to 4 points with their rescaled weights,
/// only those this rank owns kept (`local` indices).
struct Axis {
    std::array<int, 4> local{};
    std::array<real, 4> w{};
    int n = 0;
};

Axis spread_axis(const Decomposition& dec, real s, int c, int a) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    const bool periodic = dec.periodic()[a];
    // Points a force may go to along a walled direction: the faces strictly between the
    // walls for the normal component (the wall face's velocity is fixed), every cell for
    // the others.
    const int first = (a == c) ? 1 : 0, last = g.cells[a] - 1;
    const int base = static_cast<int>(std::floor(s)) - 1;
    std::array<real, 4> w{};
    real total = 0;
    for (int q = 0; q < 4; ++q) {
        const int i = base + q;
        if (!periodic && (i < first || i > last)) continue;
        w[q] = peskin4(s - i);
        total += w[q];
    }
    Axis out;
    if (!(total > 0)) return out;
    for (int q = 0; q < 4; ++q) {
        if (w[q] == 0) continue;
        int i = base + q;
        if (periodic) i = wrap(i, g.cells[a]);
        const int local = i - b.offset[a];
        if (local < 0 || local >= b.cells[a]) continue;
        out.local[out.n] = local;
        out.w[out.n] = w[q] / total;
        ++out.n;
    }
    return out;
}

} // namespace

std::size_t spread_force(VelocityField& force, const Decomposition& dec, const Real3& x,
                         const Real3& F) {
    if (!inside_walls(dec, x))
        throw RunError(
            fmt::format("adhesion: a bond force acts at {}, outside the domain", point_text(x)));
    const GlobalGrid& g = dec.grid();
    const real volume = g.cell_volume();
    std::size_t written = 0;
    for (int c = 0; c < force.dim; ++c) {
        if (F[c] == 0) continue;
        std::array<Axis, 3> ax;
        for (int a = 0; a < 3; ++a) {
            if (a >= dec.dim()) {
                ax[a].n = 1; // 2D: the single z layer
                ax[a].w[0] = 1;
                continue;
            }
            ax[a] = spread_axis(dec, grid_coordinate(g, x, c, a), c, a);
        }
        const real density = F[c] / volume;
        Field& f = force[c];
        for (int r = 0; r < ax[2].n; ++r)
            for (int q = 0; q < ax[1].n; ++q) {
                const real wqr = ax[1].w[q] * ax[2].w[r] * density;
                for (int p = 0; p < ax[0].n; ++p) {
                    f(ax[0].local[p], ax[1].local[q], ax[2].local[r]) += ax[0].w[p] * wqr;
                    ++written;
                }
            }
    }
    return written;
}

namespace {

/// The 4 global indices of the kernel along axis a for component c at grid coordinate s,
/// with phi4 weights (0 for points a force may not go to), not renormalised.
struct Stencil {
    std::array<int, 4> i{};
    std::array<real, 4> w{};
};

Stencil kernel_axis(const Decomposition& dec, real s, int c, int a) {
    const GlobalGrid& g = dec.grid();
    const bool periodic = dec.periodic()[a];
    const int first = (a == c) ? 1 : 0, last = g.cells[a] - 1;
    const int base = static_cast<int>(std::floor(s)) - 1;
    Stencil out;
    for (int q = 0; q < 4; ++q) {
        int i = base + q;
        if (!periodic && (i < first || i > last)) {
            out.i[q] = -1;
            continue;
        }
        out.w[q] = peskin4(s - i);
        if (periodic) i = wrap(i, g.cells[a]);
        out.i[q] = i;
    }
    return out;
}

} // namespace

void HeldSpreader::gather(const VelocityField& pinning, const Decomposition& dec,
                          std::span<const Real3> x) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    w_.assign(x.size() * 3 * 64, 0.0);
    for (std::size_t p = 0; p < x.size(); ++p) {
        if (!inside_walls(dec, x[p]))
            throw RunError(fmt::format("adhesion: a bond's wall reaction acts at {}, outside the "
                                       "domain",
                                       point_text(x[p])));
        for (int c = 0; c < 3; ++c) {
            std::array<Stencil, 3> st;
            for (int a = 0; a < 3; ++a)
                st[a] = kernel_axis(dec, grid_coordinate(g, x[p], c, a), c, a);
            real* slot = &w_[(p * 3 + c) * 64];
            for (int r = 0; r < 4; ++r)
                for (int q = 0; q < 4; ++q)
                    for (int o = 0; o < 4; ++o) {
                        const std::array<int, 3> gi{st[0].i[o], st[1].i[q], st[2].i[r]};
                        Int3 local{};
                        bool owned = true;
                        for (int a = 0; a < 3; ++a) {
                            local[a] = gi[a] - b.offset[a];
                            owned = owned && gi[a] >= 0 && local[a] >= 0 && local[a] < b.cells[a];
                        }
                        if (!owned) continue;
                        const real k = pinning[c](local[0], local[1], local[2]);
                        const real held = k > 0 ? k / (1 + k) : 0.0;
                        slot[o + 4 * q + 16 * r] = st[0].w[o] * st[1].w[q] * st[2].w[r] * held;
                    }
        }
    }
    if (dec.size() > 1) dec.sum_in_place(w_);
}

void HeldSpreader::held_share(const VelocityField& pinning, const Decomposition& dec,
                              std::span<const Real3> x, std::vector<real>& share) {
    gather(pinning, dec, x);
    share.assign(x.size(), 0.0);
    for (std::size_t p = 0; p < x.size(); ++p) {
        real least = std::numeric_limits<real>::infinity();
        for (int c = 0; c < 3; ++c) {
            real total = 0;
            for (int q = 0; q < 64; ++q)
                total += w_[(p * 3 + c) * 64 + q];
            least = std::min(least, total);
        }
        share[p] = least;
    }
}

std::size_t HeldSpreader::spread(VelocityField& force, const VelocityField& pinning,
                                 const Decomposition& dec, std::span<const Real3> x,
                                 std::span<const Real3> F, real min_share) {
    gather(pinning, dec, x);
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    const real volume = g.cell_volume();
    std::size_t written = 0;
    for (std::size_t p = 0; p < x.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            const real* slot = &w_[(p * 3 + c) * 64];
            real total = 0;
            for (int q = 0; q < 64; ++q)
                total += slot[q];
            if (!(total >= min_share))
                throw RunError(fmt::format(
                    "adhesion: a bond's wall reaction at {} finds a held (pinned) share of only "
                    "{:.3g} of its kernel for component {} (need >= {:g}): the ligand is not on "
                    "a fixed wall body",
                    point_text(x[p]), total, "xyz"[c], min_share));
            if (F[p][c] == 0) continue;
            std::array<Stencil, 3> st;
            for (int a = 0; a < 3; ++a)
                st[a] = kernel_axis(dec, grid_coordinate(g, x[p], c, a), c, a);
            const real density = F[p][c] / (volume * total);
            for (int r = 0; r < 4; ++r)
                for (int q = 0; q < 4; ++q)
                    for (int o = 0; o < 4; ++o) {
                        const real w = slot[o + 4 * q + 16 * r];
                        if (w == 0) continue;
                        const std::array<int, 3> gi{st[0].i[o], st[1].i[q], st[2].i[r]};
                        Int3 local{};
                        bool owned = true;
                        for (int a = 0; a < 3; ++a) {
                            local[a] = gi[a] - b.offset[a];
                            owned = owned && local[a] >= 0 && local[a] < b.cells[a];
                        }
                        if (!owned) continue;
                        force[c](local[0], local[1], local[2]) += w * density;
                        ++written;
                    }
        }
    return written;
}

void VelocityInterpolator::interpolate(const VelocityField& u, const Decomposition& dec,
                                       std::span<const Real3> x, std::span<Real3> out) {
    const GlobalGrid& g = dec.grid();
    const int dim = u.dim;
    corners_.assign(x.size() * 3 * 8, 0.0);
    frac_.assign(x.size() * 3, Real3{0, 0, 0});
    std::vector<Real3>& frac = frac_;
    for (std::size_t p = 0; p < x.size(); ++p) {
        if (!inside_walls(dec, x[p]))
            throw RunError(
                fmt::format("adhesion: point {} at {} is outside the domain", p, point_text(x[p])));
        for (int c = 0; c < dim; ++c) {
            std::array<int, 3> lo{};
            std::array<std::array<int, 2>, 3> local{};
            std::array<std::array<bool, 2>, 3> held{};
            for (int a = 0; a < 3; ++a) {
                if (a >= dec.dim()) { // 2D: the single z layer, weight (1, 0)
                    frac[p * 3 + c][a] = 0;
                    local[a] = {0, 0};
                    held[a] = {true, false};
                    continue;
                }
                const real s = grid_coordinate(g, x[p], c, a);
                lo[a] = static_cast<int>(std::floor(s));
                // A point on the high wall face itself: use the cell below it.
                if (!dec.periodic()[a] && a == c && lo[a] >= g.cells[a]) lo[a] = g.cells[a] - 1;
                frac[p * 3 + c][a] = s - lo[a];
                for (int e = 0; e < 2; ++e)
                    held[a][e] = holds_for_reading(dec, a, lo[a] + e, local[a][e]);
            }
            real* slot = &corners_[(p * 3 + c) * 8];
            for (int e2 = 0; e2 < 2; ++e2)
                for (int e1 = 0; e1 < 2; ++e1)
                    for (int e0 = 0; e0 < 2; ++e0)
                        if (held[0][e0] && held[1][e1] && held[2][e2])
                            slot[e0 + 2 * e1 + 4 * e2] =
                                u[c](local[0][e0], local[1][e1], local[2][e2]);
        }
    }
    if (dec.size() > 1) dec.sum_in_place(corners_);
    for (std::size_t p = 0; p < x.size(); ++p) {
        out[p] = {0, 0, 0};
        for (int c = 0; c < dim; ++c) {
            const real* v = &corners_[(p * 3 + c) * 8];
            const Real3& t = frac[p * 3 + c];
            // a + t (b - a): exact for a uniform field.
            auto lerp = [](real a, real b, real s) { return a + s * (b - a); };
            const real y0 = lerp(lerp(v[0], v[1], t[0]), lerp(v[2], v[3], t[0]), t[1]);
            const real y1 = lerp(lerp(v[4], v[5], t[0]), lerp(v[6], v[7], t[0]), t[1]);
            out[p][c] = lerp(y0, y1, t[2]);
        }
    }
}

} // namespace efsi::adhesion

#include "boundary/boundary.hpp"

#include <cassert>
#include <cmath>

namespace efsi {

std::string to_string(BoundaryType t) {
    switch (t) {
    case BoundaryType::Periodic:
        return "periodic";
    case BoundaryType::Wall:
        return "wall";
    case BoundaryType::FreeSlip:
        return "free_slip";
    }
    return "?";
}

real FaceBoundary::velocity_at(int c, real t) const {
    return frequency > 0 ? velocity[c] * std::sin(frequency * t) : velocity[c];
}

void HaloFiller::apply_wall(Field& f, int d, int side, Mirror mirror, real wall_value) const {
    if (bc_[d][side].type == BoundaryType::Periodic || !dec_.at_boundary(d, side)) return;
    const Int3 n = f.cells();
    assert(f.begin() == Int3({0, 0, 0}) && "whole-block fields only; patches exchange elsewhere");
    const Int3 h = f.halo();
    const int g = h[d];
    // Sweep the whole wall plane, halos of the other directions included.
    Int3 lo{-h[0], -h[1], -h[2]}, hi{n[0] + h[0], n[1] + h[1], n[2] + h[2]};
    lo[d] = 0;
    hi[d] = 1;
    // Index along d of the l-th ghost and of the interior point it mirrors.
    auto ghost_of = [&](int l) {
        if (mirror == Mirror::NormalFace) return side == 0 ? -l : n[d] + l;
        return side == 0 ? -1 - l : n[d] + l;
    };
    auto mirror_of = [&](int l) {
        if (mirror == Mirror::NormalFace) return side == 0 ? l : n[d] - l;
        return side == 0 ? l : n[d] - 1 - l;
    };
    for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j)
            for (int i = lo[0]; i < hi[0]; ++i) {
                Int3 gp{i, j, k}, mp{i, j, k};
                if (mirror == Mirror::NormalFace) {
                    // The wall face itself: index 0 (owned) or n (first high halo).
                    gp[d] = ghost_of(0);
                    f(gp) = 0;
                    const int layers = side == 0 ? g : g - 1;
                    for (int l = 1; l <= layers; ++l) {
                        gp[d] = ghost_of(l);
                        mp[d] = mirror_of(l);
                        f(gp) = -f(mp);
                    }
                } else {
                    for (int l = 0; l < g; ++l) {
                        gp[d] = ghost_of(l);
                        mp[d] = mirror_of(l);
                        f(gp) = mirror == Mirror::Even ? f(mp) : 2 * wall_value - f(mp);
                    }
                }
            }
}

void HaloFiller::fill(Field& f) const {
    for (int d = 0; d < dec_.dim(); ++d) {
        dec_.exchange(f, d);
        for (int side = 0; side < 2; ++side)
            apply_wall(f, d, side, Mirror::Even, 0);
    }
}

void HaloFiller::fill(Field& f, const Patch& patch) const {
    if (patch.empty()) return;
    const Int3 b = f.begin();
    const Int3 n = f.cells();
    const Int3 h = f.halo();
    for (int d = 0; d < dec_.dim(); ++d) {
        dec_.exchange(f, d, patch.exchange[d][0], patch.exchange[d][1]);
        Int3 lo{b[0] - h[0], b[1] - h[1], b[2] - h[2]};
        Int3 hi{b[0] + n[0] + h[0], b[1] + n[1] + h[1], b[2] + n[2] + h[2]};
        for (int side = 0; side < 2; ++side) {
            if (patch.exchange[d][side]) continue;
            Box plane{lo, hi};
            plane.lo[d] = 0;
            plane.hi[d] = 1;
            for_each_in(plane, [&](int i, int j, int k) {
                for (int l = 0; l < h[d]; ++l) {
                    Int3 ghost{i, j, k}, mirror{i, j, k};
                    ghost[d] = side == 0 ? b[d] - 1 - l : b[d] + n[d] + l;
                    mirror[d] = side == 0 ? b[d] + std::min(l, n[d] - 1)
                                          : b[d] + n[d] - 1 - std::min(l, n[d] - 1);
                    f(ghost) = f(mirror);
                }
            });
        }
    }
}

void HaloFiller::fill(VelocityField& v) const {
    for (int d = 0; d < dec_.dim(); ++d)
        for (int c = 0; c < v.dim; ++c) {
            dec_.exchange(v[c], d);
            for (int side = 0; side < 2; ++side) {
                const FaceBoundary& b = bc_[d][side];
                if (c == d)
                    apply_wall(v[c], d, side, Mirror::NormalFace, 0);
                else if (b.type == BoundaryType::FreeSlip)
                    apply_wall(v[c], d, side, Mirror::Even, 0);
                else
                    apply_wall(v[c], d, side, Mirror::Odd, b.velocity_at(c, time_));
            }
        }
}

} // namespace efsi

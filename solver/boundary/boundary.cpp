#include "boundary/boundary.hpp"

#include <algorithm>
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
    if (t >= stop_time) return 0;
    return frequency > 0 ? velocity[c] * std::sin(frequency * t) : velocity[c];
}

namespace {

/// op(ghost, mirror) for every point of the plane at storage index `to` along d and of the
/// plane at `from`, over the whole stored extent of the other directions (halos included).
/// Storage indices count from the first halo layer (0 .. extent - 1). The innermost loop
/// runs along the stored rows (unit stride) unless d is x.
template <class Op>
void for_plane_pair(Field& f, int d, int to, int from, Op&& op) {
    const Int3& e = f.extent();
    real* const a = f.data().data();
    const std::ptrdiff_t s1 = e[0], s2 = std::ptrdiff_t(e[0]) * e[1];
    if (d == 0) {
        for (int k = 0; k < e[2]; ++k)
            for (int j = 0; j < e[1]; ++j) {
                real* row = a + j * s1 + k * s2;
                op(row[to], row[from]);
            }
    } else if (d == 1) {
        for (int k = 0; k < e[2]; ++k) {
            real* dst = a + k * s2 + to * s1;
            const real* src = a + k * s2 + from * s1;
            for (int i = 0; i < e[0]; ++i)
                op(dst[i], src[i]);
        }
    } else {
        real* dst = a + to * s2;
        const real* src = a + from * s2;
        for (std::ptrdiff_t i = 0; i < s2; ++i)
            op(dst[i], src[i]);
    }
}

/// The x ghosts of a patch field at its non-exchanged ends, every layer of both ends in one
/// pass over the rows (layer by layer, as for_plane_pair does for y and z, each pass would
/// touch every row's first and last cache lines again): ghost l (0 nearest) takes the value
/// of the owned point l in from that end, the last owned point where the patch is thinner;
/// only the first `layers` ghosts.
void mirror_x_ends(Field& f, bool low, bool high, int layers) {
    const Int3& e = f.extent();
    const int n = f.cells()[0], h = f.halo()[0], g = std::min(h, layers);
    real* const a = f.data().data();
    const std::ptrdiff_t rows = std::ptrdiff_t(e[1]) * e[2];
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
        real* row = a + r * e[0];
        for (int l = 0; l < g; ++l) {
            const int m = std::min(l, n - 1);
            if (low) row[h - 1 - l] = row[h + m];
            if (high) row[h + n + l] = row[h + n - 1 - m];
        }
    }
}

} // namespace

void HaloFiller::apply_wall(Field& f, int d, int side, Mirror mirror, real wall_value) const {
    if (bc_[d][side].type == BoundaryType::Periodic || !dec_.at_boundary(d, side)) return;
    const Int3 n = f.cells();
    assert(f.begin() == Int3({0, 0, 0}) && "whole-block fields only; patches exchange elsewhere");
    const Int3 h = f.halo();
    const int g = h[d];
    // Index along d of the l-th ghost and of the interior point it mirrors (block-local).
    auto ghost_of = [&](int l) {
        if (mirror == Mirror::NormalFace) return side == 0 ? -l : n[d] + l;
        return side == 0 ? -1 - l : n[d] + l;
    };
    auto mirror_of = [&](int l) {
        if (mirror == Mirror::NormalFace) return side == 0 ? l : n[d] - l;
        return side == 0 ? l : n[d] - 1 - l;
    };
    // The whole wall plane, halos of the other directions included; ghosts and the points
    // they mirror are distinct, so the planes can be done one after the other.
    if (mirror == Mirror::NormalFace) {
        // The wall face itself: index 0 (owned) or n (first high halo).
        const int face = ghost_of(0) + g;
        for_plane_pair(f, d, face, face, [](real& v, real) { v = 0; });
        const int layers = side == 0 ? g : g - 1;
        for (int l = 1; l <= layers; ++l)
            for_plane_pair(f, d, ghost_of(l) + g, mirror_of(l) + g,
                           [](real& v, real m) { v = -m; });
    } else {
        for (int l = 0; l < g; ++l) {
            if (mirror == Mirror::Even)
                for_plane_pair(f, d, ghost_of(l) + g, mirror_of(l) + g,
                               [](real& v, real m) { v = m; });
            else
                for_plane_pair(f, d, ghost_of(l) + g, mirror_of(l) + g,
                               [w = 2 * wall_value](real& v, real m) { v = w - m; });
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
    Field* one[] = {&f};
    const Patch* of[] = {&patch};
    fill(one, of);
}

void HaloFiller::fill(std::span<Field* const> fields, std::span<const Patch* const> patches,
                      int edge_layers) const {
    if (edge_layers < 0) edge_layers = std::numeric_limits<int>::max();
    std::vector<Field*> live;
    std::vector<const Patch*> live_patch;
    for (std::size_t q = 0; q < fields.size(); ++q)
        if (!patches[q]->empty()) {
            live.push_back(fields[q]);
            live_patch.push_back(patches[q]);
        }
    std::vector<std::array<bool, 2>> with(live.size());
    for (int d = 0; d < dec_.dim(); ++d) {
        for (std::size_t q = 0; q < live.size(); ++q)
            with[q] = live_patch[q]->exchange[d];
        dec_.exchange_all(live, with, d);
        // Elsewhere (the patch's edge, a wall) the ghosts mirror the owned values, before
        // the next direction's exchange carries them into the edge and corner halos.
        for (std::size_t q = 0; q < live.size(); ++q) {
            Field& f = *live[q];
            const Patch& patch = *live_patch[q];
            if (d == 0) {
                if (!patch.exchange[0][0] || !patch.exchange[0][1])
                    mirror_x_ends(f, !patch.exchange[0][0], !patch.exchange[0][1], edge_layers);
                continue;
            }
            const Int3 n = f.cells();
            const Int3 h = f.halo();
            for (int side = 0; side < 2; ++side) {
                if (patch.exchange[d][side]) continue;
                for (int l = 0; l < std::min(h[d], edge_layers); ++l) {
                    // Storage indices along d (from the first halo layer) of the ghost and
                    // of the owned point it mirrors.
                    const int m = std::min(l, n[d] - 1);
                    const int ghost = side == 0 ? h[d] - 1 - l : h[d] + n[d] + l;
                    const int mirror = side == 0 ? h[d] + m : h[d] + n[d] - 1 - m;
                    for_plane_pair(f, d, ghost, mirror, [](real& v, real s) { v = s; });
                }
            }
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

void HaloFiller::fill_normal(VelocityField& v) const {
    for (int c = 0; c < v.dim; ++c) {
        dec_.exchange(v[c], c);
        for (int side = 0; side < 2; ++side)
            apply_wall(v[c], c, side, Mirror::NormalFace, 0);
    }
}

} // namespace efsi

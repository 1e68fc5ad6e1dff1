#include "bodies/patch.hpp"

namespace efsi {

Patch make_patch(const Box& box, const Decomposition& dec, int halo_width, bool cross_seam) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    Patch p;
    p.global = box;
    for (int d = 0; d < 3; ++d) {
        const int n = g.cells[d];
        if (d >= g.dim) {
            p.global.lo[d] = p.fitted.lo[d] = 0;
            p.global.hi[d] = p.fitted.hi[d] = n;
            continue;
        }
        const bool wraps = box.lo[d] < 0 || box.hi[d] > n;
        if (d == 0 && cross_seam && dec.periodic()[0] && dec.ranks_per_dim()[0] == 1 &&
            box.hi[0] - box.lo[0] < n) {
            // Unwrapped, its centre moved into [0, n) by whole periods (x is whole on every
            // rank, so nothing to widen).
            const int twice_centre = box.lo[0] + box.hi[0];
            const int shift = n * (twice_centre >= 0 ? twice_centre / (2 * n)
                                                     : -((-twice_centre - 1) / (2 * n) + 1));
            p.global.lo[0] = p.fitted.lo[0] = box.lo[0] - shift;
            p.global.hi[0] = p.fitted.hi[0] = box.hi[0] - shift;
            if (p.global.lo[0] < 0 || p.global.hi[0] > n) p.seam_period = n;
        } else if (dec.periodic()[d] && (wraps || box.hi[d] - box.lo[d] >= n)) {
            p.global.lo[d] = p.fitted.lo[d] = 0;
            p.global.hi[d] = p.fitted.hi[d] = n;
        } else {
            p.global.lo[d] = std::max(0, box.lo[d]);
            p.global.hi[d] = std::min(n, box.hi[d]);
            p.fitted.lo[d] = p.global.lo[d];
            p.fitted.hi[d] = p.global.hi[d];
            // Every rank the box touches must own at least `halo_width` layers of it, or
            // the slab a neighbour expects would not exist. Blocks are uniform, so every
            // rank widens the box identically.
            const int m = b.cells[d];
            const int first_block_end = (p.global.lo[d] / m + 1) * m;
            if (first_block_end - p.global.lo[d] < halo_width)
                p.global.lo[d] = first_block_end - halo_width;
            const int last_block_start = ((p.global.hi[d] - 1) / m) * m;
            if (p.global.hi[d] - last_block_start < halo_width)
                p.global.hi[d] = last_block_start + halo_width;
        }
    }
    Box block_global{
        b.offset, {b.offset[0] + b.cells[0], b.offset[1] + b.cells[1], b.offset[2] + b.cells[2]}};
    if (p.crosses_seam()) { // the rank owns all of x, across the seam too
        block_global.lo[0] = p.global.lo[0];
        block_global.hi[0] = p.global.hi[0];
    }
    p.local =
        shifted(intersect(p.global, block_global), {-b.offset[0], -b.offset[1], -b.offset[2]});
    if (p.local.empty()) return p;
    for (int d = 0; d < g.dim; ++d) {
        const bool full = p.global.lo[d] == 0 && p.global.hi[d] == g.cells[d];
        // Across a rank boundary the global box continues iff it extends past this block.
        const bool low_inside = p.global.lo[d] < b.offset[d];
        const bool high_inside = p.global.hi[d] > b.offset[d] + b.cells[d];
        const bool periodic_full = dec.periodic()[d] && full;
        // A box across the seam has its own two ends along x (the periodic neighbour of its
        // last cell is its first cell's image, not a halo to exchange).
        const bool own_ends = d == 0 && p.crosses_seam();
        p.exchange[d][0] = !own_ends && (low_inside || periodic_full) && dec.has_neighbour(d, 0);
        p.exchange[d][1] = !own_ends && (high_inside || periodic_full) && dec.has_neighbour(d, 1);
    }
    return p;
}

} // namespace efsi

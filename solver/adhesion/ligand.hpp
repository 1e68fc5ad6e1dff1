// Ligands (vWF) fixed on wall regions: each region is an axis-aligned box (a flat patch on a
// wall is a box of zero thickness) filled with sites on a lattice of the given spacing.
// A ligand's id is its index in the set; a ligand holds at most one bond.
//
// The set answers two questions cheaply:
//  - may_reach(x, d) / may_reach_box(lo, hi, d): is any ligand region within d of a point or
//    of a body's bounding box (a few box distances, no per-ligand work): the skip test;
//  - for_each_within(x, d, f): the ligands within d of x, through a uniform grid of cell
//    size reactive distance built once (ligands do not move).
// An empty set (a scene without adhesion) holds no memory.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace efsi::adhesion {

inline constexpr std::uint64_t no_receptor = std::numeric_limits<std::uint64_t>::max();

/// Box [lo, hi] [m] with ligand sites every `spacing` [m] along its non-degenerate sides
/// (a side of zero extent holds one layer of sites at lo). Surface density 1 / spacing^2.
struct LigandRegion {
    Real3 lo{};
    Real3 hi{};
    real spacing = 0;
};

/// Distance from x to the box [lo, hi] (0 inside).
real box_distance(const Real3& x, const Real3& lo, const Real3& hi);

/// Distance between two boxes (0 when they overlap).
real box_box_distance(const Real3& alo, const Real3& ahi, const Real3& blo, const Real3& bhi);

/// Throws InputError naming adhesion.ligand_regions[i] when a region is not a box
/// (lo > hi, non-finite), has a non-positive spacing, would hold more than `max_sites`
/// sites in all, or does not lie inside the domain [domain_lo, domain_hi]. Allocates nothing.
void validate_ligand_regions(std::span<const LigandRegion> regions, const Real3& domain_lo,
                             const Real3& domain_hi, std::uint64_t max_sites = 50'000'000);

class LigandSet {
  public:
    /// No ligands: allocates nothing.
    LigandSet() = default;

    /// Lattice sites in the regions (validated first, against an unbounded domain; call
    /// validate_ligand_regions with the domain before). `cell` is the lookup grid's cell
    /// size, normally the reactive distance.
    static LigandSet from_regions(std::span<const LigandRegion> regions, real cell);

    /// Explicit sites (ids 0..n-1 in the order given); the skip test uses their bounding box.
    static LigandSet from_sites(std::vector<Real3> sites, real cell);

    std::size_t size() const { return x_.size(); }
    bool empty() const { return x_.empty(); }
    const Real3& position(std::uint64_t id) const { return x_[id]; }
    /// The receptor bound to ligand `id`, or no_receptor.
    std::uint64_t bound_receptor(std::uint64_t id) const { return bound_[id]; }
    bool free(std::uint64_t id) const { return bound_[id] == no_receptor; }
    void bind(std::uint64_t id, std::uint64_t receptor) { bound_[id] = receptor; }
    void release(std::uint64_t id) { bound_[id] = no_receptor; }
    std::size_t bound_count() const;

    /// Is some region within `d` of x? (Cheap: one distance per region box.)
    bool may_reach(const Real3& x, real d) const;
    /// Is some region within `d` of the box [lo, hi] (e.g. a platelet's bounding box)?
    bool may_reach_box(const Real3& lo, const Real3& hi, real d) const;

    /// Calls f(id, distance) for every ligand within `d` of x, in increasing id order
    /// within each grid cell (the caller sorts if it needs a global order).
    template <class F>
    void for_each_within(const Real3& x, real d, F&& f) const;

    /// The index of the region (in the order given to from_regions) that holds ligand `id`;
    /// 0 for a set made from_sites.
    std::size_t region_of(std::uint64_t id) const {
        return static_cast<std::size_t>(
            std::upper_bound(region_end_.begin(), region_end_.end(), id) - region_end_.begin());
    }

    /// Region boxes of the skip test.
    std::span<const std::pair<Real3, Real3>> boxes() const { return boxes_; }

  private:
    void build_index(real cell);
    std::int64_t cell_of(real x, int dim) const;

    std::vector<Real3> x_;
    std::vector<std::uint64_t> bound_;
    std::vector<std::pair<Real3, Real3>> boxes_;
    std::vector<std::uint64_t> region_end_; ///< one past the last site of each region
    // Uniform grid over the sites' bounding box: keys_ sorted, order_[k] the site of keys_[k].
    real cell_ = 0;
    Real3 origin_{};
    std::array<std::int64_t, 3> ncell_{};
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> order_;
};

template <class F>
void LigandSet::for_each_within(const Real3& x, real d, F&& f) const {
    if (x_.empty()) return;
    std::array<std::int64_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(0, cell_of(x[a] - d, a));
        hi[a] = std::min<std::int64_t>(ncell_[a] - 1, cell_of(x[a] + d, a));
        if (lo[a] > hi[a]) return;
    }
    const real d2 = d * d;
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
            // One row of cells i = lo..hi is one contiguous key range.
            const auto key0 = static_cast<std::uint64_t>(lo[0] + ncell_[0] * (j + ncell_[1] * k));
            const auto key1 = static_cast<std::uint64_t>(hi[0] + ncell_[0] * (j + ncell_[1] * k));
            auto it = std::lower_bound(keys_.begin(), keys_.end(), key0);
            for (; it != keys_.end() && *it <= key1; ++it) {
                const std::uint32_t id = order_[static_cast<std::size_t>(it - keys_.begin())];
                const Real3& y = x_[id];
                const real r2 = (y[0] - x[0]) * (y[0] - x[0]) + (y[1] - x[1]) * (y[1] - x[1]) +
                                (y[2] - x[2]) * (y[2] - x[2]);
                if (r2 <= d2) f(std::uint64_t{id}, std::sqrt(r2));
            }
        }
}

} // namespace efsi::adhesion

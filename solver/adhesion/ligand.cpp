#include "adhesion/ligand.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <numeric>

namespace efsi::adhesion {

namespace {

/// Sites along one side of a region: one on a degenerate side, else extent / spacing
/// rounded (at least 1), centred in equal sub-intervals.
std::uint64_t sites_along(real lo, real hi, real spacing) {
    const real extent = hi - lo;
    if (extent <= 0) return 1;
    return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(extent / spacing)));
}

std::string box_text(const Real3& lo, const Real3& hi) {
    return fmt::format("[{:g}, {:g}, {:g}] - [{:g}, {:g}, {:g}]", lo[0], lo[1], lo[2], hi[0], hi[1],
                       hi[2]);
}

} // namespace

real box_distance(const Real3& x, const Real3& lo, const Real3& hi) {
    real s = 0;
    for (int a = 0; a < 3; ++a) {
        const real g = std::max({lo[a] - x[a], x[a] - hi[a], real(0)});
        s += g * g;
    }
    return std::sqrt(s);
}

real box_box_distance(const Real3& alo, const Real3& ahi, const Real3& blo, const Real3& bhi) {
    real s = 0;
    for (int a = 0; a < 3; ++a) {
        const real g = std::max({blo[a] - ahi[a], alo[a] - bhi[a], real(0)});
        s += g * g;
    }
    return std::sqrt(s);
}

void validate_ligand_regions(std::span<const LigandRegion> regions, const Real3& domain_lo,
                             const Real3& domain_hi, std::uint64_t max_sites) {
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < regions.size(); ++i) {
        const LigandRegion& r = regions[i];
        const std::string key = fmt::format("adhesion.ligand_regions[{}]", i);
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(r.lo[a]) || !std::isfinite(r.hi[a]))
                throw InputError(key + ": the box corners must be finite numbers");
            if (r.lo[a] > r.hi[a])
                throw InputError(fmt::format("{}: lo > hi along axis {} in the box {}", key, a,
                                             box_text(r.lo, r.hi)));
            if (r.lo[a] < domain_lo[a] || r.hi[a] > domain_hi[a])
                throw InputError(fmt::format("{}: the box {} is not inside the domain {}", key,
                                             box_text(r.lo, r.hi), box_text(domain_lo, domain_hi)));
        }
        if (!std::isfinite(r.spacing) || r.spacing <= 0)
            throw InputError(
                fmt::format("{}.spacing = {:g}: must be a positive length", key, r.spacing));
        std::uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            const real extent = r.hi[a] - r.lo[a];
            if (extent / r.spacing > static_cast<real>(max_sites))
                throw InputError(fmt::format("{}.spacing = {:g}: more than {} sites", key,
                                             r.spacing, max_sites));
            n *= sites_along(r.lo[a], r.hi[a], r.spacing);
            if (n > max_sites)
                throw InputError(fmt::format("{}.spacing = {:g}: more than {} sites", key,
                                             r.spacing, max_sites));
        }
        total += n;
        if (total > max_sites)
            throw InputError(
                fmt::format("{}: the regions hold more than {} sites in all", key, max_sites));
    }
}

LigandSet LigandSet::from_regions(std::span<const LigandRegion> regions, real cell) {
    const real inf = std::numeric_limits<real>::infinity();
    validate_ligand_regions(regions, {-inf, -inf, -inf}, {inf, inf, inf});
    LigandSet s;
    if (regions.empty()) return s;
    for (const LigandRegion& r : regions) {
        std::array<std::uint64_t, 3> n{};
        for (int a = 0; a < 3; ++a)
            n[a] = sites_along(r.lo[a], r.hi[a], r.spacing);
        for (std::uint64_t k = 0; k < n[2]; ++k)
            for (std::uint64_t j = 0; j < n[1]; ++j)
                for (std::uint64_t i = 0; i < n[0]; ++i) {
                    const std::array<std::uint64_t, 3> ijk{i, j, k};
                    Real3 y{};
                    for (int a = 0; a < 3; ++a) {
                        const real extent = r.hi[a] - r.lo[a];
                        y[a] = extent > 0 ? r.lo[a] + (static_cast<real>(ijk[a]) + 0.5) * extent /
                                                          static_cast<real>(n[a])
                                          : r.lo[a];
                    }
                    s.x_.push_back(y);
                }
        s.boxes_.emplace_back(r.lo, r.hi);
        s.region_end_.push_back(s.x_.size());
    }
    s.build_index(cell);
    return s;
}

LigandSet LigandSet::from_sites(std::vector<Real3> sites, real cell) {
    LigandSet s;
    if (sites.empty()) return s;
    s.x_ = std::move(sites);
    Real3 lo = s.x_[0], hi = s.x_[0];
    for (const Real3& y : s.x_) {
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(y[a]))
                throw InputError("adhesion: a ligand site is not a finite position");
            lo[a] = std::min(lo[a], y[a]);
            hi[a] = std::max(hi[a], y[a]);
        }
    }
    s.boxes_.emplace_back(lo, hi);
    s.build_index(cell);
    return s;
}

std::int64_t LigandSet::cell_of(real x, int dim) const {
    // Clamped to one cell beyond the grid before the conversion, so that a point far away
    // (or not finite) cannot overflow the integer.
    const real c = std::floor((x - origin_[dim]) / cell_);
    if (!(c >= -1)) return -1;
    return c > static_cast<real>(ncell_[dim]) ? ncell_[dim] : static_cast<std::int64_t>(c);
}

void LigandSet::build_index(real cell) {
    if (!(cell > 0) || !std::isfinite(cell))
        throw InputError(fmt::format("adhesion: the ligand grid cell ({:g} m, the reactive "
                                     "distance) must be a positive length",
                                     cell));
    if (x_.size() > std::numeric_limits<std::uint32_t>::max())
        throw InputError("adhesion: more than 2^32 ligand sites");
    bound_.assign(x_.size(), no_receptor);
    Real3 lo = x_[0], hi = x_[0];
    for (const Real3& y : x_)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], y[a]);
            hi[a] = std::max(hi[a], y[a]);
        }
    cell_ = cell;
    origin_ = lo;
    real cells = 1;
    for (int a = 0; a < 3; ++a) {
        ncell_[a] = static_cast<std::int64_t>(std::floor((hi[a] - lo[a]) / cell)) + 1;
        cells *= static_cast<real>(ncell_[a]);
    }
    if (cells > 0x1.0p62)
        throw InputError(fmt::format("adhesion: the ligand sites span too many grid cells of "
                                     "{:g} m (the reactive distance)",
                                     cell));
    const std::size_t n = x_.size();
    std::vector<std::uint64_t> key(n);
    for (std::size_t m = 0; m < n; ++m) {
        std::array<std::int64_t, 3> c{};
        for (int a = 0; a < 3; ++a)
            c[a] = std::clamp<std::int64_t>(cell_of(x_[m][a], a), 0, ncell_[a] - 1);
        key[m] = static_cast<std::uint64_t>(c[0] + ncell_[0] * (c[1] + ncell_[1] * c[2]));
    }
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0u);
    std::stable_sort(order_.begin(), order_.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    keys_.resize(n);
    for (std::size_t m = 0; m < n; ++m)
        keys_[m] = key[order_[m]];
}

std::size_t LigandSet::bound_count() const {
    return static_cast<std::size_t>(std::count_if(
        bound_.begin(), bound_.end(), [](std::uint64_t r) { return r != no_receptor; }));
}

bool LigandSet::may_reach(const Real3& x, real d) const {
    for (const auto& [lo, hi] : boxes_)
        if (box_distance(x, lo, hi) <= d) return true;
    return false;
}

bool LigandSet::may_reach_box(const Real3& lo, const Real3& hi, real d) const {
    for (const auto& [blo, bhi] : boxes_)
        if (box_box_distance(lo, hi, blo, bhi) <= d) return true;
    return false;
}

} // namespace efsi::adhesion

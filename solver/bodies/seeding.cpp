#include "bodies/seeding.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace efsi {

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

Real3 apply(const Matrix3& r, const Real3& y) {
    Real3 x{};
    for (int a = 0; a < 3; ++a)
        x[a] = r[a][0] * y[0] + r[a][1] * y[1] + r[a][2] * y[2];
    return x;
}

real dist2(const Real3& a, const Real3& b) {
    const real dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/// Surface points of a kind in body coordinates: lattice points inside the shape with a
/// lattice neighbour outside.
std::vector<Real3> surface_lattice(const SeedKind& kind, real h) {
    const auto shape = kind.make({0, 0, 0}, identity_rotation());
    const int n = int(std::ceil(kind.bounding_radius / h)) + 1;
    auto in = [&](int i, int j, int k) { return shape->inside({i * h, j * h, k * h}); };
    std::vector<Real3> pts;
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                if (!in(i, j, k)) continue;
                const bool edge = !in(i - 1, j, k) || !in(i + 1, j, k) || !in(i, j - 1, k) ||
                                  !in(i, j + 1, k) || !in(i, j, k - 1) || !in(i, j, k + 1);
                if (edge) pts.push_back({i * h, j * h, k * h});
            }
    return pts;
}

/// Points of the bodies placed so far, hashed on cells of side `cell`.
class PointHash {
  public:
    explicit PointHash(real cell) : cell_(cell) {}
    void add(const Real3& p) { map_[key(cell_of(p))].push_back(p); }
    /// True when a stored point lies closer than r (r <= cell) to p.
    bool near(const Real3& p, real r) const {
        const auto c = cell_of(p);
        const real r2 = r * r;
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const auto it = map_.find(key({c[0] + di, c[1] + dj, c[2] + dk}));
                    if (it == map_.end()) continue;
                    for (const Real3& q : it->second)
                        if (dist2(p, q) < r2) return true;
                }
        return false;
    }

  private:
    std::array<std::int64_t, 3> cell_of(const Real3& p) const {
        return {std::int64_t(std::floor(p[0] / cell_)), std::int64_t(std::floor(p[1] / cell_)),
                std::int64_t(std::floor(p[2] / cell_))};
    }
    static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
        return splitmix64(std::uint64_t(c[0]) * 73856093ULL ^ std::uint64_t(c[1]) * 19349663ULL ^
                          std::uint64_t(c[2]) * 83492791ULL);
    }
    real cell_;
    std::unordered_map<std::uint64_t, std::vector<Real3>> map_;
};

void validate(const SeedingRequest& r) {
    if (!r.region) throw InputError("seeding: no region to place the bodies in");
    if (!(r.region_volume > 0)) throw InputError("seeding: the region's volume must be > 0");
    if (r.kinds.empty()) throw InputError("seeding: no body kind to place");
    for (int d = 0; d < 3; ++d)
        if (!(r.box_hi[d] > r.box_lo[d]))
            throw InputError("seeding: the box to draw centres in is empty");
    for (const auto& k : r.kinds)
        if (!(k.volume > 0) || !(k.bounding_radius > 0) || !k.make)
            throw InputError(fmt::format("seeding: kind '{}' needs a volume, a bounding radius "
                                         "and a shape",
                                         k.name));
    if (r.fill_kind < 0 || r.fill_kind >= int(r.kinds.size()))
        throw InputError("seeding: fill_kind is not one of the kinds");
    if (!(r.target_fraction >= 0 && r.target_fraction < 1))
        throw InputError(
            fmt::format("seeding: target fraction {} is not in [0, 1)", r.target_fraction));
    if (r.counts.size() > r.kinds.size()) throw InputError("seeding: more counts than kinds");
    for (int c : r.counts)
        if (c < 0) throw InputError("seeding: a count is negative");
    if (!(r.gap >= 0)) throw InputError("seeding: the gap must be >= 0");
    if (r.max_candidates <= 0) throw InputError("seeding: max_candidates must be > 0");
}

} // namespace

real counter_uniform(std::uint64_t seed, std::uint64_t counter, std::uint64_t stream) {
    const std::uint64_t h =
        splitmix64(splitmix64(seed ^ 0x5851f42d4c957f2dULL) ^ splitmix64(counter * 4 + stream));
    return real(h >> 11) * 0x1.0p-53;
}

Matrix3 uniform_rotation(real u1, real u2, real u3) {
    // Shoemake's uniform random unit quaternion.
    const real a = std::sqrt(1 - u1), b = std::sqrt(u1);
    const real t2 = 2 * std::numbers::pi * u2, t3 = 2 * std::numbers::pi * u3;
    const real w = b * std::cos(t3), x = a * std::sin(t2), y = a * std::cos(t2),
               z = b * std::sin(t3);
    return Matrix3{Real3{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                   Real3{2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                   Real3{2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
}

SeedingResult seed_bodies(const SeedingRequest& r) {
    validate(r);
    real r_min = r.kinds[0].bounding_radius;
    for (const auto& k : r.kinds)
        r_min = std::min(r_min, k.bounding_radius);
    const real h = r.sample_spacing > 0 ? r.sample_spacing : r_min / 12;
    std::vector<std::vector<Real3>> lattice;
    for (const auto& k : r.kinds)
        lattice.push_back(surface_lattice(k, h));
    // Two surfaces closer than the gap (plus the lattice's own resolution) touch.
    const real reach = r.gap + h;
    PointHash hash(reach);
    std::vector<std::unique_ptr<Shape>> shapes;
    const bool region_is_distance = r.region->level_bounds_distance();

    SeedingResult out;
    real fill_volume = 0;
    const real target_volume = r.target_fraction * r.region_volume;
    std::vector<int> todo(r.kinds.size(), 0);
    for (std::size_t k = 0; k < r.counts.size(); ++k)
        todo[k] = r.counts[k];

    auto next_kind = [&]() -> int {
        for (std::size_t k = 0; k < todo.size(); ++k)
            if (todo[k] > 0) return int(k);
        // the fill kind while one more body keeps the fraction nearest the target
        if (fill_volume + 0.5 * r.kinds[r.fill_kind].volume <= target_volume) return r.fill_kind;
        return -1;
    };

    std::int64_t n = 0;
    for (int kind = next_kind(); kind >= 0 && n < r.max_candidates; kind = next_kind()) {
        const std::uint64_t c = std::uint64_t(n++);
        Real3 centre;
        for (int d = 0; d < 3; ++d)
            centre[d] = r.box_lo[d] + (r.box_hi[d] - r.box_lo[d]) * counter_uniform(r.seed, c, d);
        const Matrix3 rot = uniform_rotation(counter_uniform(r.seed, c, 3),
                                             counter_uniform(r.seed, c + (1ULL << 62), 0),
                                             counter_uniform(r.seed, c + (1ULL << 62), 1));
        std::vector<Real3> pts;
        pts.reserve(lattice[kind].size());
        bool ok = true;
        for (const Real3& y : lattice[kind]) {
            const Real3 d = apply(rot, y);
            const Real3 x{centre[0] + d[0], centre[1] + d[1], centre[2] + d[2]};
            const real lv = r.region->level(x);
            if (region_is_distance ? lv > -r.gap : lv >= 0) {
                ok = false;
                break;
            }
            pts.push_back(x);
        }
        if (!ok) continue;
        auto shape = r.kinds[kind].make(centre, rot);
        for (const Real3& x : pts)
            if (hash.near(x, reach)) {
                ok = false;
                break;
            }
        // Surface points of this body inside another (a body wholly inside another has no
        // surface points near the other's), for the bodies whose bounding spheres meet.
        for (std::size_t b = 0; ok && b < shapes.size(); ++b) {
            const real rr =
                r.kinds[kind].bounding_radius + r.kinds[out.bodies[b].kind].bounding_radius + r.gap;
            if (dist2(centre, out.bodies[b].centre) >= rr * rr) continue;
            if (shapes[b]->inside(centre) || shape->inside(out.bodies[b].centre)) ok = false;
            for (std::size_t m = 0; ok && m < pts.size(); ++m)
                if (shapes[b]->inside(pts[m])) ok = false;
        }
        if (!ok) continue;
        for (const Real3& x : pts)
            hash.add(x);
        shapes.push_back(std::move(shape));
        out.bodies.push_back({kind, centre, rot});
        if (todo[kind] > 0)
            --todo[kind];
        else
            fill_volume += r.kinds[kind].volume;
    }
    out.candidates = n;
    out.achieved_fraction = fill_volume / r.region_volume;
    const bool counts_done = std::all_of(todo.begin(), todo.end(), [](int t) { return t == 0; });
    out.reached = counts_done && next_kind() < 0;
    std::string placed;
    for (std::size_t k = 0; k < r.kinds.size(); ++k) {
        const auto m = std::count_if(out.bodies.begin(), out.bodies.end(),
                                     [&](const SeededBody& b) { return b.kind == int(k); });
        placed += fmt::format("{}{} {}", placed.empty() ? "" : ", ", m, r.kinds[k].name);
    }
    out.message =
        fmt::format("placed {} after {} candidates; {} volume fraction {:.4f} (target "
                    "{:.4f})",
                    placed, n, r.kinds[r.fill_kind].name, out.achieved_fraction, r.target_fraction);
    if (!out.reached)
        out.message += fmt::format(": NOT reached within {} candidates (seed {}); lower the "
                                   "target or the gap, or enlarge the region",
                                   r.max_candidates, r.seed);
    return out;
}

} // namespace efsi

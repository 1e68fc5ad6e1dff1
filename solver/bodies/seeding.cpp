#include "bodies/seeding.hpp"

#include "core/error.hpp"
#include "core/splitmix64.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

namespace efsi {

namespace {

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

/// Surface points of a shape in the lab frame: points of the lattice of spacing h through
/// `c` inside the shape with a lattice neighbour outside (`radius` bounds the shape about c).
std::vector<Real3> surface_lattice(const Shape& shape, const Real3& c, real radius, real h) {
    const int n = int(std::ceil(radius / h)) + 1;
    auto in = [&](int i, int j, int k) {
        return shape.inside({c[0] + i * h, c[1] + j * h, c[2] + k * h});
    };
    std::vector<Real3> pts;
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                if (!in(i, j, k)) continue;
                const bool edge = !in(i - 1, j, k) || !in(i + 1, j, k) || !in(i, j - 1, k) ||
                                  !in(i, j + 1, k) || !in(i, j, k - 1) || !in(i, j, k + 1);
                if (edge) pts.push_back({c[0] + i * h, c[1] + j * h, c[2] + k * h});
            }
    return pts;
}

/// Surface points of a kind in body coordinates (its shape at the origin).
std::vector<Real3> surface_lattice(const SeedKind& kind, real h) {
    const auto shape = kind.make({0, 0, 0}, identity_rotation());
    return surface_lattice(*shape, {0, 0, 0}, kind.bounding_radius, h);
}

/// Surface points of the placed bodies, binned on a regular grid of cells of side 2 r over
/// a box that holds every body (r the reach of the overlap test): the sphere of radius r
/// about any point then meets at most 2 x 2 x 2 cells. Each point remembers its body, so a
/// body can be taken out (when it moves) and left out of its own test.
class PointGrid {
  public:
    PointGrid(const Real3& lo, const Real3& hi, real reach) : lo_(lo), cell_(2 * reach) {
        for (int d = 0; d < 3; ++d)
            n_[d] = std::max<std::int64_t>(1, std::int64_t(std::ceil((hi[d] - lo[d]) / cell_)));
        cells_.resize(std::size_t(n_[0] * n_[1] * n_[2]));
        visited_.assign(cells_.size(), 0);
    }
    void add(int body, const std::vector<Real3>& pts) {
        for (const Real3& p : pts)
            cells_[index(p)].push_back({p, body});
    }
    /// Take body's points out: each cell they fall in is filtered once (a cell holds many
    /// points of one surface, so filtering it per point would scan it again and again).
    void remove(int body, const std::vector<Real3>& pts) {
        ++visit_;
        for (const Real3& p : pts) {
            const std::size_t c = index(p);
            if (visited_[c] == visit_) continue;
            visited_[c] = visit_;
            std::erase_if(cells_[c], [body](const Entry& e) { return e.body == body; });
        }
    }
    /// True when a point of a body other than `self` lies closer than r (<= reach) to p.
    bool near(const Real3& p, real r, int self) const {
        std::array<std::int64_t, 3> a{}, b{};
        for (int d = 0; d < 3; ++d) {
            a[d] = std::max<std::int64_t>(0, cell_of(p[d] - r, d));
            b[d] = std::min<std::int64_t>(n_[d] - 1, cell_of(p[d] + r, d));
        }
        const real r2 = r * r;
        for (std::int64_t k = a[2]; k <= b[2]; ++k)
            for (std::int64_t j = a[1]; j <= b[1]; ++j)
                for (std::int64_t i = a[0]; i <= b[0]; ++i)
                    for (const Entry& e : cells_[std::size_t((k * n_[1] + j) * n_[0] + i)])
                        if (e.body != self && dist2(p, e.p) < r2) return true;
        return false;
    }

  private:
    struct Entry {
        Real3 p;
        int body;
    };
    std::int64_t cell_of(real x, int d) const {
        return std::int64_t(std::floor((x - lo_[d]) / cell_));
    }
    std::size_t index(const Real3& p) const {
        std::array<std::int64_t, 3> c{};
        for (int d = 0; d < 3; ++d)
            c[d] = std::clamp<std::int64_t>(cell_of(p[d], d), 0, n_[d] - 1);
        return std::size_t((c[2] * n_[1] + c[1]) * n_[0] + c[0]);
    }
    Real3 lo_;
    real cell_;
    std::array<std::int64_t, 3> n_{};
    std::vector<std::vector<Entry>> cells_;
    std::vector<std::uint64_t> visited_; ///< per cell: the last remove() that filtered it
    std::uint64_t visit_ = 0;
};

void validate(const SeedingRequest& r) {
    if (!r.region) throw InputError("seeding: no region to place the bodies in");
    if (!(r.region_volume > 0)) throw InputError("seeding: the region's volume must be > 0");
    if (r.kinds.empty()) throw InputError("seeding: no body kind to place");
    for (int d = 0; d < 3; ++d)
        if (!(r.box_hi[d] > r.box_lo[d]))
            throw InputError("seeding: the box to draw centres in is empty");
    for (const auto& o : r.obstacles)
        if (!o.shape || !(o.bounding_radius > 0))
            throw InputError("seeding: an obstacle needs a shape and a bounding radius");
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
    if (r.max_shake_sweeps < 0) throw InputError("seeding: max_shake_sweeps must be >= 0");
    if (r.stall_candidates <= 0 || r.sweeps_per_stall <= 0)
        throw InputError("seeding: stall_candidates and sweeps_per_stall must be > 0");
}

} // namespace

real counter_uniform(std::uint64_t seed, std::uint64_t counter, std::uint64_t stream) {
    // Chained, not combined: distinct (counter, stream) pairs hash distinct inputs, for any
    // values of either.
    const std::uint64_t h =
        splitmix64(splitmix64(splitmix64(seed ^ 0x5851f42d4c957f2dULL) + counter) + stream);
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

namespace {

/// The purposes of the random numbers: a candidate's draws use the candidate's number as
/// counter, a shake move's its move number; the stream tells the purposes apart.
enum Stream : std::uint64_t {
    centre_x = 0, // centre_y = 1, centre_z = 2
    rotation_u1 = 3,
    rotation_u2 = 4,
    rotation_u3 = 5,
    shake_x = 8, // shake_y = 9, shake_z = 10
    shake_axis_z = 11,
    shake_axis_phi = 12,
    shake_angle = 13,
};

/// The bodies placed so far and the test a body must pass to be placed or moved.
class Packing {
  public:
    Packing(const SeedingRequest& r, real h) : r_(r), reach_(r.gap + h) {
        for (const auto& k : r.kinds) {
            lattice_.push_back(surface_lattice(k, h));
            real far = 0;
            for (const Real3& y : lattice_.back())
                far = std::max(far, std::sqrt(dist2(y, Real3{0, 0, 0})));
            lattice_radius_.push_back(far);
        }
        real rb = 0;
        for (const auto& k : r.kinds)
            rb = std::max(rb, k.bounding_radius);
        Real3 lo, hi;
        for (int d = 0; d < 3; ++d) {
            lo[d] = r.box_lo[d] - rb - 2 * reach_;
            hi[d] = r.box_hi[d] + rb + 2 * reach_;
        }
        grid_ = std::make_unique<PointGrid>(lo, hi, reach_);
        region_is_distance_ = r.region->level_bounds_distance();
        // The obstacles' surface points join the grid under ids below -1 (a placement
        // passes self = -1, a move its index >= 0), so no body ever skips them.
        for (std::size_t o = 0; o < r.obstacles.size(); ++o) {
            const SeedObstacle& ob = r.obstacles[o];
            grid_->add(-2 - int(o), surface_lattice(*ob.shape, ob.centre, ob.bounding_radius, h));
        }
    }

    /// A body of `kind` at (centre, rot) has its centre in the box, lies inside the region
    /// with the gap to its edge, no point of its surface lattice comes closer than gap + h
    /// to another body's (h the lattice spacing, so two surfaces closer than the gap touch)
    /// and none lies inside another body. Body `self` (a body being moved) is ignored. On
    /// success `pts_` and `shape_` hold the body's surface points and shape.
    bool fits(int kind, const Real3& centre, const Matrix3& rot, int self) {
        for (int d = 0; d < 3; ++d)
            if (centre[d] < r_.box_lo[d] || centre[d] > r_.box_hi[d]) return false;
        const std::vector<Real3>& lattice = lattice_[kind];
        const std::size_t count = lattice.size();
        pts_.resize(count);
        const bool region_holds_ball = ball_in_region(centre, lattice_radius_[kind]);
        // Point q placed, inside the region with the gap and not near another body.
        auto clear = [&](std::size_t q) {
            const Real3 d = apply(rot, lattice[q]);
            const Real3 x{centre[0] + d[0], centre[1] + d[1], centre[2] + d[2]};
            pts_[q] = x;
            if (!region_holds_ball) {
                const real lv = r_.region->level(x);
                if (region_is_distance_ ? lv > -r_.gap : lv >= 0) return false;
            }
            return !grid_->near(x, reach_, self);
        };
        // A sparse subset first (every kSparse-th point, spread over the whole surface): most
        // refused poses are refused there, before the other points are even placed. The
        // answer does not depend on the order.
        for (std::size_t q = 0; q < count; q += kSparse)
            if (!clear(q)) return false;
        for (std::size_t q = 0; q < count; ++q)
            if (q % kSparse != 0 && !clear(q)) return false;
        // Surface points of this body inside another (a body wholly inside another has no
        // surface points near the other's), for the bodies whose bounding spheres meet.
        shape_ = r_.kinds[kind].make(centre, rot);
        for (const SeedObstacle& o : r_.obstacles) {
            const real rr = r_.kinds[kind].bounding_radius + o.bounding_radius + r_.gap;
            if (dist2(centre, o.centre) >= rr * rr) continue;
            if (o.shape->inside(centre) || shape_->inside(o.centre)) return false;
            const real ro2 = o.bounding_radius * o.bounding_radius;
            for (const Real3& x : pts_)
                if (dist2(x, o.centre) < ro2 && o.shape->inside(x)) return false;
        }
        for (std::size_t b = 0; b < bodies.size(); ++b) {
            if (int(b) == self) continue;
            const real rr =
                r_.kinds[kind].bounding_radius + r_.kinds[bodies[b].kind].bounding_radius + r_.gap;
            if (dist2(centre, bodies[b].centre) >= rr * rr) continue;
            if (shapes_[b]->inside(centre) || shape_->inside(bodies[b].centre)) return false;
            const real rb2 = std::pow(r_.kinds[bodies[b].kind].bounding_radius, 2);
            for (const Real3& x : pts_)
                if (dist2(x, bodies[b].centre) < rb2 && shapes_[b]->inside(x)) return false;
        }
        return true;
    }

    /// Place the body last passed to fits().
    void add(int kind, const Real3& centre, const Matrix3& rot) {
        const int id = int(bodies.size());
        grid_->add(id, pts_);
        points_.push_back(std::move(pts_));
        shapes_.push_back(std::move(shape_));
        bodies.push_back({kind, centre, rot});
    }

    /// Move body b to (centre, rot) if it fits there; whether it moved. Its own surface
    /// points leave the grid during the test (fits() would skip them one by one, and near
    /// every point of the moved surface lie hundreds of them).
    bool try_move(int b, const Real3& centre, const Matrix3& rot) {
        grid_->remove(b, points_[b]);
        if (!fits(bodies[b].kind, centre, rot, b)) {
            grid_->add(b, points_[b]);
            return false;
        }
        grid_->add(b, pts_);
        points_[b] = std::move(pts_);
        shapes_[b] = std::move(shape_);
        bodies[b].centre = centre;
        bodies[b].rotation = rot;
        return true;
    }

    std::vector<SeededBody> bodies;

  private:
    /// Whether every point within `radius` of `centre` passes the region test, decided
    /// from the centre alone: a level that bounds the distance is 1-Lipschitz, so
    /// level(x) <= level(centre) + radius there. The margin (1e-9 of the lengths involved,
    /// far above the level's round-off) keeps every answer the per-point test would give.
    bool ball_in_region(const Real3& centre, real radius) const {
        if (!region_is_distance_) return false;
        const real lc = r_.region->level(centre);
        const real scale = std::abs(lc) + radius + r_.gap + 1;
        return lc + radius + r_.gap < -1e-9 * scale;
    }

    static constexpr std::size_t kSparse = 29; ///< fits(): the sparse subset's stride
    const SeedingRequest& r_;
    real reach_;
    bool region_is_distance_ = false;
    std::vector<std::vector<Real3>> lattice_; ///< per kind, in body coordinates
    std::vector<real> lattice_radius_;        ///< per kind: the farthest lattice point
    std::unique_ptr<PointGrid> grid_;
    std::vector<std::vector<Real3>> points_; ///< per body, in the lab frame
    std::vector<std::unique_ptr<Shape>> shapes_;
    std::vector<Real3> pts_;
    std::unique_ptr<Shape> shape_;
};

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
    Matrix3 c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    return c;
}

/// Monte Carlo shake of hard bodies: each sweep tries, body after body, a uniform random
/// displacement in [-dx, dx]^3 and a rotation by an angle in [-da, da] about a uniformly
/// random axis, accepted when the moved body still fits. The steps adapt after every sweep
/// to keep the acceptance near 1/3 (larger steps relax faster; too large are refused).
class Shaker {
  public:
    Shaker(real dx, real dx_min, real dx_max) : dx_(dx), dx_min_(dx_min), dx_max_(dx_max) {}

    void sweep(Packing& p, const SeedingRequest& r) {
        int accepted = 0;
        const int n = int(p.bodies.size());
        for (int b = 0; b < n; ++b) {
            const std::uint64_t m = moves_++;
            const SeededBody& s = p.bodies[b];
            Real3 centre = s.centre;
            for (int d = 0; d < 3; ++d)
                centre[d] += dx_ * (2 * counter_uniform(r.seed, m, shake_x + d) - 1);
            const real z = 2 * counter_uniform(r.seed, m, shake_axis_z) - 1;
            const real phi = 2 * std::numbers::pi * counter_uniform(r.seed, m, shake_axis_phi);
            const real q = std::sqrt(std::max(real(0), 1 - z * z));
            const real angle = da_ * (2 * counter_uniform(r.seed, m, shake_angle) - 1);
            const Matrix3 rot = multiply(
                axis_angle_rotation({q * std::cos(phi), q * std::sin(phi), z}, angle), s.rotation);
            if (p.try_move(b, centre, rot)) ++accepted;
        }
        ++sweeps;
        const real rate = n > 0 ? real(accepted) / n : 0;
        const real f = rate > 0.45 ? 1.25 : rate < 0.25 ? 0.8 : 1;
        dx_ = std::clamp(dx_ * f, dx_min_, dx_max_);
        da_ = std::clamp(da_ * f, real(1e-3), real(0.5));
    }

    std::int64_t sweeps = 0;

  private:
    real dx_, dx_min_, dx_max_;
    real da_ = 0.2;
    std::uint64_t moves_ = 0;
};

} // namespace

SeedingResult seed_bodies(const SeedingRequest& r) {
    validate(r);
    real r_min = r.kinds[0].bounding_radius;
    for (const auto& k : r.kinds)
        r_min = std::min(r_min, k.bounding_radius);
    const real h = r.sample_spacing > 0 ? r.sample_spacing : r_min / 12;
    Packing packing(r, h);
    Shaker shaker(4 * h, h / 8, r_min);

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

    std::int64_t n = 0, misses = 0;
    for (int kind = next_kind(); kind >= 0 && n < r.max_candidates; kind = next_kind()) {
        // Addition has stalled: shake the bodies to move the free space about.
        if (misses >= r.stall_candidates && shaker.sweeps < r.max_shake_sweeps &&
            !packing.bodies.empty()) {
            for (int s = 0; s < r.sweeps_per_stall && shaker.sweeps < r.max_shake_sweeps; ++s)
                shaker.sweep(packing, r);
            misses = 0;
        }
        const std::uint64_t c = std::uint64_t(n++);
        Real3 centre;
        for (int d = 0; d < 3; ++d)
            centre[d] = r.box_lo[d] +
                        (r.box_hi[d] - r.box_lo[d]) * counter_uniform(r.seed, c, centre_x + d);
        const Matrix3 rot = uniform_rotation(counter_uniform(r.seed, c, rotation_u1),
                                             counter_uniform(r.seed, c, rotation_u2),
                                             counter_uniform(r.seed, c, rotation_u3));
        if (!packing.fits(kind, centre, rot, -1)) {
            ++misses;
            continue;
        }
        misses = 0;
        packing.add(kind, centre, rot);
        if (todo[kind] > 0)
            --todo[kind];
        else
            fill_volume += r.kinds[kind].volume;
    }
    out.bodies = std::move(packing.bodies);
    out.candidates = n;
    out.sweeps = shaker.sweeps;
    out.achieved_fraction = fill_volume / r.region_volume;
    const bool counts_done = std::all_of(todo.begin(), todo.end(), [](int t) { return t == 0; });
    out.reached = counts_done && next_kind() < 0;
    std::string placed;
    for (std::size_t k = 0; k < r.kinds.size(); ++k) {
        const auto m = std::count_if(out.bodies.begin(), out.bodies.end(),
                                     [&](const SeededBody& b) { return b.kind == int(k); });
        placed += fmt::format("{}{} {}", placed.empty() ? "" : ", ", m, r.kinds[k].name);
    }
    out.message = fmt::format("placed {} after {} candidates and {} shake sweeps; {} volume "
                              "fraction {:.4f} (target {:.4f})",
                              placed, n, out.sweeps, r.kinds[r.fill_kind].name,
                              out.achieved_fraction, r.target_fraction);
    if (!out.reached)
        out.message += fmt::format(": NOT reached within {} candidates and {} shake sweeps "
                                   "(seed {}); lower the target or the gap, or enlarge the region",
                                   r.max_candidates, r.max_shake_sweeps, r.seed);
    return out;
}

} // namespace efsi

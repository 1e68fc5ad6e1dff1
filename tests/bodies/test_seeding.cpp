// Random placement of cells in a lumen: reproducible, inside, without overlap, to target;
// the shake takes the capillary past the 19 % at which addition alone jams.
#include "bodies/seeding.hpp"
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

using namespace efsi;

namespace {

constexpr real um = 1e-6;

SeedKind red_cell() {
    SeedKind k;
    k.name = "rbc";
    const EvansFungCoefficients c;
    k.volume = make_biconcave_disc({0, 0, 0})->exact_volume();
    k.bounding_radius = c.r0 * 1.001;
    k.make = [](const Real3& x, const Matrix3& r) { return make_biconcave_disc(x, r); };
    return k;
}

SeedKind platelet() {
    SeedKind k;
    k.name = "platelet";
    const Real3 semi{1.0 * um, 1.0 * um, 0.6 * um};
    k.volume = 4.0 / 3.0 * std::numbers::pi * semi[0] * semi[1] * semi[2];
    k.bounding_radius = 1.0 * um;
    k.make = [semi](const Real3& x, const Matrix3& r) { return make_ellipsoid(x, semi, r); };
    return k;
}

/// A tube of lumen radius 10 um along x, 44 um long (the seed paper's capillary), capped
/// by the box ends (the region is a box intersected with a cylinder: here a cylinder whose
/// axis is x, and centres drawn only where the body cannot cross the ends).
struct Tube {
    std::unique_ptr<Shape> lumen =
        make_cylinder({0, 0, 0}, 10 * um, axis_angle_rotation({0, 1, 0}, std::numbers::pi / 2));
    real length = 44 * um;
    real volume() const { return std::numbers::pi * 100 * um * um * length; }
};

SeedingRequest capillary(const Tube& t, real ht, std::uint64_t seed) {
    SeedingRequest r;
    r.region = t.lumen.get();
    r.region_volume = t.volume();
    const real R = red_cell().bounding_radius;
    r.box_lo = {-t.length / 2 + R, -10 * um, -10 * um};
    r.box_hi = {t.length / 2 - R, 10 * um, 10 * um};
    r.kinds = {red_cell(), platelet()};
    r.counts = {0, 3};
    r.fill_kind = 0;
    r.target_fraction = ht;
    r.gap = 0.2 * um;
    r.seed = seed;
    return r;
}

/// Half-extents of a body's axis-aligned bounding box: a red cell lies in the cylinder of
/// radius R0 and half-thickness t = 0.33 R0 about its axis (Evans-Fung: the thickest point
/// is 0.31 R0 from the mid-plane), a platelet in its bounding sphere.
constexpr real half_thickness = 0.33;
Real3 half_extent(const SeededBody& b) {
    if (b.kind == 1) return {1.0 * um, 1.0 * um, 1.0 * um};
    const real r0 = EvansFungCoefficients{}.r0, t = half_thickness * r0;
    Real3 e{};
    for (int a = 0; a < 3; ++a) {
        const real n = std::abs(b.rotation[a][2]); // lab component a of the disc's axis
        e[a] = r0 * std::sqrt(std::max(0.0, 1 - n * n)) + t * n;
    }
    return e;
}

/// A lower bound of the distance from x to a body (to its bounding cylinder or sphere),
/// cheap enough to skip the exact distance far from it.
real distance_bound(const SeededBody& b, const Real3& x) {
    const Real3 d{x[0] - b.centre[0], x[1] - b.centre[1], x[2] - b.centre[2]};
    if (b.kind == 1) return std::hypot(d[0], d[1], d[2]) - 1.0 * um;
    const real r0 = EvansFungCoefficients{}.r0;
    const real axial = d[0] * b.rotation[0][2] + d[1] * b.rotation[1][2] + d[2] * b.rotation[2][2];
    const real radial =
        std::sqrt(std::max(0.0, d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - axial * axial));
    return std::max(radial - r0, std::abs(axial) - half_thickness * r0);
}

/// The shape of a body for the checks: a red cell with its exact signed distance (so the
/// gap can be checked), a platelet as seeded.
std::unique_ptr<Shape> check_shape(const SeededBody& b) {
    if (b.kind == 1) return platelet().make(b.centre, b.rotation);
    return make_biconcave_distance(b.centre, b.rotation);
}

/// Independent of the seeding's surface lattices: every point of a lattice of spacing
/// `hf` (finer than the seeding's 1 um / 12) in the overlap of two bodies' bounding boxes
/// is tested against both shapes. Two red cells must keep `clear` between their surfaces
/// (level < clear / 2 in both is a violation); a pair with a platelet must not overlap.
int violations(const std::vector<SeededBody>& bodies, real hf, real clear) {
    int bad = 0;
    std::vector<std::unique_ptr<Shape>> shapes;
    for (const auto& b : bodies)
        shapes.push_back(check_shape(b));
    for (std::size_t i = 0; i < bodies.size(); ++i)
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            const Real3 ei = half_extent(bodies[i]), ej = half_extent(bodies[j]);
            Real3 lo, hi;
            bool apart = false;
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::max(bodies[i].centre[d] - ei[d], bodies[j].centre[d] - ej[d]) - clear;
                hi[d] = std::min(bodies[i].centre[d] + ei[d], bodies[j].centre[d] + ej[d]) + clear;
                apart = apart || lo[d] >= hi[d];
            }
            if (apart) continue;
            const real c = bodies[i].kind == 0 && bodies[j].kind == 0 ? clear / 2 : 0;
            bool hit = false;
            for (real z = lo[2]; z < hi[2] && !hit; z += hf)
                for (real y = lo[1]; y < hi[1] && !hit; y += hf)
                    for (real x = lo[0]; x < hi[0] && !hit; x += hf) {
                        const Real3 p{x, y, z};
                        if (distance_bound(bodies[i], p) >= c || distance_bound(bodies[j], p) >= c)
                            continue;
                        hit = shapes[i]->level(p) < c && shapes[j]->level(p) < c;
                    }
            if (hit) {
                ADD_FAILURE() << "bodies " << i << " and " << j << " closer than allowed";
                ++bad;
            }
        }
    return bad;
}

/// Every body inside the lumen with clearance `clear` to its wall, and inside the tube's
/// length (no body crosses the ends): checked on a lattice of spacing hf over each body.
int outside(const std::vector<SeededBody>& bodies, const Tube& t, real hf, real clear) {
    int bad = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const auto s = check_shape(bodies[i]);
        const Real3 e = half_extent(bodies[i]);
        const Real3& c = bodies[i].centre;
        bool out = false;
        for (real z = c[2] - e[2]; z < c[2] + e[2] && !out; z += hf)
            for (real y = c[1] - e[1]; y < c[1] + e[1] && !out; y += hf)
                for (real x = c[0] - e[0]; x < c[0] + e[0] && !out; x += hf) {
                    const Real3 p{x, y, z};
                    if (t.lumen->level(p) <= -clear && std::abs(x) <= t.length / 2) continue;
                    out = s->inside(p);
                }
        if (out) {
            ADD_FAILURE() << "body " << i << " leaves the lumen";
            ++bad;
        }
    }
    return bad;
}

/// The volume fraction of the red cells, counted from the scene itself.
real red_cell_fraction(const SeedingResult& r, const Tube& t) {
    const auto n = std::count_if(r.bodies.begin(), r.bodies.end(),
                                 [](const SeededBody& b) { return b.kind == 0; });
    return real(n) * red_cell().volume / t.volume();
}

} // namespace

TEST(Seeding, SameSeedGivesTheSameSceneAnotherSeedAnother) {
    Tube t;
    const auto a = seed_bodies(capillary(t, 0.10, 7));
    const auto b = seed_bodies(capillary(t, 0.10, 7));
    const auto c = seed_bodies(capillary(t, 0.10, 8));
    ASSERT_EQ(a.bodies.size(), b.bodies.size());
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
        EXPECT_EQ(a.bodies[i].centre, b.bodies[i].centre);
        EXPECT_EQ(a.bodies[i].rotation, b.bodies[i].rotation);
    }
    EXPECT_NE(a.bodies[0].centre, c.bodies[0].centre);
}

TEST(Seeding, CapillaryAtFifteenPercentIsReachedInsideAndWithoutOverlap) {
    Tube t;
    const auto r = seed_bodies(capillary(t, 0.15, 2026));
    ASSERT_TRUE(r.reached) << r.message;
    const real v_rbc = red_cell().volume;
    // nearest whole number of cells to the target
    EXPECT_NEAR(r.achieved_fraction, 0.15, 0.5 * v_rbc / t.volume() + 1e-12) << r.message;
    EXPECT_NEAR(red_cell_fraction(r, t), r.achieved_fraction, 1e-12);
    const auto platelets = std::count_if(r.bodies.begin(), r.bodies.end(),
                                         [](const SeededBody& b) { return b.kind == 1; });
    EXPECT_EQ(platelets, 3);
    EXPECT_EQ(violations(r.bodies, 0.05 * um, 0.1 * um), 0);
    EXPECT_EQ(outside(r.bodies, t, 0.05 * um, 0.1 * um), 0);
}

TEST(Seeding, CapillaryAtTwentyPercentIsReachedByShaking) {
    // Addition alone stalls at 28 red cells (19.1 %) of this target after 200 000
    // candidates; the shake has to do the rest.
    Tube t;
    const auto start = std::chrono::steady_clock::now();
    const auto r = seed_bodies(capillary(t, 0.20, 2026));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("capillary 20 um x 44 um, seed 2026: %s; %.2f s\n", r.message.c_str(), seconds);
    ASSERT_TRUE(r.reached) << r.message;
    const real v_rbc = red_cell().volume;
    EXPECT_NEAR(r.achieved_fraction, 0.20, 0.5 * v_rbc / t.volume() + 1e-12) << r.message;
    EXPECT_NEAR(red_cell_fraction(r, t), r.achieved_fraction, 1e-12);
    EXPECT_GT(r.sweeps, 0) << "reached without shaking: the test no longer tests the shake";
    EXPECT_EQ(violations(r.bodies, 0.05 * um, 0.1 * um), 0);
    EXPECT_EQ(outside(r.bodies, t, 0.05 * um, 0.1 * um), 0);

    // The same seed gives the same scene, shake included.
    const auto again = seed_bodies(capillary(t, 0.20, 2026));
    ASSERT_EQ(again.bodies.size(), r.bodies.size());
    EXPECT_EQ(again.sweeps, r.sweeps);
    for (std::size_t i = 0; i < r.bodies.size(); ++i) {
        EXPECT_EQ(again.bodies[i].centre, r.bodies[i].centre) << "body " << i;
        EXPECT_EQ(again.bodies[i].rotation, r.bodies[i].rotation) << "body " << i;
    }
}

// Bodies given by hand (a sphere in the middle of the lumen and a platelet near its wall)
// are obstacles: no seeded body comes within the gap of them. Checked on a lattice finer
// than the seeding's, independently of its surface points; the same seed without the
// obstacles puts bodies where they are, so the check can fail.
TEST(Seeding, BodiesGivenByHandAreKeptClearOf) {
    Tube t;
    const Real3 cs{0, 0, 0}, cp{5 * um, -8.5 * um, 0};
    const auto sphere = make_sphere(cs, 4 * um);
    const auto by_hand = platelet().make(cp, identity_rotation());
    auto hits = [&](const SeedingResult& res) {
        int bad = 0;
        const real hf = 0.05 * um;
        for (const SeededBody& b : res.bodies) {
            const auto s = check_shape(b);
            const Real3 e = half_extent(b);
            const Real3& c = b.centre;
            bool hit = false;
            for (real z = c[2] - e[2]; z < c[2] + e[2] && !hit; z += hf)
                for (real y = c[1] - e[1]; y < c[1] + e[1] && !hit; y += hf)
                    for (real x = c[0] - e[0]; x < c[0] + e[0] && !hit; x += hf) {
                        const Real3 p{x, y, z};
                        if (std::hypot(x - cs[0], y - cs[1], z - cs[2]) > 4.2 * um &&
                            std::hypot(x - cp[0], y - cp[1], z - cp[2]) > 1.1 * um)
                            continue;
                        hit = s->inside(p) && (sphere->level(p) < 0.1 * um || by_hand->inside(p));
                    }
            bad += hit;
        }
        return bad;
    };
    SeedingRequest q = capillary(t, 0.15, 2026);
    q.obstacles = {{sphere.get(), cs, 4 * um}, {by_hand.get(), cp, 1 * um}};
    const auto r = seed_bodies(q);
    ASSERT_TRUE(r.reached) << r.message;
    EXPECT_EQ(hits(r), 0);
    EXPECT_EQ(violations(r.bodies, 0.05 * um, 0.1 * um), 0);
    EXPECT_GT(hits(seed_bodies(capillary(t, 0.15, 2026))), 0);
    // An obstacle without a shape is refused.
    q.obstacles = {{nullptr, cs, 4 * um}};
    EXPECT_THROW(seed_bodies(q), InputError);
}

TEST(Seeding, AnUnreachableTargetSaysWhatWasReached) {
    Tube t;
    auto req = capillary(t, 0.60, 3);
    req.max_candidates = 20000;
    req.max_shake_sweeps = 40;
    const auto r = seed_bodies(req);
    EXPECT_FALSE(r.reached);
    EXPECT_LT(r.achieved_fraction, 0.60);
    EXPECT_GT(r.achieved_fraction, 0.10) << r.message;
    EXPECT_NEAR(red_cell_fraction(r, t), r.achieved_fraction, 1e-12);
    EXPECT_EQ(r.sweeps, 40) << r.message;
    EXPECT_NE(r.message.find("NOT reached"), std::string::npos) << r.message;
    char achieved[64];
    std::snprintf(achieved, sizeof achieved, "rbc volume fraction %.4f", r.achieved_fraction);
    EXPECT_NE(r.message.find(achieved), std::string::npos) << r.message;
}

TEST(Seeding, BadRequestsAreRefusedBeforeAnyWork) {
    Tube t;
    auto req = capillary(t, 0.2, 1);
    req.target_fraction = 1.5;
    EXPECT_THROW(seed_bodies(req), InputError);
    req = capillary(t, 0.2, 1);
    req.region = nullptr;
    EXPECT_THROW(seed_bodies(req), InputError);
    req = capillary(t, 0.2, 1);
    req.counts = {0, -1};
    EXPECT_THROW(seed_bodies(req), InputError);
    req = capillary(t, 0.2, 1);
    req.max_shake_sweeps = -1;
    EXPECT_THROW(seed_bodies(req), InputError);
}

TEST(Seeding, RandomRotationsAreProperAndUniformOnAverage) {
    real mean_zz = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const Matrix3 r = uniform_rotation(counter_uniform(5, i, 0), counter_uniform(5, i, 1),
                                           counter_uniform(5, i, 2));
        const real det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                         r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                         r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        ASSERT_NEAR(det, 1.0, 1e-12);
        mean_zz += r[2][2] * r[2][2] / n; // <cos^2> = 1/3 for a uniform axis
    }
    EXPECT_NEAR(mean_zz, 1.0 / 3.0, 4 * std::sqrt(4.0 / 45.0 / n));
}

// A measurement, not a check (run with --gtest_also_run_disabled_tests): how far the shake
// takes the capillary at seed 2026 within the default budgets, and at what cost.
TEST(Seeding, DISABLED_HowFarTheShakeGoes) {
    Tube t;
    for (const real ht : {0.20, 0.22, 0.25, 0.28, 0.30}) {
        const auto start = std::chrono::steady_clock::now();
        const auto r = seed_bodies(capillary(t, ht, 2026));
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("target %.2f: %s; %.1f s\n", ht, r.message.c_str(), seconds);
    }
}

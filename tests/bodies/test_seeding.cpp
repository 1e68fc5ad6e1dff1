// Random placement of cells in a lumen: reproducible, inside, without overlap, to target.
#include "bodies/seeding.hpp"
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

/// Independent overlap check on a fine lattice over the pair's bounding spheres.
bool overlap(const Shape& a, const Real3& ca, const Shape& b, const Real3& cb, real R) {
    const real h = R / 30;
    const int n = int(R / h);
    for (int k = -n; k <= n; ++k)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                const Real3 x{ca[0] + i * h, ca[1] + j * h, ca[2] + k * h};
                if (a.inside(x) && b.inside(x)) return true;
            }
    (void)cb;
    return false;
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
    int platelets = 0;
    std::vector<std::unique_ptr<Shape>> shapes;
    for (const auto& b : r.bodies) {
        platelets += b.kind == 1;
        shapes.push_back(capillary(t, 0.2, 1).kinds[b.kind].make(b.centre, b.rotation));
        // inside the lumen: the bounding sphere's points inside the body are in the lumen
        EXPECT_LT(t.lumen->level(b.centre), 0);
    }
    EXPECT_EQ(platelets, 3);
    for (std::size_t i = 0; i < shapes.size(); ++i)
        for (std::size_t j = i + 1; j < shapes.size(); ++j) {
            const real d = std::sqrt(std::pow(r.bodies[i].centre[0] - r.bodies[j].centre[0], 2) +
                                     std::pow(r.bodies[i].centre[1] - r.bodies[j].centre[1], 2) +
                                     std::pow(r.bodies[i].centre[2] - r.bodies[j].centre[2], 2));
            if (d > 2 * red_cell().bounding_radius) continue;
            EXPECT_FALSE(overlap(*shapes[i], r.bodies[i].centre, *shapes[j], r.bodies[j].centre,
                                 red_cell().bounding_radius))
                << "bodies " << i << " and " << j;
        }
}

TEST(Seeding, AnUnreachableTargetSaysWhatWasReached) {
    Tube t;
    auto req = capillary(t, 0.80, 3);
    req.max_candidates = 3000;
    const auto r = seed_bodies(req);
    EXPECT_FALSE(r.reached);
    EXPECT_LT(r.achieved_fraction, 0.80);
    EXPECT_NE(r.message.find("NOT reached"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("rbc volume fraction"), std::string::npos) << r.message;
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

// The [seeding] section (config/seeding_config.cpp): cells placed in a tube's lumen become
// [[body]] entries before any allocation; the same seed gives the same scene, the resolved
// case is the explicit scene, and bad input is an InputError naming the key.
#include "config/seeding_config.hpp"
#include "interface/shapes.hpp"
#include "test_support.hpp"

#include <cmath>
#include <numbers>

using namespace efsi;
using efsi::test::case_from;
using efsi::test::input_error_of;
using ::testing::HasSubstr;

namespace {

// The seed paper's capillary in um, ms, mPa s (cases/capillary_coarse), at 32 x 16 x 16.
const std::string vessel = R"(
[grid]
cells = [32, 16, 16]
length = [44.0, 22.0, 22.0]
[fluid]
density = 1.0e-3
viscosity = 1.2
[boundary]
y_low = "wall"
y_high = "wall"
z_low = "wall"
z_high = "wall"
[time]
end_time = 1.0
[[body]]
name = "wall"
kind = "solid"
shape = "tube"
centre = [22.0, 11.0, 11.0]
lumen_diameter = 20.0
pinned = true
)";

// The red cells that fill the region (the fill kind of every scene here).
const std::string rbc_kind = R"(
[[seeding.kind]]
name = "rbc"
fill = true
[seeding.kind.body]
kind = "membrane"
shape = "biconcave"
radius = 3.91
interface = "smoothed"
law = "skalak"
elastic_modulus = 9.0
area_dilation = 10.0
)";

std::string seeding(const std::string& head, const std::string& rbc_extra = "") {
    return vessel + "[seeding]\nvessel = \"wall\"\n" + head + R"(
[[seeding.kind]]
name = "platelet"
count = 2
[seeding.kind.body]
kind = "solid"
shape = "ellipsoid"
semi_axes = [1.0, 1.0, 0.6]
shear_modulus = 100.0)" +
           rbc_kind + rbc_extra;
}

} // namespace

TEST(SeedingConfig, ExpandsIntoBodiesToTheTargetHaematocrit) {
    const Config c = case_from(seeding("target_haematocrit = 0.05\nseed = 7\n"));
    ASSERT_TRUE(c.seeding.used);
    const real v_rbc = make_biconcave_disc({0, 0, 0}, identity_rotation(), {3.91})->exact_volume();
    const real lumen = std::numbers::pi * 100 * 44;
    EXPECT_NEAR(c.seeding.lumen_volume, lumen, 1e-9 * lumen);
    // the nearest whole number of cells to the target
    EXPECT_NEAR(c.seeding.achieved, 0.05, 0.5 * v_rbc / lumen + 1e-12);
    int rbc = 0, platelets = 0;
    for (const BodyConfig& b : c.bodies) {
        if (b.name.rfind("rbc_", 0) == 0) {
            ++rbc;
            EXPECT_EQ(b.kind, BodyKind::Membrane);
            EXPECT_EQ(b.law, MembraneLawKind::Skalak);
        }
        if (b.name.rfind("platelet_", 0) == 0) {
            ++platelets;
            EXPECT_EQ(b.kind, BodyKind::Solid);
        }
        if (b.name == "wall") continue;
        // inside the lumen, clear of the wall by at least the bounding radius' worth
        const real r = std::hypot(b.centre[1] - 11.0, b.centre[2] - 11.0);
        EXPECT_LT(r, 10.0) << b.name;
    }
    EXPECT_EQ(platelets, 2);
    EXPECT_EQ(rbc, c.seeding.placed[1].second);
    EXPECT_NEAR(rbc * v_rbc / lumen, c.seeding.achieved, 1e-12);
    EXPECT_EQ(c.bodies.size(), 1u + platelets + rbc);
}

// A body given by hand (a platelet near the wall, where a vWF patch would be) is in the
// scene before the seeding: the seeded cells keep clear of it (checked on a lattice of
// 0.05 um around it against every cell's shape), and the cells' count is unchanged.
TEST(SeedingConfig, CellsKeepClearOfBodiesGivenByHand) {
    const std::string hand = R"(
[[body]]
name = "platelet_by_hand"
kind = "solid"
shape = "ellipsoid"
semi_axes = [1.0, 1.0, 0.6]
centre = [22.0, 2.5, 11.0]
shear_modulus = 100.0
)";
    const std::string text = seeding("target_haematocrit = 0.05\nseed = 3\n");
    const Config c = case_from(vessel + hand + text.substr(vessel.size()));
    const Real3 cp{22.0, 2.5, 11.0};
    const auto by_hand = make_ellipsoid(cp, {1.0, 1.0, 0.6}, identity_rotation());
    int cells = 0, near = 0;
    for (const BodyConfig& b : c.bodies) {
        if (b.name == "wall" || b.name == "platelet_by_hand") continue;
        ++cells;
        const Matrix3 rot = axis_angle_rotation(b.axis, b.angle);
        const bool rbc = b.name.rfind("rbc_", 0) == 0;
        const auto s = rbc ? make_biconcave_disc(b.centre, rot, {3.91})
                           : make_ellipsoid(b.centre, {1.0, 1.0, 0.6}, rot);
        const real reach = (rbc ? 3.91 : 1.0) + 1.0;
        if (std::hypot(b.centre[0] - cp[0], b.centre[1] - cp[1], b.centre[2] - cp[2]) > reach)
            continue;
        ++near;
        for (real z = cp[2] - 1.0; z <= cp[2] + 1.0; z += 0.05)
            for (real y = cp[1] - 1.0; y <= cp[1] + 1.0; y += 0.05)
                for (real x = cp[0] - 1.0; x <= cp[0] + 1.0; x += 0.05)
                    if (by_hand->inside({x, y, z})) {
                        ASSERT_FALSE(s->inside({x, y, z})) << b.name << " overlaps the hand body";
                    }
    }
    EXPECT_EQ(c.bodies.size(), 2u + cells);
    EXPECT_GT(c.seeding.achieved, 0.045);
    EXPECT_EQ(c.bodies[1].name, "platelet_by_hand");
    (void)near;
    // A body of an open shape (a second tube) beside the seeded cells is refused by name.
    const std::string tube2 = R"(
[[body]]
name = "second_tube"
kind = "solid"
shape = "tube"
centre = [22.0, 11.0, 11.0]
lumen_diameter = 18.0
pinned = true
)";
    const std::string two_tubes = vessel + tube2 + text.substr(vessel.size());
    EXPECT_THAT(input_error_of([&] { case_from(two_tubes); }), HasSubstr("second_tube"));
}

// region = "domain": a channel between walls in y (periodic in x and z, no vessel body) is
// filled to the target, every cell inside the box and clear of its faces by the gap.
TEST(SeedingConfig, DomainRegionFillsAChannel) {
    const std::string channel = R"(
[grid]
cells = [24, 12, 12]
length = [24.0, 12.0, 12.0]
[fluid]
density = 1.0e-3
viscosity = 1.2
[boundary]
y_low = "wall"
y_high = "wall"
[time]
end_time = 1.0
[seeding]
region = "domain"
target_haematocrit = 0.1
seed = 5
gap = 0.3)" + rbc_kind;
    const Config c = case_from(channel);
    ASSERT_TRUE(c.seeding.used);
    const real box = 24.0 * 12.0 * 12.0;
    EXPECT_NEAR(c.seeding.lumen_volume, box, 1e-9 * box);
    const real v_rbc = make_biconcave_disc({0, 0, 0}, identity_rotation(), {3.91})->exact_volume();
    EXPECT_NEAR(c.seeding.achieved, 0.1, 0.5 * v_rbc / box + 1e-12);
    ASSERT_FALSE(c.bodies.empty());
    EXPECT_NEAR(c.bodies.size() * v_rbc / box, c.seeding.achieved, 1e-12);
    // every cell inside the box, 0.3 from its faces: on a lattice of 0.1 over its rim's reach
    const Real3 len{24.0, 12.0, 12.0};
    for (const BodyConfig& b : c.bodies) {
        const auto s = make_biconcave_disc(b.centre, axis_angle_rotation(b.axis, b.angle), {3.91});
        for (real z = b.centre[2] - 4; z <= b.centre[2] + 4; z += 0.1)
            for (real y = b.centre[1] - 4; y <= b.centre[1] + 4; y += 0.1)
                for (real x = b.centre[0] - 4; x <= b.centre[0] + 4; x += 0.1) {
                    const Real3 p{x, y, z};
                    bool near_face = false;
                    for (int d = 0; d < 3; ++d)
                        near_face = near_face || p[d] < 0.25 || p[d] > len[d] - 0.25;
                    if (near_face) {
                        ASSERT_FALSE(s->inside(p)) << b.name << " at a face";
                    }
                }
    }
    // region = "domain" with a vessel named is refused, naming the key
    const std::string both = channel + "";
    std::string with_vessel = both;
    with_vessel.replace(with_vessel.find("region = \"domain\""), 17,
                        "region = \"domain\"\nvessel = \"wall\"");
    EXPECT_THAT(input_error_of([&] { case_from(with_vessel); }), HasSubstr("seeding.vessel"));
}

TEST(SeedingConfig, TheSameSeedGivesTheSameSceneAndTheResolvedCaseIsThatScene) {
    const Config a = case_from(seeding("target_haematocrit = 0.04\nseed = 11\n"));
    const Config b = case_from(seeding("target_haematocrit = 0.04\nseed = 11\n"));
    const Config c = case_from(seeding("target_haematocrit = 0.04\nseed = 12\n"));
    ASSERT_EQ(a.bodies.size(), b.bodies.size());
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
        EXPECT_EQ(a.bodies[i].centre, b.bodies[i].centre);
        EXPECT_EQ(a.bodies[i].axis, b.bodies[i].axis);
        EXPECT_EQ(a.bodies[i].angle, b.bodies[i].angle);
    }
    EXPECT_NE(a.bodies[1].centre, c.bodies[1].centre);
    // The resolved case holds the placed bodies and no [seeding]: read again, same scene.
    const Config r = case_from(a.resolved_toml);
    EXPECT_FALSE(r.seeding.used);
    ASSERT_EQ(r.bodies.size(), a.bodies.size());
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
        EXPECT_EQ(r.bodies[i].name, a.bodies[i].name);
        for (int d = 0; d < 3; ++d)
            EXPECT_NEAR(r.bodies[i].centre[d], a.bodies[i].centre[d], 1e-12);
        EXPECT_NEAR(r.bodies[i].angle, a.bodies[i].angle, 1e-14);
    }
    EXPECT_EQ(case_fingerprint(r), case_fingerprint(a));
}

TEST(SeedingConfig, AnUnreachableTargetSaysWhatWasReached) {
    const std::string m = input_error_of(
        [] { case_from(seeding("target_haematocrit = 0.6\nseed = 3\nmax_candidates = 3000\n")); });
    EXPECT_THAT(m, HasSubstr("seeding.target_haematocrit = 0.6"));
    EXPECT_THAT(m, HasSubstr("NOT reached"));
    EXPECT_THAT(m, HasSubstr("rbc volume fraction"));
    EXPECT_THAT(m, HasSubstr("shake sweeps"));
}

TEST(SeedingConfig, BadInputNamesTheKey) {
    EXPECT_THAT(input_error_of([] {
                    case_from(seeding("target_haematocrit = 0.05\n", "bending_modulus = -1.0\n"));
                }),
                HasSubstr("seeding.kind[1].body.bending_modulus"));
    EXPECT_THAT(input_error_of([] {
                    case_from(seeding("target_haematocrit = 0.05\n", "centre = [1.0, 2.0, 3.0]\n"));
                }),
                HasSubstr("seeding.kind[1].body.centre"));
    EXPECT_THAT(input_error_of([] {
                    case_from(seeding("target_haematocrit = 0.05\n", "shear_modulus = 3.0\n"));
                }),
                HasSubstr("seeding.kind[1].body"));
    EXPECT_THAT(input_error_of([] {
                    auto t = seeding("target_haematocrit = 0.05\n");
                    t.replace(t.find("vessel = \"wall\""), 15, "vessel = \"pipe\"");
                    case_from(t);
                }),
                HasSubstr("seeding.vessel = \"pipe\""));
    EXPECT_THAT(input_error_of([] { case_from(seeding("target_haematocrit = 0.05\nsed = 1\n")); }),
                HasSubstr("seeding.sed"));
    EXPECT_THAT(input_error_of([] { case_from(seeding("target_haematocrit = 1.5\n")); }),
                HasSubstr("seeding.target_haematocrit"));
    EXPECT_THAT(input_error_of([] {
                    case_from(seeding("target_haematocrit = 0.05\nmax_shake_sweeps = -1\n"));
                }),
                HasSubstr("seeding.max_shake_sweeps"));
}

TEST(SeedingConfig, RotationAxisAngleInvertsAxisAngleRotation) {
    for (const real angle : {0.0, 0.3, 1.7, 3.0, std::numbers::pi}) {
        const Matrix3 r = axis_angle_rotation({0.3, -1.2, 0.7}, angle);
        Real3 axis;
        real a = 0;
        rotation_axis_angle(r, axis, a);
        const Matrix3 back = axis_angle_rotation(axis, a);
        for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q)
                EXPECT_NEAR(back[p][q], r[p][q], 1e-14) << "angle " << angle;
    }
}

TEST(SeedingConfig, TubeShapeNeedsItsLumenInsideTheBox) {
    auto t = vessel;
    t.replace(t.find("lumen_diameter = 20.0"), 21, "lumen_diameter = 23.0");
    EXPECT_THAT(input_error_of([&] { case_from(t); }), HasSubstr("body.lumen_diameter"));
}

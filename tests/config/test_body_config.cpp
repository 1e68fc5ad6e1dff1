// The [[body]] section at the config boundary (config/body_config.cpp): kinds, shapes,
// interfaces and membrane laws become enums, read once; a value outside the allowed ones,
// or a key that does not belong to the body's kind, is an InputError naming the key.
#include "config/body_config.hpp"
#include "interface/shapes.hpp"
#include "membrane/membrane_law.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace efsi;
using efsi::test::case_from;
using efsi::test::input_error_of;
using ::testing::HasSubstr;

namespace {

const std::string box = R"(
[grid]
cells = [24, 20, 1]
length = [1.2, 1.0, 0.05]

[fluid]
density = 1.0
viscosity = 0.1

[time]
end_time = 1.0
)";

std::string membrane(const std::string& extra) {
    return box + R"(
[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 0.5
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.25
interface = "smoothed"
)" + extra;
}

} // namespace

TEST(BodyConfig, ParsesKindsAndLawsIntoEnums) {
    const Config c = case_from(membrane("law = \"skalak\"\nstrain_extension = \"normal\"\n"));
    ASSERT_EQ(c.bodies.size(), 1u);
    const BodyConfig& b = c.bodies[0];
    EXPECT_EQ(b.kind, BodyKind::Membrane);
    EXPECT_EQ(b.law, MembraneLawKind::Skalak);
    EXPECT_EQ(b.shape, BodyShape::Cylinder);
    EXPECT_EQ(b.interface, InterfaceKind::Smoothed);
    EXPECT_EQ(b.strain_velocity, StrainVelocity::Surface);
    EXPECT_EQ(b.strain_extension, StrainExtension::Normal);
    EXPECT_TRUE(b.carried_by_surface_velocity());
    // Defaults: a passive body with a sharp interface; the neo-Hookean law.
    const Config p = case_from(box + R"(
[[body]]
name = "tracer"
shape = "sphere"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    EXPECT_EQ(p.bodies[0].kind, BodyKind::Passive);
    EXPECT_EQ(p.bodies[0].interface, InterfaceKind::Sharp);
    EXPECT_EQ(p.bodies[0].law, MembraneLawKind::NeoHookean);
    EXPECT_FALSE(p.bodies[0].carried_by_surface_velocity());
}

TEST(BodyConfig, KeywordsSpellTheCaseFileNames) {
    EXPECT_EQ(keyword(BodyKind::Passive), "passive");
    EXPECT_EQ(keyword(BodyKind::Solid), "solid");
    EXPECT_EQ(keyword(BodyKind::Membrane), "membrane");
    EXPECT_EQ(keyword(MembraneLawKind::NeoHookean), "neo_hookean");
    EXPECT_EQ(keyword(MembraneLawKind::Skalak), "skalak");
    EXPECT_EQ(keyword(BodyShape::Biconcave), "biconcave");
    EXPECT_EQ(keyword(BodyShape::Mask), "mask");
    EXPECT_EQ(keyword(InterfaceKind::Smoothed), "smoothed");
    EXPECT_EQ(keyword(StrainVelocity::Local), "local");
    EXPECT_EQ(keyword(StrainExtension::Layers), "layers");
    for (const auto name : membrane_law_names)
        EXPECT_EQ(keyword(parse_membrane_law(std::string(name))), name);
}

TEST(BodyConfig, UnknownKindOrLawNamesTheKey) {
    const std::string kind = input_error_of([&] {
        case_from(box + R"(
[[body]]
name = "cell"
kind = "fluid"
shape = "sphere"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    });
    EXPECT_THAT(kind, HasSubstr("body[0].kind"));
    EXPECT_THAT(kind, HasSubstr("passive, solid, membrane"));
    const std::string law = input_error_of([&] { case_from(membrane("law = \"mooney\"\n")); });
    EXPECT_THAT(law, HasSubstr("body[0].law"));
    EXPECT_THAT(law, HasSubstr("neo_hookean, skalak"));
    const std::string velocity =
        input_error_of([&] { case_from(membrane("strain_velocity = \"global\"\n")); });
    EXPECT_THAT(velocity, HasSubstr("body[0].strain_velocity"));
    EXPECT_THAT(input_error_of([&] { parse_membrane_law("mooney", "--law"); }),
                HasSubstr("--law = \"mooney\""));
    EXPECT_THROW(make_membrane_law("mooney", 1.0), InputError);
}

TEST(BodyConfig, ViscosityRatioIsAPositiveMembraneKey) {
    EXPECT_EQ(case_from(membrane("")).bodies[0].viscosity_ratio, 1.0);
    EXPECT_EQ(case_from(membrane("viscosity_ratio = 5.0\n")).bodies[0].viscosity_ratio, 5.0);
    EXPECT_THAT(input_error_of([&] { case_from(membrane("viscosity_ratio = 0.0\n")); }),
                HasSubstr("body[0].viscosity_ratio"));
    EXPECT_THAT(input_error_of([&] {
                    case_from(box + R"(
[[body]]
name = "particle"
kind = "solid"
shear_modulus = 1.0
viscosity_ratio = 5.0
shape = "sphere"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
                }),
                HasSubstr("viscosity_ratio is for kind = \"membrane\""));
}

TEST(BodyConfig, MembraneKeysBelongToMembranes) {
    EXPECT_THAT(input_error_of([&] {
                    case_from(box + R"(
[[body]]
name = "particle"
kind = "solid"
shear_modulus = 1.0
elastic_modulus = 0.5
shape = "sphere"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
                }),
                HasSubstr("elastic_modulus is for kind = \"membrane\""));
    EXPECT_THAT(input_error_of([&] {
                    case_from(membrane("").replace(membrane("").find("elastic_modulus = 0.5"), 21,
                                                   "elastic_modulus = 0.0"));
                }),
                HasSubstr("needs body.elastic_modulus > 0"));
    EXPECT_THAT(input_error_of([&] {
                    case_from(box + R"(
[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 0.5
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.25
)");
                }),
                HasSubstr("a membrane needs interface = \"smoothed\""));
    EXPECT_THAT(input_error_of([&] { case_from(membrane("pinned = true\n")); }),
                HasSubstr("pinned = true is only for kind = \"solid\""));
}

TEST(BodyConfig, MapInterpolationAndSmoothingWidthAreChecked) {
    EXPECT_EQ(case_from(membrane("")).bodies[0].map_interpolation, MapInterpolation::Cubic);
    EXPECT_EQ(case_from(membrane("map_interpolation = \"linear\"\n")).bodies[0].map_interpolation,
              MapInterpolation::Linear);
    EXPECT_THAT(input_error_of([&] { case_from(membrane("map_interpolation = \"quintic\"\n")); }),
                HasSubstr("body[0].map_interpolation"));
    // The VOF's MTHINC beta of a smoothed body is 1 / smoothing_width, at most 50.
    EXPECT_THAT(input_error_of([&] { case_from(membrane("smoothing_width = 0.01\n")); }),
                HasSubstr("body[0].smoothing_width"));
}

TEST(BodyConfig, MinDistanceGradientIsAFractionOfOne) {
    EXPECT_EQ(case_from(membrane("")).bodies[0].min_distance_gradient, 0.5);
    EXPECT_EQ(case_from(membrane("min_distance_gradient = 0.8\n")).bodies[0].min_distance_gradient,
              0.8);
    // |grad psi| is 1 in a resolved profile: a threshold above 1 would drop the whole band.
    EXPECT_THAT(input_error_of([&] { case_from(membrane("min_distance_gradient = 1.5\n")); }),
                HasSubstr("body[0].min_distance_gradient"));
    EXPECT_THAT(input_error_of([&] { case_from(membrane("min_distance_gradient = 0.0\n")); }),
                HasSubstr("body[0].min_distance_gradient"));
}

TEST(BodyConfig, HalfExtentIsTheRotatedShapes) {
    // An ellipsoid lying flat by a wall is accepted: its extent normal to the wall is its
    // short semi-axis, not the longest one.
    const std::string box3 = R"(
[grid]
cells = [16, 16, 16]
length = [4.0, 4.0, 4.0]

[fluid]
density = 1.0
viscosity = 0.1

[boundary]
y_low = "wall"
y_high = "wall"

[time]
end_time = 1.0
)";
    const std::string flat = box3 + R"(
[[body]]
name = "flat"
kind = "solid"
shear_modulus = 1.0
shape = "ellipsoid"
centre = [2.0, 0.7, 2.0]
semi_axes = [1.0, 0.6, 1.0]
)";
    const Real3 e = body_axis_extent(case_from(flat).bodies[0], 3);
    EXPECT_NEAR(e[0], 1.0, 1e-14);
    EXPECT_NEAR(e[1], 0.6, 1e-14);
    EXPECT_NEAR(e[2], 1.0, 1e-14);
    // Turned by 90 degrees about z, its long axis stands normal to the wall: refused.
    const std::string turned = flat + "axis = [0.0, 0.0, 1.0]\nangle = 1.5707963267948966\n";
    EXPECT_THAT(input_error_of([&] { case_from(turned); }), HasSubstr("reaches through a wall"));
    // Lengths in the message carry the case's unit label.
    EXPECT_THAT(input_error_of([&] { case_from(turned); }), HasSubstr("m in y"));
    EXPECT_THAT(input_error_of([&] { case_from("[case]\nlength_unit = \"um\"\n" + turned); }),
                HasSubstr("from -0.3 to 1.7 um in y"));
    // A box turned by 45 degrees about z reaches (hx + hy) / sqrt(2) in x and y.
    BodyConfig b;
    b.shape = BodyShape::Box;
    b.half_sizes = {1.0, 0.5, 0.25};
    b.axis = {0.0, 0.0, 1.0};
    b.angle = std::numbers::pi / 4;
    const Real3 f = body_axis_extent(b, 3);
    EXPECT_NEAR(f[0], 1.5 / std::sqrt(2.0), 1e-14);
    EXPECT_NEAR(f[1], 1.5 / std::sqrt(2.0), 1e-14);
    EXPECT_NEAR(f[2], 0.25, 1e-14);

    // A red cell (Evans-Fung disc, R0 = 1) lying flat by the wall y = 0, its axis along y:
    // it reaches its largest half-thickness in y, R0 in x and z. The half-thickness against
    // the profile (R0/2) sqrt(1 - r^2) (C0 + C1 r^2 + C2 r^4) sampled densely.
    const EvansFungCoefficients k;
    real sampled = 0;
    for (int q = 0; q <= 200000; ++q) {
        const real r2 = std::pow(q / 200000.0, 2);
        sampled = std::max(sampled, 0.5 * std::sqrt(1 - r2) * (k.c0 + k.c1 * r2 + k.c2 * r2 * r2));
    }
    // A cell turned by 90 degrees about `axis`, 0.4 from the wall y = 0.
    auto cell = [&](const std::string& axis) {
        return box3 + R"(
[[body]]
name = "cell"
kind = "membrane"
shape = "biconcave"
interface = "smoothed"
radius = 1.0
elastic_modulus = 1.0
angle = 1.5707963267948966
centre = [2.0, 0.4, 2.0]
axis = )" + axis +
               "\n";
    };
    const Real3 c = body_axis_extent(case_from(cell("[1.0, 0.0, 0.0]")).bodies[0], 3);
    EXPECT_NEAR(c[0], 1.0, 1e-12);
    EXPECT_NEAR(c[1], sampled, 1e-9);
    EXPECT_NEAR(c[2], 1.0, 1e-12);
    // Standing on its rim (its axis along x): refused.
    const std::string standing = cell("[0.0, 1.0, 0.0]");
    EXPECT_THAT(input_error_of([&] { case_from(standing); }), HasSubstr("reaches through a wall"));
}

TEST(BodyConfig, IncrementDampingOnMembranesNeedsAMembraneAndHypre) {
    // Confined to the membranes' bands the damping varies in space: the viscous solve is
    // hypre's, and the reason names the key; a case without a membrane is refused.
    const Overrides band{{"time.increment_damping", "4.0"},
                         {"time.increment_damping_on", "\"membranes\""}};
    const Config c = case_from(membrane(""), band);
    EXPECT_EQ(c.time.increment_damping_on, DampingRegion::Membranes);
    const LinearSolverChoice choice = choose_linear_solvers(c);
    EXPECT_FALSE(choice.viscous_fft);
    EXPECT_NE(choice.viscous_reason.find("increment_damping_on"), std::string::npos);
    // Undamped (F = 1) there is nothing to confine: the FFT solve stays.
    EXPECT_TRUE(choose_linear_solvers(
                    case_from(membrane(""), {{"time.increment_damping_on", "\"membranes\""}}))
                    .viscous_fft);
    EXPECT_EQ(case_from(membrane("")).time.increment_damping_on, DampingRegion::Everywhere);
    std::string msg;
    try {
        case_from(box, band);
    } catch (const InputError& e) {
        msg = e.what();
    }
    EXPECT_NE(msg.find("time.increment_damping_on"), std::string::npos);
    EXPECT_NE(msg.find("no membrane"), std::string::npos);
}

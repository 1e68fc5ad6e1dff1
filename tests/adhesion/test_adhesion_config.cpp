// The [adhesion] case table (solver/config/adhesion_config): keys read into the coupling's
// configuration, bad input named by its key before anything is allocated, and a scene
// without [adhesion] (or with it but away from every ligand) allocating nothing in the
// coupling. Runs on 1 and 2 ranks.
#include "adhesion/coupling.hpp"
#include "adhesion_scene.hpp"
#include "test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

// Allocation counter for the "a scene without adhesion allocates nothing" test.
namespace {
std::atomic<long> g_allocations{0};
}
[[gnu::noinline]] void* operator new(std::size_t n) {
    ++g_allocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept {
    std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}

using namespace efsi;
using efsi::test::case_from;
using efsi::test::input_error_of;
using ::testing::HasSubstr;

namespace {

// A 4 um channel of 0.25 um cells, walls in y, periodic in x and z; a platelet (solid
// oblate spheroid), a red cell (membrane) and a pinned solid (a wall).
const std::string scene = R"(
[grid]
cells = [32, 16, 16]
length = [8e-6, 4e-6, 4e-6]

[fluid]
density = 1025.0
viscosity = 1.2e-3

[boundary]
y_low = "wall"
y_high = "wall"

[time]
end_time = 1e-3

[[body]]
name = "platelet"
kind = "solid"
shape = "ellipsoid"
centre = [2e-6, 1.6e-6, 2e-6]
semi_axes = [1.5e-6, 0.5e-6, 1.5e-6]
shear_modulus = 1e4

[[body]]
name = "rbc"
kind = "membrane"
shape = "sphere"
interface = "smoothed"
centre = [6e-6, 2e-6, 2e-6]
radius = 1e-6
elastic_modulus = 5e-6

[[body]]
name = "plug"
kind = "solid"
shape = "sphere"
pinned = true
centre = [6e-6, 3.2e-6, 2e-6]
radius = 0.5e-6
)";

const std::string adhesion_table = R"(
[adhesion]
seed = 5
k_on = 20.0
bond_stiffness = 2e-3

[[adhesion.ligand_regions]]
lo = [3.9e-6, 0.0, 1.6e-6]
hi = [5.9e-6, 0.0, 2.4e-6]
density = 4e14

[[adhesion.receptors]]
body = "platelet"
count = 500
)";

std::string with(const std::string& extra) {
    return scene + adhesion_table + extra;
}

} // namespace

TEST(AdhesionConfig, ReadsTheTableAndLeavesItOffWithoutIt) {
    const Config off = case_from(scene);
    EXPECT_FALSE(off.adhesion.enabled);
    EXPECT_EQ(off.adhesion.receptors.capacity(), 0u);
    EXPECT_EQ(off.adhesion.ligand_regions.capacity(), 0u);
    EXPECT_EQ(case_fingerprint(off).find("adhesion"), std::string::npos);

    const Config c = case_from(scene + adhesion_table);
    const AdhesionConfig& a = c.adhesion;
    EXPECT_TRUE(a.enabled);
    EXPECT_EQ(a.seed, 5u);
    EXPECT_DOUBLE_EQ(a.parameters.k_on, 20.0);
    EXPECT_DOUBLE_EQ(a.parameters.bond_stiffness, 2e-3);
    EXPECT_DOUBLE_EQ(a.parameters.k_off0, 3.45); // default
    ASSERT_EQ(a.ligand_regions.size(), 1u);
    EXPECT_DOUBLE_EQ(a.ligand_regions[0].spacing, 1 / std::sqrt(4e14));
    ASSERT_EQ(a.receptors.size(), 1u);
    EXPECT_EQ(a.receptors[0].body_index, 0u);
    EXPECT_EQ(a.receptors[0].count, 500u);
    // One fingerprint line per key, so that a refused checkpoint names the key.
    EXPECT_THAT(case_fingerprint(c), HasSubstr("adhesion.receptors[0].count = 500\n"));
    EXPECT_THAT(case_fingerprint(c), HasSubstr("adhesion.seed = 5\n"));
    // Receptors follow the flow unless asked to move rigidly with their body.
    EXPECT_EQ(a.receptor_motion, ReceptorMotion::flow);
    EXPECT_EQ(case_fingerprint(c).find("receptor_motion"), std::string::npos);
    const Config rigid =
        case_from(scene + adhesion_table, {{"adhesion.receptor_motion", "\"rigid\""}});
    EXPECT_EQ(rigid.adhesion.receptor_motion, ReceptorMotion::rigid);
    EXPECT_THAT(case_fingerprint(rigid), HasSubstr("adhesion.receptor_motion = rigid\n"));

    // A density gives density x area receptors (the oblate spheroid's area).
    const Config d = case_from(scene + adhesion_table, {{"adhesion.receptors[0].count", "0"},
                                                        {"adhesion.receptors[0].density", "2e13"}});
    const real area = adhesion::ellipsoid_area({1.5e-6, 0.5e-6, 1.5e-6});
    EXPECT_EQ(d.adhesion.receptors[0].count, static_cast<std::uint64_t>(std::round(2e13 * area)));
    EXPECT_GT(d.adhesion.receptors[0].count, 300u);
    // The key table documents the adhesion keys.
    const std::string md = case_reference_markdown();
    for (const char* k : {"`adhesion.k_on`", "`adhesion.seed`",
                          "`adhesion.ligand_regions[].density`", "`adhesion.receptors[].body`",
                          "`adhesion.max_step_displacement`", "`adhesion.receptor_motion`"})
        EXPECT_THAT(md, HasSubstr(k));
}

TEST(AdhesionConfig, BadInputNamesTheKey) {
    auto error = [](const Overrides& o, const std::string& extra = "") {
        return input_error_of([&] { case_from(with(extra), o); });
    };
    EXPECT_THAT(error({{"adhesion.k_on", "-1"}}), HasSubstr("adhesion.k_on"));
    EXPECT_THAT(error({{"adhesion.k_off0", "-3"}}), HasSubstr("adhesion.k_off0"));
    EXPECT_THAT(error({{"adhesion.bond_stiffness", "-1e-3"}}),
                HasSubstr("adhesion.bond_stiffness"));
    EXPECT_THAT(error({{"adhesion.reactive_distance", "0"}}),
                HasSubstr("adhesion.reactive_distance"));
    EXPECT_THAT(error({{"adhesion.law", "\"catch_slip\""}}), HasSubstr("adhesion.catch_rate"));
    EXPECT_THAT(error({{"adhesion.typo", "1"}}), HasSubstr("adhesion.typo: unknown key"));
    EXPECT_THAT(error({{"adhesion.receptor_motion", "\"drift\""}}),
                HasSubstr("adhesion.receptor_motion"));
    // A ligand region outside the domain.
    EXPECT_THAT(error({{"adhesion.ligand_regions[0].hi", "[5.9e-6, 0.0, 4.5e-6]"}}),
                HasSubstr("adhesion.ligand_regions[0]: the box"));
    EXPECT_THAT(error({{"adhesion.ligand_regions[0].lo", "[3.9e-6, -1e-7, 1.6e-6]"}}),
                HasSubstr("not inside the domain"));
    EXPECT_THAT(error({{"adhesion.ligand_regions[0].density", "-1"}}),
                HasSubstr("adhesion.ligand_regions[0].density"));
    EXPECT_THAT(error({{"adhesion.ligand_regions[0].density", "1e30"}}),
                HasSubstr("adhesion.ligand_regions[0].density"));
    // A region across the whole periodic width is fine.
    EXPECT_NO_THROW(
        case_from(with(""), {{"adhesion.ligand_regions[0].lo", "[3.9e-6, 0.0, 0.0]"},
                             {"adhesion.ligand_regions[0].hi", "[5.9e-6, 0.0, 4e-6]"}}));
    // Receptors on a body that is not a platelet (a free solid sphere or ellipsoid).
    EXPECT_THAT(error({{"adhesion.receptors[0].body", "\"rbc\""}}),
                HasSubstr("adhesion.receptors[0].body = \"rbc\""));
    EXPECT_THAT(error({{"adhesion.receptors[0].body", "\"rbc\""}}), HasSubstr("membrane"));
    EXPECT_THAT(error({{"adhesion.receptors[0].body", "\"plug\""}}), HasSubstr("pinned"));
    EXPECT_THAT(error({{"adhesion.receptors[0].body", "\"nobody\""}}),
                HasSubstr("no [[body]] of that name"));
    EXPECT_THAT(error({{"adhesion.receptors[0].density", "1e12"}}),
                HasSubstr("exactly one of count"));
    EXPECT_THAT(error({{"adhesion.receptors[0].count", "0"}}), HasSubstr("exactly one of count"));
    EXPECT_THAT(error({{"adhesion.receptors[0].count", "-5"}}),
                HasSubstr("adhesion.receptors[0].count"));
    EXPECT_THAT(error({}, "\n[[adhesion.receptors]]\nbody = \"platelet\"\ncount = 3\n"),
                HasSubstr("already has receptors"));
    // A 2D grid.
    EXPECT_THAT(error({{"grid.cells", "[32, 16, 1]"},
                       {"grid.length", "[8e-6, 4e-6, 0.25e-6]"},
                       {"body[0].semi_axes", "[1.5e-6, 0.5e-6, 0.1e-6]"}}),
                HasSubstr("adhesion: needs a 3D grid"));
}

TEST(AdhesionConfig, NoAdhesionAllocatesNothing) {
    const Config off = case_from(scene);
    test::Channel c = test::make_channel({16, 16, 16}, 0.25e-6);
    VelocityField u("u", c.dec->block(), 3), f("f", c.dec->block(), 3);
    for (int comp = 0; comp < 3; ++comp) {
        u[comp].fill(0);
        f[comp].fill(0);
    }
    const long before = g_allocations.load();
    {
        adhesion::Coupling cp(off.adhesion, off.bodies, *c.dec, 1025, 1.2e-3);
        EXPECT_FALSE(cp.active());
        EXPECT_EQ(cp.stable_time_step(), std::numeric_limits<real>::infinity());
        for (std::uint64_t step = 0; step < 3; ++step) {
            cp.add_bond_forces(f, 1e-6);
            cp.advance(u, 1e-6, step);
        }
        EXPECT_EQ(cp.receptors().size(), 0u);
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
}

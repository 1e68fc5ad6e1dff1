// Where the bonds' reactions go (docs/method.md, "The wall takes the reaction"), on 1 and
// 2 ranks: for ligands on a no-slip wall of the domain nothing of -F enters the fluid (the
// fluid gets exactly the receptors' +F, the wall's reaction is recorded as -F) and a body
// far from the ligands costs no work; for ligands on a pinned solid, -F goes onto its held
// faces; a ligand anchored to nothing (in the fluid, or on a free-slip boundary) is refused,
// naming its region.
#include "adhesion/coupling.hpp"
#include "adhesion_scene.hpp"
#include "test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace efsi;
using namespace efsi::adhesion;
using efsi::test::adhesion_config;
using efsi::test::BondScene;
using efsi::test::nm;
using efsi::test::spread_over_ranks;
using efsi::test::total_force;
using efsi::test::um;
using efsi::test::zero_field;
using ::testing::HasSubstr;

namespace {

/// The force field of the receptors' ends alone: spread_force(+F) at every bound receptor
/// (no periodic image needed: the bodies of these scenes do not straddle a boundary).
VelocityField receptor_side(const Coupling& cp, const AdhesionParameters& p,
                            const test::Channel& c) {
    VelocityField g = zero_field(c);
    for (const Receptor& r : cp.receptors()) {
        if (!r.bound()) continue;
        const BondForce bf =
            bond_force(r.x, cp.ligands().position(r.ligand), p.bond_stiffness, p.bond_rest_length);
        spread_force(g, *c.dec, r.x, bf.on_receptor);
    }
    return g;
}

real norm(const Real3& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

} // namespace

TEST(AdhesionForces, BondsConserveMomentumAndTheFarBodyGetsNoWork) {
    BondScene s;
    Coupling cp(s.cfg, s.bodies, *s.c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(s.c);
    const real dt = 1e-7;
    std::size_t skipped = 0;
    for (std::uint64_t step = 0; step < 20; ++step) {
        cp.advance(rest, dt, step);
        skipped += cp.stats().bodies_skipped;
        EXPECT_EQ(cp.stats().bodies_near, 1u);
    }
    EXPECT_EQ(skipped, 20u);
    EXPECT_EQ(cp.bodies()[1].bonds, 0u);
    ASSERT_GT(cp.bodies()[0].bonds, 5u);
    EXPECT_EQ(cp.bond_count(), cp.ligands().bound_count());
    // The far body's receptors were never looked at: only the near body's receptors can
    // be counted as examined or skipped by the kinetics.
    EXPECT_LE(cp.stats().kinetics.examined + cp.stats().kinetics.skipped + cp.bodies()[0].bonds,
              cp.bodies()[0].end - cp.bodies()[0].begin);
    VelocityField f = zero_field(s.c);
    cp.add_bond_forces(f, dt);
    EXPECT_EQ(cp.stats().bonds_spread, cp.bond_count());
    EXPECT_GT(cp.stats().max_tension, 1e-13);
    // The ligands lie on the no-slip wall y = 0: the wall takes every -F. The fluid gets
    // the bonds' +F on the platelet and nothing else: its total is the force on the body
    // (not zero, as when -F was spread next to the wall), and the field is exactly the
    // receptors' spreading.
    const CouplingStats& st = cp.stats();
    const real scale = cp.stats().max_tension * static_cast<real>(cp.bond_count());
    ASSERT_GT(norm(st.force_on_bodies), 1e-3 * scale);
    const Real3 t = total_force(f, s.c);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t[a], st.force_on_bodies[a], 1e-13 * scale) << "component " << a;
        EXPECT_EQ(st.reaction_on_walls[a], -st.force_on_bodies[a]) << "component " << a;
        EXPECT_EQ(st.reaction_on_held[a], 0.0);
    }
    const VelocityField g = receptor_side(cp, s.cfg.parameters, s.c);
    real diff = 0, size = 0;
    for (int comp = 0; comp < 3; ++comp)
        for_each_cell(s.c.dec->block().cells, [&](int i, int j, int k) {
            diff = std::max(diff, std::abs(f[comp](i, j, k) - g[comp](i, j, k)));
            size = std::max(size, std::abs(g[comp](i, j, k)));
        });
    EXPECT_LE(test::global_max(diff), 1e-12 * test::global_max(size));
    for (std::uint64_t id = 0; id < cp.ligands().size(); ++id)
        ASSERT_EQ(cp.anchor_of(id), LigandAnchor::domain_wall);
    // Every rank holds the same bonds.
    EXPECT_EQ(spread_over_ranks(static_cast<real>(cp.bond_count())), 0.0);
    // The far body alone: no kinetics, no forces.
    AdhesionConfig far_only = s.cfg;
    far_only.receptors.erase(far_only.receptors.begin());
    Coupling lone(far_only, s.bodies, *s.c.dec, 1000, 1e-3);
    for (std::uint64_t step = 0; step < 5; ++step) {
        lone.advance(rest, dt, step);
        EXPECT_EQ(lone.stats().bodies_skipped, 1u);
        EXPECT_EQ(lone.stats().kinetics.examined + lone.stats().kinetics.skipped, 0u);
    }
    VelocityField h = zero_field(s.c);
    lone.add_bond_forces(h, dt);
    EXPECT_EQ(lone.stats().face_writes, 0u);
    EXPECT_EQ(lone.stable_time_step(), std::numeric_limits<real>::infinity());
}

// A pinned slab y <= 1 um (K = 1e8 on its faces, as a fixed wall's pinning) with the vWF
// patch on its top y = 1 um, a sphere 30 nm above: the reactions go onto the slab's held
// faces. The fluid (faces with K = 0) sees the receptors' +F only; the slab's faces get
// -F in total, so the force field sums to zero; the run is the same bits on any rank count.
TEST(AdhesionForces, ReactionOnAPinnedSolidGoesOntoItsHeldFaces) {
    auto run = [](MPI_Comm comm, Real3* bodies, std::size_t* bonds) {
        test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um, 0, 0, comm);
        VelocityField pin = zero_field(c);
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
                const Real3 x = position(c.g, c.dec->block(), face_location(comp), i, j, k);
                // The faces on the slab's top y = 1 um are held too (a pinned body's face
                // pinning averages its two cells: phi = 1/2 there, K = 5e7).
                pin[comp](i, j, k) = x[1] <= 1.0 * um ? 1e8 : 0.0;
            });
        std::vector<BodyConfig> b{test::sphere_body("p", {2 * um, 2.03 * um, 2 * um}, 1 * um)};
        AdhesionConfig cfg = adhesion_config(1, 2000, {1.0 * um, 1.0 * um, 1.0 * um},
                                             {3.0 * um, 1.0 * um, 3.0 * um});
        cfg.parameters.k_on = 2e6;
        Coupling cp(cfg, b, *c.dec, 1000, 1e-3);
        const std::array<std::array<bool, 2>, 3> walls{
            {{false, false}, {true, true}, {false, false}}};
        // Not within half a cell of a domain wall, and no pinned solid given: refused,
        // naming the region.
        try {
            cp.anchor(walls, nullptr);
            ADD_FAILURE() << "expected an InputError for a ligand anchored to nothing";
        } catch (const InputError& e) {
            EXPECT_THAT(e.what(), HasSubstr("adhesion.ligand_regions[0]"));
            EXPECT_THAT(e.what(), HasSubstr("pinned solid"));
        }
        cp.anchor(walls, &pin);
        for (std::uint64_t id = 0; id < cp.ligands().size(); ++id)
            EXPECT_EQ(cp.anchor_of(id), LigandAnchor::held_body);
        const VelocityField rest = zero_field(c);
        for (std::uint64_t step = 0; step < 20; ++step)
            cp.advance(rest, 1e-7, step);
        EXPECT_GT(cp.bond_count(), 5u);
        VelocityField f = zero_field(c);
        cp.add_bond_forces(f, 1e-7);
        const CouplingStats& st = cp.stats();
        const real scale = st.max_tension * static_cast<real>(cp.bond_count());
        EXPECT_GT(norm(st.force_on_bodies), 1e-3 * scale);
        const VelocityField g = receptor_side(cp, cfg.parameters, c);
        // Where the pinning is zero (the fluid), only the receptors' +F.
        real diff = 0;
        Real3 held{0, 0, 0};
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
                const real d = f[comp](i, j, k) - g[comp](i, j, k);
                if (pin[comp](i, j, k) == 0)
                    diff = std::max(diff, std::abs(d));
                else
                    held[comp] += d * c.g.cell_volume();
            });
        EXPECT_LE(test::global_max(diff), 1e-13 * scale / c.g.cell_volume());
        const Real3 t = total_force(f, c);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(c.dec->sum(held[a]), -st.force_on_bodies[a], 1e-12 * scale);
            EXPECT_EQ(st.reaction_on_held[a], -st.force_on_bodies[a]);
            EXPECT_EQ(st.reaction_on_walls[a], 0.0);
            EXPECT_LE(std::abs(t[a]), 1e-12 * scale); // body + wall: momentum conserved
        }
        // Held shares: 1 inside the slab, about one half on its top, 0 in the fluid.
        HeldSpreader hs;
        std::vector<real> share;
        const std::vector<Real3> pts{
            {2 * um, 0.5 * um, 2 * um}, {2 * um, 1.0 * um, 2 * um}, {2 * um, 2.0 * um, 2 * um}};
        hs.held_share(pin, *c.dec, pts, share);
        EXPECT_NEAR(share[0], 1.0, 1e-7);
        EXPECT_GT(share[1], 0.3);
        EXPECT_LT(share[1], 0.7);
        EXPECT_EQ(share[2], 0.0);
        *bodies = st.force_on_bodies;
        *bonds = cp.bond_count();
    };
    Real3 fw{}, fs{};
    std::size_t bw = 0, bs = 0;
    run(MPI_COMM_WORLD, &fw, &bw);
    run(MPI_COMM_SELF, &fs, &bs);
    EXPECT_EQ(bw, bs);
    for (int a = 0; a < 3; ++a)
        EXPECT_EQ(fw[a], fs[a]);
}

TEST(AdhesionForces, LigandsOnAFreeSlipBoundaryOrInTheFluidAreRefused) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> b{test::sphere_body("p", {2 * um, 2.03 * um, 2 * um}, 1 * um)};
    // On y = 0, but that boundary is free-slip here (it takes no tangential force).
    Coupling on_wall(adhesion_config(1, 50, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um}), b,
                     *c.dec, 1000, 1e-3);
    EXPECT_NO_THROW(on_wall.anchor({{{false, false}, {true, true}, {false, false}}}, nullptr));
    EXPECT_THROW(on_wall.anchor({{{false, false}, {false, true}, {false, false}}}, nullptr),
                 InputError);
    // Two regions, the second floating in the fluid: named as [1].
    AdhesionConfig two = adhesion_config(1, 50, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    two.ligand_regions.push_back(
        {{1.0 * um, 2.0 * um, 1.0 * um}, {1.5 * um, 2.0 * um, 1.5 * um}, 50 * nm});
    two.ligand_density.push_back(1 / (50 * nm * 50 * nm));
    Coupling floating(two, b, *c.dec, 1000, 1e-3);
    try {
        floating.anchor({{{false, false}, {true, true}, {false, false}}}, nullptr);
        ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("adhesion.ligand_regions[1]"));
    }
}

TEST(AdhesionForces, RigidReceptorsLoadTheirBodyAndTheWallSupportsIt) {
    // receptor_motion = rigid: the platelet is moved onto the wall (its cloud is lifted back
    // onto y = 0), bonds form, then it slides along x, stretching them. The bonds' force and
    // torque go to rigid_loads() and nothing into the field; in contact, the wall carries the
    // bonds' pull towards it (wall_support), and momentum balances at every step.
    BondScene s;
    s.cfg.receptor_motion = ReceptorMotion::rigid;
    Coupling cp(s.cfg, s.bodies, *s.c.dec, 1000, 1e-3);
    ASSERT_TRUE(cp.moves_rigidly());
    const VelocityField rest = zero_field(s.c);
    const real dt = 1e-7;
    std::vector<RigidMotion> m(2);
    m[0].centre = s.bodies[0].centre;
    m[1].centre = s.bodies[1].centre;
    int supported = 0;
    real lifted = 0;
    for (std::uint64_t step = 0; step < 80; ++step) {
        m[0].velocity = step < 30 ? Real3{0, -1.5e-2, 0} : Real3{1e-2, 0, 0};
        cp.advance(rest, dt, step, m);
        lifted += cp.stats().wall_lift;
        for (int a = 0; a < 3; ++a)
            m[0].centre[a] += dt * m[0].velocity[a];
        VelocityField f = zero_field(s.c);
        cp.add_bond_forces(f, dt);
        const CouplingStats& st = cp.stats();
        ASSERT_EQ(cp.rigid_loads().size(), 2u);
        const RigidLoad& load = cp.rigid_loads()[0];
        for (int a = 0; a < 3; ++a) {
            // The load is the bonds' force plus the wall's support; the walls take minus it.
            EXPECT_DOUBLE_EQ(load.force[a], st.force_on_bodies[a]) << "step " << step;
            EXPECT_NEAR(st.reaction_on_walls[a], -st.force_on_bodies[a],
                        1e-12 * (std::abs(st.force_on_bodies[a]) + 1e-15));
            EXPECT_EQ(test::total_force(f, s.c)[a], 0.0); // nothing spread at the receptors
        }
        EXPECT_TRUE(cp.rigid_loads()[1].empty()); // the far body holds no bond
        EXPECT_GE(st.wall_support[1], 0.0);       // a wall only pushes
        if (st.wall_support[1] > 0) {
            ++supported;
            EXPECT_EQ(load.force[1], 0.0); // the pull towards the wall is carried by it
        }
    }
    EXPECT_GT(cp.bodies()[0].bonds, 5u);
    EXPECT_GT(lifted, 0.0);
    EXPECT_GT(supported, 0);
    // Every receptor stays inside the walls and the same on every rank.
    for (const Receptor& r : cp.receptors())
        EXPECT_GE(r.x[1], 0.0);
    EXPECT_EQ(spread_over_ranks(cp.receptors()[7].x[0]), 0.0);
}

// The bond forces of the adhesion coupling (solver/adhesion/grid_transfer, coupling) on 1
// and 2 ranks: a spread force integrating to F on each side and centred on its point; the
// time-step limits reported, naming the body and the bond; bonds across a periodic
// boundary taken to the nearest image; the same bits as the serial run on any rank count.
#include "adhesion/coupling.hpp"
#include "adhesion_scene.hpp"
#include "test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

using namespace efsi;
using namespace efsi::adhesion;
using efsi::test::adhesion_config;
using efsi::test::BondScene;
using efsi::test::nm;
using efsi::test::total_force;
using efsi::test::um;
using efsi::test::zero_field;
using ::testing::HasSubstr;

// ---- forces ---------------------------------------------------------------------------

TEST(AdhesionForces, SpreadForceIntegratesToFOnEachSideAndConservesMomentum) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    const Real3 F{3e-12, -7e-12, 2e-12};
    // Points: on the wall y = 0 (a ligand), near the top wall, across the periodic
    // boundaries, at a rank boundary (x = 2 um on 2 ranks), at a face and a cell centre.
    const std::vector<Real3> points{
        {1.1 * um, 0, 1.3 * um},           {0.01 * um, 3.95 * um, 3.99 * um},
        {2 * um, 1 * um, 2 * um},          {1.125 * um, 0.125 * um, 0.5 * um},
        {3.97 * um, 0.06 * um, 0.02 * um}, {2.01 * um, 2.3 * um, 1.7 * um}};
    for (const Real3& x : points) {
        VelocityField f = zero_field(c);
        spread_force(f, *c.dec, x, F);
        const Real3 t = total_force(f, c);
        for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(t[a], F[a], 1e-14 * 7e-12) << "at " << x[0] << ", " << x[1] << ", " << x[2];
        // The wall's own normal faces (v at y = 0) take nothing.
        if (c.dec->at_boundary(1, 0)) {
            for (int i = 0; i < c.dec->block().cells[0]; ++i)
                for (int k = 0; k < c.dec->block().cells[2]; ++k)
                    ASSERT_EQ(f[1](i, 0, k), 0.0);
        }
    }
    // spread_force itself: +F at one point, -F at another: zero in total.
    VelocityField f = zero_field(c);
    spread_force(f, *c.dec, points[5], F);
    spread_force(f, *c.dec, points[0], {-F[0], -F[1], -F[2]});
    const Real3 t = total_force(f, c);
    for (int a = 0; a < 3; ++a)
        EXPECT_LE(std::abs(t[a]), 1e-14 * 7e-12);
    // Away from walls the spread force is centred on the point (zero first moment).
    VelocityField g = zero_field(c);
    spread_force(g, *c.dec, points[5], F);
    real moment = 0;
    for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
        const Real3 xf = position(c.g, c.dec->block(), Location::FaceX, i, j, k);
        moment += g[0](i, j, k) * c.g.cell_volume() * (xf[0] - points[5][0]);
    });
    EXPECT_NEAR(c.dec->sum(moment), 0, 1e-14 * F[0] * um);
}

TEST(AdhesionForces, TimeStepLimitsAreReportedNamingTheBodyAndTheBond) {
    BondScene s;
    Coupling cp(s.cfg, s.bodies, *s.c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(s.c);
    for (std::uint64_t step = 0; step < 20; ++step)
        cp.advance(rest, 1e-7, step);
    ASSERT_GT(cp.bond_count(), 5u);
    const real limit = cp.stable_time_step();
    ASSERT_TRUE(std::isfinite(limit));
    VelocityField f = zero_field(s.c);
    EXPECT_NO_THROW(cp.add_bond_forces(f, 0.99 * limit));
    try {
        cp.add_bond_forces(f, 1.01 * limit);
        ADD_FAILURE() << "expected a RunError above the stable time step";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("'near'"));
        EXPECT_THAT(e.what(), HasSubstr("stable_time_step"));
    }
    // The per-bond force limit: a bond whose force would move its receptor more than
    // max_step_displacement cells in one step, named with both ends.
    AdhesionConfig tight = s.cfg;
    tight.max_step_displacement = 1e-9;
    Coupling strict(tight, s.bodies, *s.c.dec, 1000, 1e-3);
    for (std::uint64_t step = 0; step < 20; ++step)
        strict.advance(rest, 1e-7, step);
    try {
        strict.add_bond_forces(f, 1e-7);
        ADD_FAILURE() << "expected a RunError above the force limit";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("receptor"));
        EXPECT_THAT(e.what(), HasSubstr("ligand"));
        EXPECT_THAT(e.what(), HasSubstr("max_step_displacement"));
        EXPECT_THAT(e.what(), HasSubstr("body 'near'"));
    }
}

TEST(AdhesionForces, BondsAcrossAPeriodicBoundaryUseTheNearestImage) {
    // A patch over the whole periodic width in z and a sphere straddling z = 0 above it:
    // receptors on both sides of the boundary bind, and every bond is short.
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 0.05 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 3000, {1.0 * um, 0, 0}, {3.0 * um, 0, 4 * um});
    cfg.parameters.k_on = 2e6;
    Coupling cp(cfg, bodies, *c.dec, 1000, 1e-3);
    const VelocityField rest = zero_field(c);
    for (std::uint64_t step = 0; step < 20; ++step)
        cp.advance(rest, 1e-7, step);
    std::size_t low = 0, high = 0;
    for (const Receptor& r : cp.receptors()) {
        if (!r.bound()) continue;
        (cp.ligands().position(r.ligand)[2] < 2 * um ? low : high) += 1;
    }
    EXPECT_GT(low, 3u);
    EXPECT_GT(high, 3u);
    // Move the cloud 30 nm in -z (across the boundary for some receptors): the bonds
    // stretch by at most that much.
    VelocityField w =
        test::velocity_from(c, [&](int comp, const Real3&) { return comp == 2 ? -0.3 : 0.0; });
    cp.carry(w, 1e-7);
    VelocityField f = zero_field(c);
    cp.add_bond_forces(f, 1e-7);
    const AdhesionParameters& p = cfg.parameters;
    EXPECT_EQ(cp.stats().bonds_spread, low + high);
    EXPECT_LE(cp.stats().max_tension,
              p.bond_stiffness * (p.reactive_distance + 31 * nm - p.bond_rest_length));
    const Real3 t = total_force(f, c);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t[a], cp.stats().force_on_bodies[a], 1e-13 * cp.stats().max_tension * 40);
        EXPECT_EQ(cp.stats().reaction_on_walls[a], -cp.stats().force_on_bodies[a]);
    }
}

TEST(AdhesionRanks, SameBitsAsTheSerialRun) {
    // The coupling on the world's decomposition and, on every rank, on a serial one
    // (MPI_COMM_SELF): the same receptor positions, bonds and face forces, bit for bit.
    const real G = 800;
    auto field = [&](const test::Channel& c) {
        return test::velocity_from(c, [&](int comp, const Real3& x) {
            return comp == 0   ? G * x[1] + 3e-4 * std::sin(x[2] / um)
                   : comp == 2 ? 1e-4 * std::cos(x[0] / um) * std::sin(x[1] * 0.7 / um)
                               : 0.0;
        });
    };
    test::Channel world = test::make_channel({16, 16, 16}, 0.25 * um, 0, G * 4 * um);
    test::Channel self = test::make_channel({16, 16, 16}, 0.25 * um, 0, G * 4 * um, MPI_COMM_SELF);
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 2 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 2000, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    cfg.parameters.k_on = 2e6;
    Coupling a(cfg, bodies, *world.dec, 1000, 1e-3), b(cfg, bodies, *self.dec, 1000, 1e-3);
    const VelocityField ua = field(world), ub = field(self);
    VelocityField fa = zero_field(world), fb = zero_field(self);
    for (std::uint64_t step = 0; step < 10; ++step) {
        a.add_bond_forces(fa, 1e-7);
        b.add_bond_forces(fb, 1e-7);
        a.advance(ua, 1e-7, step);
        b.advance(ub, 1e-7, step);
    }
    ASSERT_GT(a.bond_count(), 3u);
    for (std::size_t k = 0; k < a.receptors().size(); ++k) {
        ASSERT_EQ(a.receptors()[k].ligand, b.receptors()[k].ligand);
        for (int d = 0; d < 3; ++d)
            ASSERT_EQ(a.receptors()[k].x[d], b.receptors()[k].x[d]) << "receptor " << k;
    }
    const Int3 off = world.dec->block().offset;
    for (int comp = 0; comp < 3; ++comp)
        for_each_cell(world.dec->block().cells, [&](int i, int j, int k) {
            ASSERT_EQ(fa[comp](i, j, k), fb[comp](i + off[0], j + off[1], k + off[2]));
        });
}

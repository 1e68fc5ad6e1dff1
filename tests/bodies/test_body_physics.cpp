// One implementation of BodyPhysics per body kind (bodies/body_physics.hpp), each checked
// on its own:
//  - passive: phi only, carried by the flow, no force, no limit;
//  - solid: carries B (identity at rest, where its force vanishes), the viscosity of its
//    material, and one time-step limit named "elastic" of the shear-wave formula;
//  - fixed wall (pinned solid): keeps B = I (not even stored), never moves, adds no force
//    and no limit, only its penalisation phi / (tau / dt);
//  - membrane: Gs = P_R from its shape (tangential), limits named "membrane" and, with
//    bending, "bending", and the smallest of each name over the bodies.
// The grid is anisotropic (24 x 20 cells, 2D, and 12 x 10 x 8 in 3D).
#include "bodies/body_system.hpp"
#include "membrane/membrane_body.hpp"
#include "membrane/membrane_force.hpp"
#include "solid/solid_body.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;
using efsi::test::case_from;

namespace {

std::string grid_2d() {
    return R"(
[grid]
cells = [24, 20, 1]
length = [1.2, 1.0, 0.05]

[fluid]
density = 2.0
viscosity = 0.1

[time]
end_time = 1.0
)";
}

/// A run's bodies on this rank count: the decomposition, halos and BodySystem of `toml`.
struct Bodies {
    Config cfg;
    Decomposition dec;
    HaloFiller halos;
    BodySystem system;
    explicit Bodies(const std::string& toml)
        : cfg(case_from(toml)),
          dec(MPI_COMM_WORLD, cfg.grid, periodic_directions(cfg.boundaries), cfg.ranks),
          halos(dec, cfg.boundaries), system(cfg, dec, halos) {
        system.initialise();
    }
    Body& body(std::size_t i) { return *system.bodies()[i]; }
    const BodyPhysics& physics(std::size_t i) { return *system.physics()[i]; }
};

const TimeStepLimit* find_limit(const std::vector<TimeStepLimit>& limits, const std::string& n) {
    for (const auto& l : limits)
        if (l.name == n) return &l;
    return nullptr;
}

real largest_force(const VelocityField& f) {
    real m = 0;
    for (int c = 0; c < f.dim; ++c)
        for_each_in(f[c].owned(),
                    [&](int i, int j, int k) { m = std::max(m, std::abs(f[c](i, j, k))); });
    return efsi::test::global_max(m);
}

real volume(const Decomposition& dec, const Body& b) {
    real v = 0;
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) { v += b.phi()(i, j, k); });
    return dec.sum(v);
}

/// A uniform velocity (ux, uy) on every face, halos filled.
VelocityField uniform_velocity(Bodies& s, real ux, real uy) {
    VelocityField u("u", s.dec.block(), s.dec.dim());
    u[0].fill(ux);
    u[1].fill(uy);
    s.halos.fill(u);
    return u;
}

} // namespace

TEST(PassiveBody, CarriesPhiOnlyAndAddsNothing) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "tracer"
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    const BodyPhysics& p = s.physics(0);
    EXPECT_NE(dynamic_cast<const PassiveBody*>(&p), nullptr);
    EXPECT_FALSE(p.carries_tensor());
    EXPECT_TRUE(p.moves());
    EXPECT_FALSE(p.adds_force());
    EXPECT_TRUE(p.time_step_limits().empty());
    EXPECT_TRUE(s.body(0).tensor().comp.empty());
    EXPECT_FALSE(s.system.adds_force());
    EXPECT_FALSE(s.system.viscosity_varies());
    // Carried by a uniform flow: the volume is kept to round-off and the body moves.
    const real v0 = volume(s.dec, s.body(0));
    const VelocityField u = uniform_velocity(s, 0.5, 0.25);
    StageTimers timers;
    for (int n = 0; n < 8; ++n)
        s.system.advance(u, 0.01, n, timers);
    EXPECT_NEAR(volume(s.dec, s.body(0)), v0, 1e-12 * v0);
    const auto d = s.system.measure();
    EXPECT_NEAR(d[0].centroid[0], 0.6 + 0.5 * 0.08, 2e-3);
    EXPECT_NEAR(d[0].centroid[1], 0.5 + 0.25 * 0.08, 2e-3);
}

TEST(SolidBody, CarriesIdentityAtRestAndNamesItsElasticLimit) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "particle"
kind = "solid"
shear_modulus = 8.0
solid_viscosity = 0.3
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.2
)");
    const auto* solid = dynamic_cast<const SolidBody*>(&s.physics(0));
    ASSERT_NE(solid, nullptr);
    EXPECT_TRUE(solid->carries_tensor());
    EXPECT_TRUE(solid->adds_force());
    EXPECT_EQ(solid->viscosity(), 0.3);
    EXPECT_TRUE(s.system.viscosity_varies());
    // One limit, "elastic": half the shear-wave CFL, min(dx) / (2 sqrt(G / rho)).
    ASSERT_EQ(solid->time_step_limits().size(), 1u);
    EXPECT_EQ(solid->time_step_limits()[0].name, "elastic");
    EXPECT_DOUBLE_EQ(solid->time_step_limits()[0].dt, 0.5 * 0.05 / std::sqrt(8.0 / 2.0));
    // B = I at rest: B' = 0, so the elastic force vanishes exactly.
    Body& b = s.body(0);
    ASSERT_EQ(b.tensor().comp.size(), 3u);
    VelocityField force("force", s.dec.block(), s.dec.dim());
    s.system.add_forces(force);
    EXPECT_EQ(largest_force(force), 0.0);
    // A stretched B (B_xx = 1.2 in the solid) pushes.
    b.tensor().comp[0].fill(1.2);
    s.system.add_forces(force);
    EXPECT_GT(largest_force(force), 0.1);
}

TEST(FixedWall, KeepsBIdentityAddsNoForceAndIsPenalised) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "wall"
kind = "solid"
pinned = true
pin_tau_over_dt = 0.5
shape = "box"
centre = [0.6, 0.15, 0.0]
half_sizes = [0.3, 0.1, 1.0]
)");
    const BodyPhysics& p = s.physics(0);
    EXPECT_NE(dynamic_cast<const FixedWall*>(&p), nullptr);
    EXPECT_FALSE(p.carries_tensor()); // B = I is implicit: never stored, never transported
    EXPECT_FALSE(p.moves());
    EXPECT_FALSE(p.adds_force());
    EXPECT_TRUE(p.time_step_limits().empty());
    EXPECT_FALSE(s.system.adds_force());
    EXPECT_TRUE(s.body(0).tensor().comp.empty());
    EXPECT_EQ(s.system.measure()[0].tensor_trace_max, 0.0);
    // Not moved by the flow.
    const Field phi0 = s.body(0).phi();
    const VelocityField u = uniform_velocity(s, 0.5, 0.0);
    StageTimers timers;
    s.system.advance(u, 0.01, 0, timers);
    real change = 0;
    if (!s.body(0).patch().empty())
        for_each_in(phi0.owned(), [&](int i, int j, int k) {
            change = std::max(change, std::abs(s.body(0).phi()(i, j, k) - phi0(i, j, k)));
        });
    EXPECT_EQ(efsi::test::global_max(change), 0.0);
    // Penalisation chi = phi / (tau / dt) = 2 phi.
    Field chi("chi", Location::Cell, s.dec.block(), s.dec.dim());
    chi.fill(0);
    EXPECT_TRUE(s.system.add_pinning(chi));
    real worst = 0;
    if (!s.body(0).patch().empty())
        for_each_in(s.body(0).phi().owned(), [&](int i, int j, int k) {
            worst = std::max(worst, std::abs(chi(i, j, k) - 2 * s.body(0).phi()(i, j, k)));
        });
    EXPECT_EQ(efsi::test::global_max(worst), 0.0);
}

TEST(MembraneBody, StartsTangentialAndNamesItsLimits) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "capsule"
kind = "membrane"
law = "skalak"
area_dilation = 3.0
elastic_modulus = 0.5
bending_modulus = 1e-4
shape = "cylinder"
centre = [0.6, 0.5, 0.0]
radius = 0.25
interface = "smoothed"
)");
    const auto* m = dynamic_cast<const MembraneBody*>(&s.physics(0));
    ASSERT_NE(m, nullptr);
    EXPECT_TRUE(m->adds_force());
    EXPECT_EQ(m->viscosity(), 0.1); // the fluid's
    const GlobalGrid& g = s.cfg.grid;
    // Skalak: K = 2 Es / 3 (1 + 2 C).
    const real K = 2 * 0.5 / 3 * (1 + 2 * 3.0);
    EXPECT_DOUBLE_EQ(m->law().stiffest_modulus(), K);
    const auto& limits = m->time_step_limits();
    ASSERT_EQ(limits.size(), 2u);
    EXPECT_EQ(limits[0].name, "membrane");
    EXPECT_EQ(limits[0].dt, membrane_time_step_limit(g, 2.0, 0.1, K));
    EXPECT_EQ(limits[1].name, "bending");
    EXPECT_EQ(limits[1].dt, bending_time_step_limit(g, 2.0, 0.1, 1e-4));
    // Gs = P_R = I - n n around the circle: tr Gs = 2 (in-plane 1 + zz 1), Gs n = 0.
    const Body& b = s.body(0);
    ASSERT_NE(b.reference_curvature(), nullptr);
    real leak = 0, trace = 0;
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) {
            if (b.phi()(i, j, k) < 1e-3 || b.phi()(i, j, k) > 1 - 1e-3) return;
            const Real3 x = position(g, s.dec.block(), Location::Cell, i, j, k);
            const real dx = x[0] - 0.6, dy = x[1] - 0.5, r = std::hypot(dx, dy);
            const Int3 p{i, j, k};
            const SymmetricTensorField& G = b.tensor();
            leak = std::max(leak, std::abs(G.value(0, 0, p) * dx + G.value(0, 1, p) * dy) / r);
            leak = std::max(leak, std::abs(G.value(1, 0, p) * dx + G.value(1, 1, p) * dy) / r);
            trace = std::max(trace,
                             std::abs(G.value(0, 0, p) + G.value(1, 1, p) + G.value(2, 2, p) - 2));
        });
    EXPECT_LT(efsi::test::global_max(leak), 1e-8);
    EXPECT_LT(efsi::test::global_max(trace), 1e-8);
}

TEST(BodySystem, KeepsTheSmallestLimitOfEachName) {
    Bodies s(grid_2d() + R"(
[[body]]
name = "soft"
kind = "solid"
shear_modulus = 2.0
shape = "cylinder"
centre = [0.3, 0.5, 0.0]
radius = 0.1

[[body]]
name = "capsule"
kind = "membrane"
elastic_modulus = 0.5
shape = "cylinder"
centre = [0.9, 0.5, 0.0]
radius = 0.15
interface = "smoothed"

[[body]]
name = "stiff"
kind = "solid"
shear_modulus = 32.0
shape = "cylinder"
centre = [0.6, 0.25, 0.0]
radius = 0.1
)");
    const auto limits = s.system.time_step_limits();
    ASSERT_EQ(limits.size(), 2u);
    const TimeStepLimit* e = find_limit(limits, "elastic");
    const TimeStepLimit* m = find_limit(limits, "membrane");
    ASSERT_TRUE(e && m);
    EXPECT_EQ(e->dt, s.physics(2).time_step_limits()[0].dt);
    EXPECT_EQ(m->dt, s.physics(1).time_step_limits()[0].dt);
    EXPECT_EQ(find_limit(limits, "bending"), nullptr);
}

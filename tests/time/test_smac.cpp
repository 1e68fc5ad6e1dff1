// The SMAC fractional step (time/smac.cpp) driven directly: the projection leaves a
// discretely solenoidal field, exact steady states are fixed points, a uniform flow is
// preserved, momentum is conserved in a periodic box, and all of it on 1, 2 and 4 ranks
// with anisotropic grids.
#include "flow/initial_conditions.hpp"
#include "operators/flow_operators.hpp"
#include "test_support.hpp"
#include "time/smac.hpp"

#include <cmath>

using namespace efsi;
using efsi::test::case_from;

namespace {

/// Everything a step needs, built from a case text as the Simulation does.
struct Rig {
    Config cfg;
    Decomposition dec;
    HaloFiller halos;
    FlowState s;
    SmacStepper stepper;
    StageTimers timers;

    explicit Rig(const std::string& toml, const Overrides& o = {}) : Rig(case_from(toml, o)) {}
    explicit Rig(Config c)
        : cfg(std::move(c)),
          dec(MPI_COMM_WORLD, cfg.grid, periodic_directions(cfg.boundaries), cfg.ranks),
          halos(dec, cfg.boundaries), s(dec.block(), dec.dim()), stepper(cfg, dec, halos) {
        set_initial_condition(cfg, dec, s);
        halos.fill(s.u);
        halos.fill(s.p);
        halos.fill(s.mu);
    }

    Int3 global(const Int3& p) const {
        const Int3& o = dec.block().offset;
        return {o[0] + p[0], o[1] + p[1], o[2] + p[2]};
    }
    Real3 at(int c, const Int3& p) const {
        return position(cfg.grid, dec.block(), face_location(c), p[0], p[1], p[2]);
    }
    real max_divergence() {
        halos.fill(s.u);
        real m = 0;
        for_each_cell(dec.block().cells, [&](int i, int j, int k) {
            m = std::max(m, std::abs(divergence_at(s.u, cfg.grid, {i, j, k})));
        });
        return dec.max(m);
    }
    /// Max over faces of |u_c - f(c, x)|.
    template <class F>
    real max_error(F&& f) {
        real m = 0;
        for (int c = 0; c < s.u.dim; ++c)
            for_each_cell(dec.block().cells, [&](int i, int j, int k) {
                m = std::max(m, std::abs(s.u[c](i, j, k) - f(c, at(c, {i, j, k}))));
            });
        return dec.max(m);
    }
    real momentum(int c) {
        real m = 0;
        for_each_cell(dec.block().cells, [&](int i, int j, int k) { m += s.u[c](i, j, k); });
        return dec.sum(m);
    }
};

// Walled 12 x 10 x 8 box (walls everywhere, one moving), cubic cells of 0.1.
const std::string walled_box = R"(
[grid]
cells = [12, 10, 8]
length = [1.2, 1.0, 0.8]
[fluid]
density = 1.3
viscosity = 0.05
[boundary]
x_low = "wall"
x_high = "free_slip"
y_low = "wall"
y_high = { type = "wall", velocity = [1.0, 0.0, 0.3] }
z_low = "wall"
z_high = "wall"
[time]
end_time = 1.0
[solver.pressure]
tolerance = 1e-12
)";

// Triply periodic 16 x 8 x 4 box.
const std::string periodic_box = R"(
[grid]
cells = [16, 8, 4]
length = [1.6, 0.8, 0.4]
[fluid]
density = 1.0
viscosity = 0.02
[time]
end_time = 1.0
[solver.pressure]
tolerance = 1e-12
)";

// 2D channel 8 x 16, periodic in x: Couette / Poiseuille.
const std::string channel = R"(
[grid]
cells = [8, 16, 1]
length = [0.5, 1.0, 0.0625]
[fluid]
density = 1.0
viscosity = 0.1
[boundary]
y_low = "wall"
y_high = { type = "wall", velocity = [1.0, 0.0, 0.0] }
[initial]
type = "couette"
amplitude = 1.0
[time]
end_time = 1.0
[solver.pressure]
tolerance = 1e-12
[solver.viscous]
tolerance = 1e-13
)";

/// A rough, non-solenoidal velocity as a function of the global face index.
real rough(int c, const Int3& q) {
    return 0.3 * std::sin(0.9 * q[0] + 0.5 * c) * std::cos(0.7 * q[1]) +
           0.2 * std::cos(1.3 * q[2] + 0.4 * q[0] - c);
}

class Schemes : public ::testing::TestWithParam<std::string> {};

} // namespace

TEST_P(Schemes, ProjectionLeavesADiscretelySolenoidalField) {
    Rig r(walled_box, {{"time.viscous", GetParam()}});
    for (int c = 0; c < 3; ++c)
        for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
            const Int3 q = r.global({i, j, k});
            // Keep the fixed wall faces at zero, as the stepper does.
            r.s.u[c](i, j, k) =
                r.halos.is_fixed_wall_face(c, i * (c == 0) + j * (c == 1) + k * (c == 2))
                    ? 0.0
                    : rough(c, q);
        });
    EXPECT_GT(r.max_divergence(), 0.1);
    for (int n = 0; n < 3; ++n) {
        const StepReport rep = r.stepper.step(r.s, 0.01, r.timers);
        EXPECT_GT(rep.pressure.iterations, 0);
        EXPECT_TRUE(rep.pressure.converged);
        if (GetParam() != "explicit") {
            EXPECT_GT(rep.viscous.iterations, 0);
        }
        EXPECT_LT(r.max_divergence(), 1e-9) << "step " << n << " p-its " << rep.pressure.iterations
                                            << " res " << rep.pressure.relative_residual;
    }
    EXPECT_EQ(r.s.step, 3);
    EXPECT_NEAR(r.s.time, 0.03, 1e-15);
    // The no-penetration condition holds on every wall face.
    real wall = 0;
    for (int c = 0; c < 3; ++c)
        for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            if (r.halos.is_fixed_wall_face(c, p[c])) wall = std::max(wall, std::abs(r.s.u[c](p)));
        });
    EXPECT_EQ(r.dec.max(wall), 0.0);
}

TEST_P(Schemes, CouetteProfileIsAFixedPoint) {
    Rig r(channel, {{"time.viscous", GetParam()}});
    auto exact = [](int c, const Real3& x) { return c == 0 ? x[1] : 0.0; };
    ASSERT_LT(r.max_error(exact), 1e-14);
    for (int n = 0; n < 5; ++n)
        r.stepper.step(r.s, 0.02, r.timers);
    EXPECT_LT(r.max_error(exact), 1e-11);
}

TEST_P(Schemes, PoiseuilleParabolaIsAFixedPointUpToItsWallError) {
    // u = G/(2 mu) y (H - y) with G = 0.8, mu = 0.1: interior stencils are exact for the
    // parabola; the wall mirror differs by O(h^2), so the drift per unit time is bounded.
    Rig r(channel, {{"time.viscous", GetParam()},
                    {"initial.type", "poiseuille"},
                    {"boundary.y_high", "wall"},
                    {"forcing.body_force", "[0.8, 0.0, 0.0]"}});
    auto exact = [](int c, const Real3& x) { return c == 0 ? 4.0 * x[1] * (1 - x[1]) : 0.0; };
    ASSERT_LT(r.max_error(exact), 1e-14);
    for (int n = 0; n < 5; ++n)
        r.stepper.step(r.s, 0.01, r.timers);
    const real h = 1.0 / 16;
    const real err = r.max_error(exact);
    // The discrete steady state differs from the parabola by about G/(2 mu) h^2 / 2.
    EXPECT_LT(err, 4.0 * h * h);
    EXPECT_LT(r.max_divergence(), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Viscous, Schemes,
                         ::testing::Values("explicit", "crank_nicolson", "backward_euler"));

TEST(Smac, UniformFlowIsPreservedInAPeriodicBox) {
    Rig r(periodic_box);
    const Real3 U{0.3, -0.2, 0.1};
    for (int c = 0; c < 3; ++c)
        r.s.u[c].fill(U[c]);
    for (int n = 0; n < 4; ++n)
        r.stepper.step(r.s, 0.05, r.timers);
    EXPECT_LT(r.max_error([&](int c, const Real3&) { return U[c]; }), 1e-13);
}

TEST(Smac, MomentumIsConservedInAPeriodicBox) {
    Rig r(periodic_box, {{"forcing.body_force", "[0.5, 0.0, -0.25]"}});
    for (int c = 0; c < 3; ++c)
        for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
            r.s.u[c](i, j, k) = rough(c, r.global({i, j, k}));
        });
    r.halos.fill(r.s.u);
    Real3 before{};
    for (int c = 0; c < 3; ++c)
        before[c] = r.momentum(c);
    const real dt = 0.01;
    const int steps = 5;
    for (int n = 0; n < steps; ++n)
        r.stepper.step(r.s, dt, r.timers);
    // Advection, viscosity and the pressure gradient are all conservative: the mean
    // velocity changes only by the body force, f t / rho.
    const real faces = 16 * 8 * 4;
    const Real3 f{0.5, 0.0, -0.25};
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.momentum(c) / faces, before[c] / faces + f[c] * dt * steps, 1e-12)
            << "c = " << c;
    EXPECT_LT(r.max_divergence(), 1e-9);
}

TEST(Smac, ResultDoesNotDependOnTheRankLayout) {
    // Two layouts of the same ranks (automatic and all along x) give the same answer to
    // round-off: the stepper sees the decomposition only through halos and reductions.
    auto run = [](const Int3& ranks) {
        Config c = case_from(walled_box, {{"time.viscous", "crank_nicolson"}});
        c.ranks = ranks;
        Rig r(c);
        for (int k = 0; k < 3; ++k)
            r.stepper.step(r.s, 0.02, r.timers);
        // Probe: sum of |u| and a position-weighted sum, global.
        real a = 0, b = 0;
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
                const Int3 q = r.global({i, j, k});
                a += std::abs(r.s.u[comp](i, j, k));
                b += r.s.u[comp](i, j, k) * (1 + q[0] + 3 * q[1] + 7 * q[2] + comp);
            });
        return std::pair<real, real>{r.dec.sum(a), r.dec.sum(b)};
    };
    const int n = efsi::test::world_size();
    const auto auto_layout = run({0, 0, 0});
    const auto x_layout = run({n == 4 ? 4 : n, 1, 1});
    EXPECT_GT(auto_layout.first, 0.0);
    EXPECT_NEAR(auto_layout.first, x_layout.first, 1e-9 * auto_layout.first);
    EXPECT_NEAR(auto_layout.second, x_layout.second, 1e-9 * std::abs(auto_layout.second));
}

// Increment damping (time.increment_damping = F): the implicit solve also carries
// b lap_h (v* - v^n), b = dt (F - 1) mu / rho.
class IncrementDamping : public ::testing::TestWithParam<std::string> {};

TEST_P(IncrementDamping, ShearWaveDecaysWithTheDampedAmplificationFactor) {
    // u_x = A sin(2 pi y / L) in a periodic box: solenoidal, its advection vanishes
    // exactly (u . grad u_x = u_x d/dx u_x = 0), so a step multiplies it by
    // G = (1 - (1 - theta) s + b l) / (1 + theta s + b l), s = dt mu l / rho and -l the
    // discrete Laplacian's eigenvalue 4 sin^2(pi / N) / h^2; without damping (b = 0) the
    // factor of plain Crank-Nicolson / backward Euler.
    const std::string scheme = GetParam();
    const real theta = scheme == "backward_euler" ? 1.0 : 0.5;
    const bool hypre = scheme == "crank_nicolson_hypre";
    const real F = 9.0, rho = 1.0, mu = 0.02, dt = 0.05;
    Rig r(periodic_box, {{"time.viscous", hypre ? "crank_nicolson" : scheme},
                         {"time.increment_damping", "9.0"},
                         {"solver.viscous.method", hypre ? "pcg_pfmg" : "auto"},
                         {"solver.viscous.tolerance", "1e-14"}});
    const int ny = 8;
    const real h = 0.1, A = 0.7;
    for (int c = 0; c < 3; ++c)
        r.s.u[c].fill(0.0);
    for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
        const Int3 q = r.global({i, j, k});
        r.s.u[0](i, j, k) = A * std::sin(2 * M_PI * (q[1] + 0.5) / ny);
    });
    r.halos.fill(r.s.u);
    const real l = 4 * std::sin(M_PI / ny) * std::sin(M_PI / ny) / (h * h);
    const real s = dt * mu * l / rho, b = dt * (F - 1) * mu / rho;
    const real G = (1 - (1 - theta) * s + b * l) / (1 + theta * s + b * l);
    const int steps = 6;
    for (int n = 0; n < steps; ++n)
        r.stepper.step(r.s, dt, r.timers);
    const real amp = A * std::pow(G, steps);
    const real tol = hypre ? 1e-9 : 1e-13;
    EXPECT_LT(r.max_error([&](int c, const Real3& x) {
        return c == 0 ? amp * std::sin(2 * M_PI * x[1] / 0.8) : 0.0;
    }),
              tol);
    // The damping slows the decay: the undamped factor is smaller.
    EXPECT_LT((1 - (1 - theta) * s) / (1 + theta * s), G);
}

TEST_P(IncrementDamping, SteadyCouetteAndPoiseuilleStayFixedPoints) {
    // Exact at steady state: v* - v^n = 0 there, so the damping adds nothing (walls, one
    // moving, and a body force, on the FFT and the hypre paths).
    const std::string scheme = GetParam();
    const bool hypre = scheme == "crank_nicolson_hypre";
    const std::string viscous = hypre ? "crank_nicolson" : scheme;
    const std::string method = hypre ? "pcg_pfmg" : "auto";
    {
        Rig r(channel, {{"time.viscous", viscous},
                        {"time.increment_damping", "20.0"},
                        {"solver.viscous.method", method}});
        auto exact = [](int c, const Real3& x) { return c == 0 ? x[1] : 0.0; };
        for (int n = 0; n < 5; ++n)
            r.stepper.step(r.s, 0.02, r.timers);
        EXPECT_LT(r.max_error(exact), 1e-11);
    }
    {
        // The discrete steady Poiseuille profile, reached without damping, is a fixed point
        // with it.
        const Overrides o{{"time.viscous", viscous},
                          {"initial.type", "poiseuille"},
                          {"boundary.y_high", "wall"},
                          {"forcing.body_force", "[0.8, 0.0, 0.0]"},
                          {"solver.viscous.method", method}};
        Rig plain(channel, o);
        for (int n = 0; n < 400; ++n)
            plain.stepper.step(plain.s, 0.05, plain.timers);
        Overrides od = o;
        od.push_back({"time.increment_damping", "20.0"});
        Rig damped(channel, od);
        for (int c = 0; c < 2; ++c)
            damped.s.u[c] = plain.s.u[c];
        damped.s.p = plain.s.p;
        damped.halos.fill(damped.s.u);
        damped.halos.fill(damped.s.p);
        real before = 0;
        for_each_cell(damped.dec.block().cells, [&](int i, int j, int k) {
            before = std::max(before, std::abs(damped.s.u[0](i, j, k)));
        });
        VelocityField start = damped.s.u;
        for (int n = 0; n < 5; ++n)
            damped.stepper.step(damped.s, 0.05, damped.timers);
        real change = 0;
        for (int c = 0; c < 2; ++c)
            for_each_cell(damped.dec.block().cells, [&](int i, int j, int k) {
                change = std::max(change, std::abs(damped.s.u[c](i, j, k) - start[c](i, j, k)));
            });
        EXPECT_GT(damped.dec.max(before), 0.1);
        EXPECT_LT(damped.dec.max(change), 1e-10);
    }
}

INSTANTIATE_TEST_SUITE_P(Viscous, IncrementDamping,
                         ::testing::Values("crank_nicolson", "backward_euler",
                                           "crank_nicolson_hypre"));

// Increment damping confined by a weight field w (time.increment_damping_on = "membranes",
// set_damping_weight): the damping's Laplacian becomes div(w grad), w averaged onto the
// faces and edges like the viscosity.
TEST(IncrementDampingWeight, VaryingWeightMatchesTheOneDimensionalSolve) {
    // u_x = A sin(2 pi y / L) in the periodic box with w = w(y): the problem stays one-
    // dimensional (no advection, no pressure), and a Crank-Nicolson step is the periodic
    // system (I - theta s L + b L_w) u^{n+1} = (I + (1 - theta) s L + b L_w) u^n, L the
    // Laplacian along y and L_w u_j = (w_{j+1/2} (u_{j+1} - u_j) - w_{j-1/2} (u_j -
    // u_{j-1})) / h^2, w_{j-1/2} = (w_{j-1} + w_j) / 2 (the edge mean of the viscosity).
    const real F = 9.0, mu = 0.02, dt = 0.05, h = 0.1, A = 0.7;
    const int ny = 8, steps = 4;
    Rig r(periodic_box, {{"time.increment_damping", "9.0"},
                         {"solver.viscous.method", "pcg_pfmg"},
                         {"solver.viscous.tolerance", "1e-14"}});
    auto weight = [](int j) { return j < 0 || j >= 8 ? 0.0 : std::pow(std::sin(0.4 * j), 2); };
    Field w("damping_weight", Location::Cell, r.dec.block(), r.dec.dim());
    for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
        w(i, j, k) = weight(r.global({i, j, k})[1]);
    });
    r.halos.fill(w);
    r.stepper.set_damping_weight(&w);
    for (int c = 0; c < 3; ++c)
        r.s.u[c].fill(0.0);
    std::vector<real> u(ny);
    for (int j = 0; j < ny; ++j)
        u[j] = A * std::sin(2 * M_PI * (j + 0.5) / ny);
    for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
        r.s.u[0](i, j, k) = u[r.global({i, j, k})[1]];
    });
    r.halos.fill(r.s.u);
    for (int n = 0; n < steps; ++n)
        r.stepper.step(r.s, dt, r.timers);

    // The reference: the periodic 1D system solved densely, step after step.
    const real s = dt * mu / (h * h), b = dt * (F - 1) * mu / (h * h);
    auto wface = [&](int j) { return 0.5 * (weight((j + ny - 1) % ny) + weight(j)); };
    std::vector<std::vector<real>> M(ny, std::vector<real>(ny, 0.0));
    std::vector<std::vector<real>> R = M;
    for (int j = 0; j < ny; ++j) {
        const int jm = (j + ny - 1) % ny, jp = (j + 1) % ny;
        const real wl = wface(j), wh = wface(jp);
        M[j][j] += 1 + 0.5 * s * 2 + b * (wl + wh);
        M[j][jm] += -0.5 * s - b * wl;
        M[j][jp] += -0.5 * s - b * wh;
        R[j][j] += 1 - 0.5 * s * 2 + b * (wl + wh);
        R[j][jm] += 0.5 * s - b * wl;
        R[j][jp] += 0.5 * s - b * wh;
    }
    for (int n = 0; n < steps; ++n) {
        std::vector<real> rhs(ny, 0.0);
        for (int j = 0; j < ny; ++j)
            for (int q = 0; q < ny; ++q)
                rhs[j] += R[j][q] * u[q];
        auto a = M; // Gaussian elimination with partial pivoting
        for (int col = 0; col < ny; ++col) {
            int piv = col;
            for (int row = col + 1; row < ny; ++row)
                if (std::abs(a[row][col]) > std::abs(a[piv][col])) piv = row;
            std::swap(a[col], a[piv]);
            std::swap(rhs[col], rhs[piv]);
            for (int row = col + 1; row < ny; ++row) {
                const real f = a[row][col] / a[col][col];
                for (int q = col; q < ny; ++q)
                    a[row][q] -= f * a[col][q];
                rhs[row] -= f * rhs[col];
            }
        }
        for (int row = ny - 1; row >= 0; --row) {
            real acc = rhs[row];
            for (int q = row + 1; q < ny; ++q)
                acc -= a[row][q] * u[q];
            u[row] = acc / a[row][row];
        }
    }
    real err = 0, size = 0;
    for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
        const real ref = u[r.global({i, j, k})[1]];
        err = std::max(err, std::abs(r.s.u[0](i, j, k) - ref));
        err = std::max(err, std::abs(r.s.u[1](i, j, k)) + std::abs(r.s.u[2](i, j, k)));
        size = std::max(size, std::abs(ref));
    });
    EXPECT_GT(r.dec.max(size), 0.1);
    EXPECT_LT(r.dec.max(err), 1e-10);
}

TEST(IncrementDampingWeight, ZeroWeightIsNoDamping) {
    // w = 0 everywhere: the same step as without damping (F = 1, here on the same hypre path).
    const Overrides hypre{{"solver.viscous.method", "pcg_pfmg"},
                          {"solver.viscous.tolerance", "1e-14"}};
    Overrides damped = hypre;
    damped.push_back({"time.increment_damping", "9.0"});
    Rig plain(periodic_box, hypre), r(periodic_box, damped);
    Field w("damping_weight", Location::Cell, r.dec.block(), r.dec.dim());
    w.fill(0.0);
    r.stepper.set_damping_weight(&w);
    for (Rig* x : {&plain, &r}) {
        for_each_cell(x->dec.block().cells, [&](int i, int j, int k) {
            const Int3 q = x->global({i, j, k});
            x->s.u[0](i, j, k) = std::sin(2 * M_PI * (q[1] + 0.5) / 8) * std::cos(0.3 * q[2]);
            x->s.u[1](i, j, k) = 0.0;
            x->s.u[2](i, j, k) = 0.0;
        });
        x->halos.fill(x->s.u);
        for (int n = 0; n < 3; ++n)
            x->stepper.step(x->s, 0.05, x->timers);
    }
    real diff = 0;
    for (int c = 0; c < 3; ++c)
        for_each_cell(r.dec.block().cells, [&](int i, int j, int k) {
            diff = std::max(diff, std::abs(r.s.u[c](i, j, k) - plain.s.u[c](i, j, k)));
        });
    EXPECT_LT(r.dec.max(diff), 1e-12);
}

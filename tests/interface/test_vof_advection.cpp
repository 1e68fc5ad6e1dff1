// VOF advection: the THINC kernels, exact conservation and bounds under translation in a
// periodic box (2D and 3D, both schemes), and agreement of a decomposed run with serial.
#include "interface/prescribed_velocity.hpp"
#include "interface/shapes.hpp"
#include "interface/thinc.hpp"
#include "interface/vof_advection.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <cmath>
#include <numbers>

using namespace efsi;

namespace {

GlobalGrid box_grid(const Int3& cells, real h, int dim) {
    GlobalGrid g;
    g.dim = dim;
    g.cells = cells;
    for (int d = 0; d < 3; ++d)
        g.length[d] = cells[d] * h;
    return g;
}

} // namespace

TEST(Thinc, OneDimensionalReconstructionHoldsTheCellAverage) {
    for (real gamma : {1.0, -1.0})
        for (real phi : {1e-6, 0.03, 0.5, 0.77, 1 - 1e-6}) {
            const Thinc1D h = thinc1d_reconstruct(phi, gamma, 3.5);
            EXPECT_NEAR(thinc1d_integral(h, 0, 1), phi, 1e-12);
            // Split the cell: the parts add up, each bounded by its length.
            const real a = thinc1d_integral(h, 0, 0.3), b = thinc1d_integral(h, 0.3, 1);
            EXPECT_NEAR(a + b, phi, 1e-12);
            EXPECT_GE(a, 0);
            EXPECT_LE(a, 0.3);
        }
}

TEST(Thinc, MultidimensionalReconstructionHoldsTheCellAverage) {
    for (int dim : {2, 3})
        for (real phi : {1e-7, 0.2, 0.5, 0.93})
            for (const Real3& grad : {Real3{1, 0, 0}, Real3{0.3, -0.8, 0.5}, Real3{-1, -1, 1}}) {
                const Mthinc r = mthinc_reconstruct(phi, grad, 2.0, dim);
                const Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
                EXPECT_NEAR(mthinc_box_integral(r, lo, hi), phi, 1e-13);
                // phi increases along the normal: the half cell on the normal's side
                // holds more than the other half.
                Real3 mid_hi = lo, mid_lo = hi;
                mid_hi[r.m] = 0;
                mid_lo[r.m] = 0;
                const real up =
                    mthinc_box_integral(r, r.n[r.m] > 0 ? mid_hi : lo, r.n[r.m] > 0 ? hi : mid_lo);
                EXPECT_GT(up, 0.5 * phi);
            }
}

// The level iteration stops one Halley step after a residual below 1e-6 of
// min(phi, 1 - phi) (thinc.hpp, mthinc_level): the cubic convergence must leave the cell
// average at round-off, in the tails too, for every beta the schemes take.
TEST(Thinc, LevelIterationEndsAtRoundOff) {
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<real> uni(0, 1);
    std::normal_distribution<real> normal;
    for (int dim : {2, 3})
        for (real beta : {0.5, 1.0, 2.0, 4.0, 50.0}) {
            real worst = 0;
            for (int s = 0; s < 20000; ++s) {
                real phi = s % 2 ? std::pow(10.0, -8 * uni(gen)) : 1e-8 + (1 - 2e-8) * uni(gen);
                if (s % 4 == 1) phi = 1 - phi;
                const Real3 grad{normal(gen), normal(gen), dim == 3 ? normal(gen) : 0.0};
                const Mthinc r = mthinc_reconstruct(phi, grad, beta, dim);
                const real got = mthinc_box_integral(r, {-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
                worst = std::max(worst, std::abs(got - phi));
            }
            EXPECT_LT(worst, 2e-15) << "dim " << dim << " beta " << beta;
        }
}

namespace {

struct AdvectionResult {
    real v0 = 0, v1 = 0, min_phi = 0, max_phi = 1, clipped = 0;
};

/// Translate a sphere (a disc in 2D) with a uniform velocity for `steps` steps.
AdvectionResult translate(int dim, VofScheme scheme, int steps) {
    const GlobalGrid g = box_grid({28, 24, dim == 3 ? 20 : 1}, 1.0 / 24, dim);
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    const HaloFiller halos(dec, BoxBoundaries{});
    VofOptions opt;
    opt.scheme = scheme;
    VofAdvection vof(halos, opt);
    Field phi("phi", Location::Cell, dec.block(), dim);
    // A sphere in 3D; in 2D (cell centres at z = dz/2) the disc of a cylinder.
    const auto body =
        dim == 3 ? make_sphere({0.5, 0.45, 0.4}, 0.27) : make_cylinder({0.5, 0.45, 0}, 0.27);
    initial_volume_fraction(*body, g, dec.block(), phi);
    halos.fill(phi);
    VelocityField u("u", dec.block(), dim);
    const Real3 vel{0.9, -0.55, 0.35};
    for (int d = 0; d < dim; ++d)
        u[d].fill(vel[d]);
    const real dt = 0.4 * g.dx(0) / 0.9; // largest Courant 0.4
    AdvectionResult r;
    r.v0 = total_volume(dec, phi);
    for (int s = 0; s < steps; ++s) {
        const VofStepStats st = vof.advance(phi, u, dt, s);
        r.min_phi = std::min(r.min_phi, st.min_before_clip);
        r.max_phi = std::max(r.max_phi, st.max_before_clip);
        r.clipped += st.clipped_volume;
    }
    r.v1 = total_volume(dec, phi);
    return r;
}

} // namespace

class Translation : public ::testing::TestWithParam<std::tuple<int, VofScheme>> {};

TEST_P(Translation, ConservesVolumeAndStaysInBounds) {
    const auto [dim, scheme] = GetParam();
    // 70 steps at Courant 0.4 in x: the sphere crosses the box (28 cells) once.
    const AdvectionResult r = translate(dim, scheme, 70);
    EXPECT_LT(std::abs(r.v1 - r.v0) / r.v0, 1e-12);
    EXPECT_GE(r.min_phi, -1e-12);
    EXPECT_LE(r.max_phi, 1 + 1e-12);
    EXPECT_LT(r.clipped / r.v0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Schemes, Translation,
                         ::testing::Combine(::testing::Values(2, 3),
                                            ::testing::Values(VofScheme::Thinc1D,
                                                              VofScheme::Mthinc)));

TEST(VofAdvection, CourantAboveOneHalfIsRefused) {
    const GlobalGrid g = box_grid({12, 10, 1}, 0.1, 2);
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    const HaloFiller halos(dec, BoxBoundaries{});
    VofAdvection vof(halos, VofOptions{});
    Field phi("phi", Location::Cell, dec.block(), 2);
    VelocityField u("u", dec.block(), 2);
    u[0].fill(1.0);
    EXPECT_THROW(vof.advance(phi, u, 0.06, 0), RunError);
}

namespace {

/// Rotate a slotted disc for a few steps on `comm`; returns the global phi (x fastest).
/// `stats` (if given) receives the statistics of every step; `pointwise` selects the
/// reference sweeps.
std::vector<real> rotate(MPI_Comm comm, const GlobalGrid& g, VofScheme scheme,
                         bool pointwise = false, std::vector<VofStepStats>* stats = nullptr) {
    Decomposition dec(comm, g, {true, true, true});
    const HaloFiller halos(dec, BoxBoundaries{});
    VofOptions opt;
    opt.scheme = scheme;
    opt.pointwise = pointwise;
    VofAdvection vof(halos, opt);
    Field phi("phi", Location::Cell, dec.block(), g.dim);
    const auto shape = make_difference(g.dim == 3 ? make_sphere({0.5, 0.62, 0.45}, 0.25)
                                                  : make_cylinder({0.5, 0.62, 0}, 0.25),
                                       make_box({0.5, 0.55, 0.45}, {0.05, 0.2, 0.05}));
    initial_volume_fraction(*shape, g, dec.block(), phi);
    halos.fill(phi);
    VelocityField u("u", dec.block(), g.dim);
    // Rigid rotation about z through (0.5, 0.5) plus a swirl about x (in 3D only).
    set_velocity_from_potential(u, g, dec.block(), [&](const Real3& x) {
        const real y = x[1] - 0.5, z = x[2] - 0.45, r2 = (x[0] - 0.5) * (x[0] - 0.5) + y * y;
        return Real3{g.dim == 3 ? -0.5 * (y * y + z * z) : 0.0, 0, -r2};
    });
    for (int s = 0; s < 12; ++s) {
        const VofStepStats st = vof.advance(phi, u, 0.2 * g.dx(0), s);
        if (stats) stats->push_back(st);
    }
    std::vector<real> local(std::size_t(g.total_cells()), 0.0), global(local.size());
    for_each_cell(dec.block().cells, [&](int i, int j, int k) {
        const Int3 o = dec.block().offset;
        local[std::size_t(i + o[0]) +
              std::size_t(g.cells[0]) * (j + o[1] + std::size_t(g.cells[1]) * (k + o[2]))] =
            phi(i, j, k);
    });
    MPI_Allreduce(local.data(), global.data(), int(local.size()), MPI_DOUBLE, MPI_SUM, comm);
    return global;
}

} // namespace

TEST(VofAdvection, DecomposedRunAgreesWithSerial) {
    for (int dim : {2, 3})
        for (VofScheme scheme : {VofScheme::Thinc1D, VofScheme::Mthinc}) {
            const GlobalGrid g = box_grid({24, 20, dim == 3 ? 16 : 1}, 1.0 / 20, dim);
            const std::vector<real> par = rotate(MPI_COMM_WORLD, g, scheme);
            const std::vector<real> ser = rotate(MPI_COMM_SELF, g, scheme);
            real diff = 0, sum = 0;
            for (std::size_t q = 0; q < par.size(); ++q) {
                diff = std::max(diff, std::abs(par[q] - ser[q]));
                sum += ser[q];
            }
            EXPECT_GT(sum, 10.0); // the body is there
            EXPECT_LE(diff, 1e-14) << "dim " << dim << " scheme " << to_string(scheme);
        }
}

// The row sweeps (the default) against the pointwise sweeps they replaced: the same
// expressions in the same order, so phi and the step statistics agree bit for bit. The
// rotation has both signs of every velocity component, so both upwind sides, empty, full
// and interface cells, and (MTHINC) both the shared and the separate slab integrals occur.
TEST(VofAdvection, RowSweepsMatchThePointwiseSweeps) {
    for (int dim : {2, 3})
        for (VofScheme scheme : {VofScheme::Thinc1D, VofScheme::Mthinc}) {
            const GlobalGrid g = box_grid({24, 20, dim == 3 ? 16 : 1}, 1.0 / 20, dim);
            std::vector<VofStepStats> st_rows, st_ref;
            const std::vector<real> rows = rotate(MPI_COMM_WORLD, g, scheme, false, &st_rows);
            const std::vector<real> ref = rotate(MPI_COMM_WORLD, g, scheme, true, &st_ref);
            real diff = 0, sum = 0;
            for (std::size_t q = 0; q < ref.size(); ++q) {
                diff = std::max(diff, std::abs(rows[q] - ref[q]));
                sum += ref[q];
            }
            EXPECT_GT(sum, 10.0);
            EXPECT_EQ(diff, 0.0) << "dim " << dim << " scheme " << to_string(scheme);
            ASSERT_EQ(st_rows.size(), st_ref.size());
            for (std::size_t s = 0; s < st_ref.size(); ++s) {
                EXPECT_EQ(st_rows[s].min_before_clip, st_ref[s].min_before_clip);
                EXPECT_EQ(st_rows[s].max_before_clip, st_ref[s].max_before_clip);
                EXPECT_EQ(st_rows[s].clipped_volume, st_ref[s].clipped_volume);
                EXPECT_EQ(st_rows[s].max_courant, st_ref[s].max_courant);
            }
        }
}

// The one-call MTHINC slab integral against reconstruct + box integral, over normals whose
// exact direction is and is not the slab's direction.
TEST(Thinc, SlabIntegralMatchesReconstructionAndBoxIntegral) {
    for (int dim : {2, 3})
        for (real phi : {1e-7, 0.2, 0.5, 0.93})
            for (const Real3& grad :
                 {Real3{1, 0, 0}, Real3{0.3, -0.8, 0.5}, Real3{-1, -1, 1}, Real3{-0.2, 0.1, 0.9}})
                for (int d = 0; d < dim; ++d)
                    for (bool positive : {true, false})
                        for (real a : {0.01, 0.23, 0.49}) {
                            const Mthinc r = mthinc_reconstruct(phi, grad, 2.0, dim);
                            Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
                            if (positive)
                                lo[d] = 0.5 - a;
                            else
                                hi[d] = -0.5 + a;
                            EXPECT_EQ(mthinc_slab_integral(phi, grad, 2.0, dim, d, a, positive),
                                      mthinc_box_integral(r, lo, hi));
                        }
}

// The batched kernel puts four faces in the lanes of one vector (each with its own
// direction m, slab side and, in the tails, a residue that needs MthincLevel::finish):
// every face of a batch whose length is not a multiple of four, at several betas, against
// the one-face path (reconstruct, then the box integral), bit for bit.
TEST(Thinc, SlabIntegralsInLanesMatchOneFaceAtATime) {
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<real> uni(0, 1);
    std::normal_distribution<real> normal;
    constexpr int n = 1003;
    for (int dim : {2, 3})
        for (real beta : {0.5, 2.0, 50.0})
            for (int d = 0; d < dim; ++d) {
                std::vector<real> phi(n), courant(n), out(n);
                std::vector<Real3> grad(n);
                for (int f = 0; f < n; ++f) {
                    phi[f] = f % 2 ? std::pow(10.0, -9 * uni(gen)) : uni(gen);
                    if (f % 4 == 1) phi[f] = 1 - phi[f];
                    grad[f] = {normal(gen), normal(gen), dim == 3 ? normal(gen) : 0.0};
                    courant[f] = 0.98 * (uni(gen) - 0.5);
                }
                mthinc_slab_integrals(n, phi.data(), grad.data(), beta, dim, d, courant.data(),
                                      out.data());
                for (int f = 0; f < n; ++f) {
                    const Mthinc r = mthinc_reconstruct(phi[f], grad[f], beta, dim);
                    Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
                    if (courant[f] > 0)
                        lo[d] = 0.5 - std::abs(courant[f]);
                    else
                        hi[d] = -0.5 + std::abs(courant[f]);
                    ASSERT_EQ(out[f], mthinc_box_integral(r, lo, hi))
                        << "dim " << dim << " beta " << beta << " d " << d << " face " << f;
                }
            }
}

// MthincBoxRule's closed form (one exp and one log per evaluation) against the sum of
// ln cosh differences it replaced, evaluated in long double: the integral and its
// derivative in d over whole cells and slabs, for sharp and smooth profiles.
TEST(Thinc, ClosedFormBoxIntegralMatchesTheLnCoshForm) {
    using L = long double;
    const auto log_cosh_l = [](L z) {
        const L a = std::fabs(z);
        return a + std::log1p(std::exp(-2 * a)) - std::log(L(2));
    };
    const L g = 1 / std::sqrt(L(3));
    for (int dim : {2, 3})
        for (real beta : {0.3, 1.0, 2.0, 10.0})
            for (const Real3& grad : {Real3{0.3, -0.8, 0.5}, Real3{-1, -1, 1}, Real3{0.9, 0.2, 0}})
                for (real d : {-1.3, -0.2, 0.0, 0.45, 2.0})
                    for (int slab : {-1, 0, 1, 2}) { // -1: the whole cell, else that direction
                        if (slab >= dim) continue;
                        Mthinc r = mthinc_normal(grad, beta, dim);
                        r.d = d;
                        Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
                        if (slab >= 0) lo[slab] = 0.5 - 0.37;
                        L weight = 1, sum = 0, dsum = 0;
                        int others[2] = {0, 0}, no = 0;
                        for (int e = 0; e < dim; ++e)
                            if (e != r.m) {
                                others[no++] = e;
                                weight *= L(0.5) * (L(hi[e]) - lo[e]);
                            }
                        const L nm = r.n[r.m];
                        for (int q = 0; q < (1 << no); ++q) {
                            L level = d;
                            for (int a = 0; a < no; ++a) {
                                const int e = others[a];
                                const L mid = L(0.5) * (L(lo[e]) + hi[e]),
                                        half = L(0.5) * (L(hi[e]) - lo[e]);
                                level += r.n[e] * (mid + ((q >> a) & 1 ? g : -g) * half);
                            }
                            const L zh = beta * (nm * hi[r.m] + level),
                                    zl = beta * (nm * lo[r.m] + level);
                            sum += L(0.5) * ((L(hi[r.m]) - lo[r.m]) +
                                             (log_cosh_l(zh) - log_cosh_l(zl)) / (beta * nm));
                            dsum += L(0.5) * (std::tanh(zh) - std::tanh(zl)) / nm;
                        }
                        real slope = 0;
                        const real v = mthinc_box_integral(r, lo, hi, &slope);
                        EXPECT_NEAR(v, real(weight * sum), 1e-15)
                            << "dim " << dim << " beta " << beta << " d " << d << " slab " << slab;
                        EXPECT_NEAR(slope, real(weight * dsum), 1e-14 * beta);
                    }
}

TEST(VofAdvection, MthincBetaAboveTheLimitIsRefused) {
    const GlobalGrid g = box_grid({12, 10, 1}, 0.1, 2);
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    const HaloFiller halos(dec, BoxBoundaries{});
    VofOptions opt;
    opt.beta_mthinc = 2 * mthinc_beta_max;
    EXPECT_THROW(VofAdvection(halos, opt), InputError);
    opt.beta_mthinc = mthinc_beta_max;
    EXPECT_NO_THROW(VofAdvection(halos, opt));
}

// The whole-block sweeps (operators/flow_sweeps.hpp) against the pointwise kernels of
// operators/flow_operators.hpp, which stay the reference: the same stencils, so equal to
// round-off (divisions by h there, multiplications by 1/h in the sweeps), on an anisotropic
// 7 x 6 x 5 block with non-cubic spacing and smooth non-polynomial fields, halos included.
#include "operators/flow_operators.hpp"
#include "operators/flow_sweeps.hpp"
#include "test_support.hpp"

#include <cmath>
#include <limits>

using namespace efsi;

namespace {

struct SweepBox {
    GlobalGrid g;
    LocalBlock b;
    explicit SweepBox(int dim) {
        g.dim = dim;
        g.cells = dim == 3 ? Int3{7, 6, 5} : Int3{7, 6, 1};
        g.length = {0.7, 0.9, dim == 3 ? 0.4 : 0.1}; // dx = 0.1, dy = 0.15, dz = 0.08
        b.cells = g.cells;
    }
};

void fill_velocity(VelocityField& u) {
    for (int c = 0; c < u.dim; ++c) {
        auto& d = u[c].data();
        for (std::size_t m = 0; m < d.size(); ++m)
            d[m] = std::sin(0.37 * double(m) + 1.3 * c) + 0.2 * std::cos(0.11 * double(m));
    }
}

class Sweeps : public ::testing::TestWithParam<int> {};

std::string dim_name(const ::testing::TestParamInfo<int>& param_info) {
    return std::to_string(param_info.param) + "d";
}

} // namespace

TEST_P(Sweeps, AdvectionEqualsThePointwiseKernel) {
    const int dim = GetParam();
    SweepBox box(dim);
    VelocityField u("u", box.b, dim), adv("adv", box.b, dim);
    fill_velocity(u);
    sweep::for_each_component(
        dim, [&]<int C, int Dim>() { sweep::advection<C, Dim>(u, box.g, adv[C]); });
    for (int c = 0; c < dim; ++c)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            const real ref = advection_at(u, box.g, c, {i, j, k});
            EXPECT_NEAR(adv[c](i, j, k), ref, 1e-13 * (1 + std::abs(ref)))
                << "c = " << c << " at " << i << "," << j << "," << k;
        });
}

TEST_P(Sweeps, DivergenceEqualsThePointwiseKernelAndFindsTheLargestSpeed) {
    const int dim = GetParam();
    SweepBox box(dim);
    VelocityField u("u", box.b, dim);
    fill_velocity(u);
    Field rhs("rhs", Location::Cell, box.b, dim), rhs2("rhs2", Location::Cell, box.b, dim);
    const real scale = 2.5;
    const real speed = dim == 3 ? sweep::divergence<3>(u, box.g, scale, rhs)
                                : sweep::divergence<2>(u, box.g, scale, rhs);
    if (dim == 3)
        sweep::divergence<3, false>(u, box.g, scale, rhs2);
    else
        sweep::divergence<2, false>(u, box.g, scale, rhs2);
    real expected_speed = 0;
    for_each_cell(box.b.cells, [&](int i, int j, int k) {
        const real ref = -scale * divergence_at(u, box.g, {i, j, k});
        EXPECT_NEAR(rhs(i, j, k), ref, 1e-13 * (1 + std::abs(ref)));
        EXPECT_EQ(rhs2(i, j, k), rhs(i, j, k));
        for (int e = 0; e < dim; ++e)
            expected_speed = std::max(expected_speed, std::abs(u[e](i, j, k)));
    });
    EXPECT_EQ(speed, expected_speed);
}

TEST(Sweeps, MaxAbsIsExactAndSkipsNaNsLikeStdMax) {
    std::vector<real> x{0.5, -3.25, 1.0, 2.0, -0.125, 3.0, 0.0};
    for (int n = 0; n <= int(x.size()); ++n) {
        real expected = 0.1;
        for (int i = 0; i < n; ++i)
            expected = std::max(expected, std::abs(x[i]));
        EXPECT_EQ(sweep::max_abs(x.data(), n, 0.1), expected) << n;
    }
    x[1] = std::numeric_limits<real>::quiet_NaN();
    EXPECT_EQ(sweep::max_abs(x.data(), int(x.size()), 0.0), 3.0);
}

// SmacStepper's predictor with pinned solids and no transpose term, as its pointwise form
// writes it, against the row sweep that replaces it: equal bit for bit (the same expressions
// in the same order), for a non-uniform viscosity, a force, pinning with an explicit and a
// Crank-Nicolson viscous term, and a wall at the low face.
TEST_P(Sweeps, PredictorWithAViscosityFieldEqualsThePointwiseFormBitForBit) {
    const int dim = GetParam();
    SweepBox box(dim);
    VelocityField u("u", box.b, dim), adv("adv", box.b, dim), adv_prev("ap", box.b, dim),
        force("f", box.b, dim), pin("k", box.b, dim), out("out", box.b, dim);
    fill_velocity(u);
    fill_velocity(adv_prev);
    Field p("p", Location::Cell, box.b, dim), mu("mu", Location::Cell, box.b, dim);
    for (std::size_t m = 0; m < p.data().size(); ++m) {
        p.data()[m] = std::cos(0.23 * double(m));
        mu.data()[m] = 1.3 + 0.4 * std::sin(0.17 * double(m));
    }
    for (int c = 0; c < dim; ++c)
        for (std::size_t m = 0; m < force[c].data().size(); ++m) {
            force[c].data()[m] = std::sin(0.05 * double(m) + c);
            pin[c].data()[m] = 3.0 * std::abs(std::cos(0.07 * double(m)));
        }
    const real a1 = 1.3, a0 = -0.3, dt = 0.01, rho = 1e-3, bf = 0.4;
    for (const real share : {1.0, 0.5})
        for (const bool wall : {false, true}) {
            VelocityField a = adv, aref = adv;
            for (int c = 0; c < dim; ++c) {
                fill_velocity(a); // the same values in both
                aref[c] = a[c];
            }
            sweep::for_each_component(dim, [&]<int C, int Dim>() {
                const sweep::PredictorFieldCoefficients k{a1, a0, dt, rho, bf, share};
                sweep::predictor_viscosity_field<C, Dim>(u, p, mu, a[C], adv_prev[C], &force[C],
                                                         &pin[C], box.g, k, wall, out[C]);
            });
            for (int c = 0; c < dim; ++c)
                for_each_cell(box.b.cells, [&](int i, int j, int k) {
                    const Int3 q{i, j, k};
                    if (wall && q[c] == 0) {
                        EXPECT_EQ(out[c](q), 0.0);
                        EXPECT_EQ(a[c](q), aref[c](q));
                        return;
                    }
                    aref[c](q) += force[c](q) / rho;
                    real rate = a1 * aref[c](q) + a0 * adv_prev[c](q);
                    rate += (-gradient_at(p, box.g, c, q) + bf) / rho;
                    if (share > 0) rate += share * viscous_laplacian_at(u, mu, box.g, c, q) / rho;
                    real v = u[c](q) + dt * rate;
                    if (share == 1.0) v /= 1.0 + pin[c](q);
                    EXPECT_EQ(out[c](q), v) << "c = " << c << " at " << i << "," << j << "," << k;
                    EXPECT_EQ(a[c](q), aref[c](q));
                });
        }
}

INSTANTIATE_TEST_SUITE_P(Dims, Sweeps, ::testing::Values(2, 3), dim_name);

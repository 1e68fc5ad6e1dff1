// Staggered second-order operators (operators/flow_operators.hpp), pointwise, on an
// anisotropic 7 x 6 x 5 block with non-cubic spacing (the kernels must not assume cubes)
// filled with analytic fields at the exact staggered positions, halos included.
#include "operators/flow_operators.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;

namespace {

struct OperatorBox {
    GlobalGrid g;
    LocalBlock b;
    explicit OperatorBox(int dim) {
        g.dim = dim;
        g.cells = dim == 3 ? Int3{7, 6, 5} : Int3{7, 6, 1};
        g.length = {0.7, 0.9, dim == 3 ? 0.4 : 0.1}; // dx = 0.1, dy = 0.15, dz = 0.08
        g.origin = {-0.2, 0.3, 0.1};
        b.cells = g.cells;
    }
    Real3 at(Location loc, const Int3& p) const { return position(g, b, loc, p[0], p[1], p[2]); }
};

/// Set every stored point (halos included) of each component from f(c, x).
template <class F>
void set_velocity(VelocityField& u, const OperatorBox& box, F&& f) {
    for (int c = 0; c < u.dim; ++c) {
        const Int3 n = u[c].cells(), h = u[c].halo();
        for (int k = -h[2]; k < n[2] + h[2]; ++k)
            for (int j = -h[1]; j < n[1] + h[1]; ++j)
                for (int i = -h[0]; i < n[0] + h[0]; ++i)
                    u[c](i, j, k) = f(c, box.at(face_location(c), {i, j, k}));
    }
}

template <class F>
void set_scalar(Field& s, const OperatorBox& box, F&& f) {
    const Int3 n = s.cells(), h = s.halo();
    for (int k = -h[2]; k < n[2] + h[2]; ++k)
        for (int j = -h[1]; j < n[1] + h[1]; ++j)
            for (int i = -h[0]; i < n[0] + h[0]; ++i)
                s(i, j, k) = f(box.at(Location::Cell, {i, j, k}));
}

// A general linear velocity u_c = a_c + sum_e A_ce x_e.
constexpr real A[3][3] = {{0.7, -1.3, 0.4}, {2.1, 0.5, -0.9}, {-0.6, 1.7, -0.2}};
constexpr real a0[3] = {0.3, -0.8, 1.1};

real linear_u(int dim, int c, const Real3& x) {
    real v = a0[c];
    for (int e = 0; e < dim; ++e)
        v += A[c][e] * x[e];
    return v;
}

class Operators : public ::testing::TestWithParam<int> {};

std::string dim_name(const ::testing::TestParamInfo<int>& param_info) {
    return std::to_string(param_info.param) + "d";
}

} // namespace

TEST_P(Operators, DivergenceOfLinearVelocityIsExact) {
    const int dim = GetParam();
    OperatorBox box(dim);
    VelocityField u("u", box.b, dim);
    set_velocity(u, box, [&](int c, const Real3& x) { return linear_u(dim, c, x); });
    real trace = 0;
    for (int d = 0; d < dim; ++d)
        trace += A[d][d];
    for_each_cell(box.b.cells, [&](int i, int j, int k) {
        EXPECT_NEAR(divergence_at(u, box.g, {i, j, k}), trace, 1e-12);
    });
}

TEST_P(Operators, GradientOfLinearScalarIsExact) {
    const int dim = GetParam();
    OperatorBox box(dim);
    Field s("s", Location::Cell, box.b, dim);
    const Real3 slope{1.5, -2.5, 0.75};
    set_scalar(s, box, [&](const Real3& x) {
        return 3.0 + slope[0] * x[0] + slope[1] * x[1] + (dim == 3 ? slope[2] * x[2] : 0.0);
    });
    for (int d = 0; d < dim; ++d)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            EXPECT_NEAR(gradient_at(s, box.g, d, {i, j, k}), slope[d], 1e-12) << "d = " << d;
        });
}

TEST_P(Operators, AdvectionOfUniformFlowIsZero) {
    const int dim = GetParam();
    OperatorBox box(dim);
    VelocityField u("u", box.b, dim);
    set_velocity(u, box, [](int c, const Real3&) { return a0[c]; });
    for (int c = 0; c < dim; ++c)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            EXPECT_EQ(advection_at(u, box.g, c, {i, j, k}), 0.0);
        });
}

TEST_P(Operators, AdvectionOfLinearFlowIsExact) {
    // Averages of a linear field are exact and the fluxes are quadratic, whose central
    // differences are exact: -div(u u_c) = -(tr(A) u_c + sum_e u_e A_ce) at the face.
    const int dim = GetParam();
    OperatorBox box(dim);
    VelocityField u("u", box.b, dim);
    set_velocity(u, box, [&](int c, const Real3& x) { return linear_u(dim, c, x); });
    real trace = 0;
    for (int d = 0; d < dim; ++d)
        trace += A[d][d];
    for (int c = 0; c < dim; ++c)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            const Real3 x = box.at(face_location(c), {i, j, k});
            real exact = trace * linear_u(dim, c, x);
            for (int e = 0; e < dim; ++e)
                exact += linear_u(dim, e, x) * A[c][e];
            EXPECT_NEAR(advection_at(u, box.g, c, {i, j, k}), -exact, 1e-11) << "c = " << c;
        });
}

TEST_P(Operators, ViscousLaplacianOfQuadraticIsExact) {
    const int dim = GetParam();
    OperatorBox box(dim);
    const real mu = 0.37;
    Field muf("mu", Location::Cell, box.b, dim);
    muf.fill(mu);
    // u_c = sum_e Q_ce x_e^2 + cross terms: lap u_c = 2 sum_e Q_ce.
    const real Q[3][3] = {{1.2, -0.7, 0.5}, {0.3, 2.2, -1.4}, {-0.9, 0.8, 1.6}};
    VelocityField u("u", box.b, dim);
    set_velocity(u, box, [&](int c, const Real3& x) {
        real v = 0.1 * c + x[0] * x[1];
        for (int e = 0; e < dim; ++e)
            v += Q[c][e] * x[e] * x[e];
        return v;
    });
    for (int c = 0; c < dim; ++c) {
        real lap = 0;
        for (int e = 0; e < dim; ++e)
            lap += 2 * Q[c][e];
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            EXPECT_NEAR(viscous_laplacian_at(u, muf, box.g, c, {i, j, k}), mu * lap, 1e-10)
                << "c = " << c;
        });
    }
}

TEST_P(Operators, ViscousTransposeVanishesForUniformViscosityAndSolenoidalFlow) {
    const int dim = GetParam();
    OperatorBox box(dim);
    const GlobalGrid& g = box.g;
    Field muf("mu", Location::Cell, box.b, dim);
    muf.fill(0.8);
    // A discretely solenoidal field: the discrete curl of potentials psi (xy plane) and
    // chi (yz plane) at cell corners, plus a uniform w.
    auto psi = [](int i, int j, int k) { return std::sin(0.9 * i + 0.4 * j) * (1 + 0.1 * k); };
    auto chi = [](int i, int j, int k) { return std::cos(0.3 * i - 0.7 * j + 0.5 * k); };
    VelocityField u("u", box.b, dim);
    for (int c = 0; c < dim; ++c) {
        const Int3 n = u[c].cells(), h = u[c].halo();
        for (int k = -h[2]; k < n[2] + h[2]; ++k)
            for (int j = -h[1]; j < n[1] + h[1]; ++j)
                for (int i = -h[0]; i < n[0] + h[0]; ++i) {
                    real v = 0;
                    if (c == 0) v = (psi(i, j + 1, k) - psi(i, j, k)) / g.dx(1);
                    if (c == 1) v = -(psi(i + 1, j, k) - psi(i, j, k)) / g.dx(0);
                    if (c == 1 && dim == 3) v += (chi(i, j, k + 1) - chi(i, j, k)) / g.dx(2);
                    if (c == 2) v = 0.25 - (chi(i, j + 1, k) - chi(i, j, k)) / g.dx(1);
                    u[c](i, j, k) = v;
                }
    }
    for_each_cell(box.b.cells, [&](int i, int j, int k) {
        ASSERT_NEAR(divergence_at(u, g, {i, j, k}), 0.0, 1e-12);
    });
    for (int c = 0; c < dim; ++c)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            EXPECT_NEAR(viscous_transpose_at(u, muf, g, c, {i, j, k}), 0.0, 1e-9) << "c = " << c;
        });
    // For a compressible field it equals mu d/dx_c (div u), so it is not identically zero.
    VelocityField v("v", box.b, dim);
    set_velocity(v, box, [](int c, const Real3& x) { return c == 0 ? x[0] * x[0] : 0.0; });
    for_each_cell(box.b.cells, [&](int i, int j, int k) {
        EXPECT_NEAR(viscous_transpose_at(v, muf, g, 0, {i, j, k}), 0.8 * 2, 1e-9);
    });
}

TEST_P(Operators, VariableViscosityLaplacianIsConservative) {
    // div(mu grad u_c) with mu(x) varying: the weights of a face's neighbours are the
    // same coefficients seen from the other side, so the operator is symmetric.
    const int dim = GetParam();
    OperatorBox box(dim);
    Field muf("mu", Location::Cell, box.b, dim);
    set_scalar(muf, box, [](const Real3& x) { return 1.0 + 0.5 * std::sin(3 * x[0] + 2 * x[1]); });
    for (int c = 0; c < dim; ++c)
        for_each_cell(box.b.cells, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            const auto w = viscous_weights(muf, box.g, dim, c, p);
            for (int e = 0; e < dim; ++e) {
                if (p[e] + 1 >= box.b.cells[e]) continue;
                const auto wn = viscous_weights(muf, box.g, dim, c, shifted(p, e, 1));
                EXPECT_DOUBLE_EQ(w[e][1], wn[e][0]) << "c = " << c << " e = " << e;
                EXPECT_GT(w[e][1], 0.0);
            }
        });
}

INSTANTIATE_TEST_SUITE_P(Dims, Operators, ::testing::Values(2, 3), dim_name);

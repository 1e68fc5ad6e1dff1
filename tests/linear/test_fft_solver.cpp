// The direct FFT solver (linear/fft_poisson.cpp): for every closure it offers (periodic,
// zero gradient, zero value, mixed, wall faces), in 2D and 3D, singular and not, on
// anisotropic grids and on every rank layout the Decomposition makes from 1 to 4 ranks,
// the solve recovers a manufactured discrete solution (rhs = A x_exact, A built here
// point by point from the ghost rules) to round-off.
#include "linear/fft_poisson.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;
using efsi::test::global_max;

namespace {

constexpr FftSide G = FftSide::ZeroGradient;
constexpr FftSide V = FftSide::ZeroValue;

FftDirection periodic() {
    return {};
}
FftDirection closed(FftSide lo, FftSide hi) {
    FftDirection d;
    d.periodic = false;
    d.low = lo;
    d.high = hi;
    return d;
}
FftDirection faces() {
    FftDirection d;
    d.periodic = false;
    d.wall_faces = true;
    return d;
}

struct Problem {
    std::string name;
    Int3 cells;
    std::array<FftDirection, 3> dirs;
    real alpha, beta;
    Int3 ranks{0, 0, 0}; ///< requested layout (0: chosen by the Decomposition)
};

real exact(const Int3& q, const Int3& n) {
    return std::sin(2.1 * q[0] / n[0] + 0.3) * std::cos(1.7 * q[1] / n[1] + 0.2) +
           0.5 * std::cos(3.3 * q[2] / std::max(n[2], 1) + 0.1 * q[0]) + 0.01 * q[1];
}

/// alpha x - beta L_h x with the ghost rules of the closures, at global index q.
struct Operator {
    GlobalGrid g;
    std::array<FftDirection, 3> dirs;
    real alpha, beta;

    bool fixed(const Int3& q) const {
        for (int d = 0; d < g.dim; ++d)
            if (!dirs[d].periodic && dirs[d].wall_faces && q[d] == 0) return true;
        return false;
    }
    real apply(const Int3& q) const {
        if (fixed(q)) return exact(q, g.cells); // identity row
        const real xq = exact(q, g.cells);
        real lap = 0;
        for (int d = 0; d < g.dim; ++d) {
            const real w = 1.0 / (g.dx(d) * g.dx(d));
            const int n = g.cells[d];
            for (int side = 0; side < 2; ++side) {
                Int3 nb = q;
                nb[d] += side == 0 ? -1 : 1;
                real xn = 0;
                const FftDirection& D = dirs[d];
                if (D.periodic) {
                    nb[d] = (nb[d] + n) % n;
                    xn = exact(nb, g.cells);
                } else if (D.wall_faces) {
                    // Face unknowns: index 0 is the fixed low wall face (its coupling drops
                    // out, i.e. it counts as zero), index n the unstored high one.
                    xn = (nb[d] <= 0 || nb[d] >= n) ? 0.0 : exact(nb, g.cells);
                } else if (nb[d] < 0 || nb[d] >= n) {
                    const FftSide s = side == 0 ? D.low : D.high;
                    xn = s == FftSide::ZeroGradient ? xq : -xq;
                } else {
                    xn = exact(nb, g.cells);
                }
                lap += w * (xn - xq);
            }
        }
        return alpha * xq - beta * lap;
    }
};

class FftSolve : public ::testing::TestWithParam<Problem> {};

} // namespace

TEST_P(FftSolve, RecoversTheDiscreteSolution) {
    const Problem& prob = GetParam();
    GlobalGrid g;
    g.cells = prob.cells;
    g.dim = prob.cells[2] == 1 ? 2 : 3;
    g.length = {0.9, 1.3, 0.7}; // anisotropic on purpose
    Bool3 periodic{};
    for (int d = 0; d < 3; ++d)
        periodic[d] = prob.dirs[d].periodic;
    std::unique_ptr<Decomposition> dec;
    try {
        dec = std::make_unique<Decomposition>(MPI_COMM_WORLD, g, periodic, prob.ranks);
    } catch (const InputError&) {
        GTEST_SKIP() << "this grid cannot be split that way on " << test::world_size() << " ranks";
    }
    const LocalBlock& b = dec->block();
    FftSolver solver(*dec, prob.dirs);
    solver.set_coefficients(prob.alpha, prob.beta);
    const Operator op{g, prob.dirs, prob.alpha, prob.beta};
    auto global = [&](int i, int j, int k) {
        return Int3{b.offset[0] + i, b.offset[1] + j, b.offset[2] + k};
    };
    // The singular problem (alpha = 0, no zero-value closure) gives the zero-mean solution,
    // and the solve ignores the right-hand side's mean (its zero mode): a constant is added
    // to it, which no solution could produce.
    bool singular = prob.alpha == 0;
    for (int d = 0; d < g.dim; ++d)
        if (!prob.dirs[d].periodic &&
            (prob.dirs[d].wall_faces || prob.dirs[d].low == V || prob.dirs[d].high == V))
            singular = false;
    const real offset = singular ? 0.37 : 0.0;
    Field rhs("rhs", Location::Cell, b, g.dim), x("x", Location::Cell, b, g.dim);
    real local_sum = 0, scale = 0;
    for_each_cell(b.cells, [&](int i, int j, int k) {
        rhs(i, j, k) = op.apply(global(i, j, k)) + offset;
        x(i, j, k) = 12345; // overwritten
        local_sum += exact(global(i, j, k), g.cells);
        scale = std::max(scale, std::abs(exact(global(i, j, k), g.cells)));
    });
    const SolveReport r = solver.solve(rhs, x);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.iterations, 1);
    const real mean_exact = singular ? dec->sum(local_sum) / real(g.total_cells()) : 0.0;
    real xs = 0, err = 0;
    for_each_cell(b.cells, [&](int i, int j, int k) {
        xs += x(i, j, k);
        err = std::max(err, std::abs(x(i, j, k) - (exact(global(i, j, k), g.cells) - mean_exact)));
    });
    if (singular) {
        EXPECT_LT(std::abs(dec->sum(xs)) / real(g.total_cells()), 1e-13);
    }
    EXPECT_LT(global_max(err) / global_max(scale), 2e-12) << solver.describe();
}

namespace {

std::vector<Problem> problems() {
    std::vector<Problem> p;
    const auto P = periodic();
    // 3D, 12 x 8 x 12: splits on 2, 3 and 4 ranks in several layouts.
    const Int3 n3{12, 8, 12};
    const Int3 n2{12, 8, 1};
    for (Int3 ranks : {Int3{0, 0, 0}, Int3{1, 1, 0}, Int3{0, 1, 1}, Int3{1, 0, 1}}) {
        const std::string lay = ranks == Int3{0, 0, 0}   ? "auto"
                                : ranks == Int3{1, 1, 0} ? "zsplit"
                                : ranks == Int3{0, 1, 1} ? "xsplit"
                                                         : "ysplit";
        p.push_back({"poisson_periodic_3d_" + lay, n3, {P, P, P}, 0.0, 1.0, ranks});
        p.push_back(
            {"poisson_neumann_3d_" + lay, n3, {closed(G, G), P, closed(G, G)}, 0.0, 1.0, ranks});
        p.push_back({"helmholtz_periodic_3d_" + lay, n3, {P, P, P}, 1.0, 0.01, ranks});
        p.push_back({"helmholtz_dirichlet_3d_" + lay,
                     n3,
                     {closed(V, V), P, closed(V, G)},
                     1.0,
                     0.02,
                     ranks});
        p.push_back({"helmholtz_mixed_3d_" + lay,
                     n3,
                     {closed(G, V), closed(V, V), faces()},
                     1.0,
                     0.05,
                     ranks});
        p.push_back(
            {"helmholtz_faces_3d_" + lay, n3, {faces(), closed(G, G), P}, 1.0, 0.03, ranks});
        p.push_back(
            {"helmholtz_faces_y_3d_" + lay, n3, {P, faces(), closed(V, G)}, 1.0, 0.03, ranks});
        // x periodic, walls in y (and z): y solved as tridiagonal systems per wavenumber;
        // y periodic, walls in z: z solved so (the singular Poisson line included).
        p.push_back({"poisson_channel_3d_" + lay, n3, {P, closed(G, G), P}, 0.0, 1.0, ranks});
        p.push_back(
            {"poisson_duct_3d_" + lay, n3, {P, closed(G, G), closed(G, G)}, 0.0, 1.0, ranks});
        p.push_back({"poisson_z_walls_3d_" + lay, n3, {P, P, closed(G, G)}, 0.0, 1.0, ranks});
        p.push_back({"helmholtz_z_faces_3d_" + lay, n3, {P, P, faces()}, 1.0, 0.04, ranks});
    }
    // Two cells along the slab split: on 3 and 4 ranks some slabs are empty.
    p.push_back({"poisson_thin_3d", Int3{12, 8, 2}, {P, closed(G, G), P}, 0.0, 1.0});
    p.push_back({"helmholtz_thin_3d", Int3{12, 8, 2}, {closed(V, G), P, faces()}, 1.0, 0.02});
    // An odd number of cells along a periodic x: n/2 + 1 complex numbers per row hold one
    // real more than the row (the Nyquist wavenumber is absent).
    p.push_back({"poisson_periodic_odd_x_3d", Int3{9, 8, 6}, {P, P, P}, 0.0, 1.0});
    // An even x done as a complex DFT of half the length (HalfLengthReal), here of odd
    // length 5: no wavenumber is its own mirror.
    p.push_back({"helmholtz_periodic_x10_3d", Int3{10, 8, 6}, {P, P, P}, 1.0, 0.02});
    p.push_back({"poisson_channel_x10_2d", Int3{10, 6, 1}, {P, closed(G, G), P}, 0.0, 1.0});
    // Periodic everywhere on several ranks: z is solved as cyclic tridiagonal systems split
    // over the ranks; 10 z cells give slabs of unequal thickness on 3 and 4 ranks.
    p.push_back({"poisson_periodic_uneven_z_3d", Int3{12, 8, 10}, {P, P, P}, 0.0, 1.0});
    p.push_back({"helmholtz_periodic_uneven_z_3d", Int3{12, 8, 10}, {P, P, P}, 1.0, 0.02});
    p.push_back({"helmholtz_odd_x_walls_3d", Int3{9, 7, 6}, {P, closed(G, G), faces()}, 1.0, 0.02});
    p.push_back({"poisson_periodic_odd_x_2d", Int3{9, 8, 1}, {P, P, P}, 0.0, 1.0});
    p.push_back({"helmholtz_odd_x_channel_2d", Int3{11, 6, 1}, {P, faces(), P}, 1.0, 0.1});
    p.push_back({"poisson_periodic_2d", n2, {P, P, P}, 0.0, 1.0});
    p.push_back({"poisson_neumann_2d", n2, {closed(G, G), closed(G, G), P}, 0.0, 1.0});
    p.push_back({"poisson_channel_2d", n2, {P, closed(G, G), P}, 0.0, 1.0});
    p.push_back({"helmholtz_walls_2d", n2, {closed(V, V), faces(), P}, 1.0, 0.01});
    p.push_back({"helmholtz_lid_2d", n2, {faces(), closed(V, V), P}, 1.0, 0.01});
    p.push_back({"helmholtz_mixed_2d", n2, {closed(V, G), closed(G, V), P}, 1.0, 0.1});
    p.push_back({"helmholtz_channel_2d", n2, {P, closed(V, V), P}, 1.0, 0.1});
    p.push_back({"helmholtz_channel_normal_2d", n2, {P, faces(), P}, 1.0, 0.1});
    return p;
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Closures, FftSolve, ::testing::ValuesIn(problems()),
                         [](const auto& param_info) { return param_info.param.name; });

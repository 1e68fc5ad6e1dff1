// Cartesian domain decomposition (parallel/decomposition.cpp): the blocks tile the grid
// exactly once, neighbour exchange and periodic wrap fill halos with the neighbours'
// owned values, and the reductions see every rank. Runs on 1, 2, 3 and 4 ranks.
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <cmath>

using namespace efsi;
using efsi::test::global_max;
using efsi::test::global_sum;
using efsi::test::world_size;

namespace {

// 12 x 10 x 6 splits among 1, 2, 3 and 4 ranks.
GlobalGrid grid_3d() {
    GlobalGrid g;
    g.cells = {12, 10, 6};
    g.length = {1.2, 1.0, 0.6};
    g.dim = 3;
    return g;
}

// A value that differs at every global index of the (unwrapped) grid.
real tag(const Int3& q) {
    return 1 + q[0] + 100.0 * q[1] + 10000.0 * q[2];
}

int wrap(int i, int n) {
    return ((i % n) + n) % n;
}

} // namespace

TEST(Decomposition, BlocksTileTheGridExactlyOnce) {
    const GlobalGrid g = grid_3d();
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    EXPECT_EQ(dec.size(), world_size());
    const Int3 dims = dec.ranks_per_dim();
    EXPECT_EQ(dims[0] * dims[1] * dims[2], world_size());
    long owned = dec.block().count();
    EXPECT_EQ(global_sum(owned), g.total_cells());
    for (int d = 0; d < 3; ++d) {
        EXPECT_EQ(dec.block().cells[d] * dims[d], g.cells[d]);
        EXPECT_EQ(dec.block().offset[d], dec.coords()[d] * dec.block().cells[d]);
        EXPECT_EQ(dec.at_boundary(d, 0), dec.coords()[d] == 0);
        EXPECT_EQ(dec.at_boundary(d, 1), dec.coords()[d] == dims[d] - 1);
    }
}

TEST(Decomposition, ReductionsSeeEveryRank) {
    Decomposition dec(MPI_COMM_WORLD, grid_3d(), {false, false, false});
    const real r = dec.rank();
    EXPECT_DOUBLE_EQ(dec.sum(r + 1), 0.5 * world_size() * (world_size() + 1));
    EXPECT_DOUBLE_EQ(dec.max(r), world_size() - 1);
    EXPECT_DOUBLE_EQ(dec.min(r), 0.0);
    EXPECT_EQ(dec.sum(std::int64_t(dec.block().count())), grid_3d().total_cells());
}

TEST(Decomposition, ExchangeFillsHalosWithNeighbourValuesAndPeriodicWrap) {
    const GlobalGrid g = grid_3d();
    // Periodic in x and z, not in y: y halos on the box faces must stay untouched.
    Decomposition dec(MPI_COMM_WORLD, g, {true, false, true});
    const LocalBlock& b = dec.block();
    Field f("tag", Location::Cell, b, 3);
    const real untouched = -7;
    f.fill(untouched);
    for_each_cell(b.cells, [&](int i, int j, int k) {
        f(i, j, k) = tag({b.offset[0] + i, b.offset[1] + j, b.offset[2] + k});
    });
    for (int d = 0; d < 3; ++d)
        dec.exchange(f, d);
    const Int3 h = f.halo();
    EXPECT_EQ(h, (Int3{2, 2, 2}));
    real worst = 0;
    long checked = 0;
    for (int k = -h[2]; k < b.cells[2] + h[2]; ++k)
        for (int j = -h[1]; j < b.cells[1] + h[1]; ++j)
            for (int i = -h[0]; i < b.cells[0] + h[0]; ++i) {
                Int3 q{b.offset[0] + i, b.offset[1] + j, b.offset[2] + k};
                const bool outside_y = q[1] < 0 || q[1] >= g.cells[1];
                real expected = untouched;
                if (!outside_y) {
                    q[0] = wrap(q[0], g.cells[0]);
                    q[2] = wrap(q[2], g.cells[2]);
                    expected = tag(q);
                }
                worst = std::max(worst, std::abs(f(i, j, k) - expected));
                ++checked;
            }
    EXPECT_EQ(worst, 0.0);
    EXPECT_EQ(global_max(worst), 0.0);
    EXPECT_GT(checked, b.count());
}

TEST(Decomposition, TwoDimensionalFieldsHaveNoZHalo) {
    GlobalGrid g;
    g.cells = {16, 12, 1};
    g.length = {1.6, 1.2, 0.1};
    g.dim = 2;
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    EXPECT_EQ(dec.ranks_per_dim()[2], 1);
    const LocalBlock& b = dec.block();
    Field f("tag", Location::Cell, b, 2);
    EXPECT_EQ(f.halo(), (Int3{2, 2, 0}));
    EXPECT_EQ(f.extent()[2], 1);
    EXPECT_EQ(f.data().size(), std::size_t(b.cells[0] + 4) * (b.cells[1] + 4));
    for_each_cell(b.cells, [&](int i, int j, int k) {
        f(i, j, k) = tag({b.offset[0] + i, b.offset[1] + j, 0});
    });
    for (int d = 0; d < 3; ++d) // z is a no-op in 2D
        dec.exchange(f, d);
    real worst = 0;
    for (int j = -2; j < b.cells[1] + 2; ++j)
        for (int i = -2; i < b.cells[0] + 2; ++i)
            worst = std::max(worst, std::abs(f(i, j, 0) - tag({wrap(b.offset[0] + i, 16),
                                                               wrap(b.offset[1] + j, 12), 0})));
    EXPECT_EQ(global_max(worst), 0.0);
}

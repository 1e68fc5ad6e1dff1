// One call fills every halo (boundary/boundary.cpp): neighbour exchange, periodic wrap
// and the wall mirror rules, checked point by point (owned points, halos, edges and
// corners) against a model of the rules applied to a function of the GLOBAL index.
// Anisotropic 12 x 10 x 8 grid (and 16 x 12 x 1 in 2D) with mixed boundaries, on 1, 2
// and 4 ranks and two rank layouts.
#include "boundary/boundary.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace efsi;
using efsi::test::global_max;
using efsi::test::world_size;

namespace {

/// The value a field holds before any fill, at global index q, for component c (-1 for
/// a cell scalar). Smooth, and different under every index mirror or shift.
real smooth(int c, const Int3& q) {
    return 1.0 + 0.3 * c + 0.37 * q[0] + 0.13 * q[1] + 0.051 * q[2] + 0.011 * q[0] * q[1] +
           0.4 * std::sin(0.7 * q[2] + 0.2 * q[0]);
}

FaceBoundary face(BoundaryType t, Real3 v = {0, 0, 0}) {
    FaceBoundary f;
    f.type = t;
    f.velocity = v;
    return f;
}

/// What the halo rules should produce at global index q (inside the halo-extended box).
/// Directions are filled in the order x, y, z; a point is written last by the highest
/// direction in which it lies in a halo (or, for the normal velocity, on the low wall
/// face), so the model applies that direction's rule to the model value at the mirror.
struct HaloModel {
    GlobalGrid g;
    BoxBoundaries bc;
    int comp = -1; ///< velocity component, -1 for a cell scalar

    real operator()(Int3 q) const {
        const Int3 n = g.cells;
        for (int d = g.dim - 1; d >= 0; --d) {
            const bool outside = q[d] < 0 || q[d] >= n[d];
            const bool normal = comp == d;
            const bool periodic = bc[d][0].type == BoundaryType::Periodic;
            if (periodic) {
                if (!outside) continue;
                q[d] = ((q[d] % n[d]) + n[d]) % n[d];
                return (*this)(q);
            }
            const int side = q[d] < n[d] / 2 ? 0 : 1;
            const FaceBoundary& b = bc[d][side];
            if (normal) {
                // Normal velocity: zero on both wall faces (index 0 and n), odd beyond.
                if (q[d] == 0 || q[d] == n[d]) return 0.0;
                if (!outside) continue;
                q[d] = q[d] < 0 ? -q[d] : 2 * n[d] - q[d];
                return -(*this)(q);
            }
            if (!outside) continue;
            q[d] = q[d] < 0 ? -1 - q[d] : 2 * n[d] - 1 - q[d];
            if (comp < 0 || b.type == BoundaryType::FreeSlip) return (*this)(q);
            return 2 * b.velocity[comp] - (*this)(q);
        }
        return smooth(comp, q);
    }
};

/// Max |f - model| over every stored point of the block (halos included), all ranks.
real worst_mismatch(const Field& f, const LocalBlock& b, const HaloModel& model) {
    const Int3 n = f.cells(), h = f.halo();
    real worst = 0;
    for (int k = -h[2]; k < n[2] + h[2]; ++k)
        for (int j = -h[1]; j < n[1] + h[1]; ++j)
            for (int i = -h[0]; i < n[0] + h[0]; ++i) {
                const Int3 q{b.offset[0] + i, b.offset[1] + j, b.offset[2] + k};
                real e = std::abs(f(i, j, k) - model(q));
                if (std::isnan(e)) e = 1e300;
                if (e > worst && e > 1e-14)
                    ADD_FAILURE() << f.name() << ": halo value " << f(i, j, k) << " at global ("
                                  << q[0] << ", " << q[1] << ", " << q[2] << "), expected "
                                  << model(q);
                worst = std::max(worst, e);
            }
    return global_max(worst);
}

/// Owned values from `smooth`; the owned low wall face of a normal velocity holds 0, as
/// the stepper keeps it (the fill zeroes it only after the exchange, so with blocks of
/// two cells a neighbour's second halo layer would otherwise copy the old value).
void set_owned(Field& f, const LocalBlock& b, int comp, const BoxBoundaries& bc) {
    f.fill(std::numeric_limits<real>::quiet_NaN()); // stale halos must all be overwritten
    for_each_cell(b.cells, [&](int i, int j, int k) {
        const Int3 q{b.offset[0] + i, b.offset[1] + j, b.offset[2] + k};
        const bool wall_face =
            comp >= 0 && bc[comp][0].type != BoundaryType::Periodic && q[comp] == 0;
        f(i, j, k) = wall_face ? 0.0 : smooth(comp, q);
    });
}

struct HaloCase {
    std::string name;
    GlobalGrid grid;
    BoxBoundaries bc;
    Int3 ranks; ///< requested layout (0 = automatic)
};

class HaloFill : public ::testing::TestWithParam<HaloCase> {};

TEST_P(HaloFill, ScalarAndVelocityHalosFollowTheRules) {
    const HaloCase& s = GetParam();
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc), s.ranks);
    HaloFiller halos(dec, s.bc);
    const LocalBlock& b = dec.block();

    Field p("pressure", Location::Cell, b, s.grid.dim);
    set_owned(p, b, -1, s.bc);
    halos.fill(p);
    EXPECT_EQ(worst_mismatch(p, b, {s.grid, s.bc, -1}), 0.0) << "cell scalar";

    VelocityField u("velocity", b, s.grid.dim);
    for (int c = 0; c < s.grid.dim; ++c)
        set_owned(u[c], b, c, s.bc);
    halos.fill(u);
    for (int c = 0; c < s.grid.dim; ++c)
        EXPECT_LT(worst_mismatch(u[c], b, {s.grid, s.bc, c}), 1e-14) << "component " << c;

    // A second fill changes nothing (the rules are idempotent).
    const FieldStorage before = u[0].data();
    halos.fill(u);
    EXPECT_EQ(u[0].data(), before);
}

TEST_P(HaloFill, NormalFillEqualsTheFullFillAcrossEachComponentsFaces) {
    // fill_normal gives u_c's halos along c, at the owned positions across c, the values
    // of the full fill (what a divergence reads); the full fill is the reference.
    const HaloCase& s = GetParam();
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc), s.ranks);
    HaloFiller halos(dec, s.bc);
    const LocalBlock& b = dec.block();
    VelocityField full("velocity", b, s.grid.dim), normal("velocity", b, s.grid.dim);
    for (int c = 0; c < s.grid.dim; ++c) { // halos start as NaN: one left unfilled shows
        set_owned(full[c], b, c, s.bc);
        set_owned(normal[c], b, c, s.bc);
    }
    halos.fill(full);
    halos.fill_normal(normal);
    long compared = 0, differ = 0;
    for (int c = 0; c < s.grid.dim; ++c) {
        const int h = full[c].halo()[c];
        for_each_cell(b.cells, [&](int i, int j, int k) {
            Int3 p{i, j, k};
            if (p[c] != 0) return; // one line along c per owned position across it
            for (int q = -h; q < b.cells[c] + h; ++q) {
                p[c] = q;
                differ += !(full[c](p) == normal[c](p)); // NaN (unfilled) differs too
                ++compared;
            }
        });
    }
    EXPECT_GT(compared, 0);
    EXPECT_EQ(differ, 0);
}

TEST_P(HaloFill, WallValuesSeenByTheStencils) {
    // The mean of a tangential ghost and its mirror is the wall velocity (no-slip), the
    // difference is zero (free-slip); the normal velocity on the wall face is zero.
    const HaloCase& s = GetParam();
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc), s.ranks);
    HaloFiller halos(dec, s.bc);
    const LocalBlock& b = dec.block();
    VelocityField u("velocity", b, s.grid.dim);
    for (int c = 0; c < s.grid.dim; ++c)
        set_owned(u[c], b, c, s.bc);
    halos.fill(u);
    real worst = 0;
    long checked = 0;
    for (int d = 0; d < s.grid.dim; ++d)
        for (int side = 0; side < 2; ++side) {
            const FaceBoundary& f = s.bc[d][side];
            if (f.type == BoundaryType::Periodic || !dec.at_boundary(d, side)) continue;
            for (int c = 0; c < s.grid.dim; ++c)
                for_each_cell(b.cells, [&](int i, int j, int k) {
                    Int3 p{i, j, k};
                    if (p[d] != 0) return;
                    if (c == d) {
                        p[d] = side == 0 ? 0 : b.cells[d];
                        worst = std::max(worst, std::abs(u[c](p)));
                    } else {
                        // Skip the edge where this wall meets the wall face of u_c itself
                        // (u_c = 0 there wins, as the model test checks).
                        if (s.bc[c][0].type != BoundaryType::Periodic && dec.at_boundary(c, 0) &&
                            p[c] == 0)
                            return;
                        Int3 in = p, ghost = p;
                        in[d] = side == 0 ? 0 : b.cells[d] - 1;
                        ghost[d] = side == 0 ? -1 : b.cells[d];
                        const real wall = 0.5 * (u[c](in) + u[c](ghost));
                        const real expected =
                            f.type == BoundaryType::FreeSlip ? u[c](in) : f.velocity[c];
                        worst = std::max(worst, std::abs(wall - expected));
                    }
                    ++checked;
                });
        }
    EXPECT_LT(global_max(worst), 1e-14);
    EXPECT_GT(efsi::test::global_sum(checked), 0);
}

BoxBoundaries mixed_x_periodic() {
    // x periodic; y: no-slip bottom, moving top (x and z components); z: free-slip.
    BoxBoundaries bc;
    bc[0] = {face(BoundaryType::Periodic), face(BoundaryType::Periodic)};
    bc[1] = {face(BoundaryType::Wall), face(BoundaryType::Wall, {0.75, 0, -0.4})};
    bc[2] = {face(BoundaryType::FreeSlip), face(BoundaryType::FreeSlip)};
    return bc;
}

BoxBoundaries mixed_y_periodic() {
    // x: moving wall low (y, z components) and free-slip high; y periodic; z walls.
    BoxBoundaries bc;
    bc[0] = {face(BoundaryType::Wall, {0, 0.3, 0.6}), face(BoundaryType::FreeSlip)};
    bc[1] = {face(BoundaryType::Periodic), face(BoundaryType::Periodic)};
    bc[2] = {face(BoundaryType::Wall, {-0.2, 0.5, 0}), face(BoundaryType::Wall)};
    return bc;
}

BoxBoundaries channel_2d() {
    BoxBoundaries bc;
    bc[0] = {face(BoundaryType::Periodic), face(BoundaryType::Periodic)};
    bc[1] = {face(BoundaryType::Wall, {-0.5, 0, 0}), face(BoundaryType::Wall, {1.0, 0, 0})};
    bc[2] = {face(BoundaryType::Periodic), face(BoundaryType::Periodic)};
    return bc;
}

BoxBoundaries cavity_2d() {
    BoxBoundaries bc;
    bc[0] = {face(BoundaryType::Wall), face(BoundaryType::FreeSlip)};
    bc[1] = {face(BoundaryType::FreeSlip), face(BoundaryType::Wall, {1.0, 0, 0})};
    bc[2] = {face(BoundaryType::Periodic), face(BoundaryType::Periodic)};
    return bc;
}

GlobalGrid grid(Int3 cells) {
    GlobalGrid g;
    g.cells = cells;
    g.dim = cells[2] == 1 ? 2 : 3;
    for (int d = 0; d < 3; ++d)
        g.length[d] = 0.1 * cells[d];
    return g;
}

std::vector<HaloCase> setups() {
    const int n = world_size();
    return {
        {"x_periodic_auto", grid({12, 10, 8}), mixed_x_periodic(), {0, 0, 0}},
        // Blocks of at least 4 cells along z. (With blocks of 2 cells = the halo width,
        // a neighbour's second halo layer copies the wall plane of w before the wall rule
        // zeroes it; only the first layer is read by the stencils.)
        {"x_periodic_split_z",
         grid({12, 10, 8}),
         mixed_x_periodic(),
         {1, n / std::min(n, 2), std::min(n, 2)}},
        {"y_periodic_auto", grid({12, 10, 8}), mixed_y_periodic(), {0, 0, 0}},
        {"y_periodic_split_x", grid({12, 10, 8}), mixed_y_periodic(), {n, 1, 1}},
        {"channel_2d", grid({16, 12, 1}), channel_2d(), {0, 0, 0}},
        {"cavity_2d_split_y", grid({16, 12, 1}), cavity_2d(), {1, n, 1}},
    };
}

std::string case_name(const ::testing::TestParamInfo<HaloCase>& param_info) {
    return param_info.param.name;
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Boundaries, HaloFill, ::testing::ValuesIn(setups()), case_name);

TEST(HaloFill2D, NoZHaloAndNoZWork) {
    const GlobalGrid g = grid({16, 12, 1});
    const BoxBoundaries bc = channel_2d();
    Decomposition dec(MPI_COMM_WORLD, g, periodic_directions(bc));
    HaloFiller halos(dec, bc);
    VelocityField u("velocity", dec.block(), 2);
    EXPECT_EQ(u.dim, 2);
    EXPECT_TRUE(u.comp[2].data().empty()); // no w in 2D
    EXPECT_EQ(u[0].halo(), (Int3{2, 2, 0}));
    EXPECT_EQ(u[1].extent()[2], 1);
    halos.fill(u); // must not touch a z halo (would assert / crash)
}

// The many-field patch fill (one wait per direction for all of them, as the bodies' VOF
// sweeps use it) leaves every stored value, owned and halo, exactly as filling the fields
// one by one: patches over the whole box, across the rank boundaries, wrapping the
// periodic direction, and one held by no rank but the first, so that the ranks' lists
// of shared fields differ in length and interleave.
TEST(HaloFillPatches, ManyAtOnceEqualsOneByOne) {
    for (const HaloCase& c : setups()) {
        Decomposition dec(MPI_COMM_WORLD, c.grid, periodic_directions(c.bc), c.ranks);
        HaloFiller halos(dec, c.bc);
        const Int3 n = c.grid.cells;
        const int z1 = c.grid.dim == 3 ? 1 : 0;
        std::vector<Box> boxes = {
            Box{{0, 0, 0}, n}, Box{{2, 1, 0}, {n[0] - 3, n[1] - 2, n[2] - z1}},
            Box{{-3, 2, 0}, {4, n[1], std::max(1, n[2] / 2)}}, // wraps x when periodic
            Box{{n[0] / 2 - 2, n[1] / 2 - 2, 0}, {n[0] / 2 + 2, n[1] / 2 + 2, n[2]}},
            Box{{0, 0, 0}, {3, 3, std::max(1, n[2] / 4)}}};
        std::vector<Patch> patches;
        std::vector<Field> one, many;
        for (std::size_t b = 0; b < boxes.size(); ++b) {
            patches.push_back(make_patch(boxes[b], dec));
            const Patch& p = patches.back();
            Field f = Field::on_patch("f" + std::to_string(b), Location::Cell, p.local.lo,
                                      p.local.size(), c.grid.dim);
            auto& d = f.data();
            for (std::size_t m = 0; m < d.size(); ++m)
                d[m] = std::sin(0.37 * double(m) + double(b) + 0.1 * dec.rank());
            one.push_back(f);
            many.push_back(f);
        }
        for (std::size_t b = 0; b < boxes.size(); ++b)
            halos.fill(one[b], patches[b]);
        std::vector<Field*> fields;
        std::vector<const Patch*> of;
        for (std::size_t b = 0; b < boxes.size(); ++b) {
            fields.push_back(&many[b]);
            of.push_back(&patches[b]);
        }
        halos.fill(fields, of);
        real worst = 0;
        for (std::size_t b = 0; b < boxes.size(); ++b)
            for (std::size_t m = 0; m < one[b].data().size(); ++m)
                worst = std::max(worst, std::abs(one[b].data()[m] - many[b].data()[m]));
        EXPECT_EQ(global_max(worst), 0.0) << c.name;
    }
}

// `edge_layers`: at a patch's own edges (no neighbour across them) only that many halo layers
// mirror the owned values and the deeper ones keep what they held; across a rank boundary
// or the periodic wrap every layer is exchanged as before. Checked against the full fill on
// patches with edges, across rank boundaries and wrapping x, halos 4 wide.
TEST(HaloFillPatches, EdgeLayersMirrorOnlyThatDeepAtThePatchsOwnEdges) {
    constexpr int kWide = 4, kEdge = 2;
    constexpr real kUntouched = -7.25;
    for (const HaloCase& c : setups()) {
        Decomposition dec(MPI_COMM_WORLD, c.grid, periodic_directions(c.bc), c.ranks);
        HaloFiller halos(dec, c.bc);
        const Int3 n = c.grid.cells;
        const int dim = c.grid.dim;
        bool thin = false;
        for (int d = 0; d < dim; ++d)
            thin = thin || dec.block().cells[d] < kWide;
        if (thin) continue; // a block must hold the wide halo (as NormalExtension asks)
        const std::vector<Box> boxes = {Box{{0, 0, 0}, n},
                                        Box{{1, 1, 0}, {n[0] - 1, n[1] - 2, dim == 3 ? n[2] : 1}}};
        long deep_checked = 0;
        for (const Box& box : boxes) {
            const Patch p = make_patch(box, dec);
            Field full =
                Field::on_patch("full", Location::Cell, p.local.lo, p.local.size(), dim, kWide);
            full.fill(kUntouched);
            for_each_in(p.local, [&](int i, int j, int k) {
                const Int3 q{i + dec.block().offset[0], j + dec.block().offset[1],
                             k + dec.block().offset[2]};
                full(i, j, k) = smooth(-1, q);
            });
            Field edge = full;
            halos.fill(full, p);
            Field* fields[] = {&edge};
            const Patch* of[] = {&p};
            halos.fill(fields, of, kEdge);
            if (p.empty()) continue; // (after the collective fills)
            // Within kEdge of the owned box along every direction without an exchange the
            // two fills agree; a point deeper than kEdge past an edge is untouched.
            const Int3 lo = edge.begin(), hi = edge.begin() + edge.cells();
            real worst = 0;
            bool untouched = true;
            const Int3 h = edge.halo();
            for (int k = lo[2] - h[2]; k < hi[2] + h[2]; ++k)
                for (int j = lo[1] - h[1]; j < hi[1] + h[1]; ++j)
                    for (int i = lo[0] - h[0]; i < hi[0] + h[0]; ++i) {
                        const Int3 q{i, j, k};
                        bool deep = false;
                        for (int d = 0; d < dim; ++d) {
                            const int below = lo[d] - q[d], above = q[d] - (hi[d] - 1);
                            deep = deep || (below > kEdge && !p.exchange[d][0]) ||
                                   (above > kEdge && !p.exchange[d][1]);
                        }
                        if (deep) {
                            untouched = untouched && edge(q) == kUntouched;
                            ++deep_checked;
                        } else {
                            worst = std::max(worst, std::abs(edge(q) - full(q)));
                        }
                    }
            EXPECT_EQ(worst, 0.0) << c.name;
            EXPECT_TRUE(untouched) << c.name;
        }
        // Every setup has patch edges without a neighbour (the smaller box, and the walls).
        EXPECT_GT(global_max(real(deep_checked)), 0.0) << c.name;
    }
}

// Bodies' work in rounds of halo fills (bodies/body_work.hpp): what each body computes is what
// it computes with its fills made on the spot, on any rank count, with patches that cross the
// ranks' boundaries, wrap the periodic direction or lie on one rank only; the rounds
// interleave the bodies as documented; an error in one body's work reaches the caller.
#include "bodies/body_work.hpp"
#include "bodies/patch.hpp"
#include "boundary/boundary.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

using namespace efsi;

namespace {

real global_max(real x) {
    real r = 0;
    MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return r;
}

struct Scene {
    GlobalGrid grid;
    BoxBoundaries bc{};
    Scene() {
        grid.dim = 3;
        grid.cells = {16, 12, 8};
        for (int d = 0; d < 3; ++d)
            grid.length[d] = 0.1 * grid.cells[d];
        bc[1][0].type = bc[1][1].type = BoundaryType::Wall; // walls in y, periodic x and z
    }
};

/// One body's two-stage work: set f from the owned index, fill its halos, set g from f's
/// neighbours (halos read), fill g's. `log` records the stages in the order they ran.
BodyWork two_stages(Field& f, Field& g, const Patch& patch, int id, std::vector<int>* log) {
    if (log) log->push_back(10 * id + 1);
    for_each_in(f.owned(), [&](int i, int j, int k) {
        f(i, j, k) = std::sin(0.3 * i + 0.7 * j - 0.2 * k + id);
    });
    co_await halo_fill(f, patch);
    if (log) log->push_back(10 * id + 2);
    for_each_in(g.owned(), [&](int i, int j, int k) {
        g(i, j, k) = f(i - 1, j, k) + f(i + 1, j, k) - f(i, j - 1, k) * f(i, j + 1, k) +
                     0.5 * f(i, j, k - 1) * f(i, j, k + 1);
    });
    std::vector<Field*> both; // (a braced list here trips GCC 12's coroutine frames)
    both.push_back(&g);
    both.push_back(&f);
    co_await halo_fill(std::move(both), patch);
}

/// A work nested in another (co_await of a BodyWork): its fills are the outer one's.
BodyWork nested(Field& f, Field& g, const Patch& patch, int id, std::vector<int>* log) {
    co_await two_stages(f, g, patch, id, log);
    if (log) log->push_back(10 * id + 3);
}

} // namespace

TEST(BodyWork, RoundsEqualFillsOnTheSpot) {
    Scene s;
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc));
    HaloFiller halos(dec, s.bc);
    const Int3 n = s.grid.cells;
    const std::vector<Box> boxes = {Box{{0, 0, 0}, n}, Box{{-3, 2, 1}, {5, n[1] - 1, n[2] - 2}},
                                    Box{{n[0] / 2 - 3, 1, 0}, {n[0] / 2 + 3, 6, n[2]}},
                                    Box{{0, 0, 0}, {3, 3, 2}}};
    std::vector<Patch> patches;
    std::vector<Field> f_now, g_now, f_rounds, g_rounds;
    for (std::size_t b = 0; b < boxes.size(); ++b) {
        patches.push_back(make_patch(boxes[b], dec));
        const Patch& p = patches.back();
        const Field f = Field::on_patch("f", Location::Cell, p.local.lo, p.local.size(), 3);
        f_now.push_back(f);
        g_now.push_back(f);
        f_rounds.push_back(f);
        g_rounds.push_back(f);
    }
    for (std::size_t b = 0; b < boxes.size(); ++b)
        run_now(nested(f_now[b], g_now[b], patches[b], int(b), nullptr), halos);
    std::vector<BodyWork> works;
    for (std::size_t b = 0; b < boxes.size(); ++b)
        works.push_back(nested(f_rounds[b], g_rounds[b], patches[b], int(b), nullptr));
    run_in_rounds(works, halos);
    real worst = 0;
    for (std::size_t b = 0; b < boxes.size(); ++b)
        for (std::size_t m = 0; m < f_now[b].data().size(); ++m) {
            worst = std::max(worst, std::abs(f_now[b].data()[m] - f_rounds[b].data()[m]));
            worst = std::max(worst, std::abs(g_now[b].data()[m] - g_rounds[b].data()[m]));
        }
    EXPECT_EQ(global_max(worst), 0.0);
    // And the halos were filled: g read f across the patches' edges and the ranks' borders.
    real largest = 0;
    for (const Field& g : g_rounds)
        for (real v : g.data())
            largest = std::max(largest, std::abs(v));
    EXPECT_GT(global_max(largest), 0.1);
}

TEST(BodyWork, RoundsInterleaveTheBodiesAtTheirFills) {
    Scene s;
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc));
    HaloFiller halos(dec, s.bc);
    const Patch whole = make_patch(Box{{0, 0, 0}, s.grid.cells}, dec);
    auto field = [&] {
        return Field::on_patch("f", Location::Cell, whole.local.lo, whole.local.size(), 3);
    };
    std::vector<Field> f = {field(), field()}, g = {field(), field()};
    std::vector<int> log;
    std::vector<BodyWork> works;
    works.push_back(nested(f[0], g[0], whole, 1, &log));
    works.push_back(nested(f[1], g[1], whole, 2, &log));
    run_in_rounds(works, halos);
    EXPECT_EQ(log, (std::vector<int>{11, 21, 12, 22, 13, 23}));
}

TEST(BodyWork, AnErrorReachesTheCaller) {
    Scene s;
    Decomposition dec(MPI_COMM_WORLD, s.grid, periodic_directions(s.bc));
    HaloFiller halos(dec, s.bc);
    const Patch whole = make_patch(Box{{0, 0, 0}, s.grid.cells}, dec);
    Field f = Field::on_patch("f", Location::Cell, whole.local.lo, whole.local.size(), 3);
    auto failing = [&]() -> BodyWork {
        co_await halo_fill(f, whole);
        throw std::runtime_error("body 'b': bad state");
    };
    std::vector<BodyWork> works;
    works.push_back(failing());
    try {
        run_in_rounds(works, halos);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "body 'b': bad state");
    }
    EXPECT_THROW(run_now(failing(), halos), std::runtime_error);
}

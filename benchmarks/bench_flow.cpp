// Time per call of the flow kernels on one rank: the advection sweep and a full pressure
// solve (hypre PCG + PFMG, and the direct FFT solve periodic and with walls), at n^3
// cells. Reported as cells processed per second.
#include "boundary/boundary.hpp"
#include "linear/fft_poisson.hpp"
#include "linear/structured_solver.hpp"
#include "operators/flow_operators.hpp"
#include "parallel/decomposition.hpp"

#include "bench_grid.hpp"
#include "fft_problem.hpp"

#include <benchmark/benchmark.h>
#include <mpi.h>

#include <cmath>

using namespace efsi;

namespace {

using bench::cube;

void BM_AdvectionSweep(benchmark::State& state) {
    const int n = int(state.range(0));
    Decomposition dec(MPI_COMM_WORLD, cube(n), {true, true, true});
    BoxBoundaries bc{};
    HaloFiller halos(dec, bc);
    VelocityField u("u", dec.block(), 3), out("a", dec.block(), 3);
    for (int c = 0; c < 3; ++c)
        for_each_cell(dec.block().cells, [&](int i, int j, int k) {
            u[c](i, j, k) = std::sin(0.1 * (i + 2 * j + 3 * k + c));
        });
    halos.fill(u);
    for (auto _ : state) {
        for (int c = 0; c < 3; ++c)
            for_each_cell(dec.block().cells, [&](int i, int j, int k) {
                out[c](i, j, k) = advection_at(u, dec.grid(), c, {i, j, k});
            });
        benchmark::DoNotOptimize(out[0].data().data());
    }
    state.SetItemsProcessed(state.iterations() * dec.block().count());
}
BENCHMARK(BM_AdvectionSweep)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

void BM_PressureSolve(benchmark::State& state) {
    const int n = int(state.range(0));
    Decomposition dec(MPI_COMM_WORLD, cube(n), {true, true, true});
    StructuredSolver solver(dec, {true, true, true}, {"pcg_pfmg", 1e-10, 500});
    const real w = real(n) * n;
    solver.set_operator([&](int, int, int) {
        Stencil s;
        for (int d = 0; d < 3; ++d) {
            s.neighbour[d] = {-w, -w};
            s.centre += 2 * w;
        }
        return s;
    });
    Field rhs("rhs", Location::Cell, dec.block(), 3), x("x", Location::Cell, dec.block(), 3);
    for_each_cell(dec.block().cells, [&](int i, int j, int k) {
        rhs(i, j, k) =
            std::sin(2 * M_PI * i / n) * std::cos(2 * M_PI * j / n) * std::cos(2 * M_PI * k / n);
    });
    int iterations = 0;
    for (auto _ : state) {
        x.fill(0);
        iterations = solver.solve(rhs, x).iterations;
    }
    state.counters["pcg_iterations"] = iterations;
    state.SetItemsProcessed(state.iterations() * dec.block().count());
}
BENCHMARK(BM_PressureSolve)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

/// The direct solve of the same periodic problem, and of a channel (walls in y).
void BM_FftPressureSolve(benchmark::State& state) {
    bench::FftPressureProblem prob(int(state.range(0)), state.range(1) != 0);
    for (auto _ : state)
        prob.solver.solve(prob.rhs, prob.x);
    state.SetItemsProcessed(state.iterations() * prob.dec.block().count());
}
BENCHMARK(BM_FftPressureSolve)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->ArgNames({"n", "walls"})
    ->Unit(benchmark::kMillisecond);

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    {
        LinearAlgebraScope scope;
        benchmark::Initialize(&argc, argv);
        benchmark::RunSpecifiedBenchmarks();
        benchmark::Shutdown();
    }
    MPI_Finalize();
    return 0;
}

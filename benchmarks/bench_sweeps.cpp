// Bandwidth of the flow step's sweeps against a STREAM triad measured in the same run.
//
// Bytes are counted as STREAM counts them: each array element read or written once (8 B),
// no write-allocate traffic. Per cell and step: advection 3 x (3 reads + 1 write), predictor
// 3 x (4 reads + 1 write), correction 3 x (2 reads + 1 write), divergence 3 reads + 1 write.
// Compare each kernel's bytes_per_second with BM_StreamTriad's (same run, same machine).
#include "operators/flow_sweeps.hpp"
#include "parallel/decomposition.hpp"

#include "bench_grid.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

using namespace efsi;

namespace {

using bench::cube;

struct Fields {
    Decomposition dec;
    VelocityField u, a, ap, us;
    Field p;
    explicit Fields(int n)
        : dec(MPI_COMM_WORLD, cube(n), {true, true, true}), u("u", dec.block(), 3),
          a("a", dec.block(), 3), ap("ap", dec.block(), 3), us("us", dec.block(), 3),
          p("p", Location::Cell, dec.block(), 3) {
        for (int c = 0; c < 3; ++c) {
            auto& d = u[c].data();
            for (std::size_t m = 0; m < d.size(); ++m)
                d[m] = std::sin(0.001 * double(m) + c);
            ap[c].fill(0.1);
        }
        p.fill(1.0);
    }
    double cells() const { return double(dec.block().count()); }
};

void BM_StreamTriad(benchmark::State& state) {
    const std::size_t n = std::size_t(state.range(0));
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double s = 3.0;
    for (auto _ : state) {
        double* __restrict pa = a.data();
        const double* __restrict pb = b.data();
        const double* __restrict pc = c.data();
        for (std::size_t i = 0; i < n; ++i)
            pa[i] = pb[i] + s * pc[i];
        benchmark::DoNotOptimize(a.data());
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(n) * 24);
}
BENCHMARK(BM_StreamTriad)->Arg(1 << 24)->Unit(benchmark::kMillisecond);

void BM_AdvectionSweepFused(benchmark::State& state) {
    Fields f(int(state.range(0)));
    for (auto _ : state) {
        sweep::for_each_component(
            3, [&]<int C, int Dim>() { sweep::advection<C, Dim>(f.u, f.dec.grid(), f.a[C]); });
        benchmark::DoNotOptimize(f.a[0].data().data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * f.cells() * 3 * 4 * 8));
}
BENCHMARK(BM_AdvectionSweepFused)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

void BM_PredictorSweep(benchmark::State& state) {
    Fields f(int(state.range(0)));
    for (auto _ : state) {
        sweep::for_each_component(3, [&]<int C, int Dim>() {
            const sweep::PredictorCoefficients k{1.5, -0.5, 1e-3, 1.0, 0.0, 0.0};
            sweep::predictor<C, Dim>(f.u, f.p, f.a[C], f.ap[C], nullptr, f.dec.grid(), k, false,
                                     f.us[C]);
        });
        benchmark::DoNotOptimize(f.us[0].data().data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * f.cells() * 3 * 5 * 8));
}
BENCHMARK(BM_PredictorSweep)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

void BM_CorrectionSweep(benchmark::State& state) {
    Fields f(int(state.range(0)));
    for (auto _ : state) {
        sweep::for_each_component(3, [&]<int C, int Dim>() {
            sweep::correction<C, Dim>(f.us[C], f.p, f.dec.grid(), 1e-3, false, f.u[C]);
        });
        benchmark::DoNotOptimize(f.u[0].data().data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * f.cells() * 3 * 3 * 8));
}
BENCHMARK(BM_CorrectionSweep)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

void BM_DivergenceSweep(benchmark::State& state) {
    Fields f(int(state.range(0)));
    for (auto _ : state) {
        benchmark::DoNotOptimize(sweep::divergence<3>(f.u, f.dec.grid(), 1.0, f.p));
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * f.cells() * 4 * 8));
}
BENCHMARK(BM_DivergenceSweep)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

} // namespace

// Bandwidth of the flow step's sweeps against a STREAM triad measured in the same run.
//
// Bytes are counted as STREAM counts them: each array element read or written once (8 B),
// no write-allocate traffic. Per cell and step: advection 3 x (3 reads + 1 write), predictor
// 3 x (4 reads + 1 write), correction 3 x (2 reads + 1 write), divergence 3 reads + 1 write.
// The body tensor transport (bodies/transport.hpp, one Heun step of a membrane's Gs and
// kappa_R: n = 7 fields, 3D): the first stage reads n + 3 (the fields, u) and writes 2n (k1,
// T1), the second reads n + 3 + n + n (T1, u, k1, T) and writes n (T): 55 values per cell.
// The VOF advection of a body's phi (interface/vof_advection.hpp, one MTHINC step: three
// sweeps) over a sphere of radius 0.3 in the block: chi reads phi and writes chi (2), each
// sweep's flux pass reads u and phi and writes G (3), its update reads phi, G, chi, u and
// writes phi (5): 26 values per cell. Most of its time is the reconstruction of the
// interface cells (~6 % of them at n = 64), not memory traffic.
// Compare each kernel's bytes_per_second with BM_StreamTriad's (same run, same machine).
#include "bodies/symmetric_tensor.hpp"
#include "bodies/transport.hpp"
#include "boundary/boundary.hpp"
#include "interface/shapes.hpp"
#include "interface/thinc.hpp"
#include "interface/vof_advection.hpp"
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

// One Heun step of the tensor transport on the whole block (the body's patch in a run; the
// halo exchanges between the stages are not timed): Gs near the identity, kappa_R, and the
// benchmark's velocity, whose gradient changes sign (both upwind sides, both limiter cases).
struct TensorFields {
    Fields f;
    Box box;
    SymmetricTensorField t, t1;
    Field kappa, kappa1;
    std::vector<Field> k1, k2;
    explicit TensorFields(int n) : f(n), box{{0, 0, 0}, f.dec.block().cells} {
        t.dim = 3;
        for (int s = 0; s < SymmetricTensorField::count(3); ++s) {
            t.comp.emplace_back("Gs", Location::Cell, f.dec.block(), 3);
            auto& d = t.comp.back().data();
            for (std::size_t m = 0; m < d.size(); ++m)
                d[m] = (s < 3 ? 1.0 : 0.0) + 0.1 * std::cos(0.003 * double(m) + s);
        }
        kappa = Field("kappa_R", Location::Cell, f.dec.block(), 3);
        kappa.fill(1.0);
        t1 = t;
        kappa1 = kappa;
        k1.assign(t.comp.size() + 1, t.comp[0]);
        k2 = k1;
    }
    /// Values per cell moved by one Heun step, counted as STREAM counts (header).
    std::int64_t bytes_per_cell() const {
        const std::int64_t n = std::int64_t(k1.size());
        return ((n + 3) + 2 * n + (3 * n + 3) + n) * 8;
    }
};

void BM_TensorTransport(benchmark::State& state) {
    TensorFields b(int(state.range(0)));
    const real dt = 1e-3;
    for (auto _ : state) {
        transport_predict(b.box, b.t, &b.kappa, b.f.u, b.f.dec.grid(), dt, b.k1, b.t1, &b.kappa1);
        transport_correct(b.box, b.t1, &b.kappa1, b.f.u, b.f.dec.grid(), dt, b.k1, b.t, &b.kappa);
        benchmark::DoNotOptimize(b.t.comp[0].data().data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * b.f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * b.f.cells()) * b.bytes_per_cell());
}
BENCHMARK(BM_TensorTransport)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

// The same step the way it ran before the sweeps (the pointwise kernels per cell and
// component, k1 and k2 stored, one update pass per field and stage): the reference the
// sweep is measured against, with the same byte count.
void BM_TensorTransportPointwise(benchmark::State& state) {
    TensorFields b(int(state.range(0)));
    const real dt = 1e-3;
    const GlobalGrid& g = b.f.dec.grid();
    const int n = int(b.t.comp.size());
    auto rates = [&](const SymmetricTensorField& t, const Field& kappa, std::vector<Field>& out) {
        for_each_in(b.box, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            const Matrix3 L = velocity_gradient_at(b.f.u, g, p);
            for (int a = 0; a < 3; ++a)
                for (int c = a; c < 3; ++c) {
                    const int s = SymmetricTensorField::slot(a, c, 3);
                    real src = 0;
                    for (int e = 0; e < 3; ++e)
                        src += L[a][e] * t.value(e, c, p) + t.value(a, e, p) * L[c][e];
                    out[s](p) = advection_rate_at(t.comp[s], b.f.u, g, p) + src;
                }
            out[n](p) = advection_rate_at(kappa, b.f.u, g, p);
        });
    };
    auto field = [&](SymmetricTensorField& t, Field& kappa, int s) -> Field& {
        return s < n ? t.comp[s] : kappa;
    };
    for (auto _ : state) {
        rates(b.t, b.kappa, b.k1);
        for (int s = 0; s <= n; ++s)
            for_each_in(b.box, [&](int i, int j, int k) {
                field(b.t1, b.kappa1, s)(i, j, k) =
                    field(b.t, b.kappa, s)(i, j, k) + dt * b.k1[s](i, j, k);
            });
        rates(b.t1, b.kappa1, b.k2);
        for (int s = 0; s <= n; ++s)
            for_each_in(b.box, [&](int i, int j, int k) {
                field(b.t, b.kappa, s)(i, j, k) += 0.5 * dt * (b.k1[s](i, j, k) + b.k2[s](i, j, k));
            });
        benchmark::DoNotOptimize(b.t.comp[0].data().data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * b.f.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * b.f.cells()) * b.bytes_per_cell());
}
BENCHMARK(BM_TensorTransportPointwise)->Arg(64)->Unit(benchmark::kMillisecond);

struct VofCase {
    Decomposition dec;
    HaloFiller halos;
    VelocityField u;
    Field phi, phi0;
    real dt;
    explicit VofCase(int n)
        : dec(MPI_COMM_WORLD, cube(n), {true, true, true}), halos(dec, BoxBoundaries{}),
          u("u", dec.block(), 3), phi("phi", Location::Cell, dec.block(), 3) {
        const GlobalGrid& g = dec.grid();
        initial_volume_fraction(*make_sphere({0.5, 0.5, 0.5}, 0.3), g, dec.block(), phi);
        halos.fill(phi);
        phi0 = phi;
        // A rotation about z plus a swirl about x (every component takes both signs).
        const real h = g.dx(0);
        for (int k = -2; k < n + 2; ++k)
            for (int j = -2; j < n + 2; ++j)
                for (int i = -2; i < n + 2; ++i) {
                    const real x = (i + 0.5) * h - 0.5, y = (j + 0.5) * h - 0.5,
                               z = (k + 0.5) * h - 0.5;
                    u[0](i, j, k) = -y;
                    u[1](i, j, k) = x - 0.3 * z;
                    u[2](i, j, k) = 0.3 * y;
                }
        dt = 0.3 * h; // Courant <= 0.3 * 0.8
    }
    double cells() const { return double(dec.block().count()); }
};

void run_vof(benchmark::State& state, bool pointwise) {
    VofCase b(int(state.range(0)));
    VofOptions opt;
    opt.pointwise = pointwise;
    VofAdvection vof(b.halos, opt);
    std::int64_t step = 0;
    for (auto _ : state) {
        if (step % 8 == 0) { // start again from the sphere now and then (outside the timing)
            state.PauseTiming();
            b.phi = b.phi0;
            state.ResumeTiming();
        }
        benchmark::DoNotOptimize(vof.advance_local(b.phi, b.u, b.dt, step++));
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * b.cells()));
    state.SetBytesProcessed(std::int64_t(state.iterations() * b.cells()) * 26 * 8);
}

void BM_VofSweep(benchmark::State& state) {
    run_vof(state, false);
}
BENCHMARK(BM_VofSweep)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

// The same step through the pointwise sweeps the row sweeps replaced (the reference).
void BM_VofSweepPointwise(benchmark::State& state) {
    run_vof(state, true);
}
BENCHMARK(BM_VofSweepPointwise)->Arg(64)->Unit(benchmark::kMillisecond);

// The MTHINC face kernel alone (interface/thinc.hpp, mthinc_slab_integrals): the x-faces
// of the sphere's interface cells (0 < phi < 1) in row order, as a sweep along x gathers
// them, with central-difference normals and the case's Courant numbers. Items are faces.
void BM_MthincSlabIntegrals(benchmark::State& state) {
    VofCase b(int(state.range(0)));
    const real r = b.dt / b.dec.grid().dx(0);
    std::vector<real> phi, courant, out;
    std::vector<Real3> grad;
    const Box cells = b.phi0.owned();
    for_each_in(cells, [&](int i, int j, int k) {
        const real f = b.phi0(i, j, k);
        if (f <= 1e-6 || f >= 1 - 1e-6) return;
        const Int3 p{i, j, k};
        Real3 g{0, 0, 0};
        for (int e = 0; e < 3; ++e)
            g[e] = 0.5 * (b.phi0(p + unit(e)) - b.phi0(p - unit(e)));
        phi.push_back(f);
        grad.push_back(g);
        courant.push_back(b.u[0](p) * r);
    });
    out.resize(phi.size());
    for (auto _ : state) {
        mthinc_slab_integrals(int(phi.size()), phi.data(), grad.data(), 2.0, 3, 0, courant.data(),
                              out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations() * phi.size()));
}
BENCHMARK(BM_MthincSlabIntegrals)->Arg(128)->Unit(benchmark::kMillisecond);

} // namespace

// The row sweeps of the body transport (bodies/transport.hpp) against its pointwise kernels:
// Heun's two stages on a patch of an anisotropic block, with a velocity whose components
// change sign (both upwind sides and the limiter's both branches are taken), in 3D and 2D.
// The sweeps multiply by 1/h where the kernels divide by h, so h is not a power of two here
// and the agreement is to round-off.
#include "bodies/symmetric_tensor.hpp"
#include "bodies/transport.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

using namespace efsi;

namespace {

/// A smooth but wiggly value with sign changes, different for each seed.
real wiggle(int i, int j, int k, int seed) {
    return std::sin(0.7 * i + 1.3 * seed) * std::cos(0.45 * j - 0.3 * seed) +
           0.4 * std::sin(0.9 * k + 0.2 * i * seed) + 0.05 * seed;
}

/// f(i, j, k) = value(i, j, k) on every point of f, halos included.
template <class Value>
void fill_with(Field& f, Value&& value) {
    const Int3 b = f.begin(), h = f.halo(), n = f.cells();
    for (int k = b[2] - h[2]; k < b[2] + n[2] + h[2]; ++k)
        for (int j = b[1] - h[1]; j < b[1] + n[1] + h[1]; ++j)
            for (int i = b[0] - h[0]; i < b[0] + n[0] + h[0]; ++i)
                f(i, j, k) = value(i, j, k);
}

void fill_all(Field& f, int seed) {
    fill_with(f, [seed](int i, int j, int k) { return wiggle(i, j, k, seed); });
}

/// R(T) of the pointwise kernels at p (what the sweeps compute), component s (kappa: n).
real reference_rate(const SymmetricTensorField& t, const Field* kappa, const VelocityField& u,
                    const GlobalGrid& g, const Int3& p, int s) {
    const int n = SymmetricTensorField::count(t.dim);
    if (s == n) return advection_rate_at(*kappa, u, g, p);
    const Matrix3 L = velocity_gradient_at(u, g, p);
    for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b) {
            if (SymmetricTensorField::slot(a, b, t.dim) != s) continue;
            real src = 0;
            for (int c = 0; c < 3; ++c)
                src += L[a][c] * t.value(c, b, p) + t.value(a, c, p) * L[b][c];
            return advection_rate_at(t.comp[s], u, g, p) + src;
        }
    return 0;
}

void check_heun(int dim) {
    GlobalGrid g;
    g.dim = dim;
    g.cells = {13, 11, dim == 3 ? 9 : 1};
    g.length = {1.3, 0.7, dim == 3 ? 1.1 : 0.1};
    LocalBlock block;
    block.cells = g.cells;
    VelocityField u("u", block, dim);
    for (int d = 0; d < dim; ++d)
        fill_all(u[d], 10 + d);
    // The patch: a sub-box of the block, its fields with two halo layers.
    const Box box{{2, 1, dim == 3 ? 2 : 0}, {11, 10, dim == 3 ? 8 : 1}};
    auto on_patch = [&](const char* name) {
        return Field::on_patch(name, Location::Cell, box.lo, box.size(), dim);
    };
    SymmetricTensorField t;
    t.dim = dim;
    for (int s = 0; s < SymmetricTensorField::count(dim); ++s) {
        t.comp.push_back(on_patch("T"));
        fill_all(t.comp.back(), s);
    }
    Field kappa = on_patch("kappa");
    fill_all(kappa, 7);
    const int n = int(t.comp.size());
    const real dt = 0.01;
    std::vector<Field> k1(n + 1, t.comp[0]);
    SymmetricTensorField t1 = t;
    Field kappa1 = kappa;
    transport_predict(box, t, &kappa, u, g, dt, k1, t1, &kappa1);
    auto field = [&](SymmetricTensorField& tt, Field& kk, int s) -> Field& {
        return s < n ? tt.comp[s] : kk;
    };
    real worst = 0;
    for_each_in(box, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        for (int s = 0; s <= n; ++s) {
            const real r = reference_rate(t, &kappa, u, g, p, s);
            worst = std::max(worst, std::abs(k1[s](p) - r) / (1 + std::abs(r)));
            EXPECT_NEAR(field(t1, kappa1, s)(p), field(t, kappa, s)(p) + dt * r, 1e-13);
        }
    });
    EXPECT_LT(worst, 1e-13);
    // Stage 2 on T1 (its halos as the first stage left them: the old values).
    SymmetricTensorField tn = t;
    Field kappan = kappa;
    transport_correct(box, t1, &kappa1, u, g, dt, k1, tn, &kappan);
    for_each_in(box, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        for (int s = 0; s <= n; ++s) {
            const real r2 = reference_rate(t1, &kappa1, u, g, p, s);
            const real expect = field(t, kappa, s)(p) + 0.5 * dt * (k1[s](p) + r2);
            EXPECT_NEAR(field(tn, kappan, s)(p), expect, 1e-13 * (1 + std::abs(expect)));
        }
    });
    // Outside the box nothing is written.
    EXPECT_EQ(tn.comp[0](box.lo[0] - 1, box.lo[1], box.lo[2]),
              t.comp[0](box.lo[0] - 1, box.lo[1], box.lo[2]));
}

} // namespace

TEST(BodyTransportSweep, MatchesThePointwiseKernels3D) {
    check_heun(3);
}

TEST(BodyTransportSweep, MatchesThePointwiseKernels2D) {
    check_heun(2);
}

namespace {

/// A shell: phi = 1/2 + (0.3 - |x - c|) / 0.2 clamped, over cells of a block of n^3 (2D: n^2).
Field shell(const Box& box, int dim, int halo) {
    Field phi = Field::on_patch("phi", Location::Cell, box.lo, box.size(), dim, halo);
    fill_with(phi, [dim](int i, int j, int k) {
        const real r = std::hypot(i - 9.3, j - 8.1, dim == 3 ? k - 7.6 : 0.0);
        return std::clamp(0.5 + (5.0 - r) / 2.5, 0.0, 1.0);
    });
    return phi;
}

/// The runs as a set of cells.
std::vector<Int3> cells_of(const RowSpans& runs) {
    std::vector<Int3> out;
    for (const RowSpan& r : runs)
        for (int i = r.lo; i < r.hi; ++i)
            out.push_back({i, r.j, r.k});
    return out;
}

void check_band_spans(int dim) {
    const Box box{{1, 2, dim == 3 ? 1 : 0}, {18, 15, dim == 3 ? 16 : 1}};
    const Field phi = shell(box, dim, 4);
    const real lo = 0.05;
    const std::vector<RowSpans> runs = band_spans(phi, box, lo, {3, 1});
    for (int q = 0; q < 2; ++q) {
        const int reach = q == 0 ? 3 : 1;
        // By brute force: a cell of the box is in when a band cell lies within the cube.
        std::vector<Int3> expect;
        for_each_in(box, [&](int i, int j, int k) {
            bool in = false;
            const int rz = dim == 3 ? reach : 0;
            for (int c = -rz; c <= rz && !in; ++c)
                for (int b = -reach; b <= reach && !in; ++b)
                    for (int a = -reach; a <= reach && !in; ++a) {
                        const real f = phi(i + a, j + b, k + c);
                        in = f >= lo && f <= 1 - lo;
                    }
            if (in) expect.push_back({i, j, k});
        });
        std::vector<Int3> got = cells_of(runs[q]);
        auto order = [](const Int3& x, const Int3& y) {
            return std::tie(x[2], x[1], x[0]) < std::tie(y[2], y[1], y[0]);
        };
        EXPECT_TRUE(std::is_sorted(got.begin(), got.end(), order)) << "reach " << reach;
        EXPECT_EQ(got, expect) << "reach " << reach;
        EXPECT_GT(got.size(), 0u);
        EXPECT_LT(got.size(), std::size_t(box.count()));
    }
}

/// Heun's two stages on the band's runs (the first within 4 cells, the second within 2)
/// against the same stages on the whole box: the same values, bit for bit, on the second
/// stage's cells, and the old values elsewhere.
void check_band_heun(int dim) {
    GlobalGrid g;
    g.dim = dim;
    g.cells = {20, 17, dim == 3 ? 18 : 1};
    g.length = {1.3, 0.7, dim == 3 ? 1.1 : 0.1};
    LocalBlock block;
    block.cells = g.cells;
    VelocityField u("u", block, dim);
    for (int d = 0; d < dim; ++d)
        fill_all(u[d], 10 + d);
    const Box box{{1, 2, dim == 3 ? 1 : 0}, {18, 15, dim == 3 ? 16 : 1}};
    const Field phi = shell(box, dim, 4);
    SymmetricTensorField t;
    t.dim = dim;
    for (int s = 0; s < SymmetricTensorField::count(dim); ++s) {
        t.comp.push_back(Field::on_patch("T", Location::Cell, box.lo, box.size(), dim));
        fill_all(t.comp.back(), s);
    }
    const int n = int(t.comp.size());
    const real dt = 0.01;
    std::vector<Field> k1(n, t.comp[0]);
    SymmetricTensorField t1 = t, whole = t, band = t;
    transport_predict(box, &whole, {}, {}, u, g, dt, k1, &t1, {});
    transport_correct(box, &t1, {}, {}, u, g, dt, k1, &whole, {});
    const std::vector<RowSpans> runs = band_spans(phi, box, 0.05, {2, 4});
    SymmetricTensorField b1 = t;
    std::vector<Field> bk1(n, t.comp[0]);
    for (Field& c : b1.comp) // stale values where the first stage does not write (the halos
        for_each_in(box, [&](int i, int j, int k) { c(i, j, k) = 1e30; }); // as the whole's)
    transport_predict(box, &band, {}, {}, u, g, dt, bk1, &b1, {}, &runs[1]);
    transport_correct(box, &b1, {}, {}, u, g, dt, bk1, &band, {}, &runs[0]);
    std::vector<char> in(std::size_t(box.count()), 0);
    auto at = [&](const Int3& p) {
        return std::size_t((p[2] - box.lo[2]) * box.size()[1] + (p[1] - box.lo[1])) *
                   box.size()[0] +
               std::size_t(p[0] - box.lo[0]);
    };
    for (const Int3& p : cells_of(runs[0]))
        in[at(p)] = 1;
    int checked = 0;
    for_each_in(box, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        for (int s = 0; s < n; ++s) {
            if (in[at(p)]) {
                EXPECT_EQ(band.comp[s](p), whole.comp[s](p)) << i << " " << j << " " << k;
                ++checked;
            } else {
                EXPECT_EQ(band.comp[s](p), t.comp[s](p));
            }
        }
    });
    EXPECT_GT(checked, 0);
}

} // namespace

TEST(BodyTransportBand, SpansAreTheBandWidenedByACube3D) {
    check_band_spans(3);
}

TEST(BodyTransportBand, SpansAreTheBandWidenedByACube2D) {
    check_band_spans(2);
}

TEST(BodyTransportBand, BandStagesEqualTheWholeBoxsOnTheBand3D) {
    check_band_heun(3);
}

TEST(BodyTransportBand, BandStagesEqualTheWholeBoxsOnTheBand2D) {
    check_band_heun(2);
}

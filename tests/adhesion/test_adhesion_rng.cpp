// Counter-based random numbers of the adhesion kinetics (solver/adhesion/counter_rng.hpp):
// Philox-4x32-10 against Random123's known-answer vectors, determinism, the open interval,
// uniformity (chi-square, fixed inputs) and independence across ids, steps and purposes.
#include "adhesion/counter_rng.hpp"
#include "statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace efsi;
using namespace efsi::adhesion;

namespace {

/// Pearson correlation of two samples.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    const auto n = static_cast<double>(a.size());
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ma += a[i];
        mb += b[i];
    }
    ma /= n;
    mb /= n;
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

} // namespace

TEST(AdhesionRng, PhiloxKnownAnswers) {
    // Random123 (Salmon et al. 2011), tests/kat_vectors, philox4x32 with 10 rounds.
    EXPECT_EQ(philox4x32_10({0, 0, 0, 0}, {0, 0}),
              (Philox4x32{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
    EXPECT_EQ(philox4x32_10({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                            {0xffffffffu, 0xffffffffu}),
              (Philox4x32{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
    EXPECT_EQ(philox4x32_10({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
                            {0xa4093822u, 0x299f31d0u}),
              (Philox4x32{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

TEST(AdhesionRng, DeterministicAndKeyed) {
    const UniformPair a = uniform_pair(42, 7, 1000, Purpose::bind);
    const UniformPair b = uniform_pair(42, 7, 1000, Purpose::bind);
    EXPECT_EQ(a.u0, b.u0);
    EXPECT_EQ(a.u1, b.u1);
    // Each key component changes the draw.
    EXPECT_NE(a.u0, uniform_pair(43, 7, 1000, Purpose::bind).u0);
    EXPECT_NE(a.u0, uniform_pair(42, 8, 1000, Purpose::bind).u0);
    EXPECT_NE(a.u0, uniform_pair(42, 7, 1001, Purpose::bind).u0);
    EXPECT_NE(a.u0, uniform_pair(42, 7, 1000, Purpose::rupture).u0);
    // High bits of id, step and seed matter too (no truncation of the counter).
    EXPECT_NE(a.u0, uniform_pair(42, 7 + (std::uint64_t{1} << 40), 1000, Purpose::bind).u0);
    EXPECT_NE(a.u0, uniform_pair(42, 7, 1000 + (std::uint64_t{1} << 40), Purpose::bind).u0);
    EXPECT_NE(a.u0, uniform_pair(42 + (std::uint64_t{1} << 40), 7, 1000, Purpose::bind).u0);
    EXPECT_THROW(uniform_pair(1, max_receptor_id + 1, 0, Purpose::bind), InputError);
}

TEST(AdhesionRng, OpenUnitInterval) {
    EXPECT_GT(to_unit_open(0, 0), 0.0);
    EXPECT_LT(to_unit_open(0xffffffffu, 0xffffffffu), 1.0);
    EXPECT_EQ(to_unit_open(0xffffffffu, 0xffffffffu), 1.0 - 0x1.0p-53);
    EXPECT_EQ(to_unit_open(0, 0), 0x1.0p-53);
    EXPECT_TRUE(std::isfinite(std::log(to_unit_open(0, 0))));
}

TEST(AdhesionRng, UniformityChiSquare) {
    // 10^6 draws over ids x steps, 100 equal bins: chi-square p > 0.001 (inputs fixed, so
    // the verdict is reproducible), and mean / variance within 4 standard errors.
    const int bins = 100, ids = 1000, steps = 500;
    std::vector<double> counts(bins, 0.0);
    double sum = 0, sum2 = 0;
    const double n = 2.0 * ids * steps;
    for (int i = 0; i < ids; ++i)
        for (int s = 0; s < steps; ++s) {
            const UniformPair u = uniform_pair(2024, static_cast<std::uint64_t>(i),
                                               static_cast<std::uint64_t>(s), Purpose::test);
            for (double v : {u.u0, u.u1}) {
                ASSERT_GT(v, 0.0);
                ASSERT_LT(v, 1.0);
                counts[static_cast<std::size_t>(v * bins)] += 1;
                sum += v;
                sum2 += v * v;
            }
        }
    const std::vector<double> expected(bins, n / bins);
    const test::ChiSquare c = test::chi_square_fit(counts, expected);
    EXPECT_EQ(c.dof, bins - 1);
    EXPECT_GT(c.pvalue, 1e-3) << "chi2 = " << c.statistic;
    const double mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_NEAR(mean, 0.5, 4 * std::sqrt(1.0 / 12 / n));
    EXPECT_NEAR(var, 1.0 / 12, 4 * std::sqrt(1.0 / 180 / n)); // Var(U^2-ish) bound: 1/180
}

TEST(AdhesionRng, IndependenceAcrossIdsStepsAndPurposes) {
    // Correlations of draws whose keys differ in one component: |r| < 4 / sqrt(n).
    const int n = 200000;
    std::vector<double> base(n), next_step(n), next_id(n), other_purpose(n), second(n);
    for (int k = 0; k < n; ++k) {
        const auto id = static_cast<std::uint64_t>(k % 2000),
                   step = static_cast<std::uint64_t>(k / 2000);
        const UniformPair u = uniform_pair(99, id, step, Purpose::bind);
        base[k] = u.u0;
        second[k] = u.u1;
        next_step[k] = uniform_pair(99, id, step + 1, Purpose::bind).u0;
        next_id[k] = uniform_pair(99, id + 1, step, Purpose::bind).u0;
        other_purpose[k] = uniform_pair(99, id, step, Purpose::rupture).u0;
    }
    const double tol = 4 / std::sqrt(static_cast<double>(n));
    EXPECT_LT(std::abs(correlation(base, second)), tol);
    EXPECT_LT(std::abs(correlation(base, next_step)), tol);
    EXPECT_LT(std::abs(correlation(base, next_id)), tol);
    EXPECT_LT(std::abs(correlation(base, other_purpose)), tol);
}

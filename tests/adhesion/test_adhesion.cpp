// Platelet-adhesion kinetics (solver/adhesion): parameter and region validation naming the
// key, the ligand lookup, the dissociation laws, momentum-conserving bond forces, and the
// kinetic Monte Carlo against closed forms: exponential bond lifetime with mean 1/k_off(F),
// equilibrium bound fraction k_on / (k_on + k_off), binomial bond-count distribution
// (chi-square), reproducibility by seed, independence of the receptor order, the skip test
// and a scene without adhesion allocating nothing.
#include "adhesion/bond.hpp"
#include "adhesion/dissociation.hpp"
#include "adhesion/facing_pairs.hpp"
#include "adhesion/kinetics.hpp"
#include "core/error.hpp"
#include "statistics.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <string>
#include <vector>

// Allocation counter for the "a scene without adhesion allocates nothing" test.
namespace {
std::atomic<long> g_allocations{0};
}
// Replaced out of line (noinline), so that the compiler does not pair the inlined malloc
// and free with new and delete expressions (-Wmismatched-new-delete).
[[gnu::noinline]] void* operator new(std::size_t n) {
    ++g_allocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept {
    std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}

using namespace efsi;
using namespace efsi::adhesion;
using ::testing::HasSubstr;

namespace {

constexpr real pN = 1e-12, nm = 1e-9, um = 1e-6;

/// Message of the InputError `f` throws ("" if none).
template <class F>
std::string input_error(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

/// Bond length at which the spring carries `force`.
real length_for(const AdhesionParameters& p, real force) {
    return p.bond_rest_length + force / p.bond_stiffness;
}

/// Lifetimes (in steps, >= 1) of n pre-formed bonds under constant force, no rebinding.
std::vector<std::uint64_t> lifetimes(AdhesionParameters p, std::size_t n, real force, real dt,
                                     std::uint64_t seed) {
    p.k_on = 0;
    FacingPairs s = make_facing_pairs(n, length_for(p, force), 1 * um, p.reactive_distance, true);
    Kinetics kin(p, seed);
    // Broken bonds leave the list (k_on = 0: they never rebind; the order of the rest does
    // not matter to the kinetics).
    std::vector<std::uint64_t> life(n, 0);
    for (std::uint64_t step = 0; !s.receptors.empty(); ++step) {
        kin.step(s.receptors, s.ligands, step, dt);
        std::erase_if(s.receptors, [&](const Receptor& r) {
            if (r.bound()) return false;
            life[r.id] = step + 1;
            return true;
        });
    }
    return life;
}

/// Mean lifetime estimate (K - 1/2) dt, its standard error, and the KS distance of the
/// lifetimes to the exponential CDF at the step ends (exact there: P(K <= k) = 1 - e^{-k x}).
struct LifetimeStats {
    double mean = 0, se = 0, ks = 0;
};

LifetimeStats lifetime_stats(std::vector<std::uint64_t> life, real k_off, real dt) {
    LifetimeStats r;
    const auto n = static_cast<double>(life.size());
    double s = 0, s2 = 0;
    for (auto k : life) {
        const double t = (static_cast<double>(k) - 0.5) * dt;
        s += t;
        s2 += t * t;
    }
    r.mean = s / n;
    r.se = std::sqrt((s2 / n - r.mean * r.mean) / n);
    // Both CDFs are step functions of the integer K: compare them at every k = 1 .. max K.
    std::sort(life.begin(), life.end());
    std::size_t below = 0;
    for (std::uint64_t k = 1; k <= life.back(); ++k) {
        while (below < life.size() && life[below] <= k)
            ++below;
        const double cdf = -std::expm1(-k_off * dt * static_cast<double>(k));
        r.ks = std::max(r.ks, std::abs(static_cast<double>(below) / n - cdf));
    }
    return r;
}

/// Steps after which the bound state of a pair has forgotten its start to `rho`: the
/// per-step correlation of the two-state chain is 1 - p_on - p_off.
std::uint64_t decorrelation_steps(real p_on, real p_off, real rho) {
    return static_cast<std::uint64_t>(std::ceil(std::log(rho) / std::log1p(-(p_on + p_off))));
}

std::size_t count_bound(const std::vector<Receptor>& rs) {
    return static_cast<std::size_t>(
        std::count_if(rs.begin(), rs.end(), [](const Receptor& r) { return r.bound(); }));
}

} // namespace

// ---- parameters and regions ---------------------------------------------------------------

TEST(AdhesionParameters, DefaultsValidateAndBadValuesNameTheKey) {
    const AdhesionParameters ok;
    EXPECT_NO_THROW(ok.validate());
    EXPECT_NEAR(ok.thermal_energy() / ok.reactive_compliance, 6.0 * pN, 0.05 * pN);
    auto with = [](auto edit) {
        AdhesionParameters p;
        edit(p);
        return input_error([&] { p.validate(); });
    };
    EXPECT_THAT(with([](auto& p) { p.k_on = -1; }), HasSubstr("adhesion.k_on"));
    EXPECT_THAT(with([](auto& p) { p.k_off0 = -3; }), HasSubstr("adhesion.k_off0"));
    EXPECT_THAT(with([](auto& p) { p.bond_stiffness = -1e-3; }),
                HasSubstr("adhesion.bond_stiffness"));
    EXPECT_THAT(with([](auto& p) { p.reactive_compliance = NAN; }),
                HasSubstr("adhesion.reactive_compliance"));
    EXPECT_THAT(with([](auto& p) { p.reactive_distance = 0; }),
                HasSubstr("adhesion.reactive_distance"));
    EXPECT_THAT(with([](auto& p) { p.temperature = 0; }), HasSubstr("adhesion.temperature"));
    EXPECT_THAT(with([](auto& p) { p.law = DissociationLaw::catch_slip; }),
                HasSubstr("adhesion.catch_rate"));
    EXPECT_THAT(with([](auto& p) {
                    p.law = DissociationLaw::catch_slip;
                    p.catch_rate = 1;
                    p.slip_distance = -1;
                }),
                HasSubstr("adhesion.slip_distance"));
    AdhesionParameters bad;
    bad.k_on = -1;
    EXPECT_THROW(Kinetics(bad, 1), InputError);
}

TEST(AdhesionLigands, RegionLatticeAndValidation) {
    // A 1 um x 0.5 um patch on the wall y = 0 with 0.1 um spacing: 10 x 5 sites.
    const std::vector<LigandRegion> regions{{{0, 0, 0}, {1 * um, 0, 0.5 * um}, 0.1 * um}};
    EXPECT_NO_THROW(validate_ligand_regions(regions, {0, 0, 0}, {2 * um, 2 * um, 2 * um}));
    const LigandSet s = LigandSet::from_regions(regions, 70 * nm);
    ASSERT_EQ(s.size(), 50u);
    EXPECT_NEAR(s.position(0)[0], 0.05 * um, 1e-18);
    EXPECT_EQ(s.position(0)[1], 0.0);
    EXPECT_NEAR(s.position(49)[2], 0.45 * um, 1e-18);
    EXPECT_EQ(s.bound_count(), 0u);

    const Real3 dlo{0, 0, 0}, dhi{2 * um, 2 * um, 2 * um};
    auto err = [&](LigandRegion r) {
        const std::vector<LigandRegion> v{regions[0], r};
        return input_error([&] { validate_ligand_regions(v, dlo, dhi); });
    };
    EXPECT_THAT(err({{0, 0, 0}, {3 * um, 0, 1 * um}, 0.1 * um}),
                HasSubstr("adhesion.ligand_regions[1]: the box"));
    EXPECT_THAT(err({{0, 0, 0}, {3 * um, 0, 1 * um}, 0.1 * um}),
                HasSubstr("not inside the domain"));
    EXPECT_THAT(err({{1 * um, 0, 0}, {0, 0, 1 * um}, 0.1 * um}), HasSubstr("lo > hi"));
    EXPECT_THAT(err({{0, 0, 0}, {1 * um, 0, 1 * um}, -1}),
                HasSubstr("adhesion.ligand_regions[1].spacing"));
    EXPECT_THAT(err({{0, 0, 0}, {1 * um, 0, 1 * um}, 1e-15}), HasSubstr("more than"));
}

TEST(AdhesionLigands, LookupMatchesBruteForce) {
    const std::vector<LigandRegion> regions{{{0, 0, 0}, {2 * um, 0, 2 * um}, 37 * nm},
                                            {{3 * um, 0, 0}, {3.5 * um, 0, 0.5 * um}, 23 * nm}};
    const LigandSet s = LigandSet::from_regions(regions, 70 * nm);
    std::mt19937_64 gen(5);
    std::uniform_real_distribution<double> ux(-0.2 * um, 3.7 * um), uy(-0.1 * um, 0.2 * um);
    for (int t = 0; t < 300; ++t) {
        const Real3 x{ux(gen), uy(gen), ux(gen)};
        for (real d : {30 * nm, 70 * nm, 150 * nm}) {
            std::vector<std::uint64_t> fast, brute;
            s.for_each_within(x, d, [&](std::uint64_t id, real r) {
                fast.push_back(id);
                EXPECT_LE(r, d);
            });
            for (std::uint64_t id = 0; id < s.size(); ++id) {
                const Real3& y = s.position(id);
                if (std::hypot(y[0] - x[0], y[1] - x[1], y[2] - x[2]) <= d) brute.push_back(id);
            }
            std::sort(fast.begin(), fast.end());
            ASSERT_EQ(fast, brute);
            if (!brute.empty()) {
                EXPECT_TRUE(s.may_reach(x, d));
            }
        }
    }
    // Points far away (or not finite) find nothing and overflow nothing.
    int found = 0;
    for (real far : {1e300, -1e300, real(NAN)})
        s.for_each_within({far, far, far}, 70 * nm, [&](std::uint64_t, real) { ++found; });
    EXPECT_EQ(found, 0);
}

// ---- rates and forces ---------------------------------------------------------------------

TEST(AdhesionRates, BellAndCatchSlip) {
    AdhesionParameters p;
    const real kT = p.thermal_energy();
    EXPECT_DOUBLE_EQ(off_rate(p, 0), p.k_off0);
    EXPECT_DOUBLE_EQ(off_rate(p, 10 * pN),
                     p.k_off0 * std::exp(p.reactive_compliance * 10 * pN / kT));
    EXPECT_DOUBLE_EQ(off_rate(p, -10 * pN), off_rate(p, 10 * pN));
    // Two-pathway law: k_off is smallest (the lifetime longest) at
    // F* = kT / (x_c + x_s) ln(k_c x_c / (k_s x_s)).
    p.law = DissociationLaw::catch_slip;
    p.catch_rate = 20;
    p.catch_distance = 1.0 * nm;
    p.slip_rate = 0.5;
    p.slip_distance = 0.3 * nm;
    const real fstar = kT / (p.catch_distance + p.slip_distance) *
                       std::log(p.catch_rate * p.catch_distance / (p.slip_rate * p.slip_distance));
    EXPECT_GT(fstar, 0);
    EXPECT_LT(off_rate(p, fstar), off_rate(p, 0.9 * fstar));
    EXPECT_LT(off_rate(p, fstar), off_rate(p, 1.1 * fstar));
    EXPECT_DOUBLE_EQ(off_rate(p, 0), p.catch_rate + p.slip_rate);
    EXPECT_NEAR(event_probability(1e-12, 1e-6), 1e-18, 1e-30);
}

TEST(AdhesionBond, ForceAlongTheBondAndMomentumConserving) {
    const real sigma = 1e-3, lambda = 50 * nm;
    const BondForce b = bond_force({0, 0, 80 * nm}, {0, 0, 0}, sigma, lambda);
    EXPECT_NEAR(b.length, 80 * nm, 1e-20);
    EXPECT_NEAR(b.tension, sigma * 30 * nm, 1e-24);
    EXPECT_NEAR(b.on_receptor[2], -30 * pN, 1e-24); // stretched: pulled down to the ligand
    EXPECT_EQ(b.on_receptor[0], 0.0);
    const BondForce c = bond_force({0, 0, 20 * nm}, {0, 0, 0}, sigma, lambda);
    EXPECT_NEAR(c.on_receptor[2], 30 * pN, 1e-24); // compressed: pushed away
    EXPECT_EQ(bond_force({1, 2, 3}, {1, 2, 3}, sigma, lambda).on_receptor, (Real3{0, 0, 0}));

    // Many random bonds: every bond's two forces cancel exactly, so the total is zero.
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> u(-100 * nm, 100 * nm);
    std::vector<Receptor> rs;
    std::vector<Real3> sites;
    for (std::uint64_t k = 0; k < 1000; ++k) {
        sites.push_back({u(gen), u(gen), u(gen)});
        rs.push_back({k, {u(gen), u(gen), u(gen)}, k});
    }
    LigandSet ls = LigandSet::from_sites(sites, 70 * nm);
    for (std::uint64_t k = 0; k < 1000; ++k)
        ls.bind(k, k);
    AdhesionParameters p;
    std::vector<BondLoad> loads;
    bond_loads(rs, ls, p, loads);
    ASSERT_EQ(loads.size(), 1000u);
    Real3 total{0, 0, 0};
    real scale = 0;
    for (const BondLoad& l : loads)
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(l.force.on_receptor[a] + l.force.on_ligand[a], 0.0);
            total[a] += l.force.on_receptor[a] + l.force.on_ligand[a];
            scale += std::abs(l.force.on_receptor[a]);
        }
    EXPECT_EQ(total, (Real3{0, 0, 0}));
    EXPECT_GT(scale, 0);

    // A bond above the time step's force limit is reported with the receptor and ligand.
    p.max_bond_force = 50 * pN;
    std::vector<Receptor> one{{77, {0, 0, 200 * nm}, 0}};
    LigandSet one_site = LigandSet::from_sites(std::vector<Real3>{Real3{0, 0, 0}}, 70 * nm);
    one_site.bind(0, 77);
    loads.clear();
    try {
        bond_loads(one, one_site, p, loads);
        FAIL() << "no RunError";
    } catch (const RunError& e) {
        EXPECT_THAT(e.what(), HasSubstr("receptor 77"));
        EXPECT_THAT(e.what(), HasSubstr("ligand 0"));
        EXPECT_THAT(e.what(), HasSubstr("adhesion.max_bond_force"));
    }
}

// ---- kinetics against closed forms ----------------------------------------------------------

TEST(AdhesionKinetics, BondLifetimeIsExponentialWithMeanOneOverKoff) {
    // 20000 bonds at F = 10 pN (k_off = 3.45 exp(10/6.03) = 18 1/s), dt with k_off dt = 0.01.
    // Mean lifetime (K - 1/2) dt within 4 standard errors of 1/k_off (the midpoint bias is
    // (k_off dt)^2 / 12 relative, 1e-5); KS distance below its 0.1% critical value.
    const AdhesionParameters p;
    const real F = 10 * pN, k_off = off_rate(p, F), dt = 0.01 / k_off;
    const std::size_t n = 20000;
    const LifetimeStats s = lifetime_stats(lifetimes(p, n, F, dt, 20240521), k_off, dt);
    const double tau = 1 / k_off, x = k_off * dt;
    EXPECT_NEAR(s.mean, tau, 4 * s.se + tau * x * x / 12) << "rel error " << s.mean / tau - 1;
    EXPECT_LT(std::abs(s.mean / tau - 1), 4 / std::sqrt(static_cast<double>(n)));
    EXPECT_LT(s.ks, 1.95 / std::sqrt(static_cast<double>(n)));
}

TEST(AdhesionKinetics, CatchSlipLifetimeFollowsTheTwoPathwayRate) {
    AdhesionParameters p;
    p.law = DissociationLaw::catch_slip;
    p.catch_rate = 20;
    p.catch_distance = 1.0 * nm;
    p.slip_rate = 0.5;
    p.slip_distance = 0.3 * nm;
    const std::size_t n = 5000;
    for (real F : {0.0, 10 * pN, 40 * pN}) {
        const real k_off = off_rate(p, F), dt = 0.01 / k_off;
        const LifetimeStats s = lifetime_stats(lifetimes(p, n, F, dt, 7), k_off, dt);
        EXPECT_NEAR(s.mean * k_off, 1.0, 4 * s.se * k_off + 1e-4) << "F = " << F;
        EXPECT_LT(s.ks, 1.95 / std::sqrt(static_cast<double>(n))) << "F = " << F;
    }
}

TEST(AdhesionKinetics, EquilibriumBoundFraction) {
    // 1000 receptors, each facing its own ligand at F = 5 pN (k_off = 7.9 1/s), k_on = 10 1/s,
    // all free at t = 0. After a burn-in, 100 samples of the bound count, spaced so that the
    // samples are independent (chain correlation <= 0.005). The fraction is compared with
    // the closed form k_on / (k_on + k_off): within 4 standard errors plus the time-step bias
    // of the discrete chain (its exact fraction is p_on / (p_on + p_off)).
    const AdhesionParameters p;
    const real F = 5 * pN, k_off = off_rate(p, F), dt = 5e-4;
    const std::size_t n = 1000, samples = 100;
    const real p_on = event_probability(p.k_on, dt), p_off = event_probability(k_off, dt);
    const std::uint64_t gap = decorrelation_steps(p_on, p_off, 0.005);
    FacingPairs s = make_facing_pairs(n, length_for(p, F), 1 * um, p.reactive_distance);
    Kinetics kin(p, 31337);
    std::uint64_t step = 0;
    for (; step < 2 * gap; ++step)
        kin.step(s.receptors, s.ligands, step, dt);
    double sum = 0;
    for (std::size_t m = 0; m < samples; ++m) {
        for (std::uint64_t k = 0; k < gap; ++k, ++step)
            kin.step(s.receptors, s.ligands, step, dt);
        sum += static_cast<double>(count_bound(s.receptors));
        ASSERT_EQ(s.ligands.bound_count(), count_bound(s.receptors));
    }
    const double total = static_cast<double>(n * samples), f = sum / total;
    const double f_exact = p.k_on / (p.k_on + k_off), f_chain = p_on / (p_on + p_off);
    const double se = std::sqrt(f_exact * (1 - f_exact) / total);
    EXPECT_NEAR(f, f_exact, 4 * se + std::abs(f_chain - f_exact))
        << "rel error " << f / f_exact - 1;
    EXPECT_NEAR(f, f_chain, 4 * se);
    EXPECT_LT(std::abs(f_chain / f_exact - 1), 0.25 * se / f_exact); // dt bias << noise
}

TEST(AdhesionKinetics, BondCountDistributionIsBinomial) {
    // 20 independent pairs: at equilibrium the master equation gives a bond count
    // Binomial(20, k_on / (k_on + k_off)). 5000 independent samples; chi-square p > 0.001.
    const AdhesionParameters p;
    const real F = 5 * pN, k_off = off_rate(p, F), dt = 5e-4;
    const int n = 20;
    const std::size_t samples = 5000;
    const real p_on = event_probability(p.k_on, dt), p_off = event_probability(k_off, dt);
    const std::uint64_t gap = decorrelation_steps(p_on, p_off, 0.005);
    FacingPairs s = make_facing_pairs(n, length_for(p, F), 1 * um, p.reactive_distance);
    Kinetics kin(p, 4242);
    std::vector<double> observed(n + 1, 0.0), expected(n + 1, 0.0);
    std::uint64_t step = 0;
    for (; step < 2 * gap; ++step)
        kin.step(s.receptors, s.ligands, step, dt);
    for (std::size_t m = 0; m < samples; ++m) {
        for (std::uint64_t k = 0; k < gap; ++k, ++step)
            kin.step(s.receptors, s.ligands, step, dt);
        observed[count_bound(s.receptors)] += 1;
    }
    const double f = p.k_on / (p.k_on + k_off);
    for (int k = 0; k <= n; ++k)
        expected[k] = static_cast<double>(samples) * test::binomial_pmf(n, k, f);
    const test::ChiSquare c = test::chi_square_fit(observed, expected);
    EXPECT_GE(c.dof, 5);
    EXPECT_GT(c.pvalue, 1e-3) << "chi2 = " << c.statistic << ", dof = " << c.dof;
}

// ---- reproducibility ----------------------------------------------------------------------

namespace {

/// A contested scene: 600 receptors 10-90 nm above a 1 um x 1 um vWF patch with 50 nm
/// spacing (400 ligands), most within reach of several ligands; fast kinetics so that
/// bonds form, compete and break every step. Returns, per step, the ligand of every
/// receptor in id order, and the summed stats.
struct Trajectory {
    std::vector<std::vector<std::uint64_t>> states;
    StepStats total;
};

std::vector<Receptor> contested_receptors() {
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> ux(-0.1 * um, 1.1 * um), uz(10 * nm, 90 * nm);
    std::vector<Receptor> rs;
    for (std::uint64_t k = 0; k < 600; ++k)
        rs.push_back({1000 + 7 * k, {ux(gen), uz(gen), ux(gen)}, no_ligand});
    return rs;
}

Trajectory run_contested(std::vector<Receptor> rs, std::uint64_t seed, int steps = 60) {
    AdhesionParameters p;
    p.k_on = 2000;
    p.k_off0 = 300;
    const std::vector<LigandRegion> patch{{{0, 0, 0}, {1 * um, 0, 1 * um}, 50 * nm}};
    LigandSet ls = LigandSet::from_regions(patch, p.reactive_distance);
    Kinetics kin(p, seed);
    Trajectory t;
    for (int step = 0; step < steps; ++step) {
        const StepStats st = kin.step(rs, ls, static_cast<std::uint64_t>(step), 5e-4);
        t.total.formed += st.formed;
        t.total.broken += st.broken;
        t.total.contested += st.contested;
        t.total.examined += st.examined;
        t.total.skipped += st.skipped;
        std::vector<Receptor> sorted = rs;
        std::sort(sorted.begin(), sorted.end(),
                  [](const Receptor& a, const Receptor& b) { return a.id < b.id; });
        std::vector<std::uint64_t> state;
        for (const Receptor& r : sorted) {
            state.push_back(r.ligand);
            if (r.bound()) { // the bond is known to both ends
                EXPECT_EQ(ls.bound_receptor(r.ligand), r.id);
            }
        }
        EXPECT_EQ(ls.bound_count(), count_bound(rs)); // at most one receptor per ligand
        t.states.push_back(std::move(state));
    }
    return t;
}

} // namespace

TEST(AdhesionKinetics, SameSeedSameRunDifferentSeedDifferentRun) {
    const Trajectory a = run_contested(contested_receptors(), 1);
    const Trajectory b = run_contested(contested_receptors(), 1);
    const Trajectory c = run_contested(contested_receptors(), 2);
    EXPECT_GT(a.total.formed, 100u);
    EXPECT_GT(a.total.broken, 50u);
    EXPECT_EQ(a.states, b.states);
    EXPECT_NE(a.states, c.states);
}

TEST(AdhesionKinetics, ReceptorOrderDoesNotMatter) {
    // The same receptors processed in reversed and in shuffled order give the same bonds
    // at every step: what makes the outcome independent of how receptors are split over
    // ranks. The scene is contested (several receptors pick the same ligand).
    std::vector<Receptor> rs = contested_receptors();
    const Trajectory a = run_contested(rs, 9);
    std::reverse(rs.begin(), rs.end());
    const Trajectory b = run_contested(rs, 9);
    std::shuffle(rs.begin(), rs.end(), std::mt19937_64(17));
    const Trajectory c = run_contested(rs, 9);
    EXPECT_GT(a.total.contested, 10u);
    EXPECT_EQ(a.states, b.states);
    EXPECT_EQ(a.states, c.states);
    EXPECT_EQ(a.total.contested, c.total.contested);
}

// ---- skipping what a scene does not need --------------------------------------------------

TEST(AdhesionKinetics, FarReceptorsGetNoWork) {
    AdhesionParameters p;
    p.k_on = 1e6; // would bind at once if in reach
    const std::vector<LigandRegion> patch{{{0, 0, 0}, {1 * um, 0, 1 * um}, 50 * nm}};
    LigandSet ls = LigandSet::from_regions(patch, p.reactive_distance);
    const real skip = p.reactive_distance + p.margin;
    std::vector<Receptor> far, near_miss;
    for (std::uint64_t k = 0; k < 100; ++k) {
        far.push_back({k, {0.5 * um, 2 * um + k * nm, 0.5 * um}, no_ligand});
        // Beyond the reactive distance but inside the margin: examined, never bound.
        near_miss.push_back(
            {k,
             {0.5 * um, p.reactive_distance + 0.5 * (skip - p.reactive_distance), 0.5 * um},
             no_ligand});
    }
    Kinetics kin(p, 1);
    StepStats st = kin.step(far, ls, 0, 1e-3);
    EXPECT_EQ(st.skipped, 100u);
    EXPECT_EQ(st.examined, 0u);
    st = kin.step(near_miss, ls, 0, 1e-3);
    EXPECT_EQ(st.examined, 100u);
    EXPECT_EQ(st.formed, 0u);
    // The body-level test: a platelet's bounding box 1 um above the patch is skipped whole.
    EXPECT_FALSE(ls.may_reach_box({0, 1 * um, 0}, {2 * um, 3 * um, 2 * um}, skip));
    EXPECT_TRUE(ls.may_reach_box({0, 0.1 * um, 0}, {2 * um, 3 * um, 2 * um}, skip));
}

TEST(AdhesionKinetics, SceneWithoutAdhesionAllocatesNothing) {
    std::vector<Receptor> rs(50); // the receptors exist already (allocated before counting)
    std::vector<BondLoad> loads;
    StepStats st{};
    bool empty = false;
    const long before = g_allocations.load();
    {
        LigandSet none; // no ligand regions
        const LigandSet also_none = LigandSet::from_regions({}, 70 * nm);
        Kinetics kin(AdhesionParameters{}, 5);
        for (std::uint64_t step = 0; step < 10; ++step)
            st = kin.step(rs, none, step, 1e-4);
        bond_loads(rs, none, kin.parameters(), loads); // no bonds: nothing appended
        empty = also_none.empty() && none.empty();
    }
    const long allocated = g_allocations.load() - before;
    EXPECT_EQ(allocated, 0);
    EXPECT_TRUE(empty);
    EXPECT_EQ(st.skipped, 50u);
    EXPECT_TRUE(loads.empty());
}

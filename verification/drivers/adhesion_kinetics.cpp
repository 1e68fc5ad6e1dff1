// efsi_adhesion_kinetics: the adhesion kinetics alone (solver/adhesion), for the
// platelet_adhesion study. Receptors facing their own ligands at a fixed bond length, so
// every bond carries a constant force and the pairs are independent (facing_pairs.hpp).
//
//   lifetime     n pre-formed bonds under force F, no rebinding: the lifetime of each
//                bond in steps -> CSV column lifetime_steps
//   equilibrium  N free receptors binding and unbinding: the bound count at every step of
//                a relaxation from all-free (CSV relaxation: step, t_s, bound) and then M
//                samples spaced by `gap` steps so that they are independent
//                (CSV samples: sample, bound)
// All inputs and outputs in SI units. Prints one JSON object with the rates used.
#include "adhesion/dissociation.hpp"
#include "adhesion/facing_pairs.hpp"
#include "adhesion/kinetics.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace efsi;
using namespace efsi::adhesion;

namespace {

std::size_t count_bound(const std::vector<Receptor>& rs) {
    return static_cast<std::size_t>(
        std::count_if(rs.begin(), rs.end(), [](const Receptor& r) { return r.bound(); }));
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Platelet-adhesion kinetics alone, against closed forms (verification)"};
    app.require_subcommand(1);
    AdhesionParameters p;
    std::string law = "bell", csv, relaxation_csv;
    double force = 10e-12, rate_dt = 0.01, dt = 5e-4, rho = 0.005;
    std::uint64_t seed = 1;
    std::size_t n = 10000, samples = 1000;
    for (CLI::App* sub : {app.add_subcommand("lifetime", "bond lifetimes under constant force"),
                          app.add_subcommand("equilibrium", "bound count at equilibrium")}) {
        sub->add_option("--force", force, "bond force F [N]");
        sub->add_option("--seed", seed, "random seed");
        sub->add_option("--k-on", p.k_on, "forward rate [1/s]");
        sub->add_option("--k-off0", p.k_off0, "unstressed off rate [1/s]");
        sub->add_option("--law", law, "bell or catch_slip")
            ->check(CLI::IsMember({"bell", "catch_slip"}));
        sub->add_option("--catch-rate", p.catch_rate, "catch pathway rate [1/s]");
        sub->add_option("--catch-distance", p.catch_distance, "catch pathway distance [m]");
        sub->add_option("--slip-rate", p.slip_rate, "slip pathway rate [1/s]");
        sub->add_option("--slip-distance", p.slip_distance, "slip pathway distance [m]");
        sub->add_option("--csv", csv, "output CSV")->required();
    }
    CLI::App* life = app.get_subcommand("lifetime");
    life->add_option("--bonds", n, "number of bonds");
    life->add_option("--rate-dt", rate_dt, "k_off(F) dt, sets the time step");
    CLI::App* eq = app.get_subcommand("equilibrium");
    eq->add_option("--receptors", n, "number of receptor-ligand pairs");
    eq->add_option("--samples", samples, "independent samples of the bound count");
    eq->add_option("--dt", dt, "time step [s]");
    eq->add_option("--rho", rho, "chain correlation left between samples");
    eq->add_option("--relaxation-csv", relaxation_csv, "bound count during the burn-in");
    CLI11_PARSE(app, argc, argv);
    p.law = law == "bell" ? DissociationLaw::bell : DissociationLaw::catch_slip;

    try {
        const real k_off = off_rate(p, force);
        const real length = p.bond_rest_length + force / p.bond_stiffness;
        auto out = fmt::output_file(csv);
        if (life->parsed()) {
            p.k_on = 0;
            dt = rate_dt / k_off;
            FacingPairs s = make_facing_pairs(n, length, 1e-6, p.reactive_distance, true);
            Kinetics kin(p, seed);
            // Broken bonds leave the list: with k_on = 0 they never rebind, and the order of
            // the others does not matter to the kinetics.
            std::vector<std::uint64_t> lifetime(n, 0);
            for (std::uint64_t step = 0; !s.receptors.empty(); ++step) {
                kin.step(s.receptors, s.ligands, step, dt);
                std::erase_if(s.receptors, [&](const Receptor& r) {
                    if (r.bound()) return false;
                    lifetime[r.id] = step + 1;
                    return true;
                });
            }
            out.print("lifetime_steps\n");
            for (auto k : lifetime)
                out.print("{}\n", k);
            fmt::print("{{\"mode\": \"lifetime\", \"law\": \"{}\", \"force_N\": {:.17g}, "
                       "\"k_off\": {:.17g}, \"dt\": {:.17g}, \"bonds\": {}, \"seed\": {}}}\n",
                       law, force, k_off, dt, n, seed);
            return 0;
        }
        const real p_on = event_probability(p.k_on, dt), p_off = event_probability(k_off, dt);
        const auto gap =
            static_cast<std::uint64_t>(std::ceil(std::log(rho) / std::log1p(-(p_on + p_off))));
        FacingPairs s = make_facing_pairs(n, length, 1e-6, p.reactive_distance);
        Kinetics kin(p, seed);
        std::uint64_t step = 0;
        std::string relax = "step,t_s,bound\n";
        relax += "0,0,0\n";
        for (; step < 2 * gap; ++step) {
            kin.step(s.receptors, s.ligands, step, dt);
            relax += fmt::format("{},{:.10g},{}\n", step + 1, dt * static_cast<real>(step + 1),
                                 count_bound(s.receptors));
        }
        out.print("sample,bound\n");
        for (std::size_t m = 0; m < samples; ++m) {
            for (std::uint64_t k = 0; k < gap; ++k, ++step)
                kin.step(s.receptors, s.ligands, step, dt);
            out.print("{},{}\n", m, count_bound(s.receptors));
        }
        if (!relaxation_csv.empty()) {
            auto r = fmt::output_file(relaxation_csv);
            r.print("{}", relax);
        }
        fmt::print("{{\"mode\": \"equilibrium\", \"law\": \"{}\", \"force_N\": {:.17g}, "
                   "\"k_on\": {:.17g}, \"k_off\": {:.17g}, \"dt\": {:.17g}, \"p_on\": {:.17g}, "
                   "\"p_off\": {:.17g}, \"gap_steps\": {}, \"receptors\": {}, \"samples\": {}, "
                   "\"seed\": {}}}\n",
                   law, force, p.k_on, k_off, dt, p_on, p_off, gap, n, samples, seed);
    } catch (const std::exception& e) {
        fmt::print(stderr, "efsi_adhesion_kinetics: {}\n", e.what());
        return 1;
    }
    return 0;
}

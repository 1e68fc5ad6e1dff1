// efsi_membrane_constitutive_study: a flat membrane (normal e_z) stretched by lambda1 along
// x with the lateral tension T2 = 0, through the solver's law objects, against the closed
// forms of MODEL.md "Constitutive checks". Gs = diag(lambda1^2, lambda2^2, 0) = F P_R F^T
// with P_R = diag(1, 1, 0); lambda2 is found by bisection on tau_yy(lambda2) = 0.
// Moduli in units of the small-strain shear modulus Gs = 1: neo-Hookean Es = 3,
// Skalak Es = 3/2 (Es/6 = Gs/4) and alpha = C.
// Prints one JSON object: arrays e = (lambda1^2 - 1)/2, lambda2 and T1 (numeric and closed
// form), and the largest relative errors of the solve and of the law itself.
#include "membrane/membrane_law.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <cmath>
#include <vector>

using namespace efsi;

namespace {

Matrix3 flat_tension(const MembraneLaw& law, real l1, real l2) {
    Matrix3 Gs{};
    Gs[0][0] = l1 * l1;
    Gs[1][1] = l2 * l2;
    return law.tension(membrane_kinematics({0, 0, 1}, Gs));
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Uniaxial stretch of a flat membrane against closed forms (verification)"};
    std::string law_name = "neo_hookean";
    real alpha = 1, lambda_max = 2.2;
    int points = 200;
    app.add_option("--law", law_name, "neo_hookean or skalak")
        ->check(CLI::IsMember({"neo_hookean", "skalak"}));
    app.add_option("--alpha", alpha, "Skalak's C");
    app.add_option("--lambda-max", lambda_max, "largest lambda1");
    app.add_option("--points", points, "number of lambda1 values");
    CLI11_PARSE(app, argc, argv);
    const bool neo = law_name == "neo_hookean";
    const real Gs = 1, Es = neo ? 3 * Gs : 1.5 * Gs;
    const auto law = make_membrane_law(law_name, Es, alpha);

    std::vector<real> e, l2_num, l2_exact, t1_num, t1_exact;
    real err_solve = 0, err_law = 0, err_t2 = 0;
    for (int m = 0; m < points; ++m) {
        const real l1 = 1 + (lambda_max - 1) * m / (points - 1);
        // Closed forms.
        const real l2x = neo ? std::pow(l1, -0.5)
                             : std::sqrt((1 + alpha * l1 * l1) / (1 + alpha * l1 * l1 * l1 * l1));
        const real Jx = l1 * l2x;
        const real t1x =
            neo ? Gs * (l1 * l1 * l1 - 1) / std::pow(l1, 1.5)
                : Gs / Jx * (l1 * l1 * (l1 * l1 - 1) + alpha * Jx * Jx * (Jx * Jx - 1));
        // T2 = 0 by bisection: tau_yy > 0 at lambda2 = 1 (stretched in 1, so I_s, J > 1)
        // and < 0 as lambda2 -> 0.
        real lo = 1e-3, hi = 1.0;
        for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
            const real mid = 0.5 * (lo + hi);
            (flat_tension(*law, l1, mid)[1][1] > 0 ? hi : lo) = mid;
        }
        const real l2 = 0.5 * (lo + hi);
        const real t1 = flat_tension(*law, l1, l2)[0][0];
        // The law itself at the closed-form lambda2.
        const Matrix3 tx = flat_tension(*law, l1, l2x);
        const real scale = std::max(std::abs(t1x), Gs * 1e-3);
        err_solve = std::max({err_solve, std::abs(t1 - t1x) / scale, std::abs(l2 - l2x)});
        err_law = std::max(err_law, std::abs(tx[0][0] - t1x) / std::max(std::abs(t1x), Gs));
        err_t2 = std::max(err_t2, std::abs(tx[1][1]) / std::max(std::abs(t1x), Gs));
        e.push_back((l1 * l1 - 1) / 2);
        l2_num.push_back(l2);
        l2_exact.push_back(l2x);
        t1_num.push_back(t1 / Gs);
        t1_exact.push_back(t1x / Gs);
    }
    fmt::print("{{\"law\": \"{}\", \"alpha\": {}, \"strain\": [{:.17g}], \"lambda2\": [{:.17g}], "
               "\"lambda2_exact\": [{:.17g}], \"T1\": [{:.17g}], \"T1_exact\": [{:.17g}], "
               "\"max_rel_error_solve\": {:.3e}, \"max_rel_error_law\": {:.3e}, "
               "\"max_rel_T2_law\": {:.3e}}}\n",
               law_name, alpha, fmt::join(e, ", "), fmt::join(l2_num, ", "),
               fmt::join(l2_exact, ", "), fmt::join(t1_num, ", "), fmt::join(t1_exact, ", "),
               err_solve, err_law, err_t2);
    return 0;
}

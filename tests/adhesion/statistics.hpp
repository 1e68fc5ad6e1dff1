// Small statistics for the adhesion tests: the chi-square survival function (p-value) via
// the regularized upper incomplete gamma function, binomial probabilities, and the
// chi-square goodness-of-fit of observed counts to expected ones with sparse bins merged.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace efsi::test {

/// Regularized upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a): the series of
/// P(a, x) for x < a + 1, else the continued fraction (modified Lentz).
inline double gamma_q(double a, double x) {
    if (x <= 0) return 1.0;
    const double lg = std::lgamma(a);
    if (x < a + 1) {
        double sum = 1.0 / a, term = sum;
        for (int n = 1; n < 1000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-16) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - lg);
    }
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 1000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - lg) * h;
}

/// P(chi^2_dof >= x).
inline double chi_square_pvalue(double x, int dof) {
    return gamma_q(0.5 * dof, 0.5 * x);
}

inline double binomial_pmf(int n, int k, double p) {
    return std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) +
                    k * std::log(p) + (n - k) * std::log1p(-p));
}

struct ChiSquare {
    double statistic = 0;
    int dof = 0;
    double pvalue = 0;
};

/// Goodness of fit of `observed` counts to `expected` ones (same total), merging adjacent
/// bins from both ends until each merged bin expects at least `min_expected`; no fitted
/// parameters, so dof = bins - 1.
inline ChiSquare chi_square_fit(const std::vector<double>& observed,
                                const std::vector<double>& expected, double min_expected = 5) {
    if (observed.size() != expected.size())
        throw std::invalid_argument("chi_square_fit: sizes differ");
    std::vector<double> o, e;
    double so = 0, se = 0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        so += observed[i];
        se += expected[i];
        if (se >= min_expected) {
            o.push_back(so);
            e.push_back(se);
            so = se = 0;
        }
    }
    if (!e.empty()) { // the sparse tail joins the last bin
        o.back() += so;
        e.back() += se;
    }
    ChiSquare r;
    for (std::size_t i = 0; i < o.size(); ++i)
        r.statistic += (o[i] - e[i]) * (o[i] - e[i]) / e[i];
    r.dof = static_cast<int>(o.size()) - 1;
    r.pvalue = r.dof > 0 ? chi_square_pvalue(r.statistic, r.dof) : 1.0;
    return r;
}

} // namespace efsi::test

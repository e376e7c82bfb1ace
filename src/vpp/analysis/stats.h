// Ensemble statistics of a study: the mean of a quantity over seeds (realisations of the random
// packing) with its 95% confidence interval (docs/studies.md, "Ensembles").
//
// The interval is Student's: mean +- t_{0.975, n-1} s / sqrt(n), s the sample standard deviation
// (n - 1 in the denominator). It assumes the realisations are independent and roughly normal;
// with n = 2 or 3 seeds t is large (12.7, 4.30), so a few seeds give wide but honest intervals.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace vpp {

// Quantile of Student's t distribution with `dof` degrees of freedom (dof >= 1, any real):
// the t with P(T <= t) = p, for p in (0, 1). t_{0.975, 1} = 12.7062, t_{0.975, 4} = 2.7764,
// t_{0.975, inf} = 1.95996. Throws std::invalid_argument outside the domain.
double student_t_quantile(double p, double dof);

// Regularised incomplete beta function I_x(a, b), x in [0, 1], a, b > 0 (for the t distribution).
double incomplete_beta(double x, double a, double b);

struct Interval {
    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    std::size_t n = 0;    // finite values used
    double mean = kNaN;   // NaN when n = 0
    double sd = kNaN;     // sample standard deviation (n - 1); NaN when n < 2
    double half = kNaN;   // half width of the interval: t_{(1+c)/2, n-1} sd / sqrt(n); NaN when n < 2
    double low() const { return mean - half; }
    double high() const { return mean + half; }
};

// Mean and confidence interval (default 95%) of the finite values of x (NaN and inf are left
// out: a failed run or a quantity a run does not have).
Interval mean_interval(const std::vector<double>& x, double confidence = 0.95);

// Two intervals overlap (share at least one point). An interval without width (n < 2) is its
// mean alone.
bool overlaps(const Interval& a, const Interval& b);

}  // namespace vpp

#include "vpp/analysis/stats.h"

#include <cmath>
#include <stdexcept>

namespace vpp {

namespace {

// Continued fraction of the incomplete beta function (modified Lentz), valid for
// x < (a + 1) / (a + b + 2); the caller uses the symmetry I_x(a, b) = 1 - I_{1-x}(b, a) otherwise.
double beta_continued_fraction(double x, double a, double b) {
    const double tiny = 1e-300, eps = 1e-15;
    double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m <= 10000; ++m) {
        const double m2 = 2.0 * m;
        // Even step: d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)).
        double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
        d = 1.0 + aa * d;
        if (std::abs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        h *= d * c;
        // Odd step: d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)).
        aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
        d = 1.0 + aa * d;
        if (std::abs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < eps) break;
    }
    return h;
}

}  // namespace

double incomplete_beta(double x, double a, double b) {
    if (!(a > 0 && b > 0) || !(x >= 0 && x <= 1)) throw std::invalid_argument("incomplete_beta: x in [0, 1], a, b > 0");
    if (x == 0.0 || x == 1.0) return x;
    const double lbeta = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b);
    const double front = std::exp(lbeta + a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_continued_fraction(x, a, b) / a;
    return 1.0 - front * beta_continued_fraction(1.0 - x, b, a) / b;
}

double student_t_quantile(double p, double dof) {
    if (!(p > 0 && p < 1)) throw std::invalid_argument("student_t_quantile: p must be in (0, 1)");
    if (!(dof >= 1) || !std::isfinite(dof)) throw std::invalid_argument("student_t_quantile: dof must be >= 1");
    if (p == 0.5) return 0.0;
    if (p < 0.5) return -student_t_quantile(1.0 - p, dof);
    // P(T > t) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2) / 2, decreasing in t: bisection on
    // [0, hi], hi doubled until the tail is below 1 - p. 200 halvings reach round-off.
    const double tail = 1.0 - p;
    auto upper = [&](double t) { return 0.5 * incomplete_beta(dof / (dof + t * t), 0.5 * dof, 0.5); };
    double lo = 0.0, hi = 1.0;
    while (upper(hi) > tail) {
        lo = hi;
        hi *= 2.0;
        if (hi > 1e300) throw std::invalid_argument("student_t_quantile: p too close to 1");
    }
    for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
        const double mid = 0.5 * (lo + hi);
        (upper(mid) > tail ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

Interval mean_interval(const std::vector<double>& x, double confidence) {
    if (!(confidence > 0 && confidence < 1)) throw std::invalid_argument("mean_interval: confidence must be in (0, 1)");
    Interval r;
    double sum = 0;
    for (double v : x)
        if (std::isfinite(v)) {
            sum += v;
            ++r.n;
        }
    if (r.n == 0) return r;
    r.mean = sum / double(r.n);
    if (r.n < 2) return r;
    double ss = 0;
    for (double v : x)
        if (std::isfinite(v)) ss += (v - r.mean) * (v - r.mean);
    r.sd = std::sqrt(ss / double(r.n - 1));
    r.half = student_t_quantile(0.5 * (1.0 + confidence), double(r.n - 1)) * r.sd / std::sqrt(double(r.n));
    return r;
}

bool overlaps(const Interval& a, const Interval& b) {
    auto lo = [](const Interval& i) { return std::isfinite(i.half) ? i.low() : i.mean; };
    auto hi = [](const Interval& i) { return std::isfinite(i.half) ? i.high() : i.mean; };
    return lo(a) <= hi(b) && lo(b) <= hi(a);
}

}  // namespace vpp

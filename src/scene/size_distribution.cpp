#include "scene/size_distribution.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "dem/io/csv.h"

namespace scene {

namespace {

constexpr double kTrunc = 3.0;  // lognormal: truncation at kTrunc standard deviations of ln r

// A uniform double in [0, 1) from the generator's top 53 bits (the same on every platform).
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1p-53; }

double phi(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }  // standard normal CDF

// The normal quantile by bisection on the CDF: exact to the last bits the CDF resolves, and a pure
// function of u (no platform's inverse-erf).
double normal_quantile(double u) {
    double lo = -kTrunc - 1.0, hi = kTrunc + 1.0;
    for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo + hi);
        (phi(mid) < u ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Lognormal: location mu of ln r so that the truncated mean is `radius`. For ln r ~ N(mu, s^2)
// cut at mu +- k s: E[r^m] = exp(m mu + m^2 s^2 / 2) (Phi(k - m s) - Phi(-k - m s)) / (Phi(k) - Phi(-k)).
double truncated_moment_factor(double s, int m) {
    return std::exp(0.5 * m * m * s * s) * (phi(kTrunc - m * s) - phi(-kTrunc - m * s)) / (phi(kTrunc) - phi(-kTrunc));
}
double lognormal_mu(double radius, double s) { return std::log(radius / truncated_moment_factor(s, 1)); }

// Sieve: the number weight of each class (mass fraction over the mean volume of its radii).
std::vector<double> class_weights(const SizeDistribution& d) {
    std::vector<double> w;
    for (std::size_t k = 0; k + 1 < d.sieve_radius.size(); ++k) {
        const double a = d.sieve_radius[k], b = d.sieve_radius[k + 1];
        const double mass = d.sieve_passing[k + 1] - d.sieve_passing[k];
        const double r3 = (b * b * b * b - a * a * a * a) / (4.0 * (b - a));  // mean r^3, r uniform on [a, b]
        w.push_back(mass / r3);
    }
    return w;
}

}  // namespace

double SizeDistribution::min_radius() const {
    switch (kind) {
        case Kind::Single: return radius;
        case Kind::Uniform: return radius * (1.0 - spread);
        case Kind::Lognormal: return std::exp(lognormal_mu(radius, spread) - kTrunc * spread);
        case Kind::Sieve: {
            for (std::size_t k = 0; k + 1 < sieve_passing.size(); ++k)
                if (sieve_passing[k + 1] > sieve_passing[k]) return sieve_radius[k];
            return sieve_radius.front();
        }
    }
    return radius;
}

double SizeDistribution::max_radius() const {
    switch (kind) {
        case Kind::Single: return radius;
        case Kind::Uniform: return radius * (1.0 + spread);
        case Kind::Lognormal: return std::exp(lognormal_mu(radius, spread) + kTrunc * spread);
        case Kind::Sieve: {
            for (std::size_t k = sieve_passing.size() - 1; k > 0; --k)
                if (sieve_passing[k] > sieve_passing[k - 1]) return sieve_radius[k];
            return sieve_radius.back();
        }
    }
    return radius;
}

double SizeDistribution::mean_radius() const {
    if (kind != Kind::Sieve) return radius;
    const std::vector<double> w = class_weights(*this);
    double n = 0, sum = 0;
    for (std::size_t k = 0; k < w.size(); ++k) {
        n += w[k];
        sum += w[k] * 0.5 * (sieve_radius[k] + sieve_radius[k + 1]);
    }
    return sum / n;
}

double SizeDistribution::mean_volume() const {
    constexpr double c = 4.0 / 3.0 * std::numbers::pi;
    switch (kind) {
        case Kind::Single: return c * radius * radius * radius;
        case Kind::Uniform: {
            const double a = radius * (1.0 - spread), b = radius * (1.0 + spread);
            return spread == 0.0 ? c * radius * radius * radius : c * (b * b * b * b - a * a * a * a) / (4.0 * (b - a));
        }
        case Kind::Lognormal: return c * std::exp(3.0 * lognormal_mu(radius, spread)) * truncated_moment_factor(spread, 3);
        case Kind::Sieve: {
            const std::vector<double> w = class_weights(*this);
            double n = 0, mass = 0;
            for (std::size_t k = 0; k < w.size(); ++k) {
                n += w[k];
                mass += sieve_passing[k + 1] - sieve_passing[k];
            }
            return c * mass / n;
        }
    }
    return 0.0;
}

double SizeDistribution::draw(std::mt19937_64& rng) const {
    switch (kind) {
        case Kind::Single: return radius;
        case Kind::Uniform: return radius * (1.0 + spread * (2.0 * unit(rng) - 1.0));
        case Kind::Lognormal: {
            // Inverse CDF of the truncated normal: u mapped onto [Phi(-k), Phi(k)].
            const double lo = phi(-kTrunc), hi = phi(kTrunc);
            const double z = normal_quantile(lo + (hi - lo) * unit(rng));
            return std::exp(lognormal_mu(radius, spread) + spread * std::clamp(z, -kTrunc, kTrunc));
        }
        case Kind::Sieve: {
            const std::vector<double> w = class_weights(*this);
            double total = 0;
            for (double x : w) total += x;
            double u = unit(rng) * total;
            std::size_t k = 0;
            while (k + 1 < w.size() && (w[k] == 0.0 || u >= w[k])) {
                u -= w[k];
                ++k;
            }
            while (k > 0 && w[k] == 0.0) --k;  // rounding left u beyond the last class with grains
            const double a = sieve_radius[k], b = sieve_radius[k + 1];
            return a + (b - a) * unit(rng);
        }
    }
    return radius;
}

SizeDistribution SizeDistribution::sieve_curve(const std::string& path) {
    const auto rows = dem::read_numeric_csv(path, 2);
    const auto bad = [&](const std::string& what) {
        throw std::runtime_error("sieve curve '" + path + "': " + what);
    };
    if (rows.size() < 2) bad("has " + std::to_string(rows.size()) + " row(s); at least two sieves (size, passing) are needed");
    SizeDistribution d;
    d.kind = Kind::Sieve;
    const double scale = rows.back()[1] > 1.0 + 1e-9 ? 0.01 : 1.0;  // percent
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const double size = rows[k][0], pass = rows[k][1] * scale;
        const std::string row = "row " + std::to_string(k + 1);
        if (!(size > 0.0) || !std::isfinite(size)) bad(row + ": size " + dem::csv_number(size) + " must be a sieve opening > 0 m");
        if (!(pass >= 0.0 && pass <= 1.0)) bad(row + ": passing " + dem::csv_number(rows[k][1]) + " must be in [0, 1] (or [0, 100] %)");
        if (k > 0 && !(size > d.sieve_radius.back() * 2.0)) bad(row + ": sizes must ascend");
        if (k > 0 && pass < d.sieve_passing.back()) bad(row + ": passing must not decrease with size");
        d.sieve_radius.push_back(0.5 * size);
        d.sieve_passing.push_back(pass);
    }
    const double p0 = d.sieve_passing.front(), p1 = d.sieve_passing.back();
    if (!(p1 > p0)) bad("passing does not rise from the first sieve to the last");
    // What passes the smallest sieve (the pan) has no size in the curve: the curve is taken from
    // the smallest sieve up, normalised to 0 ... 1.
    for (double& p : d.sieve_passing) p = (p - p0) / (p1 - p0);
    // Not silent: the mass below the smallest sieve and above the largest is not drawn.
    if (p0 > 1e-9 || p1 < 1.0 - 1e-9) {
        char b[320];
        std::snprintf(b, sizeof b, "sieve curve '%s' runs from %.4g%% to %.4g%% passing, not 0 to 100%%: the %.4g%% "
                      "below its smallest sieve and the %.4g%% above its largest are left out, the rest renormalised",
                      path.c_str(), 100.0 * p0, 100.0 * p1, 100.0 * p0, 100.0 * (1.0 - p1));
        d.sieve_note = b;
    }
    d.radius = d.mean_radius();
    return d;
}

SizeStats size_stats(const std::vector<double>& radii) {
    SizeStats s;
    s.count = radii.size();
    if (radii.empty()) return s;
    std::vector<double> r = radii;
    std::sort(r.begin(), r.end());
    double sum = 0, vol = 0;
    for (double x : r) {
        sum += x;
        vol += x * x * x;
    }
    s.mean = sum / double(r.size());
    double sq = 0;
    for (double x : r) sq += (x - s.mean) * (x - s.mean);
    s.sd = r.size() > 1 ? std::sqrt(sq / double(r.size() - 1)) : 0.0;
    s.min = r.front();
    s.max = r.back();
    // Volume-weighted quantiles of the diameter: the first grain at which the volume below
    // reaches the fraction.
    double below = 0;
    double* out[3] = {&s.d10, &s.d50, &s.d90};
    const double q[3] = {0.1, 0.5, 0.9};
    int next = 0;
    for (double x : r) {
        below += x * x * x;
        while (next < 3 && below >= q[next] * vol) *out[next++] = 2.0 * x;
    }
    while (next < 3) *out[next++] = 2.0 * r.back();
    return s;
}

}  // namespace scene

// Grain size distributions: the radii of a granulate drawn from a seeded stream. Real VPP fillings
// are pellets, rice-like grains or recycled granulate of many sizes; this is how a scene or a
// damper gets them. Four kinds:
//   Single     every grain has the mean radius (the paper; draws nothing from the stream)
//   Uniform    radii uniform in [r (1 - s), r (1 + s)], s = spread < 1
//   Lognormal  ln r normal with standard deviation s = spread, truncated at 3 s around its mean,
//              its location chosen so that the truncated distribution's mean radius is r
//   Sieve      a measured sieve curve: mass (volume) fraction passing at each sieve opening
//              (a diameter); within each class the radii are uniform, and the classes are drawn
//              by number so that the drawn volume follows the curve
// `mean_radius()` is the number mean of every kind (for Sieve, the curve's), `mean_volume()` the
// mean grain volume, from which a fill's grain count follows.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace scene {

struct SizeDistribution {
    // Numbered: the damper's checkpoints and records store the number (grains.radius_distribution).
    enum class Kind : int { Single = 0, Uniform = 1, Lognormal = 2, Sieve = 3 };
    Kind kind = Kind::Single;
    double radius = 0;                    // [m] Single, Uniform, Lognormal: the number-mean radius
    double spread = 0;                    // [-] Uniform: half-width over mean; Lognormal: sd of ln r
    std::vector<double> sieve_radius;     // [m] Sieve: half the sieve openings, ascending
    std::vector<double> sieve_passing;    // [-] Sieve: mass fraction finer, ascending (normalised to 0 ... 1)
    // Sieve: what the normalisation left out (a curve not from 0 to 100%), as a warning; empty
    // when the curve spans 0 ... 100%.
    std::string sieve_note;

    double min_radius() const;            // [m] smallest radius that can be drawn
    double max_radius() const;            // [m] largest
    double mean_radius() const;           // [m] number mean
    double mean_volume() const;           // [m^3] mean of 4/3 pi r^3 by number
    // One radius [m] from the stream: the same sequence for the same stream state on every machine
    // (the draws use only the generator's integers, converted here, not std:: distributions, whose
    // algorithms differ between standard libraries).
    double draw(std::mt19937_64& rng) const;

    // Sieve curve from a CSV file: columns size (the sieve opening, a diameter [m]) and passing
    // (mass fraction finer [-], or percent when the last value is 100); rows ascending in size,
    // passing not decreasing, at least two rows, the last passing above the first. Throws
    // std::runtime_error naming the file, the row and what is allowed.
    static SizeDistribution sieve_curve(const std::string& path);
};

// What was drawn: count and radii statistics, for a run's summary.
struct SizeStats {
    std::size_t count = 0;
    double mean = 0, sd = 0, min = 0, max = 0;  // [m] number statistics of the radius
    double d10 = 0, d50 = 0, d90 = 0;           // [m] diameters below which 10, 50, 90% of the volume lies
};
SizeStats size_stats(const std::vector<double>& radii);

}  // namespace scene

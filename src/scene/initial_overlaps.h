// Initial overlaps of a scene: spheres that start inside each other or inside a wall.
//
// Why a scene refuses them: the linear contact law turns an overlap into a force kn * overlap at
// the first step, with nothing to hold it back, so two identical centres or a sphere half inside
// a floor throws spheres out at thousands of m/s (1,800-3,900 m/s seen) while the run goes on
// and ends with exit 0. Overlaps up to a small tolerance (a packing written to a few digits
// touches slightly) are normal and allowed.
//
// Only pairs that can interact count, by the World's rules: masks sharing a bit; two spheres not
// both immobile (fixed or prescribed); not two members of one clump; a fixed sphere touches no
// wall. A two-sided plane
// overlaps a sphere by r - |s| (s the signed distance of its centre), a one-sided plane by r - s
// (a centre behind it is pushed back out), a facet by r - distance to the triangle (one-sided:
// only a centre on its +normal side).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/world/world.h"

namespace scene {

struct Overlap {
    uint32_t a = 0;           // sphere index (the smaller one of a pair)
    uint32_t b = 0;           // the other sphere, or the World wall index (planes, then facets)
    bool wall = false;        // b is a wall
    double overlap = 0;       // [m]
    double fraction = 0;      // overlap / the smaller radius (the sphere's radius for a wall)
};

struct OverlapReport {
    std::size_t count = 0;    // pairs beyond the tolerance
    Overlap worst;            // the largest fraction among them (ties: the lowest indices)
};

// Sphere pairs of `w` at their current positions overlapping by more than tolerance times the
// smaller radius. Sort-based cell binning (cells of two median radii; a sphere goes into every
// cell its box touches; a pair is tested in the cell of the low corner of the boxes' overlap
// only), so similar radii cost O(N log N); a sphere much larger than the cells is tested
// against all the others instead.
OverlapReport sphere_overlaps(const dem::World& w, double tolerance);

// Sphere-wall pairs beyond tolerance times the sphere's radius, walls at t = 0.
OverlapReport wall_overlaps(const dem::World& w, double tolerance);

}  // namespace scene

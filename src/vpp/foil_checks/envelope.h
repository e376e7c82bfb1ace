// `vppdem envelope`: the paper's sanity check of the pressure model, an empty foil cylinder
// with fixed end rings under a ramped underpressure (section 4.1, Fig. 4).
#pragma once

#include <string>

#include "vpp/settings/config.h"

namespace vpp {

struct EnvelopeResult {
    double radius = 0;              // [m] chosen site-circle radius
    int columns = 0, rows = 0;
    std::size_t particles = 0, bonds = 0, pressure_nodes = 0;
    double initial_volume = 0;      // [m^3]
    double final_volume_ratio = 0;  // [-]
    double min_gap = 0;             // [r_f] smallest non-bonded gap over the run
    double final_kinetic_energy = 0;  // [J]
    double peak_kinetic_energy = 0;   // [J]
    // Translational part: after the collapse the residual kinetic energy is almost all free
    // spin of foil particles about their bond axes, which no force or torque resists (and so
    // no local damping removes); the membrane itself is at rest.
    double final_translational_energy = 0;  // [J]
    double peak_translational_energy = 0;   // [J]
    double max_radial_excursion = 0;  // [m] largest distance of a foil particle from the axis
    double dt = 0;
    uint64_t steps = 0;
};

EnvelopeResult run_envelope(const Config& c, const std::string& out_dir, bool quiet);

}  // namespace vpp

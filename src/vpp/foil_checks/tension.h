// `vppdem tension`: the paper's uniaxial strip test of the foil model (section 3.2).
#pragma once

#include <string>

#include "vpp/settings/config.h"

namespace vpp {

struct TensionResult {
    double effective_modulus = 0;  // [Pa] slope F/eps divided by t_f * w
    double target_modulus = 0;     // [Pa] E_f
    double particle_modulus = 0;   // [Pa] E_s
    double stiffness = 0;          // [N] slope dF/d(eps)
    double width = 0;              // [m] w = sites_across * 2 r_f
    double length = 0;             // [m] between the fixed and the pulled column centres
    double dt = 0;                 // [s]
    uint64_t steps = 0;
    std::size_t particles = 0, bonds = 0;
};

// Runs the test; writes DIR/tension.csv (strain,force) and DIR/summary.json when out_dir is
// not empty.
TensionResult run_tension(const Config& c, const std::string& out_dir, bool quiet);

}  // namespace vpp

// The air inside a membrane built from a mesh (vpp/membrane/membrane.h): the damper's air model
// (vpp/membrane/gas.h, docs/damper.md "The air inside") on the membrane's enclosed volume, for devices.
//
// The gas fills the membrane's enclosure less the solids inside it (grains, tools):
//   V_gas = enclosed_volume(membrane) - solids.
// Constant model: dp is held at the set value (the paper's; the gas is at p_atm - dp).
// Pump model: the gas is sealed at the atmosphere's pressure at the first step, then leaks,
// is pumped down or bled through the regulator (vpp::advance_gas), and dp = p_atm - amount / V_gas.
// The gas's work on its boundary is summed in both (isothermal in the pump model).
//
// A copy of the damper stage's air_step rules (vpp/damper/stages.cpp) rather than a call into
// it: the damper's code path stays bit for bit as it is, and a device has no damper run.
#pragma once

#include "dem/world/world.h"
#include "vpp/membrane/gas.h"
#include "vpp/membrane/membrane.h"

namespace vpp {

struct MembraneGas {
    double amount = 0.0;  // [Pa m^3] p V of the gas; 0 until sealed
    double volume = 0.0;  // [m^3] V_gas at the last step; 0 before the first
    double work = 0.0;    // [J] work done by the gas on its boundary since the first step
};

struct MembraneAirDef {
    PressureModel model = PressureModel::Constant;
    PumpLine line;                // speed, bleed, leak [m^3/s], p_atm [Pa]; p_set is set from dp_set
    bool hold_at_set = false;     // pump model: hold the gas at the set point (an evacuation along a ramp)
};

// One step of the air after w.step() (or before the next compute_forces()): updates `g` from the
// membrane's current enclosure and sets w.pressure.dp. `solids` [m^3] is the volume of what the
// membrane holds, dp_set [Pa] the regulator's set underpressure (the step is w.params.dt). Throws
// std::runtime_error when the gas volume is not positive (the membrane collapsed onto the solids).
void membrane_air_step(dem::World& w, const Membrane& m, double solids, double dp_set, const MembraneAirDef& def,
                       MembraneGas& g);

}  // namespace vpp

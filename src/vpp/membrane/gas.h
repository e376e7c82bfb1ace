// The air inside the damper (process.pressure_model = "pump"; docs/damper.md, "The air inside").
//
// The foil's pores hold air. The paper, and process.pressure_model = "constant", keep the
// pressure inside fixed; a real damper is sealed and kept at underpressure by a pump through a
// regulator, and compressing it shrinks the gas volume. The model here:
//   - the gas is ideal and isothermal (the grains and the foil hold its temperature: a pore of a
//     few millimetres exchanges heat in milliseconds), so its amount is carried as
//     n R T = p V [Pa m^3] and p = amount / V_gas;
//   - an ideal two-way regulator holds the set pressure p_set: while p > p_set it opens the pump
//     line, which removes gas at a volumetric speed S [m^3/s] at the inside pressure; while
//     p < p_set it opens a bleed valve of conductance B [m^3/s] that lets atmospheric air in at
//     B (p_atm - p); neither carries p across p_set;
//   - a leak of conductance C [m^3/s] lets air in at all times: d(amount)/dt = C (p_atm - p).
// Each is integrated exactly for a time step at fixed volume (the volume moves by a few
// micrometres' worth per step): the leak and the bleed relax p towards p_atm with time
// constants V / C and V / B, the pump draws p down with time constant V / S. The leak acts
// first, then the regulator (operator splitting, first order in dt; dt is 1e-5 of V / S and
// less). A very fast pump and bleed hold p = p_set: the constant model.
#pragma once

namespace vpp {

enum class PressureModel : int {
    Constant = 0,  // dp held at process.underpressure (the paper)
    Pump = 1,      // the gas above
};

struct PumpLine {
    double speed = 0.0;     // [m^3/s] S, the pump's volumetric speed (0: none)
    double bleed = 0.0;     // [m^3/s] B, the regulator's bleed valve conductance (0: one-way regulator)
    double leak = 0.0;      // [m^3/s] C, the leak's conductance (0: tight)
    double p_set = 0.0;     // [Pa] absolute pressure the regulator holds (p_atm - dp_set)
    double p_atm = 0.0;     // [Pa] the atmosphere outside
};

// The gas amount (p V [Pa m^3]) after a step of dt [s] in the gas volume v [m^3] (> 0).
double advance_gas(double amount, double v, double dt, const PumpLine& line);

// Work done by an isothermal gas of this amount (p V [Pa m^3]) whose volume goes from v0 to v1
// [m^3] with nothing pumped or leaked [J]: amount ln(v1 / v0) (the closed form the tests use).
double isothermal_work(double amount, double v0, double v1);

}  // namespace vpp

// energy.csv's columns, each described once (name, unit, meaning, where it comes from in the
// EnergyLedger): the scene runner, the damper and the device write their energy.csv from this
// table, the damper's per-cycle split and Python's Damper.energy_columns() read it, so a column
// cannot be written by one of them and missing from, or placed differently in, another.
// Formulas and signs: docs/energy.md.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "dem/core/energy.h"

namespace dem {

struct EnergyColumn {
    const char* name;     // as in energy.csv's header and Python
    const char* unit;     // SI
    const char* meaning;
    // The column's value in a ledger; nullptr for the first column, the time, which the writer
    // gives (the damper counts it from the start of cycling).
    double (*get)(const EnergyLedger&);
};

// In energy.csv's order (tools read it by position: append, never reorder).
inline constexpr std::array<EnergyColumn, 11> kEnergyColumns{{
    {"time", "s", "time of the row (the damper: since the start of cycling)", nullptr},
    {"boundary_work", "J", "work of the moving walls and prescribed particles on the particles since the ledger began",
     [](const EnergyLedger& L) { return L.boundary_work; }},
    {"pressure_work", "J", "work of the membrane's underpressure on its free particles",
     [](const EnergyLedger& L) { return L.pressure_work; }},
    {"gravity_work", "J", "work of gravity on the free particles (minus the change of m g z)",
     [](const EnergyLedger& L) { return L.gravity_work; }},
    {"kinetic", "J", "kinetic energy of the free particles, translation and rotation (stored)",
     [](const EnergyLedger& L) { return L.kinetic; }},
    {"elastic_contacts", "J", "energy in the touching contacts' normal and shear springs (stored)",
     [](const EnergyLedger& L) { return L.elastic_contacts; }},
    {"elastic_bonds", "J", "energy in the bonds' axial and shear springs (stored)",
     [](const EnergyLedger& L) { return L.elastic_bonds; }},
    {"friction_dissipation", "J", "Coulomb slip of the contacts' shear springs, and springs still loaded when their contact opened",
     [](const EnergyLedger& L) { return L.friction_dissipation(); }},
    {"damping_dissipation", "J", "local (non-viscous) damping of forces and torques",
     [](const EnergyLedger& L) { return L.damping_dissipation; }},
    {"viscous_dissipation", "J", "the normal dashpots (restitution < 1)",
     [](const EnergyLedger& L) { return L.viscous_dissipation; }},
    {"residual", "J", "input work - (stored - stored at the start) - dissipated: zero for an exact balance",
     [](const EnergyLedger& L) { return L.residual(); }},
}};

// A column's position in a row (0: the time); a name not in the table does not compile where the
// call is a constant expression, and throws elsewhere.
constexpr std::size_t energy_column(std::string_view name) {
    for (std::size_t k = 0; k < kEnergyColumns.size(); ++k)
        if (name == kEnergyColumns[k].name) return k;
    throw std::logic_error("energy.csv has no such column");
}

// energy.csv's header: the names, comma-separated.
inline std::string energy_csv_header() {
    std::string h;
    for (const EnergyColumn& c : kEnergyColumns) {
        if (!h.empty()) h += ',';
        h += c.name;
    }
    return h;
}

// The names in order (Python's Damper.energy_columns()).
inline std::vector<std::string> energy_column_names() {
    std::vector<std::string> v;
    for (const EnergyColumn& c : kEnergyColumns) v.emplace_back(c.name);
    return v;
}

// One row: the time, then each column of the ledger. `out` holds kEnergyColumns.size() values.
inline void energy_csv_row(const EnergyLedger& L, double time, double* out) {
    out[0] = time;
    for (std::size_t k = 1; k < kEnergyColumns.size(); ++k) out[k] = kEnergyColumns[k].get(L);
}

}  // namespace dem

#include "vpp/analysis/records.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dem/io/csv.h"
#include "dem/io/json.h"

namespace vpp {

namespace {

using G = CycleGroup;

#define CYCLE_FIELD(f)                                          \
    .get = [](const CycleResult& c) { return double(c.f); },    \
    .set = [](CycleResult& c, double v) { c.f = decltype(c.f)(v); }

}  // namespace

const std::vector<CycleColumn>& cycle_columns() {
    static const std::vector<CycleColumn> columns = {
        {.name = "cycle", .unit = "", .meaning = "the cycle, from 1", .group = G::Always, .flag = false, .added_later = false,
         .get = [](const CycleResult& c) { return double(c.cycle); },
         .set = [](CycleResult& c, double v) { c.cycle = int(std::lround(v)); }},
        {.name = "dissipated_energy", .unit = "J",
         .meaning = "the loop's area: the closed integral of force_zeroed over the displacement (vpp/analysis/analysis.h)",
         .group = G::Always, .flag = false, .added_later = false, CYCLE_FIELD(dissipated_energy)},
        {.name = "W", .unit = "J/m^2", .meaning = "dissipated_energy / (pi damper.radius^2), the paper's efficiency",
         .group = G::Always, .flag = false, .added_later = false, CYCLE_FIELD(W)},
        {.name = "peak_force", .unit = "N", .meaning = "the largest force_zeroed of the cycle", .group = G::Always,
         .flag = false, .added_later = false, CYCLE_FIELD(peak_force)},
        {.name = "min_force", .unit = "N", .meaning = "the smallest force_zeroed of the cycle", .group = G::Always,
         .flag = false, .added_later = false, CYCLE_FIELD(min_force)},
        {.name = "friction_dissipation", .unit = "J",
         .meaning = "energy ledger: Coulomb slip, and loaded shear springs lost when contacts open", .group = G::Energy,
         .flag = false, .added_later = false, CYCLE_FIELD(friction_dissipation)},
        {.name = "damping_dissipation", .unit = "J", .meaning = "energy ledger: local damping", .group = G::Energy,
         .flag = false, .added_later = false, CYCLE_FIELD(damping_dissipation)},
        {.name = "viscous_dissipation", .unit = "J", .meaning = "energy ledger: the normal dashpots (grains.restitution)",
         .group = G::Energy, .flag = false, .added_later = false, CYCLE_FIELD(viscous_dissipation)},
        {.name = "settled", .unit = "",
         .meaning = "1 when W has settled by this cycle (stationary loops, vpp/analysis/settle.h)", .group = G::Settle,
         .flag = true, .added_later = false, .get = [](const CycleResult& c) { return c.settled ? 1.0 : 0.0; },
         .set = [](CycleResult& c, double v) { c.settled = v != 0.0; }},
        {.name = "boundary_work", .unit = "J",
         .meaning = "energy ledger: work of the cap and the top ring on the sample over the cycle (docs/energy.md)",
         .group = G::Energy, .flag = false, .added_later = true, CYCLE_FIELD(boundary_work)},
        {.name = "energy_residual", .unit = "J",
         .meaning = "energy ledger: input - change of stored energy - dissipation over the cycle (the balance's error)",
         .group = G::Energy, .flag = false, .added_later = true, CYCLE_FIELD(energy_residual)},
        {.name = "events", .unit = "",
         .meaning = "rearrangement events: bursts of kinetic energy above analysis.event_threshold times the cycle's "
                    "median (vpp/analysis/events.h)",
         .group = G::Events, .flag = false, .added_later = false, CYCLE_FIELD(events)},
        {.name = "event_fraction", .unit = "", .meaning = "the share of the cycle's record intervals inside events",
         .group = G::Events, .flag = false, .added_later = false, CYCLE_FIELD(event_fraction)},
        {.name = "friction_in_events", .unit = "J", .meaning = "the part of friction_dissipation inside events",
         .group = G::Events, .flag = false, .added_later = false, CYCLE_FIELD(friction_in_events)},
        {.name = "damping_in_events", .unit = "J", .meaning = "the part of damping_dissipation inside events",
         .group = G::Events, .flag = false, .added_later = false, CYCLE_FIELD(damping_in_events)},
        {.name = "viscous_in_events", .unit = "J", .meaning = "the part of viscous_dissipation inside events",
         .group = G::Events, .flag = false, .added_later = false, CYCLE_FIELD(viscous_in_events)},
    };
    return columns;
}

#undef CYCLE_FIELD

bool cycle_has(const CycleResult& c, CycleGroup g) {
    switch (g) {
    case CycleGroup::Always: return true;
    case CycleGroup::Energy: return c.has_energy;
    case CycleGroup::Settle: return c.has_settled;
    case CycleGroup::Events: return c.has_events;
    }
    return false;
}

std::vector<const CycleColumn*> cycle_columns_of(const std::vector<CycleResult>& cycles) {
    std::vector<const CycleColumn*> out;
    for (const CycleColumn& col : cycle_columns()) {
        const bool all = !cycles.empty() && std::all_of(cycles.begin(), cycles.end(),
                                                        [&](const CycleResult& c) { return cycle_has(c, col.group); });
        if (col.group == CycleGroup::Always || all) out.push_back(&col);
    }
    return out;
}

void write_cycles_csv(const std::string& path, const std::vector<CycleResult>& cycles) {
    const std::vector<const CycleColumn*> cols = cycle_columns_of(cycles);
    std::string header;
    for (const CycleColumn* c : cols) {
        if (!header.empty()) header += ',';
        header += c->name;
    }
    // The cycle number and the flags are whole doubles: printed without a decimal point.
    dem::CsvWriter csv(path, header);
    std::vector<double> row;
    for (const CycleResult& c : cycles) {
        row.clear();
        for (const CycleColumn* col : cols) row.push_back(col->get(c));
        csv.row(row);
    }
    csv.close();
}

std::vector<CycleResult> read_cycles_csv(const std::string& path) {
    std::vector<std::string> header;
    const auto rows = dem::read_numeric_csv(path, 4, &header);
    if (rows.empty()) throw std::runtime_error(path + " holds no cycle");
    // Each column of the table: its position in the file, or -1.
    std::vector<long> at;
    bool energy = true, settle = true, events = true;
    for (const CycleColumn& col : cycle_columns()) {
        const auto it = std::find(header.begin(), header.end(), col.name);
        at.push_back(it == header.end() ? -1 : long(it - header.begin()));
        if (at.back() >= 0 || col.added_later) continue;
        if (col.group == CycleGroup::Always) throw std::runtime_error(path + ": no column " + col.name);
        (col.group == CycleGroup::Energy ? energy : col.group == CycleGroup::Settle ? settle : events) = false;
    }
    std::vector<CycleResult> cycles;
    for (const auto& r : rows) {
        CycleResult c;
        c.has_energy = energy;
        c.has_settled = settle;
        c.has_events = events;
        for (std::size_t k = 0; k < at.size(); ++k) {
            const CycleColumn& col = cycle_columns()[k];
            if (at[k] >= 0 && std::size_t(at[k]) < r.size()) col.set(c, r[std::size_t(at[k])]);
            else if (col.added_later) col.set(c, std::numeric_limits<double>::quiet_NaN());
        }
        cycles.push_back(c);
    }
    return cycles;
}

std::string cycles_json(const std::vector<CycleResult>& cycles) {
    std::string out = "[";
    for (std::size_t k = 0; k < cycles.size(); ++k) {
        dem::JsonObject j;
        for (const CycleColumn& col : cycle_columns()) {
            if (!cycle_has(cycles[k], col.group)) continue;
            if (col.flag) j.boolean(col.name, col.get(cycles[k]) != 0.0);
            else j.num(col.name, col.get(cycles[k]));
        }
        out += (k ? ", " : "") + j.value();
    }
    return out + "]";
}

const std::vector<SampleColumn>& sample_columns() {
    static const std::vector<SampleColumn> columns = {
        {"time", "s", "simulated time since the start of cycling", false},
        {"displacement", "m", "the cap's travel from its position at the start of cycling, compression positive",
         false},
        {"force_total", "N", "force_grains + force_foil", false},
        {"force_grains", "N", "the grains on the upper cap, compression positive, averaged over process.sample_window",
         false},
        {"force_foil", "N", "the foil on the top ring, compression positive, averaged as force_grains", false},
        {"force_zeroed", "N", "force_total minus its value at the first sample (the loops' force)", false},
        {"cycle", "", "the cycle of the sample, from 1", false},
        {"enclosed_volume", "m^3", "volume bounded by the foil (through its particles' centres) and the caps", true},
        {"gas_volume", "m^3", "enclosed_volume minus the grains' volume", true},
        {"pressure_inside", "Pa", "absolute pressure of the gas inside", true},
        {"underpressure", "Pa", "atmospheric minus pressure_inside", true},
        {"force_lid", "N", "what dp adds to the testing machine's force on the lid: -underpressure times its area", true},
        {"force_machine_zeroed", "N", "the testing machine's force (total + lid) minus its value at the first sample",
         true},
    };
    return columns;
}

std::vector<std::string> sample_column_names(bool air) {
    std::vector<std::string> out;
    for (const SampleColumn& c : sample_columns())
        if (air || !c.air) out.push_back(c.name);
    return out;
}

}  // namespace vpp

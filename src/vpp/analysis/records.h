// The damper's records, each column described once (name, unit, meaning, where it comes from):
// the per-cycle record (cycles.csv, summary.json "cycles", Python's Damper.cycles(), the study's
// read-back) and the per-sample record (forces.csv and Python's Damper.forces() arrays). The
// writers, the reader and the Python module iterate these tables, so a column cannot be in one
// of them and missing from another, or mean one thing here and another there.
#pragma once

#include <string>
#include <vector>

#include "vpp/analysis/analysis.h"

namespace vpp {

// Which cycles carry a column: all of them; those with the energy ledger (has_energy: a damper
// run with output.energy); those with the stationarity flag (has_settled: a damper run).
enum class CycleGroup { Always, Energy, Settle, Events };

struct CycleColumn {
    const char* name;     // as in cycles.csv's header, summary.json and Python
    const char* unit;     // SI; "-" a ratio, "" a count or a flag
    const char* meaning;  // where it comes from
    CycleGroup group;
    bool flag;            // 0/1 in cycles.csv and Python, true/false in summary.json
    // Added after cycles.csv files were published without it: a file that lacks it still has its
    // group's other columns, and reads it as NaN (the study's --report-only reads old records).
    bool added_later;
    double (*get)(const CycleResult&);
    void (*set)(CycleResult&, double);
};

// In the order of cycles.csv's header and summary.json's cycle objects: the columns a cycles.csv
// had before keep their places, later ones are appended (tools may read them by position).
const std::vector<CycleColumn>& cycle_columns();

// Whether a cycle carries the columns of a group.
bool cycle_has(const CycleResult& c, CycleGroup g);

// The columns of cycles.csv for these cycles: a group's when every cycle has it.
std::vector<const CycleColumn*> cycle_columns_of(const std::vector<CycleResult>& cycles);

// cycles.csv, atomically: the header of cycle_columns_of(cycles) and one row per cycle (the cycle
// number and the flags printed as integers).
void write_cycles_csv(const std::string& path, const std::vector<CycleResult>& cycles);

// cycles.csv read back into cycles: every column of the table that the file has, by name (other
// columns ignored); has_energy and has_settled set when their group's columns are there (a column
// added_later may be missing: NaN).
// Throws std::runtime_error naming the file when it cannot be read, holds no cycle or lacks a
// column of the Always group.
std::vector<CycleResult> read_cycles_csv(const std::string& path);

// summary.json's "cycles" array: per cycle, the Always columns, the Energy columns when it has the
// ledger and the Settle columns when it has the flag.
std::string cycles_json(const std::vector<CycleResult>& cycles);

// A column of forces.csv: one row per sample.
struct SampleColumn {
    const char* name;
    const char* unit;
    const char* meaning;
    bool air;  // only with the air record (process.pressure_model = "pump" or output.air)
};

// In forces.csv's order.
const std::vector<SampleColumn>& sample_columns();

// The column names of forces.csv, with or without the air's.
std::vector<std::string> sample_column_names(bool air);

}  // namespace vpp

// `vppdem analyze FORCES.csv`: energy per cycle and W of a force-displacement record, written
// to a new file. What it never does: replace a file without --overwrite (a damper run's own
// cycles.csv holds energy columns this command cannot compute), use another damper's radius
// without saying so, or count a cut-off cycle as a loop.
#pragma once

#include <string>

#include "vpp/analysis/record_format.h"

namespace vpp {

struct AnalyzeOptions {
    std::string forces;              // the record: a CSV with a header
    std::string out;                 // output file; empty: cycles_analyzed.csv beside the input
    double radius = 0.0;             // [m] damper radius for W; 0: see run_analyze
    bool overwrite = false;          // replace an existing output file
    // Columns, units and sign; the defaults read a damper run's forces.csv.
    RecordFormat format{.force_col = "force_total", .cycle_col = "cycle"};
};

// Default output name, beside the input: not cycles.csv, which a damper run writes itself.
inline constexpr const char* kAnalyzeOutput = "cycles_analyzed.csv";
// [m] the paper's damper radius, used when nothing else gives one.
inline constexpr double kPaperRadius = 0.0255;

// The damper radius recorded in DIR/summary.json of a damper run ("damper.radius" of its
// inputs); 0 when the file or the key is missing.
double radius_from_summary(const std::string& summary_json);

// Reads the record (vpp::read_record), finds its cycles (vpp::analyze_cycles), warns when its
// signs look the other way round (vpp::orientation_doubt, for a stroke that starts with
// compression, as the damper's default), leaves out partial cycles with a warning, writes the output atomically, prints the rows on stdout and on stderr which radius
// was used: --radius when given; else the one in summary.json beside the input (a damper run
// folder); else kPaperRadius, said so. Throws (naming the file) on an existing output without
// overwrite, a record without data rows, or no complete cycle; nothing is written then.
void run_analyze(const AnalyzeOptions& o);

}  // namespace vpp

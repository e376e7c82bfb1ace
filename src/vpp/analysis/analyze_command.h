// `vppdem analyze FORCES.csv`: energy per cycle and W of a force-displacement record, written
// to a new file. What it never does: replace a file without --overwrite (a damper run's own
// cycles.csv holds energy columns this command cannot compute), use another damper's radius
// without saying so, or count a cut-off cycle as a loop.
#pragma once

#include <string>

namespace vpp {

struct AnalyzeOptions {
    std::string forces;              // the record: a CSV with a header
    std::string out;                 // output file; empty: cycles_analyzed.csv beside the input
    double radius = 0.0;             // [m] damper radius for W; 0: see run_analyze
    bool overwrite = false;          // replace an existing output file
    std::string time_col = "time", disp_col = "displacement", force_col = "force_total", cycle_col = "cycle";
    double disp_scale = 1.0;         // to metres (1e-3 for mm)
    double force_scale = 1.0;        // to newtons (1e3 for kN)
};

// Default output name, beside the input: not cycles.csv, which a damper run writes itself.
inline constexpr const char* kAnalyzeOutput = "cycles_analyzed.csv";
// [m] the paper's damper radius, used when nothing else gives one.
inline constexpr double kPaperRadius = 0.0255;

// The damper radius recorded in DIR/summary.json of a damper run ("damper.radius" of its
// inputs); 0 when the file or the key is missing.
double radius_from_summary(const std::string& summary_json);

// Reads the record, finds its cycles (vpp::analyze_cycles), leaves out partial cycles with a
// warning, writes the output atomically, prints the rows on stdout and on stderr which radius
// was used: --radius when given; else the one in summary.json beside the input (a damper run
// folder); else kPaperRadius, said so. Throws (naming the file) on an existing output without
// overwrite, a record without data rows, or no complete cycle; nothing is written then.
void run_analyze(const AnalyzeOptions& o);

}  // namespace vpp

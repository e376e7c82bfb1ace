#include "vpp/analysis/analyze_command.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpp/analysis/analysis.h"
#include "vpp/analysis/records.h"

namespace vpp {

namespace fs = std::filesystem;

double radius_from_summary(const std::string& summary_json) {
    std::ifstream in(summary_json);
    if (!in) return 0.0;
    // Not JSON, or no positive number there: 0, and the caller says which radius it took.
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("inputs") || !j["inputs"].is_object()) return 0.0;
    const nlohmann::json& inputs = j["inputs"];
    const auto it = inputs.find("damper.radius");
    if (it == inputs.end() || !it->is_number()) return 0.0;
    const double r = it->get<double>();
    return r > 0.0 ? r : 0.0;
}

void run_analyze(const AnalyzeOptions& o) {
    const fs::path input(o.forces);
    const fs::path out = o.out.empty() ? input.parent_path() / kAnalyzeOutput : fs::path(o.out);
    std::error_code ec;
    if (fs::exists(out) && fs::equivalent(out, input, ec))
        throw std::runtime_error("--out '" + out.string() + "' is the input file");
    if (fs::exists(out) && !o.overwrite)
        throw std::runtime_error("'" + out.string() + "' exists; pass --overwrite to replace it, or --out another file");

    double radius = o.radius;
    std::string which;
    const fs::path summary = input.parent_path() / "summary.json";
    if (radius > 0.0) {
        which = "--radius";
    } else if (const double r = radius_from_summary(summary.string()); r > 0.0) {
        radius = r;
        which = "damper.radius of " + summary.string();
    } else {
        radius = kPaperRadius;
        which = "the paper's damper: no summary.json with damper.radius beside the input; give --radius";
    }

    const LoopSeries s = read_record(o.forces, o.format);
    std::vector<CycleResult> cycles, partial;
    for (const CycleResult& c : analyze_cycles(s, radius)) (c.complete ? cycles : partial).push_back(c);
    std::string left_out;
    for (const CycleResult& c : partial) left_out += (left_out.empty() ? "" : ", ") + std::to_string(c.cycle);
    if (cycles.empty())
        throw std::runtime_error("'" + o.forces + "' holds no complete cycle" +
                                 (partial.empty() ? std::string(" (a cycle goes from the start position to the far "
                                                                "end and back)")
                                                  : " (partial: cycle " + left_out + ")"));
    write_cycles_csv(out.string(), cycles);

    std::fprintf(stderr, "radius %.6g m (%s)\n", radius, which.c_str());
    // Warned, not refused: a record of a stroke that starts with extension has a negative force.
    if (const std::string doubt = orientation_doubt(s, o.format.compression_negative, true); !doubt.empty())
        std::fprintf(stderr, "warning: '%s' looks the other way round: %s (a stroke that starts by pulling "
                     "gives this too)\n", o.forces.c_str(), doubt.c_str());
    for (const CycleResult& c : partial)
        std::fprintf(stderr,
                     "warning: cycle %d is partial (it does not come back to where it started: %d samples); left "
                     "out, its area is not a loop's\n",
                     c.cycle, c.samples);
    std::printf("cycle,dissipated_energy,W,peak_force,min_force\n");
    for (const auto& r : cycles)
        std::printf("%d,%.6g,%.6g,%.6g,%.6g\n", r.cycle, r.dissipated_energy, r.W, r.peak_force, r.min_force);
    std::fprintf(stderr, "wrote %s%s\n", out.string().c_str(),
                 partial.empty() ? "" : (" (complete cycles only; left out: cycle " + left_out + ")").c_str());
}

}  // namespace vpp

#include "vpp/analysis/record_format.h"

#include <cmath>
#include <cstdio>

namespace vpp {

LoopSeries read_record(const std::string& path, const RecordFormat& f) {
    LoopSeries s = read_loop_csv(path, f.time_col, f.disp_col, f.force_col, f.cycle_col);
    const double sign = f.compression_negative ? -1.0 : 1.0;
    for (double& d : s.displacement) d *= sign * f.disp_scale;
    for (double& x : s.force) x *= sign * f.force_scale;
    // Split again after the flip: split read the stroke the file's way round, whose "start
    // position" (its minimum) is the far end of a compression-negative stroke.
    if (!s.cycles_from_column && f.compression_negative) s.cycle = split_cycles(s.displacement);
    return s;
}

std::string orientation_doubt(const LoopSeries& s, bool compression_negative, bool compression_first) {
    double sum = 0, extreme = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < s.force.size(); ++i)
        if (s.cycle[i] > 0) {
            sum += s.force[i];
            if (std::abs(s.force[i]) > std::abs(extreme)) extreme = s.force[i];
            ++n;
        }
    double area = 0;
    for (const CycleResult& c : analyze_cycles(s, 1.0)) area += c.dissipated_energy;
    char buf[160];
    if (area < 0) {
        std::snprintf(buf, sizeof buf, "%.4g J", area);
        return std::string("its loops enclose a negative area (") + buf +
               " over its cycles): a damper dissipates, so with displacement and force both compression positive "
               "its loop has a positive area; here one of the two counts compression negative: check the columns' "
               "sign conventions";
    }
    // Either sign alone can happen: a raw force with the foil's pull at rest as offset can be
    // negative on average, a loop that drops below its start on unloading can have its largest
    // |F| there. Extension first (the cap moves up first) is the one protocol where both are
    // negative.
    if (compression_first && n > 0 && sum / double(n) < 0 && extreme < 0) {
        std::snprintf(buf, sizeof buf, "mean %.4g N, largest in magnitude %.4g N", sum / double(n), extreme);
        return std::string("its force over the cycles is negative (") + buf +
               (compression_negative ? ", signs flipped" : "") +
               "): a compressed damper pushes back, so compression must count positive; " +
               (compression_negative ? "drop --compression-negative (the record counts compression positive)"
                                     : "pass --compression-negative (the record counts compression negative)");
    }
    return "";
}

}  // namespace vpp

// The device run's checks (device/checks.h).
#include "vpp/device/checks.h"

#include <cmath>
#include <cstdio>

namespace vpp::device_detail {

std::string force_segment_stopped_short(const dem::World& w, const dem::Tool& t, std::size_t k,
                                        const dem::ToolState& before, const dem::ToolState& after, int32_t stage) {
    std::string out;
    const double now = w.time, d = dem::tool_displacement(w, t, now);
    for (int32_t m = before.segment; m < after.segment && m < int32_t(t.program.size()); ++m) {
        const dem::ToolSegment& g = t.program[std::size_t(m)];
        if (g.stage != stage || g.kind != dem::SegmentKind::Force) continue;  // not this stage's (skipped), or not a force
        const double f = dem::tool_force(w, t).z;
        if (g.force > 0 ? f >= g.force : f <= g.force) continue;  // ended at its force
        // Its start: the running segment's, or now for one that started and ended in this step.
        const double d0 = m == before.segment && before.started ? before.d0 : d;
        const std::string key = "tools[" + std::to_string(k) + "].program[" + std::to_string(m) + "]";
        char msg[640];
        std::snprintf(msg, sizeof msg,
                      "%s.max_travel = %.4g m reached (tool '%s', stage %s; travel %.4g m) with a reaction F_z of %.4g N, "
                      "short of %s.force = %.4g N: the force segment ended below its target (a press that does not reach "
                      "the object leaves press_force and holding_force at 0); raise %s.max_travel or lower %s.force",
                      key.c_str(), g.max_travel, t.name.c_str(), device_stage_name(DeviceStage(stage)), std::abs(d - d0), f,
                      key.c_str(), g.force, key.c_str(), key.c_str());
        out += (out.empty() ? "" : "; ") + std::string(msg);
    }
    return out;
}

std::string fill_not_at_rest(const DeviceDef& d, double ke, double bound) {
    // Frictionless grains (the default fill) slide on each other and flow longer than rough ones.
    const std::string friction = d.fill_friction == 0.0 ? ", or a grains.fill_friction above 0 (now 0: a frictionless fill "
                                                           "flows longer than a rough one)" : "";
    char msg[900];
    std::snprintf(msg, sizeof msg,
                  "fill: the grains are not at rest after stages.fill_time = %g s (kinetic energy %.3g J, %.3g times the "
                  "bound of rest, %.3g J = 1e-4 N m g 2r, checked every 2 ms from stages.fill_min_time = %g s on): the next "
                  "stage starts on moving grains. Raise stages.fill_time (the fill ends as soon as the grains are at rest, "
                  "so a longer limit costs only the time they need; summary.json's fill_settled and fill_time say when "
                  "they were), or bring them to rest sooner with a larger simulation.local_damping (now %g, at most 0.9; it "
                  "damps every stage)%s",
                  d.fill_time, ke, bound > 0 ? ke / bound : 0.0, bound, d.fill_min_time, d.local_damping, friction.c_str());
    return msg;
}

}  // namespace vpp::device_detail

// The device run's state and its checkpoint blob (device/state.h).
#include "vpp/device/state.h"

#include "dem/io/archive.h"

namespace vpp::device_detail {

// The blob's layout: the section "DEVS", its fields in this order (the checkpoint format), then,
// only where the suction's seal is on, "SUCT" (a checkpoint without it resumes as before).
template <class A, class S> void DeviceState::fields(A& a, S& r) {
    a.section("DEVS", [&](A& s) {
        s.pod(r.at.stage);
        s.pod(r.at.t0);
        s.pod(r.sealed);
        s.vec(r.tools);
        s.pod(r.gas);
        s.vec(r.window.sums);
        s.pod(r.window.steps);
        s.vec(r.records.tools);
        s.vec(r.records.air);
        s.vec(r.records.energy);
        s.numbers(r.report);
        s.strings(r.warnings);
        s.str(r.inputs);
        s.pod(r.at.next_check);
        s.pod(r.at.free_steps);
        s.pod(r.at.tools_done);
        s.pod(r.vtk_frames);
    });
    a.optional_section("SUCT", r.suction.on != 0, [&](A& s) {
        s.pod(r.suction.on);
        SuctionSeal::fields(s, r.suction.seal);
        s.vec(r.suction.rows);
    });
}

std::string DeviceState::save() const {
    dem::io::Writer w;
    fields(w, *this);
    return w.buf;
}

DeviceState DeviceState::load(const std::string& blob, const std::string& path) {
    DeviceState r;
    dem::io::Reader rd(blob.data(), blob.size(), path);
    fields(rd, r);
    if (!rd.done()) dem::io::corrupt(path, "unread bytes after the device's run state");
    if (r.at.stage < 0 || r.at.stage > int32_t(DeviceStage::Done)) dem::io::corrupt(path, "stage out of range");
    return r;
}

DeviceState fresh_state(const DeviceDef& d, std::size_t tools) {
    DeviceState s;
    s.inputs = inputs_text(d);
    s.tools.assign(tools, dem::ToolState{});
    s.window.sums.assign(3 * tools, 0.0);
    return s;
}

std::string inputs_text(const DeviceDef& d) {
    std::string s;
    for (const auto& [k, v] : device_inputs(d))
        if (k != "file") s += k + "=" + v + "\n";  // the same device from another folder resumes
    return s;
}

}  // namespace vpp::device_detail

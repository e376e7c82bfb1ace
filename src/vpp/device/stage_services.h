// What a stage of the device run asks of the run around it (device/stages.h): the options, the
// pause points between steps (a checkpoint every --checkpoint-every seconds of wall clock, the
// stop a resume test asks for), the checkpoints, records and VTK frames through the run's
// recorder, the warnings kept in the run state, the log on the terminal. The stages see the run
// through this alone; run_device owns the options and the recorder it refers to.
// Internal to vpp/device/*.cpp.
#pragma once

#include <string>

#include "vpp/device/recorder.h"
#include "vpp/device/run.h"
#include "vpp/device/scene.h"
#include "vpp/device/state.h"

namespace vpp::device_detail {

class StageServices {
public:
    // Refers to the run's options and recorder, which outlive it.
    StageServices(const DeviceOptions& options, DeviceRecorder& recorder) : options_(options), recorder_(recorder) {}

    const DeviceOptions& options() const { return options_; }
    // Before each step within a stage: a checkpoint when one is due by the wall clock; and
    // the stop the options ask for (stop_at_time, stop): a checkpoint and the records, then true
    // (the stage returns at once, the run stops: stopped()).
    bool pause_point(DeviceScene& scene, const DeviceState& state);
    bool stopped() const { return stopped_; }
    // run.ckpt now.
    void checkpoint(DeviceScene& scene, const DeviceState& state) const;
    // The records as the state stands (device/recorder.h).
    void write_records(const DeviceScene& scene, const DeviceState& state) const { recorder_.write_records(scene, state); }
    // VTK frame vtk/NAME.vtk (and NAME_tools.vtk).
    void vtk_frame(const DeviceScene& scene, const std::string& name) const { recorder_.vtk_frame(scene, name); }
    // Keeps a warning in the state for summary.json (and the checkpoints, so that a resumed run
    // reports it too) and logs it.
    void warn(DeviceState& state, const std::string& what) const;
    // A line on stderr ("[device] ...") unless quiet.
    void log(const std::string& what) const;

private:
    const DeviceOptions& options_;
    DeviceRecorder& recorder_;
    bool stopped_ = false;  // a pause point stopped the run
};

}  // namespace vpp::device_detail

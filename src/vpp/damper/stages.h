// The protocol of the damper run, a stage at a time: fill and compress (the preparation),
// vacuum, cycle. Each stage is a function of the scene (damper/scene.h), the run state
// (damper/state.h) and what it asks of the run around it (damper/stage_services.h: the options,
// the checkpoints, the warnings); DamperRun (damper/run.h) calls them in order. A stage resumed
// from a checkpoint takes its decisions at the same steps as an uninterrupted one: the run is
// bitwise the same however it is split. Internal to vpp/damper_*.cpp.
#pragma once

#include "vpp/damper/scene.h"
#include "vpp/damper/stage_services.h"
#include "vpp/damper/state.h"

namespace vpp::damper_detail::stages {

// The grains fall (frictionless) until they are at rest, re-filled (damper.refill) until their
// level reaches the damper height.
void fill(DamperScene& scene, RunState& state, StageServices& services);
// The cap comes down onto the grains to the damper height and holds; the funnel goes. The
// preparation's measures into state.report.
void compress(DamperScene& scene, RunState& state, StageServices& services);
// The underpressure on the foil, ramped up (or drawn by the pump), until the sample is at rest.
void vacuum(DamperScene& scene, RunState& state, StageServices& services);
// Cycles until the end of cycle `upto` [-] (of process.cycles; the run is bitwise the same
// however the cycles are split into calls); the first call lays out the motion of every cycle.
void cycle(DamperScene& scene, RunState& state, StageServices& services, int upto);
// A resumed run given more cycles (process.cycles) than the `from` [-] it started with: the
// further cycles' knots, and a finished run cycling again.
void extend_cycling(DamperScene& scene, RunState& state, StageServices& services, int from);
// The run enters stage `s`: its clocks restart, a checkpoint and a VTK frame are written.
void next_stage(DamperScene& scene, RunState& state, StageServices& services, Stage s);
// The cycles finished [-] (a run stopped within a cycle counts those before it).
int cycles_done(const DamperScene& scene, const RunState& state);

}  // namespace vpp::damper_detail::stages

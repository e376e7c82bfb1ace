// The time step of a run from simulation.dt and simulation.dt_safety (scene/shared_keys.h), read
// and computed here for every command that has the two keys (scenes, the damper and the foil's
// checks, devices), so that the same keys give the same step everywhere.
#pragma once

#include <string>

#include "dem/world/world.h"
#include "scene/config.h"
#include "scene/shared_keys.h"

namespace scene {

struct TimeStep {
    bool automatic = true;                     // simulation.dt = "auto": safety times the critical step
    double dt = 0.0;                           // [s] the fixed step (unused when automatic)
    double safety = cfg::keys::dt_safety.def;  // [-] simulation.dt_safety
};

// simulation.dt, the key `key` of `s`: "auto" or a step in seconds (> 0 and finite); absent, `def`
// [s] (NaN: "auto"). Anything else is refused naming the key, with keys::dt's sentence. The
// safety keeps its default: it is a number of its own (cfg::keys::dt_safety).
TimeStep read_dt(cfg::Section& s, const std::string& key, double def);

// The step [s] of a run in `w`: the fixed one, or the safety times w.critical_dt(), which is
// infinite when no particle of `w` is free (each caller refuses that in its own words).
double time_step(const TimeStep& t, const dem::World& w);

}  // namespace scene

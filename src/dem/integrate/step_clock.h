// The step's clock: time = base + (steps - base step) * dt rather than a running sum, so output
// times stay exact multiples of dt; the base moves whenever dt changes or someone sets the time
// (e.g. a restart from a checkpoint).
#pragma once

#include <cstdint>

#include "dem/core/hd.h"

namespace dem {

struct StepClock {
    double time_base = 0.0;    // [s]
    double dt_of_base = -1.0;  // [s] the dt since the base (negative: none yet)
    uint64_t step_base = 0;

    // One step of dt: advances steps and time (World's clock and the batch engine's device's).
    VPPDEM_HD void advance(double& time, uint64_t& steps, double dt) {
        if (dt != dt_of_base || time != time_base + double(steps - step_base) * dt_of_base) {
            time_base = time;
            step_base = steps;
            dt_of_base = dt;
        }
        ++steps;
        time = time_base + double(steps - step_base) * dt;
    }
};

}  // namespace dem

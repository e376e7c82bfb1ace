// The device run's checks of what it was asked against what it did: inputs that are accepted
// but did not do what they say are returned as warnings that name the keys to change, their
// values and what to do (summary.json "warnings"). Internal to vpp/device/*.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "dem/world/tool.h"
#include "dem/world/world.h"
#include "vpp/device/definition.h"

namespace vpp::device_detail {

// Tool k [-] (tools[k]) was driven for a step of stage `stage` from `before` to `after` (its
// program's state): a force segment of the stage that ended there at its max_travel without
// its reaction reaching its force (the reaction it was decided on: the World's last forces)
// returns the warning naming tools[k].program[m].max_travel and .force, the force reached and
// the travel; "" otherwise.
std::string force_segment_stopped_short(const dem::World& w, const dem::Tool& t, std::size_t k,
                                        const dem::ToolState& before, const dem::ToolState& after, int32_t stage);

// The fill ended at stages.fill_time [s] with the grains' kinetic energy `ke` [J] above the
// rest bound `bound` [J]: the warning, with what to change.
std::string fill_not_at_rest(const DeviceDef& d, double ke, double bound);

}  // namespace vpp::device_detail

// The checks of the damper's input that need its scene built (the foil's height and radius, the
// time step, the grains' sizes): values that cannot make a damper are refused with a message
// naming the key, its value and what is allowed; values that are accepted but do not do what
// they seem to are returned as warnings (docs/config.md, "Limits from the physics"). A refused
// run writes nothing: the run calls these before its folder is touched.
// Internal to vpp/damper_*.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "vpp/settings/config.h"
#include "vpp/damper/scene.h"

namespace vpp::damper_detail {

// The process against the built foil (its height z_top): refuses a stroke the sample cannot
// take, contacts or a foil the load would crush, and a pump-down that would not end; returns
// the warnings.
std::vector<std::string> check_process(const DamperScene& scene);
// The sampling against the time step (known once the world is built): warnings; with `refuse`,
// sampling faster than the time step is refused (a fresh run or a branch, before writing).
std::vector<std::string> check_sampling(const DamperScene& scene, bool refuse);
// The time step against the contacts and the process: a step that is no number, a fixed step
// beyond the stable one, a run of more steps than any machine finishes are refused (a new run
// or a branch, before writing).
void check_steps(const DamperScene& scene);
// n grains [-] against the foil (a fresh sample): a grain too large or a clump too wide to turn
// in it, too few grains for one layer, more than the densest packing are refused; more than
// random close packing is returned as a warning.
std::vector<std::string> check_grains_fit(const DamperScene& scene, std::size_t n);
// A fresh sample's preparation needs simulation.local_damping > 0 (its only dissipation).
void check_preparation_damping(const Config& c);

}  // namespace vpp::damper_detail

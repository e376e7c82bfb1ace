// What a damper's checkpoint stores of the config that made it, and how a run from the
// checkpoint compares and adopts it: the sample's geometry (a run from it must match the keys it
// gives, and takes the others), the keys that acted during its preparation (a study's branch
// must match them), and the run settings of a run that started (a resumed run keeps them).
// The tables of keys are vpp/settings/settings.h's. Internal to vpp/damper_*.cpp.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "vpp/settings/config.h"
#include "vpp/damper/damper.h"

namespace vpp::damper_detail {

// What a run from a checkpoint learnt from it besides the settings it adopted.
struct CheckpointStart {
    std::size_t grains = 0;             // grains stored in the checkpoint (0: unknown, an older vppdem's)
    int cycles_raised_from = 0;         // process.cycles the run started with, when the config raises it (0: not raised)
    std::vector<std::string> warnings;  // for the run's warnings once its state is loaded
};

// The checkpoint options.from's geometry into `config` (a geometry key the config gives with
// another value is refused, naming both), with options.check_preparation its preparation's keys
// checked too, and for a run that started its run settings (a key given with another value is
// refused; more cycles continue the run).
CheckpointStart adopt_checkpoint_settings(Config& config, const DamperOptions& options);
// The run settings (settings.h run_settings()) of `c`: what a run applies to its prepared sample
// and is bound to from then on.
std::map<std::string, double> run_settings_of(const Config& c);
// The sample's keys of `c`: its geometry and the keys acting during its preparation.
std::map<std::string, double> sample_keys_of(const Config& c);
// A stored value of `key` as the config file writes it, for messages ("sphere", true, "auto",
// or the number).
std::string show_value(const std::string& key, double v);

}  // namespace vpp::damper_detail

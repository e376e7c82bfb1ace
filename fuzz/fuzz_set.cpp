// Fuzz target: `--set key=value` assignments (cfg::apply_override, then the settings table),
// one assignment per line of the input (empty lines left out), applied in order to the damper's defaults as
// `vppdem damper --set ... --set ...` applies them.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input.h"
#include "vpp/settings/config.h"
#include "vpp/settings/settings.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    std::vector<std::string> sets;
    const std::string_view text = fuzz::as_text(data, size);
    for (std::size_t a = 0; a <= text.size();) {
        const std::size_t b = std::min(text.find('\n', a), text.size());
        if (b > a) sets.emplace_back(text.substr(a, b - a));
        a = b + 1;
    }
    fuzz::expect_only_reader_errors([&] { vpp::load_config("", sets); });
    return 0;
}

// Fuzz target: a damper config file (TOML) through the settings table, as `vppdem damper`,
// sweep, calibrate, tension and envelope read it (vpp::load_config).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "vpp/settings/config.h"
#include "vpp/settings/settings.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::write_file("config.toml", fuzz::as_text(data, size));
    fuzz::expect_only_reader_errors([&] { vpp::load_config(path, {}); });
    return 0;
}

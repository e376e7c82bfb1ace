// Fuzz target: a study file (vpp::load_study), then its cases (vpp::expand_study: every case's
// config through the settings table), as `vppdem sweep --list` reads it.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "vpp/study/study.h"

namespace {

// A valid grid may hold 100000 cases (vpp/study/study.cpp); expanding that many is seconds of work the
// user asked for, not a fault of the reader, and would read as a hang. A larger grid is still
// read (load_study); only its expansion is left out.
constexpr std::size_t kMaxExpandedCases = 2000;

// The base config the seed studies name (base = "base.toml", relative to the study file).
void write_base_config() {
    static const bool written = [] {
        fuzz::write_file("base.toml", "[damper]\nradius = 0.012\nheight = 0.03\n[process]\ncycles = 2\n");
        return true;
    }();
    (void)written;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    write_base_config();
    const std::string path = fuzz::write_file("study.toml", fuzz::as_text(data, size));
    fuzz::expect_only_reader_errors([&] {
        const vpp::Study s = vpp::load_study(path);
        std::size_t cases = 1;
        for (const vpp::GridAxis& a : s.grid) cases = std::min(cases * a.literals.size(), kMaxExpandedCases + 1);
        if (cases <= kMaxExpandedCases) vpp::expand_study(s);
    });
    return 0;
}

// Fuzz target: checkpoints (`vppdem damper --from`, `vppdem bench --state`): the World
// (dem::load_checkpoint: sections, counts, index checks, the derived tables) and the damper's
// state blob in it (vpp::damper_detail::RunState::load), up to the first use of the state that a
// resumed run makes (the stage's name in its log line).
//
// The file ends in a checksum of everything before it (dem/io/checkpoint.h): a mutated input
// would almost never pass it and the fuzzer would not get past the header. So the harness
// writes the input with the header's payload size and the checksum made to fit, as a file
// written inconsistently by a faulty program or edited by hand would be; an input shorter than
// the header is written as it is (the header checks). The checksum check itself is covered by
// the unit tests (tests/unit/test_checkpoint.cpp).
#include <cstddef>
#include <cstdint>
#include <string>

#include "dem/io/checkpoint.h"
#include "fuzz_input.h"
#include "vpp/damper/run.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    std::string bytes(fuzz::as_text(data, size));
    dem::reseal_checkpoint_bytes(bytes);
    const std::string path = fuzz::write_file("state.ckpt", bytes);
    std::string blob;
    bool loaded = false;
    fuzz::expect_only_reader_errors(
        [&] {
            dem::World w;
            blob = dem::load_checkpoint(path, w);
            loaded = true;
        },
        path);
    if (!loaded) return 0;
    fuzz::expect_only_reader_errors(
        [&] {
            using namespace vpp::damper_detail;
            const RunState st = RunState::load(blob, path);
            const std::string stage = stage_name(st.stage);  // the resumed run's log line names it
        },
        path);
    return 0;
}

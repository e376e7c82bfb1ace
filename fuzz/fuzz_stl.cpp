// Fuzz target: STL meshes of a scene's [[facet_sets]] type = "stl" (dem::read_stl), binary and
// ASCII.
#include <cstddef>
#include <cstdint>

#include "dem/walls/facet_sets.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = fuzz::write_file("mesh.stl", fuzz::as_text(data, size));
    fuzz::expect_only_reader_errors([&] { dem::read_stl(path, 1e-3); }, path);
    return 0;
}

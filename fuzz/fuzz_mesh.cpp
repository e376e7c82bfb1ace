// Fuzz target: closed surface meshes for membranes (dem::read_closed_surface), STL (binary and
// ASCII) and OBJ; the first byte picks the extension. The reader and every check must refuse
// bad input with an error naming the file, never crash or hang.
#include <cstddef>
#include <cstdint>

#include "dem/mesh/mesh_checks.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string path = fuzz::write_file((data[0] & 1) ? "mesh.obj" : "mesh.stl", fuzz::as_text(data + 1, size - 1));
    fuzz::expect_only_reader_errors([&] { dem::read_closed_surface(path); }, path);
    return 0;
}

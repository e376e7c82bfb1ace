// Fuzz target: a scene file (`vppdem scene`): the TOML through the scene's settings table into a
// World (scene::build_scene), the initial-overlap check included; the run itself is not started.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "scene/config.h"
#include "scene/scene_runner.h"

namespace {

// Files the seed scenes name beside them ([[sphere_files]] path = "spheres.csv", [[facet_sets]]
// type = "stl", path = "wall.stl"), so that mutations of those entries reach their readers.
void write_side_files() {
    static const bool written = [] {
        fuzz::write_file("spheres.csv", "x,y,z,r\n0,0,0.01,0.001\n0.003,0,0.01,0.001\n");
        fuzz::write_file("wall.stl",
                         "solid w\nfacet normal 0 0 1\nouter loop\nvertex -1 -1 0\nvertex 1 -1 0\nvertex 0 1 0\n"
                         "endloop\nendfacet\nendsolid w\n");
        return true;
    }();
    (void)written;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    write_side_files();
    const std::string path = fuzz::write_file("scene.toml", fuzz::as_text(data, size));
    fuzz::expect_only_reader_errors([&] {
        const toml::table root = cfg::load(path, {});
        scene::build_scene(root, fuzz::work_dir().string());
    });
    return 0;
}

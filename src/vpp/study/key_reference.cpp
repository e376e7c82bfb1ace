#include "vpp/study/key_reference.h"

#include "scene/scene_settings.h"
#include "vpp/settings/settings.h"
#include "vpp/study/file.h"

namespace vpp {

std::string config_reference_markdown() {
    std::string md =
        "# Config reference\n\n"
        "<!-- Generated from the settings tables (src/vpp/settings/settings.cpp, src/vpp/study/file.cpp,\n"
        "     src/scene/scene_settings.cpp) by\n"
        "     `vppdem config-reference`; do not edit: build/vppdem config-reference > docs/config.md -->\n\n"
        "- [VPP commands](#vpp-commands): damper, sweep, calibrate, tension, envelope\n"
        "- [Study files](#study-files): the top-level keys of `vppdem sweep`'s study file\n"
        "- [`vppdem scene`](#vppdem-scene): generic DEM scenes (docs/scene.md)\n\n";
    md += settings_reference_markdown();
    md += "\n" + study_reference_markdown();
    md += "\n" + scene::scene_reference_markdown();
    return md;
}

}  // namespace vpp

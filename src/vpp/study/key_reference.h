// docs/config.md, the reference of every key a user may write (`vppdem config-reference`): the
// VPP commands' settings, a study file's top-level keys and the generic scenes' keys, each from
// its own table. It lives with the studies because it is the one page that needs all three tables.
#pragma once

#include <string>

namespace vpp {

// The whole page as Markdown.
std::string config_reference_markdown();

}  // namespace vpp

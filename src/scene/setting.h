// What every settings table shares: a key's type, how its value is checked, and how the
// reference page (docs/config.md) prints them. Two tables use it: the scene runner's
// (scene/scene_settings.cpp: `vppdem scene`) and the damper's (vpp/settings/settings.cpp: damper, sweep,
// calibrate, tension, envelope). One check and one wording for both, so a range reads the same in
// an error message, in either table and on the page.
#pragma once

#include <string>

#include "scene/config.h"

namespace cfg {

enum class SettingType {
    Real,        // a finite number
    Integer,
    Boolean,
    Choice,      // one of a few words
    RealOrAuto,  // a number or "auto"
    String,      // free text: a name or a file path
    Vec3,        // [x, y, z], finite numbers
    Rows,        // an array of arrays of numbers (a history, a triangle's vertices)
};

// How a value is checked. Positive and NonNegative use the reader's own "must be > 0 and finite",
// "must be >= 0 and finite"; Range and AtLeast refuse with the row's `allowed` text; Custom: the
// key has a reader of its own that says what is allowed.
enum class Check { None, Positive, NonNegative, Range, AtLeast, Custom };

// The bounds of a Range or AtLeast check and the sentence an error gives ("must be in (0, 1]").
struct Limits {
    Check check = Check::None;
    double lo = 0.0, hi = 0.0;  // Range: the bounds; AtLeast: lo
    bool lo_open = false, hi_open = false;
    const char* allowed = "";
};

// The value of `key` in `s` after the check: refuses (ConfigError naming the key, the value and
// `limits.allowed`) a value outside. Non-finite numbers are refused by the reader before this.
double check_real(const Section& s, const std::string& key, double v, const Limits& limits);
int64_t check_integer(const Section& s, const std::string& key, int64_t v, const Limits& limits);

// For the reference page.
const char* type_name(SettingType t);
std::string allowed_text(SettingType t, const Limits& limits);  // "> 0", "(0, 1]", "true or false"
std::string number_text(double v);                               // shortest text that reads back
std::string markdown_cell(const std::string& s);                  // a table cell: | escaped

}  // namespace cfg

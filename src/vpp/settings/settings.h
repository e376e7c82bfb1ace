// The damper's settings table: every config key of the VPP commands (damper, sweep, calibrate,
// tension, envelope) described once, with its type, default, unit, allowed range, what it acts
// on and whether cases of a study may share a preparation across it. The config reader
// (vpp/settings/config.cpp), the range messages, the study's sharing rule (vpp/study/file.cpp), what a
// damper run records in its checkpoints (vpp/damper/stored_settings.cpp) and summary.json
// (vpp/damper/record.cpp) and docs/config.md (`vppdem config-reference`) all come from it, so a
// key cannot be documented one way and read another.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "scene/setting.h"
#include "vpp/settings/config.h"

namespace cfg {
class Section;
}

namespace vpp {

// The types and checks both settings tables share (scene/setting.h); the damper's keys use Real,
// Integer, Boolean, Choice and RealOrAuto.
using cfg::Check;
using cfg::SettingType;

// What a key changes; a key acting on the geometry or contact physics changes the prepared sample.
enum class Acts { Geometry, ContactPhysics, Process, Output, Analysis, Simulation };

struct Setting {
    static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

    // Initialised for the rows of a declared key (scene/shared_keys.h), which get them from there.
    const char* key = "";   // dotted key as written in the file and in --set
    SettingType type = SettingType::Real;
    const char* unit = "";  // SI unit; "-" a ratio, "" a count, flag or word
    double def = kUnset;    // damper, sweep and calibrate default (NaN: see default_text)
    double def_foil = kUnset;  // tension and envelope default (NaN: the same as def)
    const char* default_text = "";  // the default as the reference shows it when def is NaN or a word
    Check check = Check::None;
    double lo = 0.0, hi = 0.0;  // Range: the bounds; AtLeast: lo
    bool lo_open = false, hi_open = false;  // Range: whether a bound itself is refused
    const char* allowed = "";  // what is allowed, as the error message says it ("must be ...")
    Acts acts;
    // Cases of a study that differ only in keys with this flag share one preparation: the key
    // does not act before prepared.ckpt (vpp/study/file.cpp).
    bool shares_preparation = false;
    int geometry = 0;  // position among the sample's geometry in the checkpoints (0: not there)
    int run = 0;       // position among the settings a started run keeps when resumed (0: not there)
    int summary = 0;   // position among summary.json "inputs" (0: not there)
    const char* doc = "";
    // What a key declared for every table (scene/shared_keys.h) does in these commands, printed
    // after its doc ("": nothing to add).
    const char* note = "";
    // Reads the key from its section into the config; nullptr: the generic reader of the type
    // and check (vpp/settings/config.cpp).
    void (*read)(cfg::Section&, const Setting&, Config&, CommandSet) = nullptr;
    double (*get)(const Config&);   // the value as a number (flags 0/1, "auto" dt 0, ...)
    void (*set)(Config&, double);
    // The value a checkpoint of an older vppdem, which did not store this key, was made with
    // (NaN: every checkpoint stores it).
    double legacy = kUnset;

    cfg::Limits limits() const { return {check, lo, hi, lo_open, hi_open, allowed}; }
    // The default for these commands (def_foil where the foil's checks have their own).
    double default_for(CommandSet k) const { return k == CommandSet::Foil && !std::isnan(def_foil) ? def_foil : def; }
};

// The section of a dotted key: "grains" of "grains.friction".
std::string section_of(const std::string& key);

// The table, in the order the config reader reads the keys (section by section).
const std::vector<Setting>& settings();
const Setting* find_setting(std::string_view key);

// Keys recorded in a checkpoint or summary.json, in the order they are written.
std::vector<Setting> geometry_settings();
std::vector<Setting> run_settings();
std::vector<Setting> summary_inputs();
// Keys that act while the sample is prepared but are no geometry key: the stiffnesses, the foil,
// the damping and the time step (every key of grains, foil, damper and simulation that may not
// share a preparation and has no geometry position). A prepared sample records them; a study's
// branch must match them (DamperOptions::check_preparation).
std::vector<Setting> preparation_settings();

// Whether cases that differ in this key may share a preparation. A key not in the table is
// treated like its section when every key of the section may share (process, output, analysis).
bool may_share_preparation(const std::string& key);

const char* acts_name(Acts a);

// The section "VPP commands" of docs/config.md: the table and the limits as Markdown (the whole
// page, with the study files' and the scenes' keys: vpp/study/key_reference.h).
std::string settings_reference_markdown();

}  // namespace vpp

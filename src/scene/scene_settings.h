// The scene runner's settings table: every key of a `vppdem scene` file (docs/scene.md) with its
// type, default, unit, allowed range and one line of doc. build_scene() (scene/scene_runner.cpp)
// reads each key through it, so the defaults and checks are the table's, a key outside the table
// cannot be read, and the reference page docs/config.md (`vppdem config-reference`) prints it.
// The damper's keys have their own table (vpp/settings/settings.h) over the same types and checks
// (scene/setting.h).
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "dem/core/vec3.h"
#include "scene/config.h"
#include "scene/setting.h"

namespace scene {

struct SceneSetting {
    static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

    // "simulation.dt"; keys of an array of tables carry "[]": "spheres[].radius" is the radius of
    // every [[spheres]] entry (an error names the entry: "spheres[3].radius").
    std::string key;
    cfg::SettingType type;
    const char* unit;             // SI unit; "-" a ratio, "" a count, flag, word or path
    double def = kUnset;          // Real, Integer, Boolean (0/1): the default
    dem::Vec3 def3{};             // Vec3: the default
    bool required = false;        // no default: the entry must give it
    const char* default_text = "";  // the default as the page shows it when it is no number
    cfg::Limits limits{};
    std::string doc;

    std::string group() const { return key.substr(0, key.rfind('.')); }      // "spheres[]"
    std::string name() const { return key.substr(key.rfind('.') + 1); }      // "radius"
};

// The table, group by group in the order build_scene() reads them.
const std::vector<SceneSetting>& scene_settings();
// nullptr when `key` ("spheres[].radius") is not in the table.
const SceneSetting* find_scene_setting(const std::string& key);

// One table of a scene file read through the settings table: every read looks up its row, takes
// the row's default (or refuses a missing required key) and applies the row's check. Reading a
// key the table does not list is a bug of the reader (std::logic_error), so the table is the
// complete list of keys the scene runner accepts.
class SceneSection {
public:
    // `group`: the table's name for this section ("simulation", "spheres[]").
    SceneSection(cfg::Section s, std::string group) : s_(std::move(s)), group_(std::move(group)) {}

    double real(const std::string& key);
    int64_t integer(const std::string& key);
    bool flag(const std::string& key);
    dem::Vec3 vec3(const std::string& key);
    std::string string(const std::string& key);
    // The raw value of a key with a reader of its own (nullptr when absent).
    const toml::node* node(const std::string& key);
    // The section itself, for the readers of keys declared for every table (scene/shared_keys.h,
    // scene/time_step.h); what they read is recorded with record().
    cfg::Section& section() { return s_; }

    const SceneSetting& row(const std::string& key) const;
    // Keeps every value read from here on, as (dotted key, JSON value), in `out` (summary.json's
    // "inputs": what the run used, defaults included).
    void record_into(std::vector<std::pair<std::string, std::string>>* out) { record_ = out; }
    void record(const std::string& key, const std::string& json) {
        if (record_) record_->emplace_back(group_ + "." + key, json);
    }
    bool has(const std::string& key) const { return s_.has(key); }
    double positive(const std::string& key, double v) const { return s_.positive(key, v); }
    [[noreturn]] void fail(const std::string& key, const std::string& what) const { s_.fail(key, what); }
    const std::string& path() const { return s_.path(); }
    // Refuses keys that were not read (the unknown-key message lists the keys read here).
    void finish() const { s_.finish(); }

private:
    cfg::Section s_;
    std::string group_;
    std::vector<std::pair<std::string, std::string>>* record_ = nullptr;
};

// The scene part of docs/config.md.
std::string scene_reference_markdown();

}  // namespace scene

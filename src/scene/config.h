// Strict reading of TOML configuration: every key is checked, unknown keys and bad values
// raise ConfigError naming the key, the value and what is allowed.
#pragma once

#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "dem/core/vec3.h"

namespace cfg {

struct ConfigError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Parses a TOML file (or an empty table when path is empty) and applies `--set key=value`
// overrides. A key is a dotted path ("simulation.dt", "spheres.0.radius"); the value is read
// as a TOML value ("1e-6", "[0,0,-9.81]", "true", "\"auto\"") or, failing that, a string.
toml::table load(const std::string& path, const std::vector<std::string>& overrides);
// Parses a TOML file; a syntax error becomes a ConfigError naming `what` (e.g. "config"),
// the path, the line and the column.
toml::table parse_file(const std::string& path, const std::string& what);
void apply_override(toml::table& root, const std::string& assignment);

// A view of one table that remembers which keys were read, so finish() can reject the rest.
class Section {
public:
    Section(const toml::table* t, std::string path) : t_(t), path_(std::move(path)) {}

    bool has(const std::string& key) const;
    double number(const std::string& key, double def);
    double number(const std::string& key);  // required
    int64_t integer(const std::string& key, int64_t def);
    bool boolean(const std::string& key, bool def);
    std::string string(const std::string& key, const std::string& def);
    std::string string(const std::string& key);  // required
    dem::Vec3 vec3(const std::string& key, const dem::Vec3& def);
    dem::Vec3 vec3(const std::string& key);  // required
    const toml::node* node(const std::string& key);  // raw access; marks the key as read
    Section table(const std::string& key);            // sub-table (empty if absent)
    std::vector<Section> array_of_tables(const std::string& key);

    // Range checks that name the key in the message.
    double positive(const std::string& key, double v) const;
    double non_negative(const std::string& key, double v) const;
    [[noreturn]] void fail(const std::string& key, const std::string& what) const;
    std::string name(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    const std::string& path() const { return path_; }

    // Throws on any key of the table that was not read.
    void finish() const;

private:
    const toml::node* get(const std::string& key);
    const toml::table* t_;
    std::string path_;
    std::set<std::string> used_;
};

std::string describe(const toml::node& n);  // the value as the user wrote it, for messages

}  // namespace cfg

#include "vpp/study/file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "dem/io/csv.h"
#include "scene/config.h"
#include "vpp/device/definition.h"
#include "vpp/settings/settings.h"

namespace vpp {

namespace fs = std::filesystem;
using cfg::ConfigError;

const std::vector<StudyKey>& study_keys() {
    static const std::vector<StudyKey> keys = {
        {"base", "string", "none: the damper's defaults",
         "a config file the cases start from, relative to the study file"},
        {"description", "string", "\"\"", "free text; not used by the sweep"},
        {"share_preparation", "boolean", "true",
         "cases that differ only in keys that do not act before the end of the preparation share one prepared "
         "sample (the settings' \"shares preparation\" column); false: every case prepares its own"},
        {"samples_from", "string or list of strings", "none: each preparation group prepares its sample",
         "another study's folder whose prepared samples (its cases' prepared.ckpt) this study's cases branch from: "
         "a path relative to the folder holding --out (a sibling study by its name), or absolute; a list: searched "
         "in its order, a group taking the first folder's fitting sample; a group no sample fits prepares its own "
         "(said on stderr)"},
        {"samples_match", "string", "\"preparation\"",
         "with samples_from: \"preparation\", a sample fits when its geometry (simulation.seed included) and every "
         "key that acts during the preparation are the case's; \"geometry\", the geometry alone (the case cycles the "
         "sample with its own settings, as the time-step study does)"},
        {"continues", "string", "none",
         "a second leg: the folder of a study (relative to the folder holding --out, or absolute) whose finished "
         "runs this study's cases of the same names continue to a larger process.cycles, each copied into --out "
         "(records and run.ckpt; that study's run stays as it is) and resumed from its run.ckpt; a case that folder "
         "lacks, or holds without run.ckpt, runs anew (with samples_from, from its sample); runs still going there "
         "are refused"},
        {"seeds", "integer 1..1000", "none: one run per case",
         "an ensemble: simulation.seed = 1, 2, ..., seeds as the last grid key (`--seeds` overrides it); write it "
         "before [set] and [grid]"},
        {"[set]", "table of config keys", "empty", "fixed overrides for every case (\"damper.radius\" = 0.012)"},
        {"[grid]", "table of config keys", "empty: one case",
         "every combination of the listed values is one case, the first key outermost; each key a list of values "
         "or a range \"start:stop:step\" (stop included)"},
    };
    return keys;
}

namespace {

// The StudyKey of a top-level key of the file ("set" is the table [set]); nullptr: not a key.
const StudyKey* study_key(const std::string& key) {
    for (const StudyKey& k : study_keys())
        if (k.key == key || k.key == "[" + key + "]") return &k;
    return nullptr;
}

std::string allowed_study_keys() {
    std::string out;
    for (const StudyKey& k : study_keys()) out += (out.empty() ? "" : ", ") + std::string(k.key);
    return out;
}

// A value of [set] or [grid] as a TOML literal (for --set) and as a label (names, CSV).
bool scalar_literal(const toml::node& n, std::string& literal, std::string& label) {
    if (auto i = n.as_integer()) {
        literal = label = std::to_string(i->get());
        return true;
    }
    if (auto f = n.as_floating_point()) {
        double v = f->get();
        if (!std::isfinite(v)) return false;
        // -0.0 is the value 0: one case, one label (else "0" and "-0" were two cases of one run).
        if (v == 0.0) v = 0.0;
        label.clear();
        dem::append_number(label, v);
        literal = label;
        if (literal.find_first_of(".eE") == std::string::npos) literal += ".0";  // stays a float
        return true;
    }
    if (auto b = n.as_boolean()) {
        literal = label = b->get() ? "true" : "false";
        return true;
    }
    if (auto s = n.as_string()) {
        label = s->get();
        literal = "\"";
        for (char c : label) {
            if (c == '"' || c == '\\') literal += '\\';
            literal += c;
        }
        literal += '"';
        return true;
    }
    return false;
}

struct FlatEntry {
    std::string key;
    const toml::node* node;
    std::size_t line, column;
};

// Dotted keys of a (possibly nested) table, in the order they are written in the file.
void flatten(const toml::table& t, const std::string& prefix, std::vector<FlatEntry>& out) {
    for (const auto& [k, v] : t) {
        const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
        if (const toml::table* sub = v.as_table()) flatten(*sub, key, out);
        else out.push_back({key, &v, v.source().begin.line, v.source().begin.column});
    }
}

std::vector<FlatEntry> flat_in_order(const toml::table& t) {
    std::vector<FlatEntry> out;
    flatten(t, "", out);
    std::stable_sort(out.begin(), out.end(), [](const FlatEntry& a, const FlatEntry& b) {
        return a.line != b.line ? a.line < b.line : a.column < b.column;
    });
    return out;
}

std::string sanitize(const std::string& s) {
    std::string out;
    for (char c : s) out += (std::isalnum((unsigned char)c) || c == '.' || c == '-' || c == '+' || c == '=') ? c : '-';
    return out;
}

// A study's ensemble size: the file's top-level `seeds` (0 when absent), replaced by the command
// line's --seeds when that is > 0. ConfigError naming the key or the option when out of range.
int study_seeds(const toml::table& root, const std::string& where, int seeds_override) {
    int seeds = 0;
    if (const toml::node* n = root.get("seeds")) {
        const auto v = n->value_exact<int64_t>();
        if (!v || *v < 1 || *v > kMaxSeeds)
            throw ConfigError(where + "key 'seeds' = " + cfg::describe(*n) + ": must be an integer in 1.." +
                              std::to_string(kMaxSeeds) + " (an ensemble of that many realisations: simulation.seed "
                              "1, 2, ..., seeds)");
        seeds = int(*v);
    }
    if (seeds_override < 0 || seeds_override > kMaxSeeds)
        throw ConfigError("--seeds " + std::to_string(seeds_override) + ": must be an integer in 1.." +
                          std::to_string(kMaxSeeds));
    return seeds_override > 0 ? seeds_override : seeds;
}

}  // namespace

std::string study_reference_markdown() {
    std::string md =
        "## Study files\n\n"
        "The top-level keys of a study file (`vppdem sweep STUDY`, docs/studies.md); every other key is a config "
        "key above, in [set] or [grid].\n\n"
        "| key | type | default | meaning |\n|---|---|---|---|\n";
    for (const StudyKey& k : study_keys())
        md += "| `" + std::string(k.key) + "` | " + k.type + " | " + k.def + " | " + k.doc + " |\n";
    return md;
}

// Which keys may differ between the cases of one preparation: the settings table's rule and
// why (vpp/settings/settings.cpp, shares_preparation).
bool is_shareable_key(const std::string& key) { return may_share_preparation(key); }

std::vector<double> parse_range(const std::string& key, const std::string& text, bool* integers) {
    auto bad = [&](const std::string& why) -> ConfigError {
        return ConfigError("study grid key '" + key + "' = \"" + text + "\": " + why +
                           " (expected a list of values or a range \"start:stop:step\", e.g. \"0:1:0.1\")");
    };
    std::vector<std::string> parts;
    std::stringstream ss(text);
    for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
    if (parts.size() != 3 || text.back() == ':') throw bad("not a range of three numbers");
    double v[3];
    bool all_int = true;
    for (int k = 0; k < 3; ++k) {
        const std::string& p = parts[std::size_t(k)];
        char* end = nullptr;
        v[k] = std::strtod(p.c_str(), &end);
        if (p.empty() || end == p.c_str() || *end != '\0' || !std::isfinite(v[k]))
            throw bad("'" + p + "' is not a number");
        if (p.find_first_of(".eE") != std::string::npos) all_int = false;
    }
    if (!(v[2] > 0)) throw bad("the step must be > 0");
    if (v[1] < v[0]) throw bad("stop is below start");
    const double n = std::floor((v[1] - v[0]) / v[2] + 1e-9) + 1.0;
    if (n > 100000) throw bad("more than 100000 values");
    std::vector<double> out;
    for (long i = 0; i < long(n); ++i) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.12g", v[0] + double(i) * v[2]);  // 0.1 * 3 -> 0.3
        out.push_back(std::strtod(buf, nullptr));
    }
    if (integers) *integers = all_int;
    return out;
}

namespace {

// A [grid] key's values into `ax`: a list of values, or a range "start:stop:step" (integers when
// its three numbers are); no value twice.
void read_grid_values(const FlatEntry& e, const std::string& where, GridAxis& ax) {
    if (const toml::array* a = e.node->as_array()) {
        if (a->empty()) throw ConfigError(where + "grid key '" + e.key + "' is an empty list; give at least one value");
        for (const toml::node& v : *a) {
            std::string lit, label;
            if (!scalar_literal(v, lit, label))
                throw ConfigError(where + "grid key '" + e.key + "': value " + cfg::describe(v) +
                                  " must be a number, string or boolean");
            ax.literals.push_back(lit);
            ax.labels.push_back(label);
        }
    } else if (const toml::value<std::string>* r = e.node->as_string()) {
        bool ints = false;
        for (double v : parse_range(e.key, r->get(), &ints)) {
            std::string lit, label;
            if (ints) {
                lit = label = std::to_string(std::llround(v));
            } else {
                scalar_literal(toml::value<double>(v), lit, label);
            }
            ax.literals.push_back(lit);
            ax.labels.push_back(label);
        }
    } else {
        throw ConfigError(where + "grid key '" + e.key + "' = " + cfg::describe(*e.node) +
                          ": expected a list of values or a range \"start:stop:step\"");
    }
    std::set<std::string> uniq(ax.labels.begin(), ax.labels.end());
    if (uniq.size() != ax.labels.size()) throw ConfigError(where + "grid key '" + e.key + "' repeats a value");
}

// The ensemble: simulation.seed = 1..seeds as the last grid key (varying fastest), so the seeds of
// one case sit side by side; --seeds (seeds_override) replaces a seed list of [grid].
void add_seed_axis(Study& s, int seeds, int seeds_override, const std::string& where) {
    const std::string from = seeds_override > 0 ? "--seeds" : "key 'seeds'";
    for (const std::string& x : s.set)
        if (x.starts_with("simulation.seed="))
            throw ConfigError(where + from + " and a fixed simulation.seed (" + x +
                              ") contradict each other: give one of them");
    const auto it = std::find_if(s.grid.begin(), s.grid.end(), [](const GridAxis& a) { return a.key == "simulation.seed"; });
    if (it != s.grid.end()) {
        if (seeds_override == 0)
            throw ConfigError(where + "key 'seeds' and a [grid] list of simulation.seed both give the seeds: keep one");
        s.grid.erase(it);
    }
    s.grid.push_back(axis_from_text("simulation.seed", "1:" + std::to_string(seeds) + ":1"));
}

}  // namespace

Study load_study(const std::string& path, const std::vector<std::string>& extra_sets, int seeds_override) {
    if (!fs::is_regular_file(path)) throw ConfigError("study file '" + path + "' not found");
    const toml::table root = cfg::parse_file(path, "study");
    Study s;
    s.path = path;
    const std::string where = "study '" + path + "': ";
    for (const auto& [k, v] : root) {
        const std::string key(k.str());
        if (!study_key(key)) throw ConfigError(where + "unknown key '" + key + "' (allowed: " + allowed_study_keys() + ")");
    }
    const int seeds = study_seeds(root, where, seeds_override);
    if (const toml::node* b = root.get("base")) {
        if (!b->as_string()) throw ConfigError(where + "key 'base' must be a string (a config file path)");
        fs::path p(b->as_string()->get());
        if (p.is_relative()) p = fs::path(path).parent_path() / p;
        if (!fs::is_regular_file(p))
            throw ConfigError(where + "key 'base' = \"" + b->as_string()->get() + "\": file '" + p.string() + "' not found");
        s.base = p.string();
    }
    if (const toml::node* d = root.get("description"); d && !d->as_string())
        throw ConfigError(where + "key 'description' must be a string");
    if (const toml::node* f = root.get("samples_from")) {
        const std::string allowed = "must be a folder name or path (another study's --out), or a list of them";
        if (const toml::array* a = f->as_array()) {
            if (a->empty()) throw ConfigError(where + "key 'samples_from' = []: " + allowed);
            for (const toml::node& e : *a) {
                if (!e.as_string() || e.as_string()->get().empty())
                    throw ConfigError(where + "key 'samples_from' = " + cfg::describe(*f) + ": " + allowed);
                s.samples_from.push_back(e.as_string()->get());
            }
        } else if (f->as_string() && !f->as_string()->get().empty()) {
            s.samples_from.push_back(f->as_string()->get());
        } else {
            throw ConfigError(where + "key 'samples_from' = " + cfg::describe(*f) + ": " + allowed);
        }
    }
    if (const toml::node* c = root.get("continues")) {
        if (!c->as_string() || c->as_string()->get().empty())
            throw ConfigError(where + "key 'continues' = " + cfg::describe(*c) +
                              ": must be a folder name or path (the --out of the study whose runs this one continues)");
        s.continues = c->as_string()->get();
    }
    if (const toml::node* m = root.get("samples_match")) {
        const std::string v = m->as_string() ? m->as_string()->get() : std::string();
        if (v != "preparation" && v != "geometry")
            throw ConfigError(where + "key 'samples_match' = " + cfg::describe(*m) +
                              ": must be \"preparation\" or \"geometry\"");
        if (s.samples_from.empty())
            throw ConfigError(where + "key 'samples_match' needs 'samples_from' (the folder whose samples it matches)");
        s.samples_match_geometry = v == "geometry";
    }
    if (const toml::node* sp = root.get("share_preparation")) {
        if (!sp->as_boolean()) throw ConfigError(where + "key 'share_preparation' must be true or false");
        s.share_preparation = sp->as_boolean()->get();
    }
    // TOML puts a key written after a [table] header into that table: `seeds = 3` under [set]
    // would be taken for a config key and refused as unknown, which hides the slip.
    for (const char* table : {"set", "grid"})
        if (const toml::node* t = root.get(table); t && t->as_table() && t->as_table()->contains("seeds"))
            throw ConfigError(where + "'seeds' is a top-level key of the study, not a config key: write it before "
                                      "[set] and [grid]");
    std::set<std::string> seen;
    if (const toml::node* st = root.get("set")) {
        if (!st->as_table()) throw ConfigError(where + "'set' must be a table [set] of config keys");
        for (const FlatEntry& e : flat_in_order(*st->as_table())) {
            std::string lit, label;
            if (!scalar_literal(*e.node, lit, label))
                throw ConfigError(where + "[set] key '" + e.key + "' = " + cfg::describe(*e.node) +
                                  ": must be a number, string or boolean");
            // A key written twice, quoted ("grains.friction" = ...) and bare (grains.friction =
            // ...), is two TOML keys but one config key: the later would silently win.
            if (seen.count(e.key))
                throw ConfigError(where + "[set] key '" + e.key + "' is given twice (quoted and as a dotted key are "
                                          "the same config key): keep one");
            s.set.push_back(e.key + "=" + lit);
            seen.insert(e.key);
        }
    }
    for (const std::string& x : extra_sets) s.set.push_back(x);
    if (const toml::node* g = root.get("grid")) {
        if (!g->as_table()) throw ConfigError(where + "'grid' must be a table [grid] of config keys");
        for (const FlatEntry& e : flat_in_order(*g->as_table())) {
            GridAxis ax;
            ax.key = e.key;
            if (seen.count(e.key)) throw ConfigError(where + "key '" + e.key + "' is in both [set] and [grid]");
            for (const GridAxis& o : s.grid)
                if (o.key == e.key) throw ConfigError(where + "grid key '" + e.key + "' is given twice");
            read_grid_values(e, where, ax);
            s.grid.push_back(std::move(ax));
        }
    }
    if (seeds > 0) add_seed_axis(s, seeds, seeds_override, where);
    return s;
}

bool is_device_study(const std::string& path) {
    try {
        return fs::is_regular_file(path) && toml::parse_file(path).contains("device");
    } catch (const toml::parse_error&) {
        return false;
    }
}

DeviceStudy load_device_study(const std::string& path, const std::vector<std::string>& extra_sets, int seeds_override) {
    if (!fs::is_regular_file(path)) throw ConfigError("study file '" + path + "' not found");
    const toml::table root = cfg::parse_file(path, "study");
    DeviceStudy s;
    s.path = path;
    const std::string where = "device study '" + path + "': ";
    const std::string allowed = "device, description, seeds, [set], [cases.NAME]";
    for (const auto& [k, v] : root) {
        const std::string key(k.str());
        if (key != "device" && key != "description" && key != "seeds" && key != "set" && key != "cases")
            throw ConfigError(where + "unknown key '" + key + "' (allowed in a device study: " + allowed + ")");
    }
    const toml::node* d = root.get("device");
    if (!d->as_string() || d->as_string()->get().empty())
        throw ConfigError(where + "key 'device' = " + cfg::describe(*d) + ": must be a device file's path (TOML), relative "
                                  "to the study file");
    fs::path dev(d->as_string()->get());
    if (dev.is_relative()) dev = fs::path(path).parent_path() / dev;
    if (!fs::is_regular_file(dev))
        throw ConfigError(where + "key 'device' = \"" + d->as_string()->get() + "\": file '" + dev.string() + "' not found");
    s.device = dev.lexically_normal().string();
    if (const toml::node* n = root.get("description"); n && !n->as_string())
        throw ConfigError(where + "key 'description' must be a string");
    s.seeds = study_seeds(root, where, seeds_override);
    // A table of device keys as overrides "key=literal" in file order (a key twice refused).
    auto overrides = [&](const toml::node& t, const std::string& table) {
        if (!t.as_table()) throw ConfigError(where + "'" + table + "' must be a table of device keys");
        std::vector<std::string> out;
        std::set<std::string> seen;
        for (const FlatEntry& e : flat_in_order(*t.as_table())) {
            std::string lit, label;
            if (!scalar_literal(*e.node, lit, label))
                throw ConfigError(where + table + " key '" + e.key + "' = " + cfg::describe(*e.node) +
                                  ": must be a number, string or boolean");
            if (e.key == "simulation.seed" && s.seeds > 0)
                throw ConfigError(where + table + " key 'simulation.seed': the study's seeds set it (leave it out, or "
                                              "the key 'seeds')");
            if (!seen.insert(e.key).second)
                throw ConfigError(where + table + " key '" + e.key + "' is given twice: keep one");
            out.push_back(e.key + "=" + lit);
        }
        return out;
    };
    if (const toml::node* st = root.get("set")) s.set = overrides(*st, "[set]");
    // The keys of the file's [set]: a case that gives one again is refused, as a damper study
    // refuses a key in both [set] and [grid] (the case's value would silently win).
    std::set<std::string> set_keys;
    for (const std::string& o : s.set) set_keys.insert(o.substr(0, o.find('=')));
    for (const std::string& x : extra_sets) s.set.push_back(x);
    const toml::node* cs = root.get("cases");
    if (!cs || !cs->as_table() || cs->as_table()->empty())
        throw ConfigError(where + "no cases: give one table [cases.NAME] of device keys per case (an empty table "
                                  "[cases.base] runs the device file as it is)");
    std::vector<std::pair<std::size_t, DeviceStudyCase>> in_order;
    for (const auto& [k, v] : *cs->as_table()) {
        DeviceStudyCase c;
        c.name = std::string(k.str());
        const bool safe = !c.name.empty() && c.name.size() <= 100 &&
                          std::all_of(c.name.begin(), c.name.end(), [](char ch) {
                              return std::isalnum((unsigned char)ch) || ch == '_' || ch == '-' || ch == '.';
                          }) && c.name.front() != '.';
        if (!safe)
            throw ConfigError(where + "case name '" + c.name + "': must be letters, digits, '_', '-' or '.' (it names "
                                      "the case's folder), not starting with '.'");
        if (!v.as_table())
            throw ConfigError(where + "'cases." + c.name + "' must be a table [cases." + c.name + "] of device keys");
        c.set = overrides(v, "[cases." + c.name + "]");
        for (const std::string& o : c.set)
            if (const std::string key = o.substr(0, o.find('=')); set_keys.count(key))
                throw ConfigError(where + "key '" + key + "' is in both [set] and [cases." + c.name + "]");
        in_order.emplace_back(v.source().begin.line, std::move(c));
    }
    std::stable_sort(in_order.begin(), in_order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [line, c] : in_order) s.cases.push_back(std::move(c));
    // Every case as `vppdem device --set` would read it, before anything runs.
    for (const DeviceStudyCase& c : s.cases) {
        std::vector<std::string> all = s.set;
        all.insert(all.end(), c.set.begin(), c.set.end());
        if (s.seeds > 0) all.push_back("simulation.seed=1");
        try {
            (void)load_device(s.device, all);
        } catch (const ConfigError& e) {
            throw ConfigError(where + "case '" + c.name + "': " + e.what());
        }
    }
    return s;
}

int seed_axis(const Study& s) {
    for (std::size_t k = 0; k < s.grid.size(); ++k)
        if (s.grid[k].key == "simulation.seed") return int(k);
    return -1;
}

GridAxis axis_from_text(const std::string& key, const std::string& values) {
    GridAxis ax;
    ax.key = key;
    if (values.find(':') != std::string::npos) {
        bool ints = false;
        for (double v : parse_range(key, values, &ints)) {
            std::string lit, label;
            if (ints) lit = label = std::to_string(std::llround(v));
            else scalar_literal(toml::value<double>(v), lit, label);
            ax.literals.push_back(lit);
            ax.labels.push_back(label);
        }
        return ax;
    }
    std::stringstream ss(values);
    for (std::string item; std::getline(ss, item, ',');) {
        toml::table t;
        try {
            t = toml::parse("v = " + item);
        } catch (const toml::parse_error&) {
            t.insert("v", item);
        }
        std::string lit, label;
        if (!scalar_literal(*t.get("v"), lit, label))
            throw ConfigError("'" + key + "': value '" + item + "' must be a number, string or boolean");
        ax.literals.push_back(lit);
        ax.labels.push_back(label);
    }
    if (ax.literals.empty()) throw ConfigError("'" + key + "': no values given");
    return ax;
}

std::vector<StudyCase> expand_study(const Study& s) {
    std::size_t total = 1;
    for (const GridAxis& a : s.grid) {
        total *= a.literals.size();
        if (total > 100000) throw ConfigError("study '" + s.path + "': the grid has more than 100000 cases");
    }
    bool threads_given = false;
    for (const std::string& o : s.set)
        if (o.starts_with("simulation.threads=")) threads_given = true;
    for (const GridAxis& a : s.grid)
        if (a.key == "simulation.threads") threads_given = true;

    std::vector<StudyCase> cases(total);
    std::map<std::string, int> groups;
    std::set<std::string> names;
    const int seed = seed_axis(s);  // the axis left out of name_without_seed
    for (std::size_t i = 0; i < total; ++i) {
        StudyCase& c = cases[i];
        c.index = i;
        if (!threads_given) c.overrides.push_back("simulation.threads=1");
        c.overrides.insert(c.overrides.end(), s.set.begin(), s.set.end());
        std::size_t rest = i;
        std::vector<std::size_t> idx(s.grid.size());
        for (std::size_t k = s.grid.size(); k-- > 0;) {  // last key varies fastest
            idx[k] = rest % s.grid[k].literals.size();
            rest /= s.grid[k].literals.size();
        }
        std::string group_key;
        for (std::size_t k = 0; k < s.grid.size(); ++k) {
            const GridAxis& a = s.grid[k];
            c.overrides.push_back(a.key + "=" + a.literals[idx[k]]);
            c.labels.push_back(a.labels[idx[k]]);
            if (k) c.name += '_';
            c.name += sanitize(a.key + "=" + a.labels[idx[k]]);
            if (seed >= 0 && int(k) != seed)
                c.name_without_seed += (c.name_without_seed.empty() ? "" : "_") + sanitize(a.key + "=" + a.labels[idx[k]]);
            if (!is_shareable_key(a.key)) group_key += a.key + "=" + a.literals[idx[k]] + "\n";
        }
        if (seed >= 0 && c.name_without_seed.empty()) c.name_without_seed = "base";
        if (c.name.empty()) c.name = "base";
        if (names.count(c.name)) c.name += "_" + std::to_string(i);
        names.insert(c.name);
        if (!s.share_preparation) group_key = std::to_string(i);
        auto [it, inserted] = groups.emplace(group_key, int(groups.size()));
        c.group = it->second;
        if (inserted) c.preparer = i;
        else
            for (std::size_t j = 0; j < i; ++j)
                if (cases[j].group == c.group) {
                    c.preparer = j;
                    break;
                }
        try {
            c.config = load_config(s.base, c.overrides);
        } catch (const std::exception& e) {
            throw ConfigError("study '" + s.path + "', case " + c.name + ": " + e.what());
        }
    }
    return cases;
}

std::string list_cases(const std::vector<StudyCase>& cases, const std::map<int, std::string>& samples) {
    std::string out;
    for (const StudyCase& c : cases) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%4zu  prep %-3d ", c.index + 1, c.group + 1);
        const auto sample = samples.find(c.group);
        const std::string how = c.preparer != c.index ? "branches from " + cases[c.preparer].name
                                : sample != samples.end() ? "branches from " + sample->second
                                                          : std::string("prepares");
        out += buf + c.name + "  (" + how + ")\n";
    }
    return out;
}

}  // namespace vpp

#include "vpp/study.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#ifdef VPPDEM_WITH_MPI
#include <mpi.h>
#endif

#include <nlohmann/json.hpp>

#include "scene/config.h"
#include "scene/scene_runner.h"
#include "scene/threads.h"
#include "dem/io/csv.h"
#include "vpp/damper.h"
#include "vpp/settings.h"
#include "vpp/settle.h"
#include "vpp/stats.h"

namespace vpp {

namespace fs = std::filesystem;
using cfg::ConfigError;

// Which keys may differ between the cases of one preparation: the settings table's rule and
// why (vpp/settings.cpp, shares_preparation).
bool is_shareable_key(const std::string& key) { return may_share_preparation(key); }

namespace {

// A value of [set] or [grid] as a TOML literal (for --set) and as a label (names, CSV).
bool scalar_literal(const toml::node& n, std::string& literal, std::string& label) {
    if (auto i = n.as_integer()) {
        literal = label = std::to_string(i->get());
        return true;
    }
    if (auto f = n.as_floating_point()) {
        const double v = f->get();
        if (!std::isfinite(v)) return false;
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

// Cells of summary.csv and summary_cases.csv: the CSV rules every hand-built table shares
// (dem/io/csv.h).
std::string csv_field(const std::string& s) { return dem::csv_text(s); }
std::string num(double v) { return dem::csv_number(v); }

std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// What identifies a case's inputs: written to DIR/<case>/case.toml, compared on resume.
std::string case_record(const Study& s, const StudyCase& c) {
    std::ostringstream os;
    os << "# vppdem sweep case (compared when the sweep resumes)\n";
    if (!s.base.empty())
        os << "base = \"" << fs::absolute(s.base).lexically_normal().string() << "\"\nbase_hash = \""
           << std::hash<std::string>{}(read_text(s.base)) << "\"\n";
    os << "overrides = [\n";
    for (const std::string& o : c.overrides) {
        os << "  \"";
        for (char ch : o) {
            if (ch == '"' || ch == '\\') os << '\\';
            os << ch;
        }
        os << "\",\n";
    }
    os << "]\n";
    return os.str();
}

// A case folder written for other settings (its case.toml differs from `record`): refused rather
// than mixing results of two studies.
void check_case_folder(const fs::path& dir, const std::string& record) {
    if (fs::exists(dir / "case.toml") && read_text(dir / "case.toml") != record)
        throw std::runtime_error("folder '" + dir.string() +
                                 "' holds a case run with other settings (see its case.toml); the study "
                                 "changed: use another --out, or remove the folder");
}

// Shares of the dissipation in a cycle: friction / total, damping / total (NaN without energy).
void dissipation_shares(double friction, double damping, double viscous, CaseOutcome& o) {
    const double total = friction + damping + viscous;
    if (!(total > 0)) return;
    o.friction_share = friction / total;
    o.damping_share = damping / total;
}

// The last cycle of a finished case folder (cycles.csv), the stationarity of its cycles (the
// case's analysis.settle_tolerance applied to the W column, as the damper did), its run time
// and warnings (summary.json).
CaseOutcome read_finished(const fs::path& dir, const Config& config) {
    CaseOutcome o;
    o.ok = true;
    o.skipped = true;
    std::vector<std::string> header;
    const auto rows = dem::read_numeric_csv((dir / "cycles.csv").string(), 4, &header);
    if (rows.empty()) throw std::runtime_error((dir / "cycles.csv").string() + " holds no cycle");
    auto index = [&](const std::string& name) -> long {
        const auto it = std::find(header.begin(), header.end(), name);
        return it == header.end() ? -1 : long(it - header.begin());
    };
    auto col = [&](const std::string& name) {
        const long k = index(name);
        if (k < 0) throw std::runtime_error((dir / "cycles.csv").string() + ": no column " + name);
        return rows.back()[std::size_t(k)];
    };
    o.W = col("W");
    o.dissipated_energy = col("dissipated_energy");
    o.peak_force = col("peak_force");
    if (index("friction_dissipation") >= 0 && index("damping_dissipation") >= 0 && index("viscous_dissipation") >= 0)
        dissipation_shares(col("friction_dissipation"), col("damping_dissipation"), col("viscous_dissipation"), o);
    std::vector<CycleResult> cycles;
    for (const auto& r : rows) {
        CycleResult c;
        c.cycle = int(std::lround(r[std::size_t(index("cycle"))]));
        c.W = r[std::size_t(index("W"))];
        cycles.push_back(c);
    }
    const Settling st = settle_cycles(cycles, config.analysis.settle_tolerance);
    o.W_settled = st.W_mean;
    o.settled_cycles = int(st.count);
    o.first_settled = st.first;
    // A key that is absent (a summary of an older vppdem) keeps its default; one that is not a
    // number (null: a non-finite value) reads as 0, as the string search before did.
    const nlohmann::json js = nlohmann::json::parse(read_text(dir / "summary.json"), nullptr, false);
    auto number = [](const nlohmann::json& obj, const char* key, auto& out) {
        if (!obj.is_object()) return;
        const auto it = obj.find(key);
        using T = std::remove_reference_t<decltype(out)>;
        if (it != obj.end()) out = it->is_number() ? T(it->template get<double>()) : T(0);
    };
    number(js, "run_seconds", o.run_seconds);
    number(js, "grains", o.grains);
    if (js.is_object() && js.contains("preparation")) number(js["preparation"], "packing_fraction", o.packing_fraction);
    if (js.is_object() && js.contains("warnings") && js["warnings"].is_array())
        for (const nlohmann::json& w : js["warnings"]) {
            if (!w.is_string()) break;  // anything but a string ends the list, as before
            o.warnings.push_back(w.get<std::string>());
        }
    return o;
}

std::string one_line(std::string msg) {
    for (char& c : msg)
        if (c == '\t' || c == '\n' || c == '\r') c = ' ';
    return msg;
}

// One case's outcome as a line of tab-separated fields (MPI gather); the message last.
std::string serialize(std::size_t i, const CaseOutcome& o) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%zu\t%d\t%d\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%d\t%d\t%.17g\t%.17g\t%d\t%.17g\t",
                  i, int(o.ok), int(o.skipped), o.W, o.dissipated_energy, o.peak_force, o.run_seconds, o.W_settled,
                  o.settled_cycles, o.first_settled, o.friction_share, o.damping_share, o.grains, o.packing_fraction);
    std::string warnings;
    for (const std::string& w : o.warnings) {
        if (!warnings.empty()) warnings += '\x1f';
        warnings += one_line(w);
    }
    return buf + warnings + "\t" + one_line(o.message) + "\n";
}

void deserialize(const std::string& text, std::vector<CaseOutcome>& out) {
    std::istringstream is(text);
    constexpr int kFields = 15;  // before the message
    for (std::string line; std::getline(is, line);) {
        if (line.empty()) continue;
        std::vector<std::string> f;
        std::size_t p = 0;
        for (int k = 0; k < kFields; ++k) {
            const std::size_t q = line.find('\t', p);
            f.push_back(line.substr(p, q - p));
            p = q + 1;
        }
        CaseOutcome o;
        const std::size_t i = std::stoul(f[0]);
        auto num = [&](int k) { return std::strtod(f[std::size_t(k)].c_str(), nullptr); };
        o.ok = f[1] == "1";
        o.skipped = f[2] == "1";
        o.W = num(3);
        o.dissipated_energy = num(4);
        o.peak_force = num(5);
        o.run_seconds = num(6);
        o.W_settled = num(7);
        o.settled_cycles = std::atoi(f[8].c_str());
        o.first_settled = std::atoi(f[9].c_str());
        o.friction_share = num(10);
        o.damping_share = num(11);
        o.grains = std::atoi(f[12].c_str());
        o.packing_fraction = num(13);
        std::stringstream ws(f[14]);
        for (std::string w; std::getline(ws, w, '\x1f');) o.warnings.push_back(w);
        o.message = line.substr(p);
        if (i < out.size()) out[i] = o;
    }
}

[[maybe_unused]] bool mpi_active() {
#ifdef VPPDEM_WITH_MPI
    int init = 0, fin = 0;
    MPI_Initialized(&init);
    MPI_Finalized(&fin);
    return init && !fin;
#else
    return false;
#endif
}

void barrier() {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

// Rank 0 receives every rank's text (others get their own back).
std::string gather_text(const std::string& mine, int ranks) {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active() && ranks > 1) {
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        int len = int(mine.size());
        std::vector<int> lens(ranks), displs(ranks);
        MPI_Gather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::string all;
        if (rank == 0) {
            int total = 0;
            for (int r = 0; r < ranks; ++r) {
                displs[r] = total;
                total += lens[r];
            }
            all.resize(std::size_t(total));
        }
        MPI_Gatherv(mine.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
        return rank == 0 ? all : mine;
    }
#endif
    (void)ranks;
    return mine;
}

int broadcast_int(int v) {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return v;
}

}  // namespace

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

Study load_study(const std::string& path, const std::vector<std::string>& extra_sets, int seeds_override) {
    if (!fs::is_regular_file(path)) throw ConfigError("study file '" + path + "' not found");
    const toml::table root = cfg::parse_file(path, "study");
    Study s;
    s.path = path;
    const std::string where = "study '" + path + "': ";
    static const std::set<std::string> allowed = {"base", "description", "share_preparation", "seeds", "set", "grid"};
    for (const auto& [k, v] : root) {
        const std::string key(k.str());
        if (!allowed.count(key))
            throw ConfigError(where + "unknown key '" + key +
                              "' (allowed: base, description, share_preparation, seeds, [set], [grid])");
    }
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
    if (seeds_override > 0) seeds = seeds_override;
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
            s.grid.push_back(std::move(ax));
        }
    }
    if (seeds > 0) {
        // The ensemble: simulation.seed = 1..seeds as the last grid key (varying fastest), so
        // the seeds of one case sit side by side; --seeds replaces a seed list of [grid].
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
            if (!is_shareable_key(a.key)) group_key += a.key + "=" + a.literals[idx[k]] + "\n";
        }
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
            c.config = load_config(s.base, c.overrides, damper_command_defaults());
        } catch (const std::exception& e) {
            throw ConfigError("study '" + s.path + "', case " + c.name + ": " + e.what());
        }
    }
    return cases;
}

std::string list_cases(const std::vector<StudyCase>& cases) {
    std::string out;
    for (const StudyCase& c : cases) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%4zu  prep %-3d ", c.index + 1, c.group + 1);
        out += buf + c.name + (c.preparer == c.index ? "  (prepares)" : "  (branches from " + cases[c.preparer].name + ")") + "\n";
    }
    return out;
}

std::string summary_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes) {
    std::string out;
    for (const GridAxis& a : s.grid) out += csv_field(a.key) + ",";
    out += "W,dissipated_energy,peak_force,run_seconds,status,case,"
           "W_settled,settled_cycles,first_settled_cycle,friction_share,damping_share,grains,packing_fraction,warnings\n";
    for (std::size_t i = 0; i < cases.size(); ++i) {
        for (const std::string& l : cases[i].labels) out += csv_field(l) + ",";
        const CaseOutcome& o = outcomes[i];
        if (o.ok) out += num(o.W) + "," + num(o.dissipated_energy) + "," + num(o.peak_force) + ",";
        else out += ",,,";
        out += num(o.run_seconds) + "," + csv_field(o.ok ? "ok" : o.not_run ? "not run" : "failed: " + o.message) + "," +
               csv_field(cases[i].name) + ",";
        if (o.ok)
            out += num(o.W_settled) + "," + std::to_string(o.settled_cycles) + "," +
                   (o.first_settled > 0 ? std::to_string(o.first_settled) : std::string()) + "," +
                   num(o.friction_share) + "," + num(o.damping_share) + "," + std::to_string(o.grains) + "," +
                   num(o.packing_fraction) + ",";
        else
            out += ",,,,,,,";
        std::string w;
        for (const std::string& x : o.warnings) {
            if (!w.empty()) w += " | ";
            w += x;
        }
        out += csv_field(w) + "\n";
    }
    return out;
}

namespace {

// A quantity of kEnsembleQuantities or kPairedQuantities by its column name.
double quantity(const CaseOutcome& o, const std::string& q) {
    if (q == "W") return o.W;
    if (q == "W_settled") return o.W_settled;
    if (q == "peak_force") return o.peak_force;
    if (q == "dissipated_energy") return o.dissipated_energy;
    if (q == "friction_share") return o.friction_share;
    if (q == "damping_share") return o.damping_share;
    if (q == "packing_fraction") return o.packing_fraction;
    throw std::logic_error("no study quantity '" + q + "'");
}

}  // namespace

std::vector<std::vector<std::size_t>> ensemble_groups(const Study& s, const std::vector<StudyCase>& cases) {
    const int seed = seed_axis(s);
    std::vector<std::vector<std::size_t>> groups;
    std::map<std::vector<std::string>, std::size_t> index;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        std::vector<std::string> key = cases[i].labels;
        if (seed >= 0) key.erase(key.begin() + seed);
        const auto [it, inserted] = index.emplace(key, groups.size());
        if (inserted) groups.emplace_back();
        groups[it->second].push_back(i);
    }
    return groups;
}

std::string cases_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes) {
    const int seed = seed_axis(s);
    std::string out;
    for (std::size_t k = 0; k < s.grid.size(); ++k)
        if (int(k) != seed) out += csv_field(s.grid[k].key) + ",";
    out += "seeds,ok";
    for (const std::string& q : kEnsembleQuantities) out += "," + q + "_n," + q + "_mean," + q + "_sd," + q + "_ci95";
    out += ",cases\n";
    for (const auto& g : ensemble_groups(s, cases)) {
        const StudyCase& first = cases[g.front()];
        for (std::size_t k = 0; k < first.labels.size(); ++k)
            if (int(k) != seed) out += csv_field(first.labels[k]) + ",";
        std::size_t ok = 0;
        for (std::size_t i : g) ok += outcomes[i].ok;
        out += std::to_string(g.size()) + "," + std::to_string(ok);
        for (const std::string& q : kEnsembleQuantities) {
            std::vector<double> x;
            for (std::size_t i : g)
                if (outcomes[i].ok) x.push_back(quantity(outcomes[i], q));
            const Interval iv = mean_interval(x);
            for (const std::string& field : {std::to_string(iv.n), num(iv.mean), num(iv.sd), num(iv.half)}) {
                out += ',';
                out += field;
            }
        }
        std::string names;
        for (std::size_t i : g) {
            if (!names.empty()) names += ';';
            names += cases[i].name;
        }
        out += "," + csv_field(names) + "\n";
    }
    return out;
}

std::string paired_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes) {
    const int seed = seed_axis(s);
    if (seed < 0 || s.grid[std::size_t(seed)].labels.size() < 2) return "";
    // The case at grid position (i_0, i_1, ...) is sum_k i_k stride_k: expand_study's order, the
    // first axis slowest. Pairs are found by this arithmetic, not by matching labels.
    const std::size_t axes = s.grid.size(), sk = std::size_t(seed), seeds = s.grid[sk].labels.size();
    std::vector<std::size_t> stride(axes, 1);
    for (std::size_t k = axes - 1; k > 0; --k) stride[k - 1] = stride[k] * s.grid[k].labels.size();
    if (cases.size() != stride[0] * s.grid[0].labels.size() || outcomes.size() != cases.size())
        throw std::logic_error("paired_csv: the cases are not the study's full grid");
    auto position = [&](std::size_t i, std::size_t k) { return i / stride[k] % s.grid[k].labels.size(); };

    std::string out = "key,value,reference,group,quantity,n,diff_mean,diff_sd,diff_ci95,ref_mean,rel_diff\n";
    for (std::size_t a = 0; a < axes; ++a) {
        const GridAxis& axis = s.grid[a];
        if (a == sk || axis.labels.size() < 2) continue;
        // One group per combination of the other axes: its run at A's reference and the first seed.
        for (std::size_t base = 0; base < cases.size(); ++base) {
            if (position(base, a) != 0 || position(base, sk) != 0) continue;
            std::string group;
            for (std::size_t k = 0; k < axes; ++k) {
                if (k == a || k == sk) continue;
                if (!group.empty()) group += ';';
                group += s.grid[k].key + "=" + cases[base].labels[k];
            }
            for (std::size_t v = 1; v < axis.labels.size(); ++v)
                for (const std::string& q : kPairedQuantities) {
                    std::vector<double> diff, ref;
                    for (std::size_t j = 0; j < seeds; ++j) {
                        const std::size_t r = base + j * stride[sk], c = r + v * stride[a];
                        if (!outcomes[r].ok || !outcomes[c].ok) continue;
                        const double qr = quantity(outcomes[r], q), qc = quantity(outcomes[c], q);
                        if (!std::isfinite(qr) || !std::isfinite(qc)) continue;
                        diff.push_back(qc - qr);
                        ref.push_back(qr);
                    }
                    const Interval d = mean_interval(diff);
                    const double ref_mean = mean_interval(ref).mean;
                    out += csv_field(axis.key) + "," + csv_field(axis.labels[v]) + "," + csv_field(axis.labels[0]) + "," +
                           csv_field(group) + "," + q + "," + std::to_string(d.n) + "," + num(d.mean) + "," +
                           num(d.sd) + "," + num(d.half) + "," + num(ref_mean) + "," + num(d.mean / ref_mean) + "\n";
                }
        }
    }
    return out;
}

namespace {

// The tables of a sweep, each written atomically into `out`: summary.csv, summary_cases.csv and,
// with seeds, summary_paired.csv. Returns the names written, for the closing message.
std::string write_tables(const fs::path& out, const Study& s, const std::vector<StudyCase>& cases,
                         const std::vector<CaseOutcome>& outcomes) {
    dem::write_text_atomic((out / "summary.csv").string(), summary_csv(s, cases, outcomes));
    dem::write_text_atomic((out / "summary_cases.csv").string(), cases_csv(s, cases, outcomes));
    std::string names = (out / "summary.csv").string() + ", summary_cases.csv";
    if (const std::string paired = paired_csv(s, cases, outcomes); !paired.empty()) {
        dem::write_text_atomic((out / "summary_paired.csv").string(), paired);
        names += ", summary_paired.csv";
    }
    return names;
}

// --report-only: the tables from the records already in DIR. Only reads: no case folder, FAILED
// marker or case.toml is written, so a sweep running into DIR at the same time is not disturbed
// (a case it finishes meanwhile is either read whole or not at all: summary.json is written
// last and atomically).
SweepResult report_sweep(const Study& s, const SweepOptions& opt, SweepResult res) {
    const fs::path out(opt.out_dir);
    if (!fs::is_directory(out))
        throw ConfigError("--out '" + opt.out_dir + "': " + (fs::exists(out) ? "not a directory" : "no such folder") +
                          " (--report-only reads the cases a sweep finished there and runs nothing)");
    res.outcomes.assign(res.cases.size(), CaseOutcome{});
    if (opt.rank != 0) return res;
    std::size_t finished = 0;
    for (std::size_t i = 0; i < res.cases.size(); ++i) {
        const StudyCase& c = res.cases[i];
        const fs::path dir = out / c.name;
        CaseOutcome& o = res.outcomes[i];
        if (!fs::exists(dir / "summary.json")) {
            o.not_run = true;
            o.run_seconds = CaseOutcome::kNaN;  // an empty cell: it has not run, rather than ran 0 s
            continue;
        }
        try {
            check_case_folder(dir, case_record(s, c));
            o = read_finished(dir, c.config);
            ++finished;
        } catch (const std::exception& e) {
            o.message = e.what();
            ++res.failed;
            if (!opt.quiet) std::fprintf(stderr, "sweep: %s: unreadable: %s\n", c.name.c_str(), e.what());
        }
    }
    const std::string names = write_tables(out, s, res.cases, res.outcomes);
    if (!opt.quiet)
        std::fprintf(stderr, "sweep --report-only: %zu of %zu cases finished%s; ran nothing; wrote %s\n", finished,
                     res.cases.size(), res.failed ? (", " + std::to_string(res.failed) + " unreadable").c_str() : "",
                     names.c_str());
    return res;
}

}  // namespace

SweepResult run_sweep(const Study& s, const SweepOptions& opt) {
    SweepResult res;
    res.cases = expand_study(s);  // every case's config is checked before anything runs
    if (opt.report_only) return report_sweep(s, opt, std::move(res));
    const auto& cases = res.cases;
    const fs::path out(opt.out_dir);
    if (fs::exists(out) && !fs::is_directory(out))
        throw ConfigError("--out '" + opt.out_dir + "' exists and is not a directory");
    // The ranks share the folder, so one lock serves them all: rank 0's. The others wait for it
    // at the barrier; if rank 0 is refused, its error aborts them there, before they write.
    if (opt.rank == 0) res.lock = scene::lock_output_dir(opt.out_dir);
    barrier();
    fs::create_directories(out);
    res.outcomes.assign(cases.size(), CaseOutcome{});

    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < cases.size(); ++i)
        if (int(i % std::size_t(std::max(1, opt.ranks))) == opt.rank) mine.push_back(i);
    // Preparers first, then the branches, each in grid order.
    std::stable_sort(mine.begin(), mine.end(), [&](std::size_t a, std::size_t b) {
        return (cases[a].preparer == a) > (cases[b].preparer == b);
    });
    // Failure markers of an earlier attempt are cleared before any rank looks at them.
    for (std::size_t i : mine) fs::remove(out / cases[i].name / "FAILED");
    barrier();

    int jobs = opt.jobs;
    if (jobs <= 0) {
        // The free cores, not all of them: a busy core slows every case's threads (scene/threads.h).
        const int cores = scene::default_threads();
        const int per_case = cases.empty() ? 1 : std::max(1, cases[0].config.simulation.threads);
        jobs = opt.ranks > 1 ? 1 : std::max(1, cores / per_case);
    }
    jobs = std::max(1, std::min<int>(jobs, int(mine.size())));

    std::mutex mu;
    std::map<std::size_t, int> state;  // 0 pending, 1 running, 2 finished
    for (std::size_t i : mine) state[i] = 0;
    std::size_t finished = 0;
    int ngroups = 0;
    for (const StudyCase& c : cases) ngroups = std::max(ngroups, c.group + 1);
    if (!opt.quiet && opt.rank == 0)
        std::fprintf(stderr, "sweep: %zu cases, %d preparation(s), %d job(s)%s, out %s\n", cases.size(), ngroups, jobs,
                     opt.ranks > 1 ? (" per rank x " + std::to_string(opt.ranks) + " ranks").c_str() : "",
                     opt.out_dir.c_str());

    auto report = [&](std::size_t i, const CaseOutcome& o) {
        if (opt.quiet) return;
        std::lock_guard<std::mutex> lk(mu);
        const std::string who = (opt.ranks > 1 ? "rank " + std::to_string(opt.rank) + " " : "");
        if (o.ok)
            std::fprintf(stderr, "%s[%zu/%zu] %s: %s W = %.5g J/m^2, energy %.5g J, peak %.4g N (%.1f s)\n", who.c_str(),
                         i + 1, cases.size(), cases[i].name.c_str(), o.skipped ? "done earlier," : "ok,", o.W,
                         o.dissipated_energy, o.peak_force, o.run_seconds);
        else
            std::fprintf(stderr, "%s[%zu/%zu] %s: FAILED: %s\n", who.c_str(), i + 1, cases.size(),
                         cases[i].name.c_str(), o.message.c_str());
    };

    // What a case waits for: its preparer's prepared.ckpt (unless it has its own checkpoint).
    // Returns 1 ready, 0 wait, -1 the preparation failed (message set).
    auto readiness = [&](std::size_t i, std::string& why) -> int {
        const StudyCase& c = cases[i];
        const fs::path dir = out / c.name;
        if (c.preparer == i || fs::exists(dir / "summary.json") || fs::exists(dir / "run.ckpt")) return 1;
        const fs::path pdir = out / cases[c.preparer].name;
        if (fs::exists(pdir / "prepared.ckpt")) return 1;
        if (fs::exists(pdir / "FAILED")) {
            why = "its preparation (case " + cases[c.preparer].name + ") failed";
            return -1;
        }
        // The preparer finished earlier but its prepared.ckpt is gone: prepare this case itself.
        if (fs::exists(pdir / "summary.json")) return 2;
        return 0;
    };

    // Cancelling (SweepOptions::progress): `stop` makes the workers take no new case and the
    // running cases throw at their next poll; `hook_error` keeps what the hook threw.
    std::atomic<bool> stop{false};
    std::exception_ptr hook_error;
    std::mutex hook_mu;  // one hook call at a time
    auto ask_hook = [&](std::size_t done, const std::string& name) {
        if (!opt.progress || stop.load()) return;
        std::lock_guard<std::mutex> lk(hook_mu);
        if (stop.load()) return;
        try {
            if (!opt.progress(done, mine.size(), name)) stop.store(true);
        } catch (...) {
            if (!hook_error) hook_error = std::current_exception();
            stop.store(true);
        }
    };

    auto run_case = [&](std::size_t i, bool self_prepare) -> CaseOutcome {
        const StudyCase& c = cases[i];
        const fs::path dir = out / c.name;
        CaseOutcome o;
        try {
            fs::create_directories(dir);
            const std::string rec = case_record(s, c);
            check_case_folder(dir, rec);
            if (fs::exists(dir / "summary.json")) return read_finished(dir, c.config);
            dem::write_text_atomic((dir / "case.toml").string(), rec);
            DamperOptions d;
            d.out_dir = dir.string();
            d.quiet = true;
            d.plot = false;
            d.overwrite = true;  // the folder holds case.toml, perhaps leftovers of a killed start
            d.checkpoint_every = opt.checkpoint_every;
            if (opt.progress)
                d.progress = [&](const char*, uint64_t, uint64_t, double) {
                    ask_hook(0, "");
                    if (stop.load()) throw SweepStopped();
                };
            if (fs::exists(dir / "run.ckpt")) d.from = (dir / "run.ckpt").string();
            else if (c.preparer != i && !self_prepare) d.from = (out / cases[c.preparer].name / "prepared.ckpt").string();
            const DamperResult r = run_damper(c.config, d);
            if (r.cycles.empty()) throw std::runtime_error("the run recorded no complete cycle");
            o.ok = true;
            const CycleResult& last = r.cycles.back();
            o.W = last.W;
            o.dissipated_energy = last.dissipated_energy;
            o.peak_force = last.peak_force;
            o.run_seconds = r.run_seconds;
            o.W_settled = r.settling.W_mean;
            o.settled_cycles = int(r.settling.count);
            o.first_settled = r.settling.first;
            if (last.has_energy)
                dissipation_shares(last.friction_dissipation, last.damping_dissipation, last.viscous_dissipation, o);
            o.warnings = r.warnings;
            o.grains = int(r.grains);
            if (const auto it = r.report.find("prepare.packing_fraction"); it != r.report.end())
                o.packing_fraction = it->second;
        } catch (const SweepStopped&) {
            // Stopped, not failed: no FAILED marker, the next run of the sweep takes it up.
            o.ok = false;
            o.message = "stopped";
        } catch (const dem::FolderLocked& e) {
            // Another process (a damper run started by hand) writes into the case folder: failed,
            // but no FAILED marker in a folder that is not ours now.
            o.ok = false;
            o.message = e.what();
        } catch (const std::exception& e) {
            o.ok = false;
            o.message = e.what();
            try {
                dem::write_text_atomic((dir / "FAILED").string(), o.message + "\n");
            } catch (...) {
            }
        }
        return o;
    };

    auto worker = [&]() {
        for (;;) {
            std::size_t pick = SIZE_MAX;
            bool self_prepare = false;
            {
                std::unique_lock<std::mutex> lk(mu);
                if (finished == mine.size() || stop.load()) return;
                for (std::size_t i : mine) {
                    if (state[i] != 0) continue;
                    std::string why;
                    const int r = readiness(i, why);
                    if (r == -1) {
                        state[i] = 2;
                        ++finished;
                        res.outcomes[i].ok = false;
                        res.outcomes[i].message = why;
                        lk.unlock();
                        report(i, res.outcomes[i]);
                        lk.lock();
                        break;  // rescan
                    }
                    if (r > 0) {
                        pick = i;
                        self_prepare = r == 2;
                        state[i] = 1;
                        break;
                    }
                }
            }
            if (pick == SIZE_MAX) {
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
                continue;
            }
            const CaseOutcome o = run_case(pick, self_prepare);
            std::size_t done = 0;
            {
                std::lock_guard<std::mutex> lk(mu);
                res.outcomes[pick] = o;
                state[pick] = 2;
                done = ++finished;
            }
            if (stop.load()) return;  // a stopped case is neither reported nor counted as done
            report(pick, o);
            ask_hook(done, cases[pick].name);
        }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    if (hook_error) std::rethrow_exception(hook_error);
    if (stop.load()) throw SweepStopped();

    // Gather on rank 0 and write the summary.
    std::string text;
    for (std::size_t i : mine) text += serialize(i, res.outcomes[i]);
    const std::string all = gather_text(text, opt.ranks);
    if (opt.rank == 0) {
        deserialize(all, res.outcomes);
        for (const CaseOutcome& o : res.outcomes) res.failed += o.ok ? 0 : 1;
        const std::string names = write_tables(out, s, cases, res.outcomes);
        if (!opt.quiet)
            std::fprintf(stderr, "sweep: %zu cases, %d failed; wrote %s\n", cases.size(), res.failed, names.c_str());
    }
    res.failed = broadcast_int(res.failed);
    return res;
}

void mpi_init_if_launched(int* argc, char*** argv, int* rank, int* ranks) {
    *rank = 0;
    *ranks = 1;
#ifdef VPPDEM_WITH_MPI
    // Only under a launcher: a plain run does not start the MPI runtime.
    const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") ||
                          std::getenv("PMIX_RANK") || std::getenv("MPI_LOCALNRANKS");
    if (!launched) return;
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, ranks);
#else
    (void)argc;
    (void)argv;
#endif
}

void mpi_abort_if_active(int code) {
#ifdef VPPDEM_WITH_MPI
    int ranks = 1;
    if (mpi_active()) {
        MPI_Comm_size(MPI_COMM_WORLD, &ranks);
        if (ranks > 1) MPI_Abort(MPI_COMM_WORLD, code);
    }
#endif
    (void)code;
}

void mpi_finalize() {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Finalize();
#endif
}

}  // namespace vpp

#include "vpp/study/records.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "dem/io/csv.h"
#include "vpp/damper/damper.h"
#include "vpp/analysis/records.h"
#include "vpp/settings/settings.h"
#include "vpp/analysis/settle.h"
#include "vpp/analysis/stats.h"

namespace vpp {

namespace fs = std::filesystem;
using cfg::ConfigError;

namespace {

// Cells of summary.csv and summary_cases.csv: the CSV rules every hand-built table shares
// (dem/io/csv.h).
std::string csv_field(const std::string& s) { return dem::csv_text(s); }
std::string num(double v) { return dem::csv_number(v); }

std::string read_text(const fs::path& p) { return dem::read_text(p.string()); }

// Shares of the dissipation in a cycle: friction / total, damping / total (NaN without energy).
void dissipation_shares(double friction, double damping, double viscous, CaseOutcome& o) {
    const double total = friction + damping + viscous;
    if (!(total > 0)) return;
    o.friction_share = friction / total;
    o.damping_share = damping / total;
}

// A quantity of kEnsembleQuantities or kPairedQuantities by its column name.
double quantity(const CaseOutcome& o, const std::string& q) {
    for (const OutcomeNumber& n : outcome_numbers())
        if (q == n.name) return n.value(o);
    throw std::logic_error("no study quantity '" + q + "'");
}

// A number of an outcome's JSON: null (how nlohmann writes NaN and infinities) reads as NaN.
double json_real(const nlohmann::json& j, const char* key) {
    const auto it = j.find(key);
    return it != j.end() && it->is_number() ? it->get<double>() : CaseOutcome::kNaN;
}

}  // namespace

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

namespace {

// A case record (case_record's text, TOML) as its settings besides the overrides (base, base_hash)
// and the overrides' values by key, the last of a key winning as in the config. False when the
// text is not such a record.
struct ParsedRecord {
    std::map<std::string, std::string> head, values;
};

bool parse_record(const std::string& text, ParsedRecord& r) {
    toml::table t;
    try {
        t = toml::parse(text);
    } catch (const toml::parse_error&) {
        return false;
    }
    for (const auto& [key, node] : t) {
        if (key.str() == "overrides") continue;
        const auto* v = node.as_string();
        if (!v) return false;
        r.head[std::string(key.str())] = v->get();
    }
    const toml::array* overrides = t["overrides"].as_array();
    if (!overrides) return false;
    for (const toml::node& n : *overrides) {
        const auto* v = n.as_string();
        if (!v) return false;
        const std::string& o = v->get();
        const std::size_t eq = o.find('=');
        if (eq == std::string::npos) return false;
        r.values[o.substr(0, eq)] = o.substr(eq + 1);
    }
    return true;
}

// process.cycles of a record's overrides (0 where absent or not a number).
double record_cycles(const ParsedRecord& r) {
    const auto it = r.values.find("process.cycles");
    double n = 0;
    if (it != r.values.end()) std::istringstream(it->second) >> n;
    return n;
}

// The outcome of a finished case folder from its cycles (read by the caller) and summary.json.
CaseOutcome outcome_of(const fs::path& dir, const std::vector<CycleResult>& cycles, const Config& config) {
    CaseOutcome o;
    o.ok = true;
    if (cycles.empty()) throw std::runtime_error("'" + (dir / "cycles.csv").string() + "' holds no cycle");
    const CycleResult& last = cycles.back();
    o.W = last.W;
    o.dissipated_energy = last.dissipated_energy;
    o.peak_force = last.peak_force;
    if (last.has_energy)
        dissipation_shares(last.friction_dissipation, last.damping_dissipation, last.viscous_dissipation, o);
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

}  // namespace

// A script's branch run before the studies had samples_from (the paper's time-step runs): its
// case.toml holds the one command it ran, `command = "vppdem damper --from SAMPLE ... --set k=v
// ..."`. It is the case of `record` when every --set of the command has the record's value
// (numbers compared as numbers: 0.06e6 and 60000.0 are one value) and every other key of the
// record is one the run took from its sample: a geometry key (simulation.seed among them), as a
// study with samples_match = "geometry" branches.
static bool legacy_branch_fits(const std::string& held, const ParsedRecord& record) {
    toml::table t;
    try {
        t = toml::parse(held);
    } catch (const toml::parse_error&) {
        return false;
    }
    const auto* command = t["command"].as_string();
    if (!command || t.size() != 1) return false;
    std::istringstream words(command->get());
    std::map<std::string, std::string> sets;
    bool from = false;
    for (std::string w, prev; words >> w; prev = w) {
        if (prev == "--from") from = true;
        if (prev != "--set") continue;
        const std::size_t eq = w.find('=');
        if (eq == std::string::npos) return false;
        sets[w.substr(0, eq)] = w.substr(eq + 1);
    }
    if (!from) return false;
    auto same = [](const std::string& a, const std::string& b) {
        if (a == b) return true;
        char* ea = nullptr;
        char* eb = nullptr;
        const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
        return ea != a.c_str() && !*ea && eb != b.c_str() && !*eb && x == y;
    };
    for (const auto& [key, value] : sets) {
        const auto it = record.values.find(key);
        if (it == record.values.end() || !same(it->second, value)) return false;
    }
    for (const auto& [key, value] : record.values) {
        if (sets.count(key)) continue;
        const Setting* s = find_setting(key);
        if (!s || s->acts != Acts::Geometry) return false;
    }
    return true;
}

CaseFolder check_case_folder(const fs::path& dir, const std::string& record) {
    if (!fs::exists(dir / "case.toml")) return CaseFolder::Same;
    const std::string held = read_text(dir / "case.toml");
    if (held == record) return CaseFolder::Same;
    // The study's record parsed once, for both readings of the held one.
    ParsedRecord b;
    const bool parsed = parse_record(record, b);
    if (parsed && legacy_branch_fits(held, b)) return CaseFolder::Same;
    ParsedRecord a;
    if (parsed && parse_record(held, a) && a.head == b.head) {
        // The same settings in another order (an older build wrote --set before [set]): the
        // overrides as the case applies them, the last of a key winning, are what count.
        if (a.values == b.values) return CaseFolder::Same;
        const double na = record_cycles(a), nb = record_cycles(b);
        a.values.erase("process.cycles");
        b.values.erase("process.cycles");
        if (na > 0 && nb > na && a.values == b.values) return CaseFolder::MoreCycles;
    }
    throw std::runtime_error("folder '" + dir.string() +
                             "' holds a case run with other settings (see its case.toml); the study "
                             "changed: use another --out, or remove the folder (a larger process.cycles alone "
                             "continues the cases)");
}

std::vector<std::string> adopt_seedless_runs(const fs::path& out, const Study& s, const std::vector<StudyCase>& cases) {
    std::vector<std::string> adopted;
    const int seed = seed_axis(s);
    if (seed < 0 || !fs::is_directory(out)) return adopted;
    for (const StudyCase& c : cases) {
        const fs::path from = out / c.name_without_seed, to = out / c.name;
        if (c.name_without_seed.empty() || fs::exists(to) || !fs::exists(from / "case.toml")) continue;
        // The case as the study without seeds had it: its overrides less the seed's.
        StudyCase bare = c;
        const auto it = std::find_if(bare.overrides.rbegin(), bare.overrides.rend(),
                                     [](const std::string& o) { return o.starts_with("simulation.seed="); });
        if (it == bare.overrides.rend()) continue;
        bare.overrides.erase(std::next(it).base());
        try {
            // Its seed was the config's: the one seed of the study that ran then.
            if (load_config(s.base, bare.overrides).simulation.seed != c.config.simulation.seed) continue;
            if (check_case_folder(from, case_record(s, bare)) != CaseFolder::Same) continue;
        } catch (const std::exception&) {
            continue;  // other settings: the folder stays as it is, and the sweep refuses it if it runs that case
        }
        fs::rename(from, to);
        dem::write_text_atomic((to / "case.toml").string(), case_record(s, c));
        adopted.push_back(c.name);
    }
    return adopted;
}

std::vector<std::string> run_warning_lines(const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes) {
    struct Kind {
        std::vector<std::string> cases;
        std::string first;
    };
    std::vector<std::pair<std::string, Kind>> kinds;  // in the order first met
    std::size_t finished = 0;
    for (std::size_t i = 0; i < outcomes.size() && i < cases.size(); ++i) {
        if (!outcomes[i].ok) continue;
        ++finished;
        for (const std::string& w : outcomes[i].warnings) {
            const std::string kind = w.substr(0, w.find(':'));
            auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == kind; });
            if (it == kinds.end()) {
                kinds.push_back({kind, Kind{{}, w}});
                it = kinds.end() - 1;
            }
            if (it->second.cases.empty() || it->second.cases.back() != cases[i].name)  // a kind once per run
                it->second.cases.push_back(cases[i].name);
        }
    }
    std::vector<std::string> lines;
    for (const auto& [kind, k] : kinds) {
        std::string which;
        for (std::size_t j = 0; j < k.cases.size() && j < 3; ++j) which += (j ? ", " : "") + k.cases[j];
        if (k.cases.size() > 3) which += ", ...";
        lines.push_back(kind + ": " + std::to_string(k.cases.size()) + " of " + std::to_string(finished) + " runs (" +
                        which + "); " + k.first);
    }
    return lines;
}

std::size_t recorded_cycles(const fs::path& dir) {
    if (!fs::exists(dir / "cycles.csv")) return 0;
    return read_cycles_csv((dir / "cycles.csv").string()).size();
}

std::optional<CaseOutcome> finished_case(const fs::path& dir, const std::string& record, const Config& config) {
    const CaseFolder held = check_case_folder(dir, record);
    if (held != CaseFolder::Same || !fs::exists(dir / "summary.json") || !fs::exists(dir / "cycles.csv"))
        return std::nullopt;
    const std::vector<CycleResult> cycles = read_cycles_csv((dir / "cycles.csv").string());
    if (cycles.size() < std::size_t(config.process.cycles)) return std::nullopt;
    return outcome_of(dir, cycles, config);
}

CaseOutcome read_case_outcome(const fs::path& dir, const Config& config) {
    return outcome_of(dir, read_cycles_csv((dir / "cycles.csv").string()), config);
}

const std::vector<OutcomeNumber>& outcome_numbers() {
    using O = CaseOutcome;
    static const std::vector<OutcomeNumber> t = {
        {"W", "J/m^2", "the last cycle's dissipated energy per lateral area", &O::W, nullptr, true},
        {"dissipated_energy", "J", "the last cycle's loop area", &O::dissipated_energy, nullptr, true},
        {"peak_force", "N", "the last cycle's largest force", &O::peak_force, nullptr, true},
        {"run_seconds", "s", "the run's wall time (summary.json)", &O::run_seconds, nullptr, true, false, true},
        {"W_settled", "J/m^2", "mean W of the stationary cycles (vpp/analysis/settle.h; empty: none)", &O::W_settled},
        {"settled_cycles", "", "how many cycles are stationary", nullptr, &O::settled_cycles},
        {"first_settled_cycle", "", "the first stationary cycle (empty: none)", nullptr, &O::first_settled, false,
         true},
        {"friction_share", "-", "friction / (friction + damping + viscous) in the last cycle (energy ledger)",
         &O::friction_share},
        {"damping_share", "-", "local damping / (the same)", &O::damping_share},
        {"grains", "", "grains in the prepared sample", nullptr, &O::grains},
        {"packing_fraction", "-", "the grains' share of the foil's interior at the end of the preparation",
         &O::packing_fraction},
    };
    return t;
}

std::string outcome_json(std::size_t index, const CaseOutcome& o) {
    nlohmann::ordered_json j;
    j["case"] = index;
    j["ok"] = o.ok;
    j["skipped"] = o.skipped;
    j["not_run"] = o.not_run;
    j["message"] = o.message;
    for (const OutcomeNumber& n : outcome_numbers()) {
        if (n.real) j[n.name] = o.*n.real;
        else j[n.name] = o.*n.count;
    }
    j["warnings"] = o.warnings;
    // Invalid UTF-8 in a message (a path) is replaced, not a reason to lose the outcome.
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void read_outcome_lines(const std::string& text, std::vector<CaseOutcome>& out) {
    std::istringstream is(text);
    for (std::string line; std::getline(is, line);) {
        if (line.empty()) continue;
        const nlohmann::json j = nlohmann::json::parse(line);
        const std::size_t i = j.at("case").get<std::size_t>();
        if (i >= out.size()) continue;
        CaseOutcome o;
        o.ok = j.at("ok").get<bool>();
        o.skipped = j.at("skipped").get<bool>();
        o.not_run = j.at("not_run").get<bool>();
        o.message = j.at("message").get<std::string>();
        for (const OutcomeNumber& n : outcome_numbers()) {
            if (n.real) o.*n.real = json_real(j, n.name);
            else o.*n.count = j.at(n.name).get<int>();
        }
        o.warnings = j.at("warnings").get<std::vector<std::string>>();
        out[i] = o;
    }
}

std::string summary_csv(const Study& s, const std::vector<StudyCase>& cases, const std::vector<CaseOutcome>& outcomes) {
    std::string out;
    for (const GridAxis& a : s.grid) out += csv_field(a.key) + ",";
    // The numbers in two blocks around status and case (the columns' first contract kept them
    // there); a run that did not finish leaves its numbers empty but those any run has.
    auto block = [&](bool before, const CaseOutcome* o) {
        std::string b;
        for (const OutcomeNumber& n : outcome_numbers()) {
            if (n.before_status != before) continue;
            if (!o) b += n.name;
            else if (o->ok || n.any_run) {
                if (n.real) b += num(o->*n.real);
                else if (!(n.zero_empty && o->*n.count == 0)) b += std::to_string(o->*n.count);
            }
            b += ",";
        }
        return b;
    };
    out += block(true, nullptr) + "status,case," + block(false, nullptr) + "warnings\n";
    for (std::size_t i = 0; i < cases.size(); ++i) {
        for (const std::string& l : cases[i].labels) out += csv_field(l) + ",";
        const CaseOutcome& o = outcomes[i];
        out += block(true, &o) + csv_field(o.ok ? "ok" : o.not_run ? "not run" : "failed: " + o.message) + "," +
               csv_field(cases[i].name) + "," + block(false, &o);
        std::string w;
        for (const std::string& x : o.warnings) {
            if (!w.empty()) w += " | ";
            w += x;
        }
        out += csv_field(w) + "\n";
    }
    return out;
}

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
        out.append(",").append(csv_field(names)).append("\n");
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

std::string write_study_tables(const fs::path& out, const Study& s, const std::vector<StudyCase>& cases,
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

namespace {


// The finished runs ("ok" rows) of a published summary.csv; 0 when there is none.
std::size_t ok_rows(const fs::path& summary) {
    if (!fs::exists(summary)) return 0;
    std::istringstream in(read_text(summary));
    std::string line;
    if (!std::getline(in, line)) return 0;
    // The fields up to the status column hold no comma (swept values and numbers).
    auto fields = [](const std::string& l) {
        std::vector<std::string> f;
        for (std::size_t a = 0; a <= l.size();) {
            const std::size_t b = std::min(l.find(',', a), l.size());
            f.push_back(l.substr(a, b - a));
            a = b + 1;
        }
        return f;
    };
    const std::vector<std::string> head = fields(line);
    const auto col = std::find(head.begin(), head.end(), "status") - head.begin();
    if (col == std::ptrdiff_t(head.size())) return 0;
    std::size_t n = 0;
    while (std::getline(in, line)) {
        const std::vector<std::string> f = fields(line);
        n += std::ptrdiff_t(f.size()) > col && f[std::size_t(col)] == "ok";
    }
    return n;
}

}  // namespace

std::size_t restore_published(const fs::path& results, const fs::path& out, const std::vector<StudyCase>& cases) {
    std::size_t n = 0;
    if (!fs::is_directory(results)) return 0;
    for (const StudyCase& c : cases) {
        const fs::path pub = results / c.name, run = out / c.name;
        if (!fs::exists(pub / "summary.json") || fs::exists(run / "summary.json") || fs::exists(run / "run.ckpt")) continue;
        for (const std::string& f : kRunRecords)
            if (fs::exists(pub / f)) dem::copy_text_if_changed(pub / f, run / f);
        ++n;
    }
    return n;
}

std::size_t publish_records(const fs::path& results, const fs::path& out, const std::vector<StudyCase>& cases,
                            const std::vector<CaseOutcome>& outcomes) {
    fs::create_directories(results);
    std::size_t held = 0, finished = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const fs::path run = out / cases[i].name;
        if (outcomes[i].ok) {
            ++finished;
            if (fs::exists(run / "case.toml"))
                for (const std::string& f : kRunRecords)
                    if (fs::exists(run / f)) dem::copy_text_if_changed(run / f, results / cases[i].name / f);
        }
        held += fs::exists(results / cases[i].name / "summary.json");
    }
    if (finished >= ok_rows(results / "summary.csv"))
        for (const std::string& f : kStudyTables)
            if (fs::exists(out / f)) dem::copy_text_if_changed(out / f, results / f);
    if (fs::exists(out / kStudyCommand)) dem::copy_text_if_changed(out / kStudyCommand, results / kStudyCommand);
    return held;
}

std::size_t copy_continued_runs(const fs::path& from, const fs::path& out, const Study& s,
                                const std::vector<StudyCase>& cases, std::vector<std::string>* anew) {
    if (!fs::is_directory(from))
        throw ConfigError("study '" + s.path + "': key 'continues' = \"" + s.continues + "\": no folder '" +
                          from.string() + "' (the study it continues: its --out, relative to the folder that holds this --out)");
    std::vector<const StudyCase*> copy;
    std::string unfinished;
    for (const StudyCase& c : cases) {
        const fs::path src = from / c.name;
        if (fs::exists(out / c.name) || !fs::is_directory(src)) {
            if (!fs::exists(out / c.name) && anew) anew->push_back(c.name);
            continue;
        }
        if (!fs::exists(src / "summary.json")) {
            if (fs::exists(src / "run.ckpt")) unfinished += (unfinished.empty() ? "" : ", ") + c.name;
            else if (anew) anew->push_back(c.name);
            continue;
        }
        if (!fs::exists(src / "run.ckpt")) {
            if (anew) anew->push_back(c.name);
            continue;
        }
        try {
            check_case_folder(src, case_record(s, c));
        } catch (const std::exception& e) {
            throw ConfigError("study '" + s.path + "': key 'continues' = \"" + s.continues + "\": " + e.what());
        }
        copy.push_back(&c);
    }
    if (!unfinished.empty())
        throw ConfigError("study '" + s.path + "': key 'continues' = \"" + s.continues + "\": " + from.string() +
                          " holds runs still going (run.ckpt, no summary.json): " + unfinished +
                          "; let that study finish them first (nothing was copied)");
    fs::create_directories(out);
    for (const StudyCase* c : copy) {
        const fs::path dst = out / c->name, tmp = out / ("." + c->name + ".continuing");
        fs::remove_all(tmp);  // a copy a killed sweep left half made
        fs::create_directories(tmp);
        for (const auto& e : fs::directory_iterator(from / c->name)) {
            if (e.path().filename().string().rfind('.', 0) == 0) continue;  // a lock, a temporary
            fs::copy(e.path(), tmp / e.path().filename(), fs::copy_options::recursive);
        }
        fs::rename(tmp, dst);
    }
    return copy.size();
}

}  // namespace vpp

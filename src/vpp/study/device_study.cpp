#include "vpp/study/device_study.h"

#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dem/io/csv.h"
#include "scene/build_info.h"
#include "scene/config.h"
#include "scene/scene_runner.h"
#include "vpp/analysis/stats.h"
#include "vpp/device/run.h"

namespace vpp {

namespace fs = std::filesystem;
using cfg::ConfigError;

namespace {

// What a run's folder holds of the study, case.toml: the device file and the run's overrides,
// which a later sweep into the folder compares (a study changed under its folder is refused).
std::string case_record(const DeviceStudy& s, const DeviceStudyRun& r) {
    std::string t = "# a run of the device study '" + s.path + "' (vppdem sweep): vppdem device DEVICE --set KEY=VALUE ...\n";
    t += "device = " + nlohmann::json(s.device).dump() + "\nset = [";
    for (std::size_t i = 0; i < r.overrides.size(); ++i) t += (i ? ", " : "") + nlohmann::json(r.overrides[i]).dump();
    return t + "]\n";
}

// The overrides a folder's case.toml records; nullopt when it has none (a run of the script
// before the studies ran devices, accepted as the case its folder names).
std::optional<std::vector<std::string>> recorded_overrides(const fs::path& dir) {
    if (!fs::exists(dir / "case.toml")) return std::nullopt;
    std::vector<std::string> out;
    try {
        const toml::table t = toml::parse_file((dir / "case.toml").string());
        if (const toml::array* a = t["set"].as_array())
            for (const toml::node& n : *a)
                if (n.as_string()) out.push_back(n.as_string()->get());
    } catch (const toml::parse_error&) {
        out = {"(unreadable case.toml)"};
    }
    return out;
}

// The folder's summary.json when the run finished (stage "done"), else null.
nlohmann::json finished_summary(const fs::path& dir) {
    if (!fs::exists(dir / "summary.json")) return nullptr;
    nlohmann::json j = nlohmann::json::parse(dem::read_text((dir / "summary.json").string()), nullptr, false);
    if (j.is_object() && j.value("stage", std::string()) == "done") return j;
    return nullptr;
}

DeviceRunOutcome outcome_of(const nlohmann::json& summary) {
    DeviceRunOutcome o;
    o.status = "ok";
    for (const std::string& k : device_study_numbers()) {
        const auto it = summary.find(k);
        o.numbers.push_back(it != summary.end() && it->is_number() ? it->get<double>() : std::nan(""));
    }
    return o;
}

// tools.csv from the press on (stage >= 2), each value with six digits, gzipped into `to`
// through a temporary name: the published record the device report reads (docs/devices.md).
void publish_tools(const fs::path& from, const fs::path& to) {
    std::ifstream in(from);
    std::string line, text;
    if (!std::getline(in, line)) throw std::runtime_error("'" + from.string() + "' is empty");
    text = line + "\n";
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::istringstream cells(line);
        for (std::string c; std::getline(cells, c, ',');) v.push_back(std::strtod(c.c_str(), nullptr));
        if (v.size() < 2 || v[1] < 2.0) continue;
        for (std::size_t i = 0; i < v.size(); ++i) {
            char b[32];
            std::snprintf(b, sizeof b, "%.6g", v[i]);
            if (i) text += ',';
            text += b;
        }
        text += "\n";
    }
    const std::string tmp = to.string() + ".part";
    gzFile g = gzopen(tmp.c_str(), "wb9");
    if (!g) throw std::runtime_error("cannot write '" + tmp + "'");
    const bool ok = gzwrite(g, text.data(), unsigned(text.size())) == int(text.size());
    if (gzclose(g) != Z_OK || !ok) throw std::runtime_error("cannot write '" + tmp + "'");
    fs::rename(tmp, to);
}

std::string summary_csv(const DeviceStudy& s, const DeviceSweepResult& r) {
    std::string t = "case,seed,folder";
    for (const std::string& k : device_study_numbers()) t += "," + k;
    t += ",status,message\n";
    for (std::size_t i = 0; i < r.runs.size(); ++i) {
        const DeviceStudyRun& run = r.runs[i];
        const DeviceRunOutcome& o = r.outcomes[i];
        t += s.cases[run.case_index].name + "," + std::to_string(run.seed) + "," + run.folder;
        // The CSV rules of every hand-built table (dem/io/csv.h): numbers round-trip, empty when
        // missing; the message quoted when it holds a comma or a quote.
        for (std::size_t k = 0; k < device_study_numbers().size(); ++k) {
            t += ',';
            if (k < o.numbers.size()) t += dem::csv_number(o.numbers[k]);
        }
        t += ',';
        t += o.status;
        t += ',';
        t += dem::csv_text(o.message);
        t += '\n';
    }
    return t;
}

// summary_cases.csv: a row per case over its seeds, as a damper study's (docs/studies.md,
// "Outputs"): case, seeds (its runs), ok (finished), then per number Q of summary.csv
// Q_n,Q_mean,Q_sd,Q_ci95 (the finished runs that have Q, their mean, sample standard deviation
// and the half width of the 95% Student-t interval; sd and ci95 empty for n < 2, all three for
// n = 0), then folders (the runs' folders, ';'-separated).
std::string cases_csv(const DeviceStudy& s, const DeviceSweepResult& r) {
    std::string t = "case,seeds,ok";
    for (const std::string& q : device_study_numbers()) t += "," + q + "_n," + q + "_mean," + q + "_sd," + q + "_ci95";
    t += ",folders\n";
    for (std::size_t c = 0; c < s.cases.size(); ++c) {
        std::size_t runs = 0, ok = 0;
        std::string folders;
        for (std::size_t i = 0; i < r.runs.size(); ++i) {
            if (r.runs[i].case_index != c) continue;
            ++runs;
            ok += r.outcomes[i].status == "ok";
            folders += (folders.empty() ? "" : ";") + r.runs[i].folder;
        }
        t += dem::csv_text(s.cases[c].name) + "," + std::to_string(runs) + "," + std::to_string(ok);
        for (std::size_t k = 0; k < device_study_numbers().size(); ++k) {
            std::vector<double> x;
            for (std::size_t i = 0; i < r.runs.size(); ++i)
                if (r.runs[i].case_index == c && r.outcomes[i].status == "ok" && k < r.outcomes[i].numbers.size())
                    x.push_back(r.outcomes[i].numbers[k]);
            const Interval iv = mean_interval(x);  // the finite values: a number the run lacks is NaN
            for (const std::string& field :
                 {std::to_string(iv.n), dem::csv_number(iv.mean), dem::csv_number(iv.sd), dem::csv_number(iv.half)}) {
                t += ',';
                t += field;
            }
        }
        t += ',';
        t += dem::csv_text(folders);
        t += '\n';
    }
    return t;
}

// Before anything runs: a folder that holds a run of other overrides, or (without mix_builds) a
// run another build made, refuses the study.
void check_folders(const fs::path& out, const DeviceSweepResult& r, bool mix_builds) {
    std::string other_settings, other_builds;
    for (const DeviceStudyRun& run : r.runs) {
        const fs::path dir = out / run.folder;
        if (const auto held = recorded_overrides(dir); held && *held != run.overrides)
            other_settings += (other_settings.empty() ? "" : ", ") + run.folder;
        if (!mix_builds && fs::is_directory(dir)) {
            const std::vector<scene::BuildStamp> b = scene::other_builds(dir.string());
            if (!b.empty()) other_builds += (other_builds.empty() ? "" : ", ") + run.folder + " (" + b.front().commit + ")";
        }
    }
    if (!other_settings.empty())
        throw ConfigError("--out '" + out.string() + "': the runs " + other_settings +
                          " were made with other settings (their case.toml): the study changed; use another --out, or "
                          "remove those folders");
    if (!other_builds.empty())
        throw ConfigError("--out '" + out.string() + "' holds runs another build made: " + other_builds +
                          "; their results would mix with this build's: pass --mix-builds to continue them anyway, or "
                          "use another --out");
}

}  // namespace

const std::vector<std::string>& device_study_numbers() {
    static const std::vector<std::string> k = {
        "holding_force", "press_force", "underpressure", "volume_change", "volume_change_vacuum", "packing_seal",
        "packing_vacuum", "grains", "stiffness", "work_per_cycle", "peak_force", "energy_residual", "energy_scale",
        // Added after the first columns (issue 61), so that a reader by position keeps them: the
        // gripper's F / (dp A) (Brown et al.'s measure), the object's cross-section and the seal.
        "holding_ratio", "object_area", "suction_force_max", "seal_area"};
    return k;
}

std::vector<DeviceStudyRun> expand_device_study(const DeviceStudy& s) {
    std::vector<DeviceStudyRun> runs;
    for (int seed = s.seeds > 0 ? 1 : 0; seed <= s.seeds; ++seed)
        for (std::size_t i = 0; i < s.cases.size(); ++i) {
            DeviceStudyRun r;
            r.case_index = i;
            r.seed = seed;
            r.folder = s.cases[i].name + (seed > 0 ? "_s" + std::to_string(seed) : "");
            r.overrides = s.set;
            r.overrides.insert(r.overrides.end(), s.cases[i].set.begin(), s.cases[i].set.end());
            if (seed > 0) r.overrides.push_back("simulation.seed=" + std::to_string(seed));
            runs.push_back(std::move(r));
        }
    return runs;
}

std::string list_device_runs(const DeviceStudy& s) {
    std::string t = "# device study " + s.path + ": " + s.device + "\n# folder case seed overrides\n";
    for (const DeviceStudyRun& r : expand_device_study(s)) {
        t += r.folder + " " + s.cases[r.case_index].name + " " + std::to_string(r.seed);
        for (const std::string& o : r.overrides) t += " " + o;
        t += "\n";
    }
    return t;
}

DeviceSweepResult run_device_study(const DeviceStudy& s, const DeviceSweepOptions& opt) {
    DeviceSweepResult r;
    r.runs = expand_device_study(s);
    r.outcomes.resize(r.runs.size());
    const fs::path out(opt.out_dir), pub(opt.publish);
    dem::FolderLock lock;
    if (opt.report_only) {
        if (!fs::is_directory(out)) throw ConfigError("--out '" + opt.out_dir + "': no such folder (--report-only reads a study's folder)");
    } else {
        lock = scene::lock_output_dir(opt.out_dir);
        check_folders(out, r, opt.mix_builds);
        // The published records of runs the folder lacks come back first and count as finished.
        if (!opt.publish.empty())
            for (const DeviceStudyRun& run : r.runs) {
                const fs::path from = pub / run.folder, to = out / run.folder;
                if (finished_summary(from).is_null() || !finished_summary(to).is_null() || fs::exists(to / "run.ckpt")) continue;
                for (const char* f : {"summary.json", "case.toml", "build.json"})
                    if (fs::exists(from / f)) dem::copy_text_if_changed(from / f, to / f);
            }
    }
    std::size_t done = 0;
    for (std::size_t i = 0; i < r.runs.size(); ++i) {
        const DeviceStudyRun& run = r.runs[i];
        const fs::path dir = out / run.folder;
        DeviceRunOutcome& o = r.outcomes[i];
        if (const nlohmann::json j = finished_summary(dir); !j.is_null()) {
            o = outcome_of(j);
            ++done;
            continue;
        }
        if (opt.report_only) {
            o.status = "not run";
            continue;
        }
        if (opt.stop && opt.stop()) {
            o.status = "not run";
            o.message = "the study was stopped before it";
            continue;
        }
        if (!opt.quiet)
            std::fprintf(stderr, "sweep: [%zu/%zu] %s%s\n", i + 1, r.runs.size(), run.folder.c_str(),
                         fs::exists(dir / "run.ckpt") ? " (resumes its run.ckpt)" : "");
        try {
            fs::create_directories(dir);
            dem::write_text_atomic((dir / "case.toml").string(), case_record(s, run));
            DeviceOptions d;
            d.out_dir = dir.string();
            d.from = scene::resume_checkpoint(d.out_dir, "", false);
            d.overwrite = true;  // the folder holds case.toml
            d.quiet = opt.quiet;
            d.checkpoint_every = opt.checkpoint_every;
            d.stop = opt.stop;
            const DeviceResult res = run_device(load_device(s.device, run.overrides), d);
            if (res.stage != "done" && opt.stop && opt.stop()) {  // stopped, not failed: it resumes
                o.status = "not run";
                o.message = "the study was stopped in its stage '" + res.stage + "'; its run.ckpt resumes it";
                continue;
            }
            if (res.stage != "done") throw std::runtime_error("the run stopped before the stage '" + res.stage + "'");
            o = outcome_of(finished_summary(dir));
            if (fs::exists(dir / "FAILED")) fs::remove(dir / "FAILED");
            ++done;
        } catch (const std::exception& e) {
            o.status = "failed";
            o.message = e.what();
            ++r.failed;
            std::fprintf(stderr, "sweep: %s failed: %s\n", run.folder.c_str(), e.what());
            try {
                dem::write_text_atomic((dir / "FAILED").string(), o.message + "\n");
            } catch (...) {
            }
        }
    }
    const std::string table = summary_csv(s, r);
    dem::write_text_atomic((out / "summary.csv").string(), table);
    dem::write_text_atomic((out / "summary_cases.csv").string(), cases_csv(s, r));
    if (!opt.publish.empty()) {
        std::size_t published = 0;
        for (std::size_t i = 0; i < r.runs.size(); ++i) {
            if (r.outcomes[i].status != "ok") continue;
            const fs::path from = out / r.runs[i].folder, to = pub / r.runs[i].folder;
            // tools.csv.gz again only when the run's summary changed (a gzip of the same rows is
            // the same record: a republished study leaves its files as they were).
            const bool changed = dem::copy_text_if_changed(from / "summary.json", to / "summary.json");  // ok: the run has one
            for (const char* f : {"case.toml", "build.json"})
                if (fs::exists(from / f)) dem::copy_text_if_changed(from / f, to / f);
            if ((changed || !fs::exists(to / "tools.csv.gz")) && fs::exists(from / "tools.csv"))
                publish_tools(from / "tools.csv", to / "tools.csv.gz");
            ++published;
        }
        for (const char* f : {"summary.csv", "summary_cases.csv"}) dem::copy_text_if_changed(out / f, pub / f);
        if (!opt.quiet) std::fprintf(stderr, "sweep: %zu finished run(s) published in %s\n", published, opt.publish.c_str());
    }
    if (!opt.quiet)
        std::fprintf(stderr, "sweep: %zu of %zu run(s) finished, %d failed; %s, summary_cases.csv\n", done,
                     r.runs.size(), r.failed, (out / "summary.csv").string().c_str());
    return r;
}

}  // namespace vpp

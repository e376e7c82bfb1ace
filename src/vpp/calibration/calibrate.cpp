#include "vpp/calibration/calibrate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

#include "scene/config.h"
#include "dem/io/csv.h"
#include "dem/io/json.h"
#include "vpp/analysis/plot.h"
#include "vpp/settings/settings.h"
#include "vpp/analysis/stats.h"

namespace vpp {

namespace fs = std::filesystem;

namespace {

void shift_to_zero(LoopSeries& s) {
    if (s.displacement.empty()) return;
    const double m = *std::min_element(s.displacement.begin(), s.displacement.end());
    for (double& d : s.displacement) d -= m;
}

// Samples of each cycle (in record order), cycles in increasing order.
std::map<int, std::vector<std::size_t>> by_cycle(const LoopSeries& s) {
    std::map<int, std::vector<std::size_t>> m;
    for (std::size_t i = 0; i < s.cycle.size(); ++i)
        if (s.cycle[i] > 0) m[s.cycle[i]].push_back(i);
    return m;
}

struct Branch {
    std::vector<double> d, f;  // sorted by d
    double lo = 0, hi = 0;
};

Branch make_branch(const LoopSeries& s, const std::vector<std::size_t>& idx, std::size_t a, std::size_t b) {
    std::vector<std::pair<double, double>> p;
    for (std::size_t k = a; k <= b; ++k) p.emplace_back(s.displacement[idx[k]], s.force[idx[k]]);
    std::stable_sort(p.begin(), p.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    Branch br;
    for (const auto& [d, f] : p) {
        br.d.push_back(d);
        br.f.push_back(f);
    }
    br.lo = br.d.front();
    br.hi = br.d.back();
    return br;
}

double interp(const Branch& b, double x) {
    if (x <= b.d.front()) return b.f.front();
    if (x >= b.d.back()) return b.f.back();
    const std::size_t k = std::size_t(std::upper_bound(b.d.begin(), b.d.end(), x) - b.d.begin());
    const double x0 = b.d[k - 1], x1 = b.d[k];
    if (x1 <= x0) return b.f[k];
    return b.f[k - 1] + (b.f[k] - b.f[k - 1]) * (x - x0) / (x1 - x0);
}

// Loading branch: from the cycle's first sample to its largest displacement; unloading: the rest.
std::pair<Branch, Branch> branches(const LoopSeries& s, const std::vector<std::size_t>& idx) {
    std::size_t im = 0;
    for (std::size_t k = 1; k < idx.size(); ++k)
        if (s.displacement[idx[k]] > s.displacement[idx[im]]) im = k;
    if (im == 0 || im + 1 >= idx.size()) throw std::runtime_error("a cycle has no loading or no unloading branch");
    return {make_branch(s, idx, 0, im), make_branch(s, idx, im, idx.size() - 1)};
}

std::string json_value(const std::string& label, const std::string& literal) {
    return literal.starts_with("\"") ? dem::json_string(label) : label;
}

}  // namespace

LoopSeries read_experiment(const std::string& path, const ExperimentFormat& f) {
    RecordFormat own = f;
    own.cycle_col.clear();  // a rig's record: cycles from the stroke
    LoopSeries s = read_record(path, own);
    shift_to_zero(s);
    if (std::none_of(s.cycle.begin(), s.cycle.end(), [](int c) { return c > 0; }))
        throw std::runtime_error("experiment '" + path + "': no complete cycle found in column '" + f.disp_col +
                                 "' (a cycle goes from the start position to the far end and back; check "
                                 "--compression-negative)");
    return s;
}

void check_experiment_orientation(const LoopSeries& s, const std::string& path, bool compression_negative,
                                  bool compression_first) {
    const std::string doubt = orientation_doubt(s, compression_negative, compression_first);
    if (!doubt.empty()) throw std::runtime_error("experiment '" + path + "': " + doubt);
}

LoopSeries read_simulated(const std::string& forces_csv, const std::string& force_column) {
    LoopSeries s = read_loop_csv(forces_csv, "time", "displacement", force_column, "cycle");
    shift_to_zero(s);
    return s;
}

Misfit loop_misfit(const LoopSeries& sim, const LoopSeries& exp, int points) {
    const auto cs = by_cycle(sim), ce = by_cycle(exp);
    const std::size_t n = std::min(cs.size(), ce.size());
    if (n == 0) throw std::runtime_error("no complete cycle to compare");
    const auto es = analyze_cycles(sim, 1.0), ee = analyze_cycles(exp, 1.0);
    auto sit = cs.begin();
    auto eit = ce.begin();
    Misfit m;
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k, ++sit, ++eit) {
        if (n > 1 && k == 0) continue;  // the first cycle is not stabilised
        const auto [sl, su] = branches(sim, sit->second);
        const auto [el, eu] = branches(exp, eit->second);
        double sq = 0;
        int cnt = 0;
        for (const auto& [a, b] : {std::pair<const Branch&, const Branch&>(sl, el), {su, eu}}) {
            const double lo = std::max(a.lo, b.lo), hi = std::min(a.hi, b.hi);
            if (!(hi > lo))
                throw std::runtime_error("cycle " + std::to_string(k + 1) +
                                         ": the simulated and measured displacement ranges do not overlap");
            for (int j = 0; j < points; ++j) {
                const double x = lo + (j + 0.5) * (hi - lo) / points;
                const double d = interp(a, x) - interp(b, x);
                sq += d * d;
                ++cnt;
            }
        }
        double peak = 0;
        for (std::size_t i : eit->second) peak = std::max(peak, std::abs(exp.force[i]));
        if (!(peak > 0)) throw std::runtime_error("a measured cycle has zero force");
        const double rms = std::sqrt(sq / cnt) / peak;
        double E_s = 0, E_e = 0;
        for (const auto& c : es)
            if (c.cycle == sit->first) E_s = c.dissipated_energy;
        for (const auto& c : ee)
            if (c.cycle == eit->first) E_e = c.dissipated_energy;
        const double de = std::abs(E_s - E_e) / std::max(std::abs(E_e), 1e-300);
        m.cycles.push_back(int(k + 1));
        m.rms.push_back(rms);
        m.energy.push_back(de);
        sum += rms + de;
    }
    m.value = sum / double(m.cycles.size());
    return m;
}

// The steps of run_calibration, in the order it takes them. Every MPI rank takes each step up to the
// scale checks (the sweeps are run by all of them, and every rank reads the same case folders, so
// they agree on the result); rank 0 alone writes the tables, calibration.json and the summary.
namespace {

// The index of one of an axis's labels (a case's value of that key) among its values.
std::size_t index_of(const GridAxis& ax, const std::string& label) {
    return std::size_t(std::find(ax.labels.begin(), ax.labels.end(), label) - ax.labels.begin());
}

// No grid (the seeds alone are no grid): the paper's calibration grid, grains.friction from 0 to 1
// in steps of 0.1 [-], put first.
void add_default_grid(Study& s) {
    if (s.grid.size() == (seed_axis(s) >= 0 ? 1u : 0u))
        s.grid.insert(s.grid.begin(), axis_from_text("grains.friction", "0:1:0.1"));
}

// What the checks of a measured record need to know of the cases they will be compared with.
struct Protocol {
    bool compression_first = true;  // every case loads in compression first (the mean force check)
    double amplitude = 0;           // [m] the largest stroke of the cases
};

// From every case of the study (expand_study checks each case's config too, before anything runs).
Protocol protocol_of(const Study& s) {
    Protocol p;
    for (const StudyCase& c : expand_study(s)) {
        p.compression_first = p.compression_first && c.config.process.compression_first;
        p.amplitude = std::max(p.amplitude, c.config.process.amplitude);
    }
    return p;
}

// The measured loop (SI units, compression positive, vpp::read_experiment), refused before anything
// runs when its signs are the other way (check_experiment_orientation) or its units are not the
// cases': hours of simulation must not end in a comparison that could never mean anything.
LoopSeries read_checked_experiment(const CalibrateOptions& opt, const Protocol& protocol) {
    LoopSeries exp = read_experiment(opt.experiment, opt.format);
    check_experiment_orientation(exp, opt.experiment, opt.format.compression_negative, protocol.compression_first);
    // A unit slip of the displacement (--displacement-unit m on data in mm is a factor of 1000)
    // shows before anything runs: the measured stroke against the cases' process.amplitude.
    const double amplitude = protocol.amplitude;  // [m]
    if (const double stroke = *std::max_element(exp.displacement.begin(), exp.displacement.end());
        amplitude > 0 && stroke > 0 && (stroke > 10.0 * amplitude || stroke < 0.1 * amplitude)) {
        char msg[400];
        std::snprintf(msg, sizeof msg, "experiment '%s': implausible units: its stroke %.4g m is %.3g times the "
                      "study's process.amplitude %.4g m: check --displacement-unit (now %s)", opt.experiment.c_str(),
                      stroke, stroke / amplitude, amplitude, opt.format.disp_scale == 1.0 ? "m" : "mm");
        throw cfg::ConfigError(msg);
    }
    return exp;
}

// --predict key=v1,v2,...: the values to run at the best grid point once it is known, and the
// measured loops to compare them with (--predict-experiment: none, or one per value, in order).
struct PredictRequest {
    GridAxis axis;                        // an empty key: no prediction asked
    std::vector<LoopSeries> experiments;  // read and checked as the calibration's experiment
};

// Parses and checks the prediction request before anything runs, as the experiment: a typo in a
// key or a value must not show only after the grid has run for hours.
PredictRequest read_predict_request(const Study& s, const CalibrateOptions& opt, const Protocol& protocol) {
    PredictRequest req;
    if (!opt.predict.empty()) {
        const auto eq = opt.predict.find('=');
        if (eq == std::string::npos || eq == 0)
            throw cfg::ConfigError("--predict '" + opt.predict +
                                   "': expected key=v1,v2,... e.g. process.underpressure=0.02e6,0.04e6");
        req.axis = axis_from_text(opt.predict.substr(0, eq), opt.predict.substr(eq + 1));
        if (!opt.predict_experiments.empty() && opt.predict_experiments.size() != req.axis.literals.size())
            throw cfg::ConfigError("--predict gives " + std::to_string(req.axis.literals.size()) + " value(s) but " +
                                   std::to_string(opt.predict_experiments.size()) +
                                   " --predict-experiment file(s); give one per value, or none");
        for (const std::string& p : opt.predict_experiments) {
            req.experiments.push_back(read_experiment(p, opt.format));
            check_experiment_orientation(req.experiments.back(), p, opt.format.compression_negative,
                                         protocol.compression_first);
        }
        // The predicted values must be valid config values too (before the grid runs for hours).
        for (const std::string& lit : req.axis.literals) {
            std::vector<std::string> sets = s.set;
            sets.push_back(req.axis.key + "=" + lit);
            try {
                load_config(s.base, sets);
            } catch (const std::exception& e) {
                throw cfg::ConfigError("--predict '" + opt.predict + "': " + e.what());
            }
        }
    } else if (!opt.predict_experiments.empty()) {
        throw cfg::ConfigError("--predict-experiment needs --predict key=v1,v2,...");
    }
    return req;
}

// Each run's comparison with the experiment, index for index with the sweep's cases.
struct RunFits {
    std::vector<double> misfit;       // [-] loop_misfit's value; NaN where the run was not compared
    std::vector<std::string> status;  // "ok", or "failed: " and why
    std::vector<Misfit> detail;       // per compared cycle (for calibration.json's best run)
};

// Misfit of every finished run (read from its folder, so every MPI rank agrees).
RunFits compare_runs(const std::vector<StudyCase>& cases, const LoopSeries& exp, const CalibrateOptions& opt) {
    const fs::path out(opt.sweep.out_dir);
    RunFits f;
    f.misfit.assign(cases.size(), std::numeric_limits<double>::quiet_NaN());
    f.status.resize(cases.size());
    f.detail.resize(cases.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const fs::path dir = out / cases[i].name;
        // A case that failed in this sweep is not compared, even when its folder still holds
        // the results of an earlier run (e.g. of a study that has changed since).
        if (fs::exists(dir / "FAILED")) {
            std::ifstream in(dir / "FAILED");
            std::string why;
            std::getline(in, why);
            f.status[i] = "failed: " + why;
            continue;
        }
        if (!fs::exists(dir / "summary.json")) {
            f.status[i] = "failed: simulation did not finish";
            continue;
        }
        try {
            f.detail[i] = loop_misfit(read_simulated((dir / "forces.csv").string(), opt.force_column), exp, opt.points);
            f.misfit[i] = f.detail[i].value;
            f.status[i] = "ok";
        } catch (const std::exception& e) {
            f.status[i] = std::string("failed: ") + e.what();
        }
    }
    return f;
}

// A grid point: the runs of its seeds (the ensemble's runs share the point) and their mean misfit.
struct GridPoint {
    std::vector<std::size_t> runs;  // case indices, one per seed
    Interval misfit;                // [-] the mean over the seeds and its 95% interval
    std::string status = "ok";      // the first failed seed's status, if any
};

// The grid points and the best of them.
struct GridFit {
    std::vector<GridPoint> points;
    std::size_t best = SIZE_MAX;      // index in points; SIZE_MAX when no point could be compared
    std::size_t best_run = SIZE_MAX;  // the best point's first seed (a case index): its run stands for it
    std::vector<std::size_t> near;    // indices in points whose misfit interval overlaps the best's
};

// Per grid point: the mean misfit over its seeds and its 95% interval (vpp/analysis/stats.h); a point
// counts only when every seed was compared. The best point has the smallest mean.
GridFit score_grid_points(const Study& s, const std::vector<StudyCase>& cases, const RunFits& runs) {
    GridFit g;
    for (const auto& group : ensemble_groups(s, cases)) {
        GridPoint p;
        p.runs = group;
        std::vector<double> m;
        for (std::size_t i : group) {
            if (runs.status[i] != "ok" && p.status == "ok") p.status = runs.status[i];
            m.push_back(runs.misfit[i]);
        }
        if (p.status == "ok") p.misfit = mean_interval(m);
        g.points.push_back(p);
    }
    const auto& points = g.points;
    std::size_t best = SIZE_MAX;
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points[k].status == "ok" && (best == SIZE_MAX || points[k].misfit.mean < points[best].misfit.mean))
            best = k;
    // Uncertainty of the best point: the grid points whose misfit interval overlaps the best's
    // (with one seed there is no interval and only equal misfits overlap).
    if (best != SIZE_MAX)
        for (std::size_t k = 0; k < points.size(); ++k)
            if (points[k].status == "ok" && overlaps(points[k].misfit, points[best].misfit)) g.near.push_back(k);
    g.best = best;
    g.best_run = best == SIZE_MAX ? SIZE_MAX : points[best].runs.front();
    return g;
}

// One predicted value: the runs of its seeds at the best grid point.
struct Prediction {
    std::string label, literal;      // the value as the grid axis holds it
    std::vector<std::string> names;  // the runs' folders under the calibration's ("predict/...")
    Interval W, misfit;              // [J/m^2] the last cycle's W and [-] the misfit, over the seeds
    std::string status = "ok";
};

struct Predictions {
    std::vector<Prediction> values;  // one per --predict value; none when nothing was predicted
    int failed = 0;                  // failed cases of the prediction's sweep
};

// Prediction at the best grid point (every seed of the ensemble): the --predict values run into
// DIR/predict with the best point's other grid values set; nothing when none was asked or no
// point could be compared.
Predictions run_predictions(const Study& s, const CalibrateOptions& opt, const PredictRequest& req,
                            const std::vector<StudyCase>& cases, const GridFit& grid) {
    const GridAxis& pred = req.axis;
    const fs::path out(opt.sweep.out_dir);
    const int seed = seed_axis(s);
    Predictions preds;
    if (pred.key.empty() || grid.best == SIZE_MAX) return preds;
    Study p = s;
    p.grid = {pred};
    if (seed >= 0) p.grid.push_back(s.grid[std::size_t(seed)]);
    for (std::size_t k = 0; k < s.grid.size(); ++k) {
        if (s.grid[k].key == pred.key || int(k) == seed) continue;
        const auto& ax = s.grid[k];
        const std::size_t j = index_of(ax, cases[grid.best_run].labels[k]);
        p.set.push_back(ax.key + "=" + ax.literals[j]);
    }
    SweepOptions so = opt.sweep;
    so.out_dir = (out / "predict").string();
    if (!opt.sweep.quiet && opt.sweep.rank == 0)
        std::fprintf(stderr, "calibrate: predicting %s at the best grid point\n", opt.predict.c_str());
    const SweepResult pr = run_sweep(p, so);
    preds.failed = pr.failed;
    for (const auto& g : ensemble_groups(p, pr.cases)) {
        Prediction q;
        const std::size_t v = index_of(pred, pr.cases[g.front()].labels[0]);
        q.label = pred.labels[v];
        q.literal = pred.literals[v];
        std::vector<double> W, m;
        for (std::size_t i : g) {
            const std::string name = "predict/" + pr.cases[i].name;
            q.names.push_back(name);
            const fs::path dir = out / name;
            if (!fs::exists(dir / "summary.json")) {
                if (q.status == "ok") q.status = "failed: simulation did not finish";
                continue;
            }
            try {
                const LoopSeries sim = read_simulated((dir / "forces.csv").string(), opt.force_column);
                const auto cyc = analyze_cycles(sim, pr.cases[i].config.damper.radius);
                if (!cyc.empty()) W.push_back(cyc.back().W);
                if (!req.experiments.empty()) m.push_back(loop_misfit(sim, req.experiments[v], opt.points).value);
            } catch (const std::exception& e) {
                if (q.status == "ok") q.status = std::string("failed: ") + e.what();
            }
        }
        q.W = mean_interval(W);
        q.misfit = mean_interval(m);
        preds.values.push_back(q);
    }
    return preds;
}

// What the scale checks found: the warnings (stderr and calibration.json) and whether the units
// are so far off that the calibration counts as failed.
struct ScaleCheck {
    std::vector<std::string> warnings;
    bool implausible = false;
};

// The best run against the experiment in scale: the stroke and the peak force. A stroke off
// by more than 10% makes the comparison meaningless (warned). Off by more than a factor of
// 10 either is not a fit at all: a unit slip (--force-unit kN on data in N is a factor of
// 1000, mm for m the same) is the likely cause, and a calibration in the wrong unit must not
// replace a good calibration.json: the run counts as failed (calibration_failed.json).
ScaleCheck check_best_scale(const std::vector<StudyCase>& cases, const GridFit& grid, const LoopSeries& exp,
                            const CalibrateOptions& opt) {
    const fs::path out(opt.sweep.out_dir);
    ScaleCheck sc;
    if (grid.best != SIZE_MAX) {
        try {
            const fs::path forces = out / cases[grid.best_run].name / "forces.csv";
            const LoopSeries sim = read_simulated(forces.string(), opt.force_column);
            auto peak = [](const std::vector<double>& v) {
                double m = 0;
                for (double x : v) m = std::max(m, std::abs(x));
                return m;
            };
            const double rs = *std::max_element(sim.displacement.begin(), sim.displacement.end());  // [m]
            const double re = *std::max_element(exp.displacement.begin(), exp.displacement.end());  // [m]
            const double fs_ = peak(sim.force), fe = peak(exp.force);                                 // [N]
            char msg[512];
            constexpr double kUnitSlip = 10.0;  // [-] a ratio no fit explains; a unit slip is 1000
            if (re > 0 && rs > 0 && (rs / re > kUnitSlip || re / rs > kUnitSlip)) {
                sc.implausible = true;
                std::snprintf(msg, sizeof msg, "implausible units: the measured stroke %.4g m is %.3g times the "
                              "simulated %.4g m: check --displacement-unit (now %s)", re, re / rs, rs,
                              opt.format.disp_scale == 1.0 ? "m" : "mm");
                sc.warnings.push_back(msg);
            } else if (std::abs(rs - re) > 0.1 * re) {
                std::snprintf(msg, sizeof msg, "simulated stroke %.4g mm, measured %.4g mm: set process.amplitude to "
                              "the experiment's", rs * 1e3, re * 1e3);
                sc.warnings.push_back(msg);
            }
            if (fe > 0 && fs_ > 0 && (fe / fs_ > kUnitSlip || fs_ / fe > kUnitSlip)) {
                sc.implausible = true;
                std::snprintf(msg, sizeof msg, "implausible units: the measured peak force %.4g N is %.3g times the "
                              "best simulated %.4g N: check --force-unit (now %s)", fe, fe / fs_, fs_,
                              opt.format.force_scale == 1.0 ? "N" : "kN");
                sc.warnings.push_back(msg);
            }
        } catch (const std::exception& e) {
            sc.warnings.push_back(std::string("the best case's forces could not be read for the scale checks: ") +
                                  e.what());
        }
    }
    return sc;
}

// A calibration counts (exit status 0, calibration.json) only when every case ran and was
// compared, the predictions ran, some point is best and the units are plausible.
bool calibration_ok(const SweepResult& r, const Predictions& preds, const GridFit& grid, const ScaleCheck& scale) {
    return !r.failed && !preds.failed && grid.best != SIZE_MAX && !scale.implausible &&
           std::all_of(grid.points.begin(), grid.points.end(), [](const GridPoint& p) { return p.status == "ok"; });
}

// The scale checks' warnings, on stderr whatever --quiet says (and in calibration.json).
void print_warnings(const ScaleCheck& scale) {
    for (const std::string& w : scale.warnings) std::fprintf(stderr, "WARNING: calibrate: %s\n", w.c_str());
}

// A calibration that failed (a case failed or could not be compared, a prediction failed)
// writes its results under other names: a good calibration.json and misfit.csv from an
// earlier run of the same folder stay as they are.
struct OutputNames {
    std::string misfit, runs, json;  // misfit.csv, misfit_runs.csv, calibration.json or their *_failed
};

OutputNames output_names(bool ok) {
    const std::string suffix = ok ? "" : "_failed";
    return {"misfit" + suffix + ".csv", "misfit_runs" + suffix + ".csv", "calibration" + suffix + ".json"};
}

// What the writers of rank 0 read: the study, the options and every step's result.
struct Report {
    const Study& s;
    const CalibrateOptions& opt;
    const std::vector<StudyCase>& cases;  // the sweep's
    const RunFits& runs;
    const GridFit& grid;
    const GridAxis& pred;  // the --predict axis (an empty key when none)
    const Predictions& preds;
    const ScaleCheck& scale;
    const int failed;  // failed cases of the sweep
    const bool ok;     // calibration_ok
    const OutputNames names;
    fs::path out() const { return opt.sweep.out_dir; }
};

// The grid point of a case as a json object: its labels without the seed (the ensemble's runs
// share it), each a number or a string as its literal in the study file.
dem::JsonObject point_json(const Study& s, const StudyCase& c) {
    const int seed = seed_axis(s);
    dem::JsonObject b;
    for (std::size_t k = 0; k < s.grid.size(); ++k) {
        if (int(k) == seed) continue;
        const auto& ax = s.grid[k];
        const std::size_t v = index_of(ax, c.labels[k]);
        b.raw(ax.key, json_value(ax.labels[v], ax.literals[v]));
    }
    return b;
}

// misfit.csv: one row per grid point; misfit_runs.csv (with seeds): one row per run. The study's
// cells (dem/io/csv.h), so that they quote as summary.csv does.
void write_misfit_tables(const Report& rep) {
    const Study& s = rep.s;
    const auto& cases = rep.cases;
    const int seed = seed_axis(s);
    auto field = [](const std::string& x) { return dem::csv_text(x); };
    auto number = [](double v) { return dem::csv_number(v); };
    // misfit.csv: one row per grid point: the grid keys but the seed, misfit (the mean over the
    // seeds), status, case (its first seed's folder), then misfit_n, misfit_sd, misfit_ci95.
    std::string csv;
    for (std::size_t k = 0; k < s.grid.size(); ++k)
        if (int(k) != seed) csv += field(s.grid[k].key) + ",";
    csv += "misfit,status,case,misfit_n,misfit_sd,misfit_ci95\n";
    for (const GridPoint& p : rep.grid.points) {
        const StudyCase& c = cases[p.runs.front()];
        for (std::size_t k = 0; k < c.labels.size(); ++k)
            if (int(k) != seed) csv += field(c.labels[k]) + ",";
        csv += number(p.misfit.mean) + "," + field(p.status) + "," + field(c.name) + "," + std::to_string(p.misfit.n) +
               "," + number(p.misfit.sd) + "," + number(p.misfit.half) + "\n";
    }
    dem::write_text_atomic((rep.out() / rep.names.misfit).string(), csv);
    if (seed >= 0) {
        // misfit_runs.csv: one row per run, the seed included.
        std::string runs;
        for (const GridAxis& a : s.grid) runs += field(a.key) + ",";
        runs += "misfit,status,case\n";
        for (std::size_t i = 0; i < cases.size(); ++i) {
            for (const std::string& l : cases[i].labels) runs += field(l) + ",";
            runs += number(rep.runs.misfit[i]) + "," + field(rep.runs.status[i]) + "," + field(cases[i].name) + "\n";
        }
        dem::write_text_atomic((rep.out() / rep.names.runs).string(), runs);
    }
}

// The processed experiment (SI units, compression positive, cycles numbered), DIR/experiment.csv,
// for the overlay plot.
void write_experiment_csv(const fs::path& out, const LoopSeries& exp) {
    // The cycle number is a whole double: the writer prints it without a decimal point.
    dem::CsvWriter e((out / "experiment.csv").string(), "time,displacement,force,cycle");
    for (std::size_t i = 0; i < exp.time.size(); ++i)
        e.row({exp.time[i], exp.displacement[i], exp.force[i], double(exp.cycle[i])});
    e.close();
}

std::string names_json(const std::vector<StudyCase>& cases, const std::vector<std::size_t>& runs) {
    std::vector<std::string> names;
    for (std::size_t k : runs) names.push_back(cases[k].name);
    return dem::json_string_array(names);
}

// calibration.json's account of the best point: its grid values and misfit, its uncertainty (the
// range of each grid key over the points whose interval overlaps the best's) and its best run's
// misfit per compared cycle. Null when no point could be compared.
void add_best_json(dem::JsonObject& j, const Report& rep) {
    const Study& s = rep.s;
    const auto& cases = rep.cases;
    const GridFit& grid = rep.grid;
    const int seed = seed_axis(s);
    if (grid.best == SIZE_MAX) {
        j.raw("best", "null").raw("misfit", "null");
        return;
    }
    const GridPoint& b = grid.points[grid.best];
    j.raw("best", point_json(s, cases[grid.best_run]).value())
        .num("misfit", b.misfit.mean)
        .num("misfit_sd", b.misfit.sd)
        .num("misfit_ci95", b.misfit.half)
        .num("seeds", double(b.misfit.n))
        .str("case", cases[grid.best_run].name)
        .raw("cases", names_json(cases, b.runs));
    // The range of each grid key over the points whose interval overlaps the best's.
    dem::JsonObject u;
    u.str("rule", "grid points whose 95% misfit interval (mean over seeds +- t_{0.975,n-1} sd/sqrt(n)) overlaps "
                  "the best point's; with one seed, only points of equal misfit");
    for (std::size_t k = 0; k < s.grid.size(); ++k) {
        if (int(k) == seed) continue;
        const auto& ax = s.grid[k];
        std::vector<std::size_t> idx;
        for (std::size_t q : grid.near) idx.push_back(index_of(ax, cases[grid.points[q].runs.front()].labels[k]));
        std::sort(idx.begin(), idx.end());
        idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
        std::string vals = "[";
        for (std::size_t m = 0; m < idx.size(); ++m)
            vals += (m ? ", " : "") + json_value(ax.labels[idx[m]], ax.literals[idx[m]]);
        u.raw(ax.key, vals + "]");
    }
    j.raw("uncertainty", u.value());
    std::string cyc = "[", rms = "[", en = "[";
    const Misfit& d = rep.runs.detail[grid.best_run];
    for (std::size_t k = 0; k < d.cycles.size(); ++k) {
        cyc += (k ? ", " : "") + std::to_string(d.cycles[k]);
        rms += (k ? ", " : "");
        dem::append_number(rms, d.rms[k]);
        en += (k ? ", " : "");
        dem::append_number(en, d.energy[k]);
    }
    j.raw("cycles_compared", cyc + "]").raw("best_rms_per_cycle", rms + "]").raw("best_energy_per_cycle", en + "]");
}

// calibration.json's "grid": every grid point with its misfit, the misfit of each of its seeds
// (null where a run was not compared), its runs and status.
std::string grid_json(const Report& rep) {
    const auto& cases = rep.cases;
    const auto& points = rep.grid.points;
    const auto& misfit = rep.runs.misfit;
    std::string grid = "[";
    for (std::size_t k = 0; k < points.size(); ++k) {
        const GridPoint& p = points[k];
        dem::JsonObject g = point_json(rep.s, cases[p.runs.front()]);
        std::string per = "[";
        for (std::size_t m = 0; m < p.runs.size(); ++m) {
            per += (m ? ", " : "");
            if (std::isfinite(misfit[p.runs[m]])) dem::append_number(per, misfit[p.runs[m]]);
            else per += "null";
        }
        g.num("misfit", p.misfit.mean)
            .num("misfit_sd", p.misfit.sd)
            .num("misfit_ci95", p.misfit.half)
            .raw("misfit_per_seed", per + "]")
            .str("case", cases[p.runs.front()].name)
            .raw("cases", names_json(cases, p.runs))
            .str("status", p.status);
        const std::string t = g.value();
        grid += (k ? ", " : "") + t;
    }
    return grid + "]";
}

// calibration.json's "predictions": per predicted value, the mean W [J/m^2] and misfit [-] over
// the seeds with their 95% intervals, and its measured loop's file when one was given.
std::string predictions_json(const Report& rep) {
    const auto& preds = rep.preds.values;
    std::string pj = "[";
    for (std::size_t i = 0; i < preds.size(); ++i) {
        dem::JsonObject q;
        q.raw(rep.pred.key, json_value(preds[i].label, preds[i].literal))
            .str("case", preds[i].names.empty() ? "" : preds[i].names.front())
            .raw("cases", dem::json_string_array(preds[i].names))
            .num("W", preds[i].W.mean)
            .num("W_ci95", preds[i].W.half)
            .num("misfit", preds[i].misfit.mean)
            .num("misfit_ci95", preds[i].misfit.half)
            .str("status", preds[i].status);
        if (!rep.opt.predict_experiments.empty()) q.str("experiment", rep.opt.predict_experiments[i]);
        const std::string t = q.value();
        pj += (i ? ", " : "") + t;
    }
    return pj + "]";
}

// calibration.json (or calibration_failed.json): the best point, how the misfit is defined, every
// grid point, the predictions and the warnings.
void write_calibration_json(const Report& rep) {
    const CalibrateOptions& opt = rep.opt;
    dem::JsonObject j;
    add_best_json(j, rep);
    j.str("experiment", fs::absolute(opt.experiment).string())
        .str("simulated_force", opt.force_column)
        .num("points_per_branch", opt.points)
        .str("misfit_definition",
             "mean over the stabilised cycles (2..n) of rms_c + energy_c; rms_c = RMS of F_sim - F_exp over "
             "points_per_branch displacements per loading and unloading branch, over the measured cycle's peak "
             "|F|; energy_c = |E_sim - E_exp| / |E_exp| (loop areas); with seeds, the mean over the seeds of a grid "
             "point, with its 95% interval (Student t, n - 1 degrees of freedom)");
    j.raw("grid", grid_json(rep));
    if (!rep.preds.values.empty()) j.raw("predictions", predictions_json(rep));
    j.raw("warnings", dem::json_string_array(rep.scale.warnings));
    dem::write_text_atomic((rep.out() / rep.names.json).string(), j.text());
}

// No stale failure report beside a good result (nor the runs' table of an earlier calibration
// with seeds beside one without).
void remove_stale_reports(const Report& rep) {
    const fs::path out = rep.out();
    fs::remove(out / "misfit_failed.csv");
    fs::remove(out / "misfit_runs_failed.csv");
    fs::remove(out / "calibration_failed.json");
    if (seed_axis(rep.s) < 0) fs::remove(out / "misfit_runs.csv");  // of an earlier calibration with seeds
}

// The summary on stderr (not with --quiet): each grid point's misfit (the best marked *), the
// predictions, the best point with the values within its interval, and why a failed calibration
// failed.
void print_summary(const Report& rep) {
    const Study& s = rep.s;
    const auto& cases = rep.cases;
    const auto& points = rep.grid.points;
    const std::size_t best = rep.grid.best;
    const int seed = seed_axis(s);
    std::fprintf(stderr, "\n=== vppdem calibrate: %s ===\n", rep.opt.sweep.out_dir.c_str());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const GridPoint& p = points[k];
        std::string name = cases[p.runs.front()].name;
        if (p.runs.size() > 1) name += " and " + std::to_string(p.runs.size() - 1) + " more seed(s)";
        char m[128];
        if (p.status != "ok") std::snprintf(m, sizeof m, "%s", p.status.substr(0, 120).c_str());
        else if (std::isfinite(p.misfit.half)) std::snprintf(m, sizeof m, "%.4g +- %.2g", p.misfit.mean, p.misfit.half);
        else std::snprintf(m, sizeof m, "%.4g", p.misfit.mean);
        std::fprintf(stderr, "%s %-48s misfit %s\n", k == best ? "*" : " ", name.c_str(), m);
    }
    for (const Prediction& q : rep.preds.values)
        std::fprintf(stderr, "  predicted %s = %s: W = %.5g J/m^2%s\n", rep.pred.key.c_str(), q.label.c_str(), q.W.mean,
                     std::isfinite(q.misfit.mean) ? (", misfit " + std::to_string(q.misfit.mean)).c_str() : "");
    const std::string& misfit_name = rep.names.misfit;
    const std::string& json_name = rep.names.json;
    if (best != SIZE_MAX) {
        std::string range;
        for (std::size_t k = 0; k < s.grid.size(); ++k) {
            if (int(k) == seed) continue;
            std::vector<std::string> v;
            for (std::size_t q : rep.grid.near) v.push_back(cases[points[q].runs.front()].labels[k]);
            range += " " + s.grid[k].key + " in {";
            for (std::size_t m = 0; m < v.size(); ++m) range += (m ? ", " : "") + v[m];
            range += "}";
        }
        // One seed gives no interval (no scatter to measure): say so rather than list the points of
        // equal misfit as if they were one.
        const std::string interval = points[best].misfit.n < 2
                                         ? std::string("one seed: no interval (run --seeds 2 or more for one)")
                                         : "within its interval:" + range;
        std::fprintf(stderr, "best: %s (misfit %.4g over %zu seed(s)); %s; wrote %s, %s\n",
                     cases[rep.grid.best_run].name.c_str(), points[best].misfit.mean, points[best].misfit.n,
                     interval.c_str(), misfit_name.c_str(), json_name.c_str());
    } else {
        std::fprintf(stderr, "no case could be compared with the experiment; wrote %s, %s\n", misfit_name.c_str(),
                     json_name.c_str());
    }
    if (!rep.ok)
        std::fprintf(stderr, "calibration FAILED (%d case(s) failed%s%s): results in %s; %s\n", rep.failed,
                     rep.preds.failed ? ", predictions failed" : "", rep.scale.implausible ? ", implausible units" : "",
                     json_name.c_str(),
                     fs::exists(rep.out() / "calibration.json") ? "the earlier calibration.json is kept"
                                                                : "no calibration.json written");
}

}  // namespace

int run_calibration(Study s, const CalibrateOptions& opt) {
    add_default_grid(s);
    // Fail fast on a bad experiment or prediction request, before any simulation.
    const Protocol protocol = protocol_of(s);
    const LoopSeries exp = read_checked_experiment(opt, protocol);
    const PredictRequest request = read_predict_request(s, opt, protocol);

    // r holds the folder's lock (SweepResult::lock) to the end: the calibration's tables and
    // plots are written under it too.
    const SweepResult r = run_sweep(s, opt.sweep);             // every case of the grid, every seed
    const RunFits runs = compare_runs(r.cases, exp, opt);      // each run's misfit against the experiment
    const GridFit grid = score_grid_points(s, r.cases, runs);  // the mean over the seeds; the best point
    const Predictions preds = run_predictions(s, opt, request, r.cases, grid);
    const ScaleCheck scale = check_best_scale(r.cases, grid, exp, opt);
    const bool ok = calibration_ok(r, preds, grid, scale);
    const bool root = opt.sweep.rank == 0;
    if (root) print_warnings(scale);
    if (!root) return ok ? 0 : 1;  // rank 0 alone writes

    const Report rep{s, opt, r.cases, runs, grid, request.axis, preds, scale, r.failed, ok, output_names(ok)};
    write_misfit_tables(rep);                            // misfit.csv, misfit_runs.csv (or *_failed)
    if (ok) write_experiment_csv(rep.out(), exp);        // experiment.csv, for the overlay plot
    write_calibration_json(rep);                         // calibration.json (or calibration_failed.json)
    if (ok) remove_stale_reports(rep);
    if (!opt.sweep.quiet) print_summary(rep);
    if (opt.plot && ok) plot_calibration_dir(opt.sweep.out_dir, opt.sweep.quiet);  // calibration.png
    return ok ? 0 : 1;
}

}  // namespace vpp

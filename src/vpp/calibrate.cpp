#include "vpp/calibrate.h"

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
#include "vpp/plot.h"
#include "vpp/settings.h"
#include "vpp/stats.h"

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
    LoopSeries s = read_loop_csv(path, f.time_col, f.disp_col, f.force_col, "");
    const double sign = f.compression_negative ? -1.0 : 1.0;
    for (double& d : s.displacement) d *= sign * f.disp_scale;
    for (double& x : s.force) x *= sign * f.force_scale;
    s.cycle = split_cycles(s.displacement);  // after the sign flip: a cycle starts at the start position
    shift_to_zero(s);
    if (std::none_of(s.cycle.begin(), s.cycle.end(), [](int c) { return c > 0; }))
        throw std::runtime_error("experiment '" + path + "': no complete cycle found in column '" + f.disp_col +
                                 "' (a cycle goes from the start position to the far end and back; check "
                                 "--compression-negative)");
    return s;
}

void check_experiment_orientation(const LoopSeries& s, const std::string& path, bool compression_negative,
                                  bool compression_first) {
    double sum = 0, extreme = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < s.force.size(); ++i)
        if (s.cycle[i] > 0) {
            sum += s.force[i];
            if (std::abs(s.force[i]) > std::abs(extreme)) extreme = s.force[i];
            ++n;
        }
    double area = 0;
    for (const CycleResult& c : analyze_cycles(s, 1.0)) area += c.dissipated_energy;
    const std::string flag = compression_negative ? "drop --compression-negative (the rig counts compression positive)"
                                                  : "pass --compression-negative (the rig counts compression negative)";
    char buf[160];
    if (area < 0) {
        std::snprintf(buf, sizeof buf, "%.4g J", area);
        throw std::runtime_error("experiment '" + path + "': its loops enclose a negative area (" + buf +
                                 " over its cycles): a damper dissipates, so with displacement and force both "
                                 "compression positive its loop has a positive area; here one of the two counts "
                                 "compression negative: check the columns' sign conventions");
    }
    // A compressed damper pushes back: compression positive, its force is positive on average
    // and largest at full compression. Both negative: the signs are the other way. (Either alone
    // can happen: a raw force with the foil's pull at rest as offset can be negative on average,
    // a loop that drops below its start on unloading can have its largest |F| there.) Extension
    // first (the cap moves up first) is the one protocol where both are negative.
    if (compression_first && n > 0 && sum / double(n) < 0 && extreme < 0) {
        std::snprintf(buf, sizeof buf, "mean %.4g N, largest in magnitude %.4g N", sum / double(n), extreme);
        throw std::runtime_error("experiment '" + path + "': its force over the cycles is negative (" + buf +
                                 (compression_negative ? std::string(", signs flipped") : std::string()) +
                                 "): a compressed damper pushes back, so compression must count positive; " + flag);
    }
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

int run_calibration(Study s, const CalibrateOptions& opt) {
    // No grid (the seeds alone are no grid): the paper's calibration grid.
    if (s.grid.size() == (seed_axis(s) >= 0 ? 1u : 0u))
        s.grid.insert(s.grid.begin(), axis_from_text("grains.friction", "0:1:0.1"));
    const bool root = opt.sweep.rank == 0;
    const fs::path out(opt.sweep.out_dir);
    // Fail fast on a bad experiment or prediction request, before any simulation.
    bool compression_first = true;  // every case loads in compression first (the mean force check)
    double amplitude = 0;           // [m] the largest stroke of the cases
    for (const StudyCase& c : expand_study(s)) {
        compression_first = compression_first && c.config.process.compression_first;
        amplitude = std::max(amplitude, c.config.process.amplitude);
    }
    const LoopSeries exp = read_experiment(opt.experiment, opt.format);
    check_experiment_orientation(exp, opt.experiment, opt.format.compression_negative, compression_first);
    // A unit slip of the displacement (--displacement-unit m on data in mm is a factor of 1000)
    // shows before anything runs: the measured stroke against the cases' process.amplitude.
    if (const double stroke = *std::max_element(exp.displacement.begin(), exp.displacement.end());
        amplitude > 0 && stroke > 0 && (stroke > 10.0 * amplitude || stroke < 0.1 * amplitude)) {
        char msg[400];
        std::snprintf(msg, sizeof msg, "experiment '%s': implausible units: its stroke %.4g m is %.3g times the "
                      "study's process.amplitude %.4g m: check --displacement-unit (now %s)", opt.experiment.c_str(),
                      stroke, stroke / amplitude, amplitude, opt.format.disp_scale == 1.0 ? "m" : "mm");
        throw cfg::ConfigError(msg);
    }
    GridAxis pred;
    std::vector<LoopSeries> pred_exp;
    if (!opt.predict.empty()) {
        const auto eq = opt.predict.find('=');
        if (eq == std::string::npos || eq == 0)
            throw cfg::ConfigError("--predict '" + opt.predict + "': expected key=v1,v2,... e.g. process.underpressure=0.02e6,0.04e6");
        pred = axis_from_text(opt.predict.substr(0, eq), opt.predict.substr(eq + 1));
        if (!opt.predict_experiments.empty() && opt.predict_experiments.size() != pred.literals.size())
            throw cfg::ConfigError("--predict gives " + std::to_string(pred.literals.size()) + " value(s) but " +
                                   std::to_string(opt.predict_experiments.size()) +
                                   " --predict-experiment file(s); give one per value, or none");
        for (const std::string& p : opt.predict_experiments) {
            pred_exp.push_back(read_experiment(p, opt.format));
            check_experiment_orientation(pred_exp.back(), p, opt.format.compression_negative, compression_first);
        }
        // The predicted values must be valid config values too (before the grid runs for hours).
        for (const std::string& lit : pred.literals) {
            std::vector<std::string> sets = s.set;
            sets.push_back(pred.key + "=" + lit);
            try {
                load_config(s.base, sets);
            } catch (const std::exception& e) {
                throw cfg::ConfigError("--predict '" + opt.predict + "': " + e.what());
            }
        }
    } else if (!opt.predict_experiments.empty()) {
        throw cfg::ConfigError("--predict-experiment needs --predict key=v1,v2,...");
    }

    // r holds the folder's lock (SweepResult::lock) to the end: the calibration's tables and
    // plots are written under it too.
    const SweepResult r = run_sweep(s, opt.sweep);
    const auto& cases = r.cases;
    const int seed = seed_axis(s);
    // The grid point of a case: its labels without the seed (the ensemble's runs share it).
    auto point_json = [&](const StudyCase& c) {
        dem::JsonObject b;
        for (std::size_t k = 0; k < s.grid.size(); ++k) {
            if (int(k) == seed) continue;
            const auto& ax = s.grid[k];
            const std::size_t v = std::size_t(std::find(ax.labels.begin(), ax.labels.end(), c.labels[k]) - ax.labels.begin());
            b.raw(ax.key, json_value(ax.labels[v], ax.literals[v]));
        }
        return b;
    };

    // Misfit of every finished run (read from its folder, so every MPI rank agrees).
    std::vector<double> misfit(cases.size(), std::numeric_limits<double>::quiet_NaN());
    std::vector<std::string> status(cases.size());
    std::vector<Misfit> detail(cases.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const fs::path dir = out / cases[i].name;
        // A case that failed in this sweep is not compared, even when its folder still holds
        // the results of an earlier run (e.g. of a study that has changed since).
        if (fs::exists(dir / "FAILED")) {
            std::ifstream in(dir / "FAILED");
            std::string why;
            std::getline(in, why);
            status[i] = "failed: " + why;
            continue;
        }
        if (!fs::exists(dir / "summary.json")) {
            status[i] = "failed: simulation did not finish";
            continue;
        }
        try {
            detail[i] = loop_misfit(read_simulated((dir / "forces.csv").string(), opt.force_column), exp, opt.points);
            misfit[i] = detail[i].value;
            status[i] = "ok";
        } catch (const std::exception& e) {
            status[i] = std::string("failed: ") + e.what();
        }
    }

    // Per grid point: the mean misfit over its seeds and its 95% interval (vpp/stats.h); a point
    // counts only when every seed was compared. The best point has the smallest mean.
    struct Point {
        std::vector<std::size_t> runs;  // case indices, one per seed
        Interval misfit;
        std::string status = "ok";
    };
    std::vector<Point> points;
    for (const auto& g : ensemble_groups(s, cases)) {
        Point p;
        p.runs = g;
        std::vector<double> m;
        for (std::size_t i : g) {
            if (status[i] != "ok" && p.status == "ok") p.status = status[i];
            m.push_back(misfit[i]);
        }
        if (p.status == "ok") p.misfit = mean_interval(m);
        points.push_back(p);
    }
    std::size_t best = SIZE_MAX;
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points[k].status == "ok" && (best == SIZE_MAX || points[k].misfit.mean < points[best].misfit.mean)) best = k;
    // Uncertainty of the best point: the grid points whose misfit interval overlaps the best's
    // (with one seed there is no interval and only equal misfits overlap).
    std::vector<std::size_t> near;
    if (best != SIZE_MAX)
        for (std::size_t k = 0; k < points.size(); ++k)
            if (points[k].status == "ok" && overlaps(points[k].misfit, points[best].misfit)) near.push_back(k);
    const std::size_t best_run = best == SIZE_MAX ? SIZE_MAX : points[best].runs.front();

    // Prediction at the best grid point (every seed of the ensemble).
    struct Prediction {
        std::string label, literal;
        std::vector<std::string> names;
        Interval W, misfit;
        std::string status = "ok";
    };
    std::vector<Prediction> preds;
    int pred_failed = 0;
    if (!pred.key.empty() && best != SIZE_MAX) {
        Study p = s;
        p.grid = {pred};
        if (seed >= 0) p.grid.push_back(s.grid[std::size_t(seed)]);
        for (std::size_t k = 0; k < s.grid.size(); ++k) {
            if (s.grid[k].key == pred.key || int(k) == seed) continue;
            const auto& ax = s.grid[k];
            const std::size_t j = std::size_t(std::find(ax.labels.begin(), ax.labels.end(), cases[best_run].labels[k]) -
                                              ax.labels.begin());
            p.set.push_back(ax.key + "=" + ax.literals[j]);
        }
        SweepOptions so = opt.sweep;
        so.out_dir = (out / "predict").string();
        if (!opt.sweep.quiet && root)
            std::fprintf(stderr, "calibrate: predicting %s at the best grid point\n", opt.predict.c_str());
        const SweepResult pr = run_sweep(p, so);
        pred_failed = pr.failed;
        for (const auto& g : ensemble_groups(p, pr.cases)) {
            Prediction q;
            const std::size_t v = std::size_t(std::find(pred.labels.begin(), pred.labels.end(), pr.cases[g.front()].labels[0]) -
                                              pred.labels.begin());
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
                    if (!pred_exp.empty()) m.push_back(loop_misfit(sim, pred_exp[v], opt.points).value);
                } catch (const std::exception& e) {
                    if (q.status == "ok") q.status = std::string("failed: ") + e.what();
                }
            }
            q.W = mean_interval(W);
            q.misfit = mean_interval(m);
            preds.push_back(q);
        }
    }
    // The best run against the experiment in scale: the stroke and the peak force. A stroke off
    // by more than 10% makes the comparison meaningless (warned). Off by more than a factor of
    // 10 either is not a fit at all: a unit slip (--force-unit kN on data in N is a factor of
    // 1000, mm for m the same) is the likely cause, and a calibration in the wrong unit must not
    // replace a good calibration.json: the run counts as failed (calibration_failed.json).
    std::vector<std::string> warnings;
    bool implausible = false;
    if (best != SIZE_MAX) {
        try {
            const LoopSeries sim = read_simulated((out / cases[best_run].name / "forces.csv").string(), opt.force_column);
            auto peak = [](const std::vector<double>& v) {
                double m = 0;
                for (double x : v) m = std::max(m, std::abs(x));
                return m;
            };
            const double rs = *std::max_element(sim.displacement.begin(), sim.displacement.end());
            const double re = *std::max_element(exp.displacement.begin(), exp.displacement.end());
            const double fs_ = peak(sim.force), fe = peak(exp.force);
            char msg[512];
            constexpr double kUnitSlip = 10.0;  // [-] a ratio no fit explains; a unit slip is 1000
            if (re > 0 && rs > 0 && (rs / re > kUnitSlip || re / rs > kUnitSlip)) {
                implausible = true;
                std::snprintf(msg, sizeof msg, "implausible units: the measured stroke %.4g m is %.3g times the "
                              "simulated %.4g m: check --displacement-unit (now %s)", re, re / rs, rs,
                              opt.format.disp_scale == 1.0 ? "m" : "mm");
                warnings.push_back(msg);
            } else if (std::abs(rs - re) > 0.1 * re) {
                std::snprintf(msg, sizeof msg, "simulated stroke %.4g mm, measured %.4g mm: set process.amplitude to "
                              "the experiment's", rs * 1e3, re * 1e3);
                warnings.push_back(msg);
            }
            if (fe > 0 && fs_ > 0 && (fe / fs_ > kUnitSlip || fs_ / fe > kUnitSlip)) {
                implausible = true;
                std::snprintf(msg, sizeof msg, "implausible units: the measured peak force %.4g N is %.3g times the "
                              "best simulated %.4g N: check --force-unit (now %s)", fe, fe / fs_, fs_,
                              opt.format.force_scale == 1.0 ? "N" : "kN");
                warnings.push_back(msg);
            }
        } catch (const std::exception& e) {
            warnings.push_back(std::string("the best case's forces could not be read for the scale checks: ") + e.what());
        }
    }
    const bool ok = !r.failed && !pred_failed && best != SIZE_MAX && !implausible &&
                    std::all_of(points.begin(), points.end(), [](const Point& p) { return p.status == "ok"; });
    // On stderr whatever --quiet says, and in the json below.
    if (root)
        for (const std::string& w : warnings) std::fprintf(stderr, "WARNING: calibrate: %s\n", w.c_str());
    if (!root) return ok ? 0 : 1;
    // A calibration that failed (a case failed or could not be compared, a prediction failed)
    // writes its results under other names: a good calibration.json and misfit.csv from an
    // earlier run of the same folder stay as they are.
    const std::string suffix = ok ? "" : "_failed";
    const std::string misfit_name = "misfit" + suffix + ".csv", runs_name = "misfit_runs" + suffix + ".csv";
    const std::string json_name = "calibration" + suffix + ".json";

    // The study's cells (dem/io/csv.h), so that misfit.csv quotes as summary.csv does.
    auto field = [](const std::string& x) { return dem::csv_text(x); };
    auto number = [](double v) { return dem::csv_number(v); };
    // misfit.csv: one row per grid point: the grid keys but the seed, misfit (the mean over the
    // seeds), status, case (its first seed's folder), then misfit_n, misfit_sd, misfit_ci95.
    std::string csv;
    for (std::size_t k = 0; k < s.grid.size(); ++k)
        if (int(k) != seed) csv += field(s.grid[k].key) + ",";
    csv += "misfit,status,case,misfit_n,misfit_sd,misfit_ci95\n";
    for (const Point& p : points) {
        const StudyCase& c = cases[p.runs.front()];
        for (std::size_t k = 0; k < c.labels.size(); ++k)
            if (int(k) != seed) csv += field(c.labels[k]) + ",";
        csv += number(p.misfit.mean) + "," + field(p.status) + "," + field(c.name) + "," + std::to_string(p.misfit.n) +
               "," + number(p.misfit.sd) + "," + number(p.misfit.half) + "\n";
    }
    dem::write_text_atomic((out / misfit_name).string(), csv);
    if (seed >= 0) {
        // misfit_runs.csv: one row per run, the seed included.
        std::string runs;
        for (const GridAxis& a : s.grid) runs += field(a.key) + ",";
        runs += "misfit,status,case\n";
        for (std::size_t i = 0; i < cases.size(); ++i) {
            for (const std::string& l : cases[i].labels) runs += field(l) + ",";
            runs += number(misfit[i]) + "," + field(status[i]) + "," + field(cases[i].name) + "\n";
        }
        dem::write_text_atomic((out / runs_name).string(), runs);
    }

    // The processed experiment, for the overlay plot.
    if (ok) {
        // The cycle number is a whole double: the writer prints it without a decimal point.
        dem::CsvWriter e((out / "experiment.csv").string(), "time,displacement,force,cycle");
        for (std::size_t i = 0; i < exp.time.size(); ++i)
            e.row({exp.time[i], exp.displacement[i], exp.force[i], double(exp.cycle[i])});
        e.close();
    }

    auto names_json = [&](const std::vector<std::size_t>& runs) {
        std::vector<std::string> names;
        for (std::size_t k : runs) names.push_back(cases[k].name);
        return dem::json_string_array(names);
    };
    dem::JsonObject j;
    if (best != SIZE_MAX) {
        const Point& b = points[best];
        j.raw("best", point_json(cases[best_run]).value())
            .num("misfit", b.misfit.mean)
            .num("misfit_sd", b.misfit.sd)
            .num("misfit_ci95", b.misfit.half)
            .num("seeds", double(b.misfit.n))
            .str("case", cases[best_run].name)
            .raw("cases", names_json(b.runs));
        // The range of each grid key over the points whose interval overlaps the best's.
        dem::JsonObject u;
        u.str("rule", "grid points whose 95% misfit interval (mean over seeds +- t_{0.975,n-1} sd/sqrt(n)) overlaps "
                      "the best point's; with one seed, only points of equal misfit");
        for (std::size_t k = 0; k < s.grid.size(); ++k) {
            if (int(k) == seed) continue;
            const auto& ax = s.grid[k];
            std::vector<std::size_t> idx;
            for (std::size_t q : near)
                idx.push_back(std::size_t(std::find(ax.labels.begin(), ax.labels.end(), cases[points[q].runs.front()].labels[k]) -
                                          ax.labels.begin()));
            std::sort(idx.begin(), idx.end());
            idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
            std::string vals = "[";
            for (std::size_t m = 0; m < idx.size(); ++m) vals += (m ? ", " : "") + json_value(ax.labels[idx[m]], ax.literals[idx[m]]);
            u.raw(ax.key, vals + "]");
        }
        j.raw("uncertainty", u.value());
        std::string cyc = "[", rms = "[", en = "[";
        const Misfit& d = detail[best_run];
        for (std::size_t k = 0; k < d.cycles.size(); ++k) {
            cyc += (k ? ", " : "") + std::to_string(d.cycles[k]);
            rms += (k ? ", " : "");
            dem::append_number(rms, d.rms[k]);
            en += (k ? ", " : "");
            dem::append_number(en, d.energy[k]);
        }
        j.raw("cycles_compared", cyc + "]").raw("best_rms_per_cycle", rms + "]").raw("best_energy_per_cycle", en + "]");
    } else {
        j.raw("best", "null").raw("misfit", "null");
    }
    j.str("experiment", fs::absolute(opt.experiment).string())
        .str("simulated_force", opt.force_column)
        .num("points_per_branch", opt.points)
        .str("misfit_definition",
             "mean over the stabilised cycles (2..n) of rms_c + energy_c; rms_c = RMS of F_sim - F_exp over "
             "points_per_branch displacements per loading and unloading branch, over the measured cycle's peak "
             "|F|; energy_c = |E_sim - E_exp| / |E_exp| (loop areas); with seeds, the mean over the seeds of a grid "
             "point, with its 95% interval (Student t, n - 1 degrees of freedom)");
    std::string grid = "[";
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Point& p = points[k];
        dem::JsonObject g = point_json(cases[p.runs.front()]);
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
            .raw("cases", names_json(p.runs))
            .str("status", p.status);
        const std::string t = g.value();
        grid += (k ? ", " : "") + t;
    }
    j.raw("grid", grid + "]");
    if (!preds.empty()) {
        std::string pj = "[";
        for (std::size_t i = 0; i < preds.size(); ++i) {
            dem::JsonObject q;
            q.raw(pred.key, json_value(preds[i].label, preds[i].literal))
                .str("case", preds[i].names.empty() ? "" : preds[i].names.front())
                .raw("cases", dem::json_string_array(preds[i].names))
                .num("W", preds[i].W.mean)
                .num("W_ci95", preds[i].W.half)
                .num("misfit", preds[i].misfit.mean)
                .num("misfit_ci95", preds[i].misfit.half)
                .str("status", preds[i].status);
            if (!opt.predict_experiments.empty()) q.str("experiment", opt.predict_experiments[i]);
            const std::string t = q.value();
            pj += (i ? ", " : "") + t;
        }
        j.raw("predictions", pj + "]");
    }
    j.raw("warnings", dem::json_string_array(warnings));
    dem::write_text_atomic((out / json_name).string(), j.text());
    if (ok) {  // no stale failure report beside a good result
        fs::remove(out / "misfit_failed.csv");
        fs::remove(out / "misfit_runs_failed.csv");
        fs::remove(out / "calibration_failed.json");
        if (seed < 0) fs::remove(out / "misfit_runs.csv");  // of an earlier calibration with seeds
    }

    if (!opt.sweep.quiet) {
        std::fprintf(stderr, "\n=== vppdem calibrate: %s ===\n", opt.sweep.out_dir.c_str());
        for (std::size_t k = 0; k < points.size(); ++k) {
            const Point& p = points[k];
            std::string name = cases[p.runs.front()].name;
            if (p.runs.size() > 1) name += " and " + std::to_string(p.runs.size() - 1) + " more seed(s)";
            char m[128];
            if (p.status != "ok") std::snprintf(m, sizeof m, "%s", p.status.substr(0, 120).c_str());
            else if (std::isfinite(p.misfit.half)) std::snprintf(m, sizeof m, "%.4g +- %.2g", p.misfit.mean, p.misfit.half);
            else std::snprintf(m, sizeof m, "%.4g", p.misfit.mean);
            std::fprintf(stderr, "%s %-48s misfit %s\n", k == best ? "*" : " ", name.c_str(), m);
        }
        for (const Prediction& q : preds)
            std::fprintf(stderr, "  predicted %s = %s: W = %.5g J/m^2%s\n", pred.key.c_str(), q.label.c_str(), q.W.mean,
                         std::isfinite(q.misfit.mean) ? (", misfit " + std::to_string(q.misfit.mean)).c_str() : "");
        if (best != SIZE_MAX) {
            std::string range;
            for (std::size_t k = 0; k < s.grid.size(); ++k) {
                if (int(k) == seed) continue;
                std::vector<std::string> v;
                for (std::size_t q : near) v.push_back(cases[points[q].runs.front()].labels[k]);
                range += " " + s.grid[k].key + " in {";
                for (std::size_t m = 0; m < v.size(); ++m) range += (m ? ", " : "") + v[m];
                range += "}";
            }
            std::fprintf(stderr, "best: %s (misfit %.4g over %zu seed(s)); within its interval:%s; wrote %s, %s\n",
                         cases[best_run].name.c_str(), points[best].misfit.mean, points[best].misfit.n, range.c_str(),
                         misfit_name.c_str(), json_name.c_str());
        } else {
            std::fprintf(stderr, "no case could be compared with the experiment; wrote %s, %s\n", misfit_name.c_str(),
                         json_name.c_str());
        }
        if (!ok)
            std::fprintf(stderr, "calibration FAILED (%d case(s) failed%s%s): results in %s; %s\n", r.failed,
                         pred_failed ? ", predictions failed" : "", implausible ? ", implausible units" : "",
                         json_name.c_str(),
                         fs::exists(out / "calibration.json") ? "the earlier calibration.json is kept"
                                                              : "no calibration.json written");
    }
    if (opt.plot && ok) plot_calibration_dir(opt.sweep.out_dir, opt.sweep.quiet);
    return ok ? 0 : 1;
}

}  // namespace vpp

// Every file in examples/ runs, shortened, as a smoke test (README: "example scenes, also run as
// smoke tests"): scenes for a few milliseconds, studies on their first grid point in the tests'
// small damper for one cycle, the scripts on small inputs. A file of a kind this test does not
// know fails it, so a new example cannot go untested.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "cli_helpers.h"
#include "vpp/study/study.h"

namespace {

using namespace cli_test;

const fs::path kExamples = fs::path(VPPDEM_SOURCE_DIR) / "examples";

std::vector<std::string> example_files() {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(kExamples))
        if (e.is_regular_file()) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// The small quick damper (tests/physics/cli_helpers.h, kSmallDamper: mass-scaled at the feature
// tests' step) for one short cycle; a study's [set] and [grid] values of these keys are replaced.
const std::vector<std::pair<std::string, std::string>> kSmallStudy = {
    {"damper.radius", "0.012"},           {"damper.height", "0.03"},      {"grains.volume_fraction", "0.45"},
    {"process.velocity", "0.1"},          {"process.amplitude", "0.002"}, {"process.cycles", "1"},
    {"process.samples_per_cycle", "40"},  {"simulation.threads", "1"},    {"simulation.dt_safety", "0.45"},
    {"grains.density", "268963.9"},       {"foil.density", "15177.0"}};

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string number_literal(double v) {  // a TOML float
    std::string s;
    dem::append_number(s, v);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

// A TOML value as written in a file.
std::string cfg_literal(const toml::node& n) {
    if (auto i = n.as_integer()) return std::to_string(i->get());
    if (auto f = n.as_floating_point()) return number_literal(f->get());
    if (auto b = n.as_boolean()) return b->get() ? "true" : "false";
    if (auto s = n.as_string()) return quoted(s->get());
    return "?";
}

// The study reduced to one case: every grid key keeps its first value (or the small damper's),
// the small damper's keys are fixed, `base` is made absolute.
std::string shortened_study(const fs::path& file) {
    const toml::table t = toml::parse_file(file.string());
    std::string out;
    if (auto b = t["base"].value<std::string>()) out += "base = " + quoted((file.parent_path() / *b).string()) + "\n";
    if (auto s = t["share_preparation"].value<bool>()) out += std::string("share_preparation = ") + (*s ? "true" : "false") + "\n";
    auto small = [](const std::string& key) -> const std::string* {
        for (const auto& [k, v] : kSmallStudy)
            if (k == key) return &v;
        return nullptr;
    };
    auto flat = [](const toml::table* tab) {
        std::vector<std::pair<std::string, const toml::node*>> kv;
        if (!tab) return kv;
        std::function<void(const toml::table&, const std::string&)> walk = [&](const toml::table& x, const std::string& p) {
            for (const auto& [k, v] : x) {
                const std::string key = p.empty() ? std::string(k.str()) : p + "." + std::string(k.str());
                if (v.as_table()) walk(*v.as_table(), key);
                else kv.push_back({key, &v});
            }
        };
        walk(*tab, "");
        return kv;
    };
    const auto grid = flat(t["grid"].as_table());
    auto in_grid = [&](const std::string& key) {
        return std::any_of(grid.begin(), grid.end(), [&](const auto& g) { return g.first == key; });
    };
    std::string set = "[set]\n";
    for (const auto& [k, v] : flat(t["set"].as_table()))
        if (!small(k)) set += quoted(k) + " = " + cfg_literal(*v) + "\n";
    for (const auto& [k, v] : kSmallStudy)
        if (!in_grid(k)) set += quoted(k) + " = " + v + "\n";
    std::string g = "[grid]\n";
    for (const auto& [k, v] : grid) {
        std::string first;
        if (const std::string* s = small(k)) first = *s;
        else if (const toml::array* a = v->as_array()) first = cfg_literal(*a->get(0));
        else if (auto r = v->value<std::string>()) {
            bool ints = false;
            const double x = vpp::parse_range(k, *r, &ints).front();
            first = ints ? std::to_string(std::llround(x)) : number_literal(x);
        }
        g += quoted(k) + " = [" + first + "]\n";
    }
    return out + set + g;
}

class ExampleRuns : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(ExampleRuns, FinishesWithItsOutputs) {
    const std::string name = GetParam();
    const fs::path file = kExamples / name, dir = scratch_path("examples", name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    if (name.ends_with(".toml") && toml::parse_file(file.string()).contains("materials")) {
        // A scene: a few milliseconds, VTK frames included.
        const Outcome r = run("scene " + file.string() + " --out " + (dir / "out").string() +
                              " --quiet --set simulation.duration=0.004 --set simulation.output_interval=0.001"
                              " --set output.vtk_interval=0.002 --set simulation.threads=1");
        ASSERT_EQ(r.status, 0) << r.output;
        for (const char* f : {"tracked.csv", "walls.csv", "summary.json", "vtk/particles_000002.vtk"})
            EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
        EXPECT_GE(data_rows(dir / "out" / "walls.csv"), 5u);
    } else if (name.ends_with(".toml")) {
        // A study: its first grid point in the small damper, one cycle.
        write_file(dir / "study.toml", shortened_study(file));
        const Outcome r = run("sweep " + (dir / "study.toml").string() + " --out " + (dir / "out").string() +
                              " --no-plot --quiet");
        ASSERT_EQ(r.status, 0) << r.output << "\n" << slurp(dir / "study.toml");
        const std::string summary = slurp(dir / "out" / "summary.csv");
        EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 2) << summary;
        EXPECT_NE(summary.find(",ok,"), std::string::npos) << summary;
    } else if (name.ends_with(".py")) {
        // gen_column.py N RADIUS CIRCLE_RADIUS Z0 OUT.csv [SEED]
        const Outcome r = shell("python3 " + file.string() + " 50 0.003 0.02 0.004 " + (dir / "c.csv").string() + " 2");
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_EQ(data_rows(dir / "c.csv") + 1, 50u);  // no header: data_rows skips the first line
    } else if (name == "underpressure_series.sh") {
        // The four underpressures from the small damper's preparation, one short cycle each.
        const std::string small = " --set process.amplitude=0.002 --set process.cycles=1"
                                  " --set process.samples_per_cycle=40 --set simulation.threads=1";
        const Outcome p = run("damper --out " + (dir / "prep").string() + " " + kSmallDamper + " --set process.cycles=1");
        ASSERT_EQ(p.status, 0) << p.output;
        const Outcome r = shell("VPPDEM=" + kBinary + " bash " + file.string() + " " + (dir / "prep/prepared.ckpt").string() +
                                " " + (dir / "series").string() + " 0.1" + small);
        ASSERT_EQ(r.status, 0) << r.output;
        for (const char* dp : {"0.02e6", "0.04e6", "0.06e6", "0.08e6"})
            EXPECT_EQ(data_rows(dir / "series" / ("dp_" + std::string(dp)) / "cycles.csv"), 1u) << dp;
    } else {
        FAIL() << "examples/" << name << ": no smoke test for this kind of file; add one to " << __FILE__;
    }
    fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Examples, ExampleRuns, ::testing::ValuesIn(example_files()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string n = info.param;
                             for (char& c : n)
                                 if (!std::isalnum((unsigned char)c)) c = '_';
                             return n;
                         });

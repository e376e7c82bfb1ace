// The scene runner's settings table (scene/scene_settings.h): every key it lists is one the
// reader accepts and every key the reader accepts is in it, its defaults are the ones the reader
// applies (and the ones `vppdem scene` always had), its ranges are the ones the reader enforces
// with messages naming the key and what is allowed, and the reference page prints every row.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "scene/config.h"
#include "toml_literal.h"
#include "scene/scene_runner.h"
#include "scene/scene_settings.h"

namespace fs = std::filesystem;
using scene::SceneSetting;

namespace {

// A scene that gives every key of every group at least once: each facet set type, a sphere and a
// wall with a displacement history, a sphere file and an STL file. Bodies far apart (no overlaps).
constexpr const char* kEveryKey = R"(
[simulation]
dt = 1e-6
dt_safety = 0.5
duration = 1e-5
gravity = [0.0, 0.0, -1.0]
local_damping = 0.1
threads = 2
output_interval = 2e-6
skin = 0.001
max_initial_overlap = 0.02

[output]
vtk_interval = 0.0
energy = true

[[materials]]
name = "a"
density = 1000.0
young = 1e7
stiffness_ratio = 0.3
friction = 0.2
restitution = 0.9

[[spheres]]
material = "a"
radius = 0.01
position = [0.0, 0.0, 0.5]
velocity = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 0.0]
mask = 1
fixed = false
prescribed = false
track = true

[[spheres]]
material = "a"
radius = 0.01
position = [0.1, 0.0, 0.5]
displacement = [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 1.0]]

[[sphere_files]]
path = "grains.csv"
material = "a"
velocity = [0.0, 0.0, 0.0]
mask = 1
fixed = false
track = false

[[clumps]]
material = "a"
shape = "template"
template = "clump.csv"
radius = 0.01
position = [0.8, 0.0, 0.5]
orientation = [0.0, 0.0, 0.3]
velocity = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 0.0]
mask = 1

[[planes]]
material = "a"
point = [0.0, 0.0, -1.0]
normal = [0.0, 0.0, 1.0]
one_sided = true
mask = 1
velocity = [0.0, 0.0, 0.0]

[[planes]]
material = "a"
point = [0.0, 0.0, 2.0]
normal = [0.0, 0.0, -1.0]
displacement = [[0.0, 0.0, 0.0, 0.0]]

[[facets]]
material = "a"
vertices = [[3.0, 0.0, 0.0], [4.0, 0.0, 0.0], [3.0, 1.0, 0.0]]
one_sided = true
mask = 1
velocity = [0.0, 0.0, 0.0]

[[facets]]
material = "a"
vertices = [[6.0, 0.0, 0.0], [7.0, 0.0, 0.0], [6.0, 1.0, 0.0]]
displacement = [[0.0, 0.0, 0.0, 0.0]]

[[facet_sets]]
type = "cylinder"
material = "a"
one_sided = false
mask = 1
velocity = [0.0, 0.0, 0.0]
base = [10.0, 10.0, 0.0]
radius = 0.1
height = 0.1
segments = 12
inward = true

[[facet_sets]]
type = "funnel"
material = "a"
displacement = [[0.0, 0.0, 0.0, 0.0]]
base = [20.0, 20.0, 0.0]
bottom_radius = 0.05
top_radius = 0.1
height = 0.1
segments = 8
inward = false

[[facet_sets]]
type = "stl"
material = "a"
path = "tri.stl"
scale = 1e-3
)";

// A fresh folder with the files kEveryKey refers to.
class SceneFolder {
public:
    SceneFolder() : dir_(fs::temp_directory_path() / ("vppdem_scene_settings_" + std::to_string(::getpid()))) {
        fs::create_directories(dir_);
        std::ofstream(dir_ / "grains.csv") << "x,y,z,r\n0.5,0.0,0.5,0.01\n0.6,0.0,0.5,0.01\n";
        std::ofstream(dir_ / "clump.csv") << "x,y,z,r\n0,0,0,0.01\n0.01,0,0,0.01\n";
        std::ofstream(dir_ / "tri.stl") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 30000 0 0\n"
                                           "vertex 31000 0 0\nvertex 30000 1000 0\nendloop\nendfacet\nendsolid t\n";
    }
    ~SceneFolder() {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path() const { return dir_.string(); }

private:
    fs::path dir_;
};

scene::Scene build(const std::string& text, const std::string& dir = ".") {
    return scene::build_scene(toml::parse(text), dir);
}

constexpr const char* kMinimal = "[[materials]]\nname = \"a\"\n"
                                 "[[spheres]]\nmaterial = \"a\"\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n";

std::string message_of(const std::string& text) {
    try {
        build(text);
    } catch (const cfg::ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SceneSettings, EveryKeyOfTheTableIsReadAndNoOther) {
    // The scene above builds: every key in it is one the reader reads (an unread key is refused).
    SceneFolder folder;
    const toml::table root = toml::parse(kEveryKey);
    ASSERT_NO_THROW(scene::build_scene(root, folder.path()));

    // And it gives every key of the table: so every row is a key the reader accepts.
    std::map<std::string, std::set<std::string>> given;  // group -> keys
    for (const auto& [k, v] : root) {
        const std::string name(k.str());
        if (const toml::table* t = v.as_table()) {
            for (const auto& [kk, vv] : *t) given[name].insert(std::string(kk.str()));
        } else if (const toml::array* a = v.as_array()) {
            for (const auto& e : *a)
                for (const auto& [kk, vv] : *e.as_table()) given[name + "[]"].insert(std::string(kk.str()));
        }
    }
    std::size_t rows = 0;
    for (const SceneSetting& s : scene::scene_settings()) {
        EXPECT_TRUE(given[s.group()].count(s.name())) << s.key << " is in the table but not in the scene above";
        ++rows;
    }
    std::size_t keys = 0;
    for (const auto& [g, names] : given) {
        keys += names.size();
        for (const auto& n : names) EXPECT_NE(scene::find_scene_setting(g + "." + n), nullptr) << g << "." << n;
    }
    EXPECT_EQ(rows, keys);

    // The reader asks the table for each key; a key outside the table is a bug of the reader.
    scene::SceneSection sim(cfg::Section(nullptr, "simulation"), "simulation");
    EXPECT_THROW(sim.real("time_step"), std::logic_error);
    EXPECT_DOUBLE_EQ(sim.real("duration"), 1e-3);
}

TEST(SceneSettings, DefaultsAreTheTablesAndTheDocumentedOnes) {
    const scene::Scene sc = build(kMinimal);
    auto def = [](const std::string& key) {
        const SceneSetting* s = scene::find_scene_setting(key);
        EXPECT_NE(s, nullptr) << key;
        return s ? s->def : NAN;
    };
    // What `vppdem scene` has read since docs/scene.md was written: a change here changes runs.
    EXPECT_EQ(sc.world.params.dt, 1e-7);
    EXPECT_EQ(sc.dt_safety, 0.3);
    EXPECT_EQ(sc.duration, 1e-3);
    EXPECT_EQ(sc.world.params.gravity.z, -9.81);
    EXPECT_EQ(sc.world.params.local_damping, 0.0);
    EXPECT_EQ(sc.world.params.threads, 1);
    EXPECT_EQ(sc.output_interval, 1e-6);
    EXPECT_EQ(sc.world.params.skin, 0.0);
    EXPECT_EQ(sc.vtk_interval, 0.0);
    EXPECT_FALSE(sc.world.params.track_energy);
    // ... and they are the table's.
    EXPECT_EQ(sc.world.params.dt, def("simulation.dt"));
    EXPECT_EQ(sc.dt_safety, def("simulation.dt_safety"));
    EXPECT_EQ(sc.duration, def("simulation.duration"));
    EXPECT_EQ(sc.world.params.gravity.z, scene::find_scene_setting("simulation.gravity")->def3.z);
    EXPECT_EQ(sc.world.params.local_damping, def("simulation.local_damping"));
    EXPECT_EQ(double(sc.world.params.threads), def("simulation.threads"));
    EXPECT_EQ(sc.output_interval, def("simulation.output_interval"));
    EXPECT_EQ(sc.world.params.skin, def("simulation.skin"));
    EXPECT_EQ(sc.vtk_interval, def("output.vtk_interval"));
    const dem::Material& m = sc.world.materials[0];
    EXPECT_EQ(m.density, 2800.0);
    EXPECT_EQ(m.young, 4.8e10);
    EXPECT_EQ(m.stiffness_ratio, 0.5);
    EXPECT_EQ(m.friction, 0.35);
    EXPECT_EQ(m.restitution, 1.0);
    EXPECT_EQ(m.density, def("materials[].density"));
    EXPECT_EQ(m.young, def("materials[].young"));
    EXPECT_EQ(m.friction, def("materials[].friction"));
    EXPECT_EQ(m.restitution, def("materials[].restitution"));
    EXPECT_EQ(sc.world.particles.mask[0], uint32_t(def("spheres[].mask")));
}

TEST(SceneSettings, RangesAreEnforcedWithTheTablesWords) {
    // Every checked number of [simulation], [output] and [[materials]]: a value outside its range
    // is refused naming the key and what is allowed; a value inside is taken.
    int checked = 0;
    for (const SceneSetting& s : scene::scene_settings()) {
        const std::string g = s.group();
        if (g != "simulation" && g != "output" && g != "materials[]") continue;
        if (s.type != cfg::SettingType::Real && s.type != cfg::SettingType::Integer) continue;
        const cfg::Limits& l = s.limits;
        std::vector<double> bad;
        double good = NAN;
        std::string words;
        switch (l.check) {
        case cfg::Check::Positive: bad = {0.0, -1.0}; good = 2.0; words = "must be > 0"; break;
        case cfg::Check::NonNegative: bad = {-1e-9}; good = 0.0; words = "must be >= 0"; break;
        case cfg::Check::Range: {
            const double step = s.type == cfg::SettingType::Integer ? 1.0 : 1e-9;
            bad = {l.lo_open ? l.lo : l.lo - step, l.hi_open ? l.hi : l.hi + step};
            good = s.type == cfg::SettingType::Integer ? l.lo : 0.5 * (l.lo + l.hi);
            words = l.allowed;
            break;
        }
        default: continue;  // dt: a reader of its own, tested in SceneCli.ErrorsNameTheKeyAndWriteNothing
        }
        auto scene_with = [&](double v) {
            const std::string value = s.type == cfg::SettingType::Integer ? std::to_string(int64_t(v)) : toml_float_literal(v);
            if (g == "materials[]")
                return "[[materials]]\nname = \"a\"\n" + s.name() + " = " + value + "\n" +
                       "[[spheres]]\nmaterial = \"a\"\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n";
            return "[" + g + "]\n" + s.name() + " = " + value + "\n" + kMinimal;
        };
        const std::string shown = g == "materials[]" ? "materials[0]." + s.name() : s.key;
        for (double v : bad) {
            const std::string msg = message_of(scene_with(v));
            EXPECT_NE(msg.find("'" + shown + "'"), std::string::npos) << s.key << " = " << v << ": " << msg;
            EXPECT_NE(msg.find(words), std::string::npos) << s.key << " = " << v << ": " << msg;
            ++checked;
        }
        EXPECT_EQ(message_of(scene_with(good)), "") << s.key << " = " << good;
    }
    EXPECT_GE(checked, 12);
    // A mask and the segments of a cylinder, the integer checks of body entries.
    const std::string ok = std::string(kMinimal);
    EXPECT_NE(message_of(ok + "mask = 0\n").find("positive 32-bit bit mask"), std::string::npos);
    EXPECT_NE(message_of(ok + "mask = 4294967296\n").find("positive 32-bit bit mask"), std::string::npos);
    EXPECT_EQ(message_of(ok + "mask = 4294967295\n"), "");
    const std::string cyl = "[[facet_sets]]\ntype = \"cylinder\"\nmaterial = \"a\"\nbase = [5.0, 0.0, 0.0]\n"
                            "radius = 0.1\nheight = 0.1\nsegments = ";
    EXPECT_NE(message_of(ok + cyl + "2\n").find("'facet_sets[0].segments' = 2: must be an integer 3 ... 100000"),
              std::string::npos)
        << message_of(ok + cyl + "2\n");
    EXPECT_EQ(message_of(ok + cyl + "3\n"), "");
    // Above the range: 10^9 segments ran out of memory, 2^32 + 3 wrapped to 3 segments in the
    // conversion to int (found by fuzz/fuzz_scene.cpp's harness).
    for (const char* v : {"100001", "1000000000", "4294967299"})
        EXPECT_NE(message_of(ok + cyl + v + "\n").find("must be an integer 3 ... 100000"), std::string::npos) << v;
    EXPECT_EQ(message_of(ok + cyl + "100000\n"), "");
}

TEST(SceneSettings, TheReferencePrintsEveryRowUnderItsGroup) {
    const std::string md = scene::scene_reference_markdown();
    std::string group;
    std::size_t at = 0;
    for (const SceneSetting& s : scene::scene_settings()) {
        if (s.group() != group) {
            group = s.group();
            const bool array = group.ends_with("[]");
            const std::string name = array ? group.substr(0, group.size() - 2) : group;
            const std::string heading = "### Scene `" + std::string(array ? "[[" : "[") + name + (array ? "]]`" : "]`");
            at = md.find(heading, at);
            ASSERT_NE(at, std::string::npos) << heading;
        }
        // Rows follow their heading, in table order.
        const std::size_t row = md.find("| `" + s.name() + "` |", at);
        ASSERT_NE(row, std::string::npos) << s.key;
        at = row;
    }
}

TEST(SceneSettings, SummaryInputsAreEverySimulationAndOutputKeyAsUsed) {
    // summary.json "inputs" (Scene::inputs): each [simulation] and [output] row of the table, in
    // its order, with the value the run used: the table's default where the file is silent.
    const scene::Scene sc = build(std::string("[simulation]\ndt = \"auto\"\nduration = 0.5\n") + kMinimal);
    std::vector<std::string> expected;
    for (const SceneSetting& s : scene::scene_settings())
        if (s.group() == "simulation" || s.group() == "output") expected.push_back(s.key);
    std::vector<std::string> keys;
    std::map<std::string, std::string> value;
    for (const auto& [k, v] : sc.inputs) {
        keys.push_back(k);
        value[k] = v;
    }
    EXPECT_EQ(keys, expected);
    EXPECT_EQ(value["simulation.dt"], "\"auto\"");
    EXPECT_EQ(value["simulation.duration"], "0.5");
    EXPECT_EQ(value["simulation.output_interval"], "1e-06");  // the default, shortest round-trip text
    EXPECT_EQ(value["simulation.threads"], "1");
    EXPECT_EQ(value["simulation.gravity"], "[0, 0, -9.81]");
    EXPECT_EQ(value["output.energy"], "false");
}

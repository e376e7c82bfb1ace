// The settings table (vpp/settings/settings.h): its defaults are the ones the reader applies, its ranges
// are the ones the reader enforces with messages naming key, value and what is allowed, and its
// sharing rule is the study's rule of before the table.
// At its end, the keys every settings table shares (scene/shared_keys.h) and the enumerated settings.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dem/clumps/clump_shape.h"
#include "dem/world/world.h"
#include "scene/config.h"
#include "scene/scene_runner.h"
#include "scene/scene_settings.h"
#include "scene/shared_keys.h"
#include "scene/time_step.h"
#include "toml_literal.h"
#include "vpp/device/definition.h"
#include "vpp/settings/choices.h"
#include "vpp/settings/config.h"
#include "vpp/settings/settings.h"
#include "vpp/study/key_reference.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_settings {

using namespace vpp;

namespace {

std::string message_of(const std::vector<std::string>& sets) {
    try {
        load_config("", sets);
    } catch (const cfg::ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Settings, KeysAreUniqueAndSectionsStayTogether) {
    std::set<std::string> keys, closed;
    std::string section;
    for (const Setting& s : settings()) {
        EXPECT_TRUE(keys.insert(s.key).second) << s.key;
        const std::string sec = std::string(s.key).substr(0, std::string(s.key).find('.'));
        if (sec != section) {
            EXPECT_FALSE(closed.count(sec)) << s.key << ": its section appears twice";
            closed.insert(section);
            section = sec;
        }
        EXPECT_NE(std::string(s.doc), "") << s.key;
        EXPECT_EQ(find_setting(s.key), &s);
    }
    EXPECT_EQ(find_setting("grains.colour"), nullptr);
}

TEST(Settings, DefaultsAreTheReadersDefaults) {
    const Config damper = load_config("", {});
    const Config foil = load_config("", {}, CommandSet::Foil);
    for (const Setting& s : settings()) {
        if (std::string(s.key) == "simulation.threads") continue;  // 0: the free cores, measured
        if (std::isnan(s.def)) continue;
        EXPECT_EQ(s.get(damper), s.def) << s.key;
        EXPECT_EQ(s.get(foil), std::isnan(s.def_foil) ? s.def : s.def_foil) << s.key;
    }
    // The ones given as text.
    EXPECT_EQ(damper.foil.particle_radius, damper.grains.radius / 3.0);
    EXPECT_LT(damper.damper.cap_friction, 0.0);  // the grains' friction
    EXPECT_TRUE(damper.process.compression_first);
    EXPECT_TRUE(damper.simulation.dt_auto);
    EXPECT_LT(damper.process.local_damping, 0.0);  // "auto"
    EXPECT_EQ(foil.simulation.threads, 1);
    // The defaults the commands had before the table; dt_safety 0.3 for both since the time-step
    // study (issue 44: 0.45 lay +3.1% above the converged W, 0.3 within 2%).
    EXPECT_EQ(damper.process.underpressure, 0.06e6);
    EXPECT_EQ(damper.simulation.dt_safety, 0.3);
    EXPECT_EQ(foil.process.underpressure, 0.01e6);
    EXPECT_EQ(foil.simulation.dt_safety, 0.3);
}

// One default per key (issue 21): a Config built in code is the command line's model, not a
// second set of defaults written beside the table (the structs of vpp/settings/config.h hold none).
TEST(Settings, AConfigBuiltInCodeIsTheCommandLinesConfig) {
    for (const CommandSet k : {CommandSet::Damper, CommandSet::Foil}) {
        const Config built(k);
        const Config read = load_config("", {}, k);
        for (const Setting& s : settings()) {
            if (std::string(s.key) == "simulation.threads") continue;  // measured: may differ between two calls
            EXPECT_EQ(s.get(built), s.get(read)) << s.key;
        }
        EXPECT_EQ(built.foil.particle_radius, read.foil.particle_radius);
        EXPECT_EQ(built.simulation.dt_auto, read.simulation.dt_auto);
        EXPECT_TRUE(built.given.empty());
    }
    // The two values that drifted before: the table's dt_safety (0.3) and the free cores.
    EXPECT_EQ(Config().simulation.dt_safety, 0.3);
    EXPECT_GE(Config().simulation.threads, 1);
    EXPECT_EQ(Config(CommandSet::Foil).simulation.threads, 1);
    // A key read on top of a built Config is the file's; the others stay the table's.
    const Config c = load_config("", {"grains.radius=0.003"});
    EXPECT_EQ(c.grains.radius, 0.003);
    EXPECT_EQ(c.foil.particle_radius, 0.001);  // follows grains.radius
    EXPECT_EQ(c.grains.friction, Config().grains.friction);
}

TEST(Settings, EveryKeyIsReadAndNoOther) {
    for (const Setting& s : settings()) {
        std::string v;
        if (s.type == SettingType::Boolean) v = "false";
        else if (s.type == SettingType::Choice)
            v = std::string(s.key) == "process.pressure_model" ? "\"pump\""
                : std::string(s.key) == "process.waveform"     ? "\"sine\""
                : std::string(s.key) == "grains.shape"         ? "\"dimer\""
                : std::string(s.key) == "foil.builder"         ? "\"mesh\""
                : std::string(s.key) == "foil.bond_arm"        ? "\"bond_point\""
                                                                : "\"extension\"";  // the other word
        else if (s.type == SettingType::RealOrAuto) v = "1e-6";
        else if (s.type == SettingType::Integer) v = "5";
        else if (std::string(s.key) == "analysis.event_threshold") v = "3";  // 0 or above 1
        else v = toml_float_literal(std::isnan(s.def) || s.def == 0.0 ? 0.001 : s.def);
        std::vector<std::string> sets{std::string(s.key) + "=" + v};
        // The size distribution's keys go together: a law with its width, a sieve law with its file.
        if (std::string(s.key) == "grains.radius_distribution")
            sets = {"grains.radius_distribution=\"uniform\"", "grains.radius_spread=0.1"};
        if (std::string(s.key) == "grains.sieve_curve") {
            const std::string csv = ::testing::TempDir() + "settings_sieve.csv";
            std::ofstream(csv) << "size,passing\n0.004,0\n0.006,100\n";
            sets = {"grains.radius_distribution=\"sieve\"", "grains.sieve_curve=\"" + csv + "\""};
        }
        // A clump template with its shape.
        if (std::string(s.key) == "grains.clump_template") {
            const std::string csv = ::testing::TempDir() + "settings_clump.csv";
            std::ofstream(csv) << "x,y,z,r\n0,0,0,0.001\n0.001,0,0,0.001\n";
            sets = {"grains.shape=\"template\"", "grains.clump_template=\"" + csv + "\""};
        }
        EXPECT_EQ(message_of(sets), "") << s.key << "=" << v;
    }
    EXPECT_NE(message_of({"grains.colour=1.0"}).find("unknown config key 'grains.colour'"), std::string::npos);
}

TEST(Settings, RangesAreEnforcedWithTheTablesMessage) {
    for (const Setting& s : settings()) {
        std::vector<std::string> bad;
        if (s.check == Check::Positive) bad = {"0.0", "-1.0"};
        else if (s.check == Check::NonNegative) bad = {"-1.0"};
        else if (s.check == Check::Range && s.type == SettingType::Integer)
            bad = {std::to_string(int64_t(s.lo) - 1), std::to_string(int64_t(s.hi) + 1)};
        else if (s.check == Check::Range) bad = {toml_float_literal(s.lo - 1.0), toml_float_literal(s.hi + 1.0)};
        else if (s.check == Check::AtLeast) bad = {std::to_string(int64_t(s.lo) - 1)};
        for (const std::string& v : bad) {
            const std::string m = message_of({std::string(s.key) + "=" + v});
            EXPECT_NE(m.find(s.key), std::string::npos) << s.key << "=" << v << ": " << m;
            const std::string allowed = s.check == Check::Positive      ? "must be > 0 and finite"
                                        : s.check == Check::NonNegative ? "must be >= 0 and finite"
                                                                        : s.allowed;
            EXPECT_NE(m.find(allowed), std::string::npos) << s.key << "=" << v << ": " << m;
        }
        if (s.check == Check::Range) {  // a bound itself: refused when open, accepted when closed
            for (const auto& [bound, open] : {std::pair{s.lo, s.lo_open}, std::pair{s.hi, s.hi_open}}) {
                const std::string v = s.type == SettingType::Integer ? std::to_string(int64_t(bound)) : toml_float_literal(bound);
                const std::string m = message_of({std::string(s.key) + "=" + v});
                EXPECT_EQ(m.empty(), !open) << s.key << "=" << bound << ": " << m;
            }
        }
    }
}

// Integers travel through the table as doubles: beyond 2^53 they are refused, not rounded
// (or, at 2^63, converted back with undefined behaviour: found by fuzz/fuzz_config.cpp).
TEST(Settings, IntegersBeyondTwoToThe53AreRefused) {
    for (const Setting& s : settings()) {
        if (s.type != SettingType::Integer || s.read) continue;  // the generic reader's keys
        if (s.check == Check::Range && s.hi < 9007199254740992.0) continue;  // their range is narrower
        const std::string m = message_of({std::string(s.key) + "=9223372036854775807"});
        EXPECT_NE(m.find("'" + std::string(s.key) + "' = 9223372036854775807: must be at most 2^53"),
                  std::string::npos) << m;
        EXPECT_EQ(message_of({std::string(s.key) + "=9007199254740992"}), "") << s.key;
    }
}

// The rule before the table: {"grains.friction", "damper.cap_friction", "process.*",
// "simulation.threads", "output.*", "analysis.*"}, and grains.restitution since (like the friction
// it is given to the grains after the preparation, which has no dashpot).
TEST(Settings, SharingAPreparationKeepsTheStudysRule) {
    auto old_rule = [](const std::string& key) {
        return key == "grains.friction" || key == "grains.restitution" || key == "damper.cap_friction" ||
               key.starts_with("process.") ||
               key == "simulation.threads" || key.starts_with("output.") || key.starts_with("analysis.");
    };
    for (const Setting& s : settings()) EXPECT_EQ(may_share_preparation(s.key), old_rule(s.key)) << s.key;
    for (const char* k : {"process.future", "output.future", "analysis.future", "grains.future", "foil.future",
                          "simulation.future", "tension.future", "nosuchsection.key", "process"})
        EXPECT_EQ(may_share_preparation(k), old_rule(k)) << k;
}

TEST(Settings, RecordedKeysAreNumberedWithoutGaps) {
    for (auto list : {geometry_settings(), run_settings(), summary_inputs()}) {
        EXPECT_FALSE(list.empty());
    }
    EXPECT_EQ(geometry_settings().size(), 17u);
    EXPECT_EQ(run_settings().size(), 32u);
    EXPECT_EQ(summary_inputs().size(), 36u);
    auto positions = [](int Setting::*p) {
        std::set<int> s;
        for (const Setting& r : settings())
            if (r.*p) {
                EXPECT_TRUE(s.insert(r.*p).second) << r.key;
            }
        return s;
    };
    for (int Setting::*p : {&Setting::geometry, &Setting::run, &Setting::summary}) {
        const std::set<int> s = positions(p);
        EXPECT_EQ(*s.begin(), 1);
        EXPECT_EQ(*s.rbegin(), int(s.size()));
    }
    // What a checkpoint stores keeps its first key (older checkpoints are read by name, any order).
    EXPECT_STREQ(geometry_settings().front().key, "grains.radius");
    EXPECT_STREQ(run_settings().front().key, "grains.friction");
    EXPECT_STREQ(summary_inputs().back().key, "foil.exact_radius");  // the newest keys come last
    EXPECT_STREQ(geometry_settings().back().key, "foil.exact_radius");
}

TEST(Settings, TheReferenceListsEveryKey) {
    const std::string md = config_reference_markdown();
    for (const Setting& s : settings()) EXPECT_NE(md.find("| `" + std::string(s.key) + "` |"), std::string::npos) << s.key;
}

// Issue 48: counts past 2^31 wrapped round in the run's int (process.cycles = 2147483648 ran 0
// cycles, 4294967297 ran one while summary.json said 4294967297; samples_per_cycle = 4294967300
// wrote 4 rows a cycle). They are refused, naming the key, the value and the range.
TEST(Settings, CountsPastTheirRangeAreRefusedNotWrapped) {
    for (const char* v : {"2147483648", "4294967297", "1000001"}) {
        const std::string m = message_of({std::string("process.cycles=") + v});
        EXPECT_NE(m.find(std::string("'process.cycles' = ") + v), std::string::npos) << m;
        EXPECT_NE(m.find("must be an integer in 1..1000000"), std::string::npos) << m;
    }
    const std::string m = message_of({"process.samples_per_cycle=4294967300"});
    EXPECT_NE(m.find("'process.samples_per_cycle' = 4294967300"), std::string::npos) << m;
    EXPECT_NE(m.find("4..1000000"), std::string::npos) << m;
    EXPECT_EQ(message_of({"process.cycles=1000000", "process.samples_per_cycle=1000000"}), "");
}

// Issue 48: foil.stiffness_ratio = 1.5 was accepted and the run failed with "cannot create
// std::vector larger than max_size()". ks/kn of elastic spheres is at most 1, and the time step
// is sized on kn: above 1 is refused for the grains and the foil alike. Below 0.01 too: at 0 the
// shear spring's elongation f_t / k_s was NaN in cycles.csv (the property test's long run).
TEST(Settings, StiffnessRatiosAboveOneAreRefused) {
    for (const char* k : {"foil.stiffness_ratio", "grains.stiffness_ratio"}) {
        for (const char* bad : {"1.5", "0", "0.005"}) {
            const std::string m = message_of({std::string(k) + "=" + bad});
            EXPECT_NE(m.find(std::string("'") + k + "' = " + bad), std::string::npos) << m;
            EXPECT_NE(m.find("must be in [0.01, 1]"), std::string::npos) << m;
        }
        EXPECT_EQ(message_of({std::string(k) + "=1.0"}), "") << k;
        EXPECT_EQ(message_of({std::string(k) + "=0.01"}), "") << k;
    }
}

// Issue 48: keys that act during the preparation (grains.young: a sweep branched a changed value
// from the old sample) are recorded with it, so a study's branch can check them.
TEST(Settings, EveryKeyActingDuringThePreparationIsRecordedWithTheSample) {
    std::set<std::string> prep;
    for (const Setting& s : preparation_settings()) prep.insert(s.key);
    for (const char* k : {"grains.young", "grains.stiffness_ratio", "foil.young", "foil.thickness",
                          "foil.stiffness_ratio", "simulation.dt_safety", "simulation.local_damping"})
        EXPECT_TRUE(prep.count(k)) << k;
    for (const Setting& s : settings()) {
        const std::string sec = std::string(s.key).substr(0, std::string(s.key).find('.'));
        if (sec == "tension") continue;  // the tension command's strip, no damper sample
        // Every key either shares a preparation (acts after it), is geometry, or is recorded.
        EXPECT_TRUE(s.shares_preparation || s.geometry > 0 || prep.count(s.key)) << s.key;
    }
}

}  // namespace test_settings

// ---- One declaration per shared key (issue 59, item 2; scene/shared_keys.h): the scene runner's,
// the damper's and the device file's tables read a key they share with its one range, and the
// time step comes from one rule (scene/time_step.h). The enumerated settings' words and numbers
// (vpp/settings/choices.h).
namespace test_shared_keys {

namespace {

namespace keys = cfg::keys;

const std::vector<const cfg::KeyDecl*> kDeclared = {
    &keys::dt,           &keys::dt_safety, &keys::local_damping, &keys::threads,         &keys::seed,
    &keys::skin,         &keys::gravity,   &keys::grain_radius,  &keys::density,         &keys::young,
    &keys::friction,     &keys::stiffness_ratio, &keys::restitution,
};

bool same_limits(const cfg::Limits& a, const cfg::Limits& b) {
    return a.check == b.check && a.lo == b.lo && a.hi == b.hi && a.lo_open == b.lo_open && a.hi_open == b.hi_open &&
           std::string(a.allowed) == b.allowed;
}

// The scene's key of a declared one: the same, or the [[materials]] key of a grains' property.
std::string scene_key(const cfg::KeyDecl& k) {
    const std::string key = k.key;
    return key.starts_with("grains.") ? "materials[]." + key.substr(7) : key;
}

std::string scene_refusal(const std::string& simulation) {
    const std::string text = "[simulation]\n" + simulation +
                             "\n[[materials]]\nname = \"a\"\n"
                             "[[spheres]]\nmaterial = \"a\"\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n";
    try {
        scene::build_scene(toml::parse(text), ".");
    } catch (const cfg::ConfigError& e) {
        return e.what();
    }
    return "";
}

const std::string kTinyGripperPath = std::string(VPPDEM_SOURCE_DIR) + "/tests/data/devices/tiny_gripper.toml";

std::string device_refusal(const std::string& set) {
    try {
        vpp::load_device(kTinyGripperPath, {set});
    } catch (const cfg::ConfigError& e) {
        return e.what();
    }
    return "";
}

std::string damper_refusal(const std::string& set) {
    try {
        vpp::load_config("", {set});
    } catch (const cfg::ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SharedKeys, EveryTableTakesTypeUnitAndRangeFromTheDeclaration) {
    int damper_rows = 0, scene_rows = 0;
    for (const cfg::KeyDecl* k : kDeclared) {
        SCOPED_TRACE(k->key);
        if (const vpp::Setting* s = vpp::find_setting(k->key)) {
            ++damper_rows;
            EXPECT_EQ(s->type, k->type);
            EXPECT_EQ(std::string(s->unit), k->unit);
            EXPECT_TRUE(same_limits(s->limits(), k->limits));
            EXPECT_EQ(std::string(s->doc), k->doc);  // the same key: the same doc
        }
        if (const scene::SceneSetting* s = scene::find_scene_setting(scene_key(*k))) {
            ++scene_rows;
            EXPECT_EQ(s->type, k->type);
            EXPECT_EQ(std::string(s->unit), k->unit);
            EXPECT_TRUE(same_limits(s->limits, k->limits));
        }
    }
    EXPECT_EQ(damper_rows, 12);  // all but gravity
    EXPECT_EQ(scene_rows, 11);   // all but seed and the grains' radius
    // The foil's stiffness ratio is the grains' property.
    EXPECT_TRUE(same_limits(vpp::find_setting("foil.stiffness_ratio")->limits(), keys::stiffness_ratio.limits));
    // A default differs only where a table says why: the rest are the declaration's.
    EXPECT_EQ(vpp::find_setting("simulation.dt_safety")->def, keys::dt_safety.def);
    EXPECT_EQ(scene::find_scene_setting("simulation.dt_safety")->def, keys::dt_safety.def);
    EXPECT_EQ(vpp::DeviceDef{}.dt_safety, keys::dt_safety.def);
    EXPECT_EQ(scene::Scene{}.dt_safety, keys::dt_safety.def);
}

TEST(SharedKeys, ADtSafetyAboveHalfIsRefusedByEveryCommand) {
    // One range, (0, 0.5]: scenes and devices allowed up to 1 before.
    const std::string words = "(0, 0.5]";
    const std::string scene = scene_refusal("dt_safety = 0.6");
    EXPECT_NE(scene.find("'simulation.dt_safety' = 0.6"), std::string::npos) << scene;
    EXPECT_NE(scene.find(words), std::string::npos) << scene;
    const std::string device = device_refusal("simulation.dt_safety=0.6");
    EXPECT_NE(device.find("'simulation.dt_safety' = 0.6"), std::string::npos) << device;
    EXPECT_NE(device.find(words), std::string::npos) << device;
    const std::string damper = damper_refusal("simulation.dt_safety=0.6");
    EXPECT_NE(damper.find("'simulation.dt_safety' = 0.6"), std::string::npos) << damper;
    EXPECT_NE(damper.find(words), std::string::npos) << damper;
    // The bound itself is allowed everywhere.
    EXPECT_EQ(scene_refusal("dt_safety = 0.5"), "");
    EXPECT_EQ(device_refusal("simulation.dt_safety=0.5"), "");
    EXPECT_EQ(damper_refusal("simulation.dt_safety=0.5"), "");
}

TEST(SharedKeys, TheOtherSharedRangesReadTheSameInEveryCommand) {
    struct Case {
        const char* key;
        const char* value;
        bool refused;
    };
    // local_damping [0, 0.9] (scenes and devices [0, 1) before), threads 0 ... 1024 with 0 the
    // free cores (scenes and devices 1 ... 1024), a seed any integer >= 0 (devices 0 ... 2^31).
    const std::vector<Case> cases = {
        {"local_damping", "0.95", true}, {"local_damping", "0.9", false}, {"threads", "1025", true},
        {"threads", "-1", true},         {"threads", "0", false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.key) + " = " + c.value);
        const std::string scene = scene_refusal(std::string(c.key) + " = " + c.value);
        const std::string device = device_refusal(std::string("simulation.") + c.key + "=" + c.value);
        const std::string damper = damper_refusal(std::string("simulation.") + c.key + "=" + c.value);
        EXPECT_EQ(!scene.empty(), c.refused) << scene;
        EXPECT_EQ(!device.empty(), c.refused) << device;
        EXPECT_EQ(!damper.empty(), c.refused) << damper;
        if (c.refused) {
            const std::string allowed = c.key == std::string("threads") ? keys::threads.limits.allowed
                                                                         : keys::local_damping.limits.allowed;
            for (const std::string& m : {scene, device, damper}) EXPECT_NE(m.find(allowed), std::string::npos) << m;
        }
    }
    EXPECT_EQ(vpp::load_device(kTinyGripperPath, {"simulation.seed=4294967297"}).seed, 4294967297ull);
    EXPECT_NE(device_refusal("simulation.seed=-1").find(keys::seed.limits.allowed), std::string::npos);
    // ks/kn of a scene's material: [0.01, 1] as the damper's grains and the device's membrane.
    const std::string m = [] {
        try {
            scene::build_scene(toml::parse("[[materials]]\nname = \"a\"\nstiffness_ratio = 0.0\n[[spheres]]\n"
                                           "material = \"a\"\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n"),
                               ".");
        } catch (const cfg::ConfigError& e) {
            return std::string(e.what());
        }
        return std::string();
    }();
    EXPECT_NE(m.find(keys::stiffness_ratio.limits.allowed), std::string::npos) << m;
    EXPECT_NE(device_refusal("membrane.stiffness_ratio=0").find(keys::stiffness_ratio.limits.allowed), std::string::npos);
}

TEST(TimeStep, OneRuleForEveryCommand) {
    dem::World w;
    const uint32_t m = w.add_material(dem::Material{});
    dem::SphereDef s;
    s.radius = 1e-3;
    s.material = m;
    w.add_sphere(s);
    const double critical = w.critical_dt();
    ASSERT_TRUE(std::isfinite(critical) && critical > 0.0);
    EXPECT_EQ(scene::time_step({.automatic = true, .safety = 0.25}, w), 0.25 * critical);
    EXPECT_EQ(scene::time_step({.automatic = false, .dt = 1e-7, .safety = 0.25}, w), 1e-7);
    vpp::SimulationDef sim;
    sim.dt_auto = true;
    sim.dt_safety = 0.3;
    EXPECT_EQ(vpp::resolve_dt(sim, w), 0.3 * critical);
    // A scene's "auto" step is the same rule.
    const scene::Scene sc = scene::build_scene(
        toml::parse("[simulation]\ndt = \"auto\"\ndt_safety = 0.4\n[[materials]]\nname = \"a\"\n"
                    "[[spheres]]\nmaterial = \"a\"\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n"),
        ".");
    EXPECT_EQ(sc.world.params.dt, scene::time_step({.automatic = true, .safety = 0.4}, sc.world));
    // simulation.dt's reader: the same words for every command.
    for (const char* bad : {"dt = -1", "dt = \"fast\"", "dt = 0.0"}) {
        EXPECT_NE(scene_refusal(bad).find("'simulation.dt'"), std::string::npos) << bad;
        const std::string set = std::string("simulation.") + bad;
        std::string compact;
        for (char ch : set)
            if (ch != ' ') compact += ch;
        EXPECT_NE(device_refusal(compact).find("'simulation.dt'"), std::string::npos) << compact;
        EXPECT_EQ(device_refusal(compact), damper_refusal(compact)) << compact;
    }
}

TEST(Choices, WordsAndNumbersOfTheEnumeratedSettings) {
    using vpp::GrainShape;
    // The numbers are what checkpoints and records hold: they never change.
    EXPECT_EQ(int(GrainShape::Template), 5);
    EXPECT_EQ(int(vpp::RadiusDistribution::Sieve), 3);
    EXPECT_EQ(int(vpp::PressureModel::Pump), 1);
    EXPECT_EQ(int(vpp::Waveform::Sine), 1);
    EXPECT_EQ(int(vpp::FoilBuilder::Mesh), 1);
    // The first shapes are dem's built-in ones, in their order (grain_shape() asks for them by word).
    const std::vector<std::string>& builtin = dem::builtin_clump_shapes();
    for (std::size_t i = 0; i < builtin.size(); ++i) EXPECT_EQ(builtin[i], vpp::word_of(GrainShape(i)));
    EXPECT_EQ(vpp::from_word<GrainShape>("template"), GrainShape::Template);
    EXPECT_EQ(vpp::from_word<GrainShape>("cube"), std::nullopt);
    EXPECT_EQ(vpp::from_number<vpp::Waveform>(1.0), vpp::Waveform::Sine);
    EXPECT_EQ(vpp::from_number<vpp::Waveform>(2.0), std::nullopt);
    EXPECT_EQ(vpp::from_number<vpp::Waveform>(0.5), std::nullopt);
    // Each Choice key's sentence names its words, and a config reads each of them.
    auto check = [](const char* key, const auto& words) {
        const std::string allowed = vpp::find_setting(key)->allowed;
        for (const char* w : words) {
            EXPECT_NE(allowed.find(std::string("\"") + w + "\""), std::string::npos) << key << ": " << w;
            if (std::string(key) == "grains.radius_distribution" || std::string(key) == "grains.shape") continue;
            EXPECT_EQ(damper_refusal(std::string(key) + "=" + w), "") << key << " = " << w;
        }
    };
    check("grains.radius_distribution", vpp::Words<vpp::RadiusDistribution>::words);
    check("grains.shape", vpp::Words<GrainShape>::words);
    check("foil.builder", vpp::Words<vpp::FoilBuilder>::words);
    check("process.pressure_model", vpp::Words<vpp::PressureModel>::words);
    check("process.waveform", vpp::Words<vpp::Waveform>::words);
    const vpp::Config c = vpp::load_config("", {"process.waveform=sine", "process.pressure_model=pump", "grains.shape=dimer"});
    EXPECT_EQ(c.process.waveform, vpp::Waveform::Sine);
    EXPECT_EQ(c.process.pressure_model, vpp::PressureModel::Pump);
    EXPECT_EQ(c.grains.shape, GrainShape::Dimer);
    // Stored as their numbers.
    EXPECT_EQ(vpp::find_setting("grains.shape")->get(c), 1.0);
    EXPECT_EQ(vpp::find_setting("process.waveform")->get(c), 1.0);
}

}  // namespace test_shared_keys

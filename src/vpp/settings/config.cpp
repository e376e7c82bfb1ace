#include "vpp/settings/config.h"

#include <numbers>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dem/io/csv.h"
#include "scene/clump_template.h"
#include "scene/config.h"
#include "scene/time_step.h"
#include "vpp/settings/settings.h"

namespace vpp {

using cfg::Section;

namespace {

// Dotted keys of every value in the table ("process.velocity"), for Config::given.
void collect_keys(const toml::table& t, const std::string& prefix, std::set<std::string>& out) {
    for (const auto& [k, v] : t) {
        const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
        if (const toml::table* sub = v.as_table()) collect_keys(*sub, key, out);
        else out.insert(key);
    }
}

// 2^53: the largest integer up to which every integer is a double.
constexpr int64_t kMaxExactInteger = int64_t(1) << 53;

// Reads a key whose row needs no reader of its own: the type, the table's default and check.
void read_generic(Section& s, const Setting& row, Config& c, CommandSet commands) {
    const std::string key = std::string(row.key).substr(std::string(row.key).find('.') + 1);
    switch (row.type) {
    case SettingType::Real:
        row.set(c, cfg::check_real(s, key, s.number(key, row.default_for(commands)), row.limits()));
        return;
    case SettingType::Integer: {
        const int64_t v = cfg::check_integer(s, key, s.integer(key, int64_t(row.default_for(commands))), row.limits());
        // The table carries every value as a double (Setting::set, the checkpoints, summary.json):
        // a larger integer would come back another number, or overflow the conversion back to
        // int64_t (undefined behaviour; fuzz/regressions/config).
        if (v > kMaxExactInteger || v < -kMaxExactInteger)
            s.fail(key, "must be at most 2^53 = 9007199254740992 in magnitude (the settings are kept as doubles)");
        row.set(c, double(v));
        return;
    }
    case SettingType::Boolean:
        row.set(c, s.boolean(key, row.default_for(commands) != 0.0) ? 1.0 : 0.0);
        return;
    default:
        throw std::logic_error(std::string("settings: ") + row.key + " needs a reader of its own");
    }
}

// Reads every key of the table, section by section as the table lists them, from the file into
// c; a key the file does not give takes the table's default for these commands (every row's
// reader sets its field either way, so this also makes a Config from nothing).
void read_table(const toml::table& root, CommandSet commands, Config& c) {
    Section top(&root, "");
    const std::vector<Setting>& rows = settings();
    for (std::size_t i = 0; i < rows.size();) {
        const std::string section = section_of(rows[i].key);
        Section s = top.table(section);
        for (; i < rows.size() && section_of(rows[i].key) == section; ++i) {
            const Setting& row = rows[i];
            if (row.read) row.read(s, row, c, commands);
            else read_generic(s, row, c, commands);
        }
        if (section == "damper") {
            // The foil must close around at least a few of its own particles.
            const Setting& radius = *find_setting("damper.radius");
            const Setting& height = *find_setting("damper.height");
            // Say where the foil's radius comes from: by default grains.radius / 3, so a huge
            // grains.radius refuses damper.radius, which must then name the key behind it.
            const std::string rf_text = " (4 x foil.particle_radius = " + cfg::number_text(4.0 * c.foil.particle_radius) +
                                        " m" + (c.given.count("foil.particle_radius") ? "" : "; foil.particle_radius is grains.radius / 3 unless given") + ")";
            if (c.damper.radius < 4.0 * c.foil.particle_radius) s.fail("radius", radius.allowed + rf_text);
            if (c.damper.height < 4.0 * c.foil.particle_radius) s.fail("height", height.allowed + rf_text);
            // Largest: the foil's particles are counted in int and held in memory. A radius of
            // 1e300 m overflowed the column count and the refusal then blamed grains.radius; a
            // limit of its own names the key (10 million foil particles: gigabytes, days a step).
            constexpr double kMaxFoil = 1e7;  // [-] foil particles
            const double rf = c.foil.particle_radius;
            const double cols = std::numbers::pi * c.damper.radius / rf, rows = c.damper.height / (2.0 * rf);
            auto too_big = [&](const char* key, double limit) {
                s.fail(key, "must give at most 10 million foil particles (columns pi r_p / r_f times rows H_p / "
                            "(2 r_f), r_f = foil.particle_radius " + cfg::number_text(rf) + " m" +
                            (c.given.count("foil.particle_radius") ? "" : ", grains.radius / 3 unless given") +
                            "): at most " + cfg::number_text(limit) + " m here");
            };
            if (cols > kMaxFoil) too_big("radius", kMaxFoil * rf / std::numbers::pi);
            if (rows > kMaxFoil) too_big("height", kMaxFoil * 2.0 * rf);
            if (cols * rows > kMaxFoil)
                too_big(cols >= rows ? "radius" : "height",
                        cols >= rows ? kMaxFoil / rows * rf / std::numbers::pi : kMaxFoil / cols * 2.0 * rf);
            // The target is reached by the re-fills: without them the pour's N stands.
            if (c.damper.packing_target > 0.0 && !c.damper.refill)
                s.fail("packing_target", "must be 0 when damper.refill = false (the re-fills reach the target)");
        }
        if (section == "grains") {
            const bool from_template = c.grains.shape == GrainShape::Template;
            if (from_template && c.grains.clump_template.empty())
                s.fail("clump_template", "must name a CSV file of the members when grains.shape = \"template\"");
            if (!from_template && !c.grains.clump_template.empty())
                s.fail("shape", "must be \"template\" when grains.clump_template is given");
            const RadiusDistribution sizes = c.grains.radius_distribution;
            if (sizes == RadiusDistribution::Sieve && c.grains.sieve_curve.empty())
                s.fail("sieve_curve", "must name a CSV file of the sieve curve when grains.radius_distribution = \"sieve\"");
            if (sizes != RadiusDistribution::Sieve && !c.grains.sieve_curve.empty())
                s.fail("radius_distribution", "must be \"sieve\" when grains.sieve_curve is given");
            if ((sizes == RadiusDistribution::Uniform || sizes == RadiusDistribution::Lognormal) &&
                !(c.grains.radius_spread > 0.0))
                s.fail("radius_spread", "must be > 0 for a uniform or lognormal distribution (0: every grain grains.radius; "
                                        "say grains.radius_distribution = \"single\")");
            if (sizes == RadiusDistribution::Lognormal && c.grains.radius_spread > 0.5)
                s.fail("radius_spread", "must be at most 0.5 for a lognormal distribution (the sd of ln r: radii span a "
                                        "factor exp(6 sd) = 20 at 0.5)");
        }
        if (section == "process" && c.process.pressure_model == PressureModel::Pump && c.process.pump_down &&
            !(c.process.pump_speed > 0.0))
            s.fail("pump_down", "must be false when process.pump_speed is 0 (a pump-down needs a pump)");
        s.finish();
    }
    top.finish();
}

}  // namespace

Config::Config(const toml::table& file, CommandSet commands) {
    collect_keys(file, "", given);
    read_table(file, commands, *this);
}

Config::Config(CommandSet commands) : Config(toml::table{}, commands) {}

Config load_config(const std::string& path, const std::vector<std::string>& overrides, CommandSet commands) {
    return Config(cfg::load(path, overrides), commands);
}

scene::SizeDistribution grain_sizes(const Config& c) {
    if (c.grains.radius_distribution == RadiusDistribution::Sieve)
        return scene::SizeDistribution::sieve_curve(c.grains.sieve_curve);
    scene::SizeDistribution d;
    d.kind = c.grains.radius_distribution;
    d.radius = c.grains.radius;
    d.spread = d.kind == RadiusDistribution::Single ? 0.0 : c.grains.radius_spread;
    return d;
}

dem::ClumpShape clump_template_shape(const std::string& path) {
    return dem::scaled_to_radius(scene::read_clump_template(path), 1.0);
}

dem::ClumpShape grain_shape(const Config& c) {
    if (c.grains.shape == GrainShape::Template) return clump_template_shape(c.grains.clump_template);
    return dem::builtin_clump_shape(word_of(c.grains.shape), 1.0);
}

double cycling_local_damping(const Config& c) {
    return c.process.local_damping < 0.0 ? c.simulation.local_damping : c.process.local_damping;
}

double cycle_period(const ProcessDef& p) {
    return p.frequency > 0.0 ? 1.0 / p.frequency : 2.0 * p.amplitude / p.velocity;
}

double peak_speed(const ProcessDef& p) {
    if (p.waveform == Waveform::Sine) return std::numbers::pi * p.amplitude / cycle_period(p);
    return p.frequency > 0.0 ? 2.0 * p.amplitude * p.frequency : p.velocity;
}

double resolve_dt(const SimulationDef& s, const dem::World& w) {
    return scene::time_step({.automatic = s.dt_auto, .dt = s.dt, .safety = s.dt_safety}, w);
}

}  // namespace vpp

#include "vpp/config.h"

#include <algorithm>
#include "scene/config.h"
#include "scene/threads.h"

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

}  // namespace

Config load_config(const std::string& path, const std::vector<std::string>& overrides,
                   const CommandDefaults& defaults) {
    const toml::table root = cfg::load(path, overrides);
    Section top(&root, "");
    Config c;
    collect_keys(root, "", c.given);

    Section g = top.table("grains");
    c.grains.radius = g.positive("radius", g.number("radius", c.grains.radius));
    c.grains.density = g.positive("density", g.number("density", c.grains.density));
    c.grains.young = g.positive("young", g.number("young", c.grains.young));
    c.grains.friction = g.non_negative("friction", g.number("friction", c.grains.friction));
    c.grains.stiffness_ratio = g.non_negative("stiffness_ratio", g.number("stiffness_ratio", c.grains.stiffness_ratio));
    c.grains.volume_fraction = g.number("volume_fraction", c.grains.volume_fraction);
    if (!(c.grains.volume_fraction > 0.0 && c.grains.volume_fraction < 0.74))
        g.fail("volume_fraction", "must be in (0, 0.74) (0.74 is the densest sphere packing)");
    g.finish();

    Section f = top.table("foil");
    c.foil.young = f.positive("young", f.number("young", c.foil.young));
    c.foil.thickness = f.positive("thickness", f.number("thickness", c.foil.thickness));
    c.foil.particle_radius = f.positive("particle_radius", f.number("particle_radius", c.grains.radius / 3.0));
    c.foil.density = f.positive("density", f.number("density", c.foil.density));
    c.foil.friction = f.non_negative("friction", f.number("friction", c.foil.friction));
    c.foil.stiffness_ratio = f.non_negative("stiffness_ratio", f.number("stiffness_ratio", c.foil.stiffness_ratio));
    f.finish();

    Section d = top.table("damper");
    c.damper.radius = d.positive("radius", d.number("radius", c.damper.radius));
    c.damper.height = d.positive("height", d.number("height", c.damper.height));
    c.damper.cap_friction = d.number("cap_friction", -1.0);
    if (d.has("cap_friction") && !(c.damper.cap_friction >= 0.0)) d.fail("cap_friction", "must be >= 0");
    c.damper.refill = d.boolean("refill", c.damper.refill);
    if (c.damper.radius < 4.0 * c.foil.particle_radius) d.fail("radius", "must be at least 4 foil particle radii");
    if (c.damper.height < 4.0 * c.foil.particle_radius) d.fail("height", "must be at least 4 foil particle radii");
    d.finish();

    Section p = top.table("process");
    // dp = atmospheric - inside pressure: 0 (no vacuum) up to a perfect vacuum. A negative dp
    // would blow the foil up, and NaN or inf would run to the end with NaN forces.
    c.process.underpressure = defaults.underpressure;
    if (const toml::node* n = p.node("underpressure")) {
        const auto v = n->value<double>();
        if (!v || !(*v >= 0.0 && *v <= kAtmosphericPressure))
            p.fail("underpressure", "must be a pressure difference in [0, 101325] Pa (0.101325 MPa, a perfect "
                                    "vacuum): atmospheric minus the pressure inside the foil");
        c.process.underpressure = *v;
    }
    c.process.ramp_time = p.positive("ramp_time", p.number("ramp_time", c.process.ramp_time));
    c.process.hold_time = p.non_negative("hold_time", p.number("hold_time", c.process.hold_time));
    c.process.amplitude = p.positive("amplitude", p.number("amplitude", c.process.amplitude));
    c.process.velocity = p.positive("velocity", p.number("velocity", c.process.velocity));
    c.process.start_offset = p.number("start_offset", c.process.start_offset);
    const std::string dir = p.string("direction", "compression");
    if (dir != "compression" && dir != "extension") p.fail("direction", "must be \"compression\" or \"extension\"");
    c.process.compression_first = dir == "compression";
    c.process.cycles = p.integer("cycles", c.process.cycles);
    if (c.process.cycles < 1) p.fail("cycles", "must be an integer >= 1");
    c.process.samples_per_cycle = p.integer("samples_per_cycle", c.process.samples_per_cycle);
    if (c.process.samples_per_cycle < 4) p.fail("samples_per_cycle", "must be an integer >= 4");
    c.process.sample_window = p.positive("sample_window", p.number("sample_window", c.process.sample_window));
    p.finish();

    Section t = top.table("tension");
    c.tension.sites_along = t.integer("sites_along", c.tension.sites_along);
    if (c.tension.sites_along < 3) t.fail("sites_along", "must be an integer >= 3");
    c.tension.sites_across = t.integer("sites_across", c.tension.sites_across);
    if (c.tension.sites_across < 1) t.fail("sites_across", "must be an integer >= 1");
    c.tension.strain = t.number("strain", c.tension.strain);
    if (!(c.tension.strain > 0.0 && c.tension.strain < 0.5)) t.fail("strain", "must be in (0, 0.5)");
    c.tension.speed = t.positive("speed", t.number("speed", c.tension.speed));
    t.finish();

    Section s = top.table("simulation");
    if (const toml::node* n = s.node("dt")) {
        if (auto str = n->as_string()) {
            if (str->get() != "auto") s.fail("dt", "must be a time step in seconds (> 0) or \"auto\"");
        } else if (auto v = n->value<double>()) {
            c.simulation.dt_auto = false;
            c.simulation.dt = s.positive("dt", *v);
        } else {
            s.fail("dt", "must be a time step in seconds (> 0) or \"auto\"");
        }
    }
    c.simulation.dt_safety = s.number("dt_safety", defaults.dt_safety);
    if (!(c.simulation.dt_safety > 0.0 && c.simulation.dt_safety <= 1.0)) s.fail("dt_safety", "must be in (0, 1]");
    c.simulation.local_damping = s.number("local_damping", c.simulation.local_damping);
    if (!(c.simulation.local_damping >= 0.0 && c.simulation.local_damping < 1.0))
        s.fail("local_damping", "must be in [0, 1)");
    const int64_t th = s.integer("threads", defaults.threads);
    if (th < 0 || th > 1024) s.fail("threads", "must be an integer 1..1024, or 0 for the default (the free cores)");
    // 0: the free cores (scene/threads.h), measured only when asked for.
    c.simulation.threads = th == 0 ? cli::default_threads() : int(th);
    const int64_t seed = s.integer("seed", int64_t(c.simulation.seed));
    if (seed < 0) s.fail("seed", "must be an integer >= 0");
    c.simulation.seed = uint64_t(seed);
    c.simulation.skin = s.non_negative("skin", s.number("skin", c.simulation.skin));
    s.finish();

    Section o = top.table("output");
    c.output.interval = o.non_negative("interval", o.number("interval", 0.0));
    c.output.vtk_interval = o.non_negative("vtk_interval", o.number("vtk_interval", 0.0));
    c.output.energy = o.boolean("energy", true);
    o.finish();

    Section a = top.table("analysis");
    c.analysis.settle_tolerance = a.number("settle_tolerance", c.analysis.settle_tolerance);
    if (!(c.analysis.settle_tolerance > 0.0 && c.analysis.settle_tolerance < 1.0))
        a.fail("settle_tolerance", "must be a fraction in (0, 1), e.g. 0.03 for 3% (the relative change of W from "
                                   "one cycle to the next below which W counts as settled)");
    a.finish();

    top.finish();
    return c;
}

double resolve_dt(const SimulationDef& s, const dem::World& w) {
    return s.dt_auto ? s.dt_safety * w.critical_dt() : s.dt;
}

}  // namespace vpp

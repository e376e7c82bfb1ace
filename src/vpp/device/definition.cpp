#include "vpp/device/definition.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <stdexcept>

#include "dem/io/json.h"
#include "dem/mesh/mesh_checks.h"
#include "dem/mesh/mesh_read.h"
#include "dem/mesh/mesh_shapes.h"
#include "scene/config.h"
#include "scene/setting.h"
#include "scene/shared_keys.h"
#include "scene/time_step.h"
#include "vpp/device/size_checks.h"
#include "vpp/settings/choices.h"
#include "vpp/settings/config.h"

namespace vpp {

namespace {

using cfg::Check;
using cfg::Section;

// The device file's number keys: key within its section, unit, default, check, and the field.
// The defaults are the gripper's scale (examples/devices/gripper.toml): millimetre grains in a
// latex-like bag. Keys with words, vectors or lists are read by hand below.
struct NumberKey {
    const char* key;   // "section.key"
    const char* unit;  // SI; "-" a ratio
    double def;
    cfg::Limits limits;
    double DeviceDef::*field;
};

constexpr cfg::Limits kPos{Check::Positive};
constexpr cfg::Limits kNonNeg{Check::NonNegative};

// A key declared for every table (scene/shared_keys.h): its range and default are the damper's
// and the scene's too.
NumberKey declared_key(const cfg::KeyDecl& k, double DeviceDef::*field) { return {k.key, k.unit, k.def, k.limits, field}; }

const std::vector<NumberKey>& number_keys() {
    namespace keys = cfg::keys;
    using cfg::with_default;
    static const std::vector<NumberKey> number_keys = {
        declared_key(keys::dt_safety, &DeviceDef::dt_safety),
        // 0.3: what the device files were tuned with (examples/devices/ give it).
        declared_key(with_default(keys::local_damping, 0.3), &DeviceDef::local_damping),
        // The gripper's millimetre grains in a latex-like bag, not the paper's.
        declared_key(with_default(keys::grain_radius, 1e-3), &DeviceDef::grain_radius),
        declared_key(with_default(keys::density, 1500.0), &DeviceDef::grain_density),
        declared_key(with_default(keys::young, 1e8), &DeviceDef::grain_young),
        declared_key(with_default(keys::friction, 0.5), &DeviceDef::grain_friction),
        {"grains.fill_friction", "-", 0.0, kNonNeg, &DeviceDef::fill_friction},
        declared_key(keys::stiffness_ratio, &DeviceDef::grain_stiffness_ratio),
        {"grains.fill", "-", 0.8, {Check::Range, 0.0, 1.0, true, false, "must be in (0, 1]: the fraction of the fill lattice's sites inside the membrane that get a grain"},
         &DeviceDef::fill},
        {"grains.lattice_spacing", "-", 2.2, {Check::Range, 2.0, 10.0, true, false, "must be in (2, 10] grain radii (2: touching neighbours)"},
         &DeviceDef::lattice_spacing},
        {"stages.fill_time", "s", 0.1, kPos, &DeviceDef::fill_time},
        {"stages.fill_min_time", "s", 0.02, kNonNeg, &DeviceDef::fill_min_time},
        {"stages.underpressure", "Pa", 5e4, {Check::Range, 0.0, kAtmosphericPressure, false, true, "must be in [0, 101325) Pa: below the atmosphere's pressure"},
         &DeviceDef::underpressure},
        {"stages.ramp_time", "s", 0.01, kPos, &DeviceDef::ramp_time},
        {"stages.vacuum_hold", "s", 0.02, kNonNeg, &DeviceDef::vacuum_hold},
        {"membrane.clamp_height", "m", 0.0, kNonNeg, &DeviceDef::clamp_height},
        {"output.sample_interval", "s", 1e-3, kPos, &DeviceDef::sample_interval},
        {"output.vtk_interval", "s", 0.0, kNonNeg, &DeviceDef::vtk_interval},
        {"result.release_time", "s", 2e-3, kNonNeg, &DeviceDef::release_time},
    };
    return number_keys;
}

void read_numbers(Section& s, const std::string& section, DeviceDef& d) {
    for (const NumberKey& k : number_keys()) {
        const std::string full = k.key;
        if (full.substr(0, full.find('.')) != section) continue;
        const std::string key = full.substr(full.find('.') + 1);
        d.*k.field = cfg::check_real(s, key, s.number(key, k.def), k.limits);
    }
}

double positive(Section& s, const std::string& key, double def) { return s.positive(key, s.number(key, def)); }

int integer_in(Section& s, const std::string& key, int64_t def, int64_t lo, int64_t hi) {
    const int64_t v = s.integer(key, def);
    if (v < lo || v > hi) s.fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

void read_shape(Section& s, DeviceShape& sh, bool allow_none) {
    sh.kind = s.string("shape", allow_none ? "none" : "sphere");
    const std::set<std::string> kinds = allow_none ? std::set<std::string>{"sphere", "box", "cylinder", "mesh", "none"}
                                                   : std::set<std::string>{"sphere", "box", "cylinder", "mesh"};
    if (!kinds.count(sh.kind))
        s.fail("shape", allow_none ? "must be \"sphere\", \"box\", \"cylinder\", \"mesh\" or \"none\""
                                   : "must be \"sphere\", \"box\", \"cylinder\" or \"mesh\"");
    sh.center = s.vec3("center", {0, 0, 0});
    if (sh.kind == "sphere" || sh.kind == "cylinder") sh.radius = positive(s, "radius", 0.0);
    if (sh.kind == "cylinder") sh.height = positive(s, "height", 0.0);
    if (sh.kind == "box") {
        sh.size = s.vec3("size");
        if (!(sh.size.x > 0 && sh.size.y > 0 && sh.size.z > 0)) s.fail("size", "must be three edge lengths > 0 [m]");
    }
    if (sh.kind != "none" && sh.kind != "mesh") sh.resolution = integer_in(s, "resolution", 8, 1, 256);
    if (sh.kind == "mesh") {
        sh.file = s.string("file");
        sh.scale = positive(s, "scale", 1.0);
        sh.offset = s.vec3("offset", {0, 0, 0});
    }
}

// One [[tools.program]] segment.
dem::ToolSegment read_segment(Section& s) {
    dem::ToolSegment g;
    const std::string stage = s.string("stage", "load");
    if (stage == "press") g.stage = int32_t(DeviceStage::Press);
    else if (stage == "vacuum") g.stage = int32_t(DeviceStage::Vacuum);
    else if (stage == "load") g.stage = int32_t(DeviceStage::Load);
    else s.fail("stage", "must be \"press\", \"vacuum\" or \"load\" (the stages in which tools move)");
    const std::string kind = s.string("kind");
    if (kind == "move") {
        g.kind = dem::SegmentKind::Move;
        const toml::node* to = s.node("to");
        if (!to || !to->value<double>()) s.fail("to", "is required: the z displacement [m] from the tool's build position");
        g.to = *to->value<double>();
        if (!std::isfinite(g.to)) s.fail("to", "must be finite");
        g.speed = positive(s, "speed", 0.0);
    } else if (kind == "hold") {
        g.kind = dem::SegmentKind::Hold;
        g.duration = positive(s, "duration", 0.0);
    } else if (kind == "force") {
        g.kind = dem::SegmentKind::Force;
        const toml::node* f = s.node("force");
        if (!f || !f->value<double>() || !std::isfinite(*f->value<double>()) || *f->value<double>() == 0.0)
            s.fail("force", "is required: the reaction F_z [N] to reach, not 0 (> 0: pressed down onto the particles)");
        g.force = *f->value<double>();
        g.speed = positive(s, "speed", 0.0);
        g.max_travel = positive(s, "max_travel", 0.0);
    } else if (kind == "force_hold") {
        g.kind = dem::SegmentKind::ForceHold;
        const toml::node* f = s.node("force");
        if (!f || !f->value<double>() || !std::isfinite(*f->value<double>()) || *f->value<double>() == 0.0)
            s.fail("force", "is required: the reaction F_z [N] to hold, not 0 (> 0: pressed down onto the particles)");
        g.force = *f->value<double>();
        g.speed = positive(s, "speed", 0.0);
        g.duration = positive(s, "duration", 0.0);
    } else if (kind == "cycle") {
        g.kind = dem::SegmentKind::Cycle;
        const toml::node* a = s.node("amplitude");
        if (!a || !a->value<double>() || !std::isfinite(*a->value<double>()) || *a->value<double>() == 0.0)
            s.fail("amplitude", "is required: the z excursion [m], not 0 (its sign: the first leg's direction)");
        g.amplitude = *a->value<double>();
        g.speed = positive(s, "speed", 0.0);
        g.cycles = integer_in(s, "cycles", 1, 1, 100000);
    } else {
        s.fail("kind", "must be \"move\", \"hold\", \"force\", \"force_hold\" or \"cycle\"");
    }
    s.finish();
    return g;
}

std::string json_number(double v) { return dem::json_double(v); }
std::string json_string(const std::string& s) { return dem::json_string(s); }
std::string json_vec(const dem::Vec3& v) {
    // Appended piece by piece: "[" + a temporary trips GCC 12's -Wrestrict (a false positive).
    std::string s = "[";
    s += json_number(v.x);
    s += ", ";
    s += json_number(v.y);
    s += ", ";
    s += json_number(v.z);
    return s + "]";
}

}  // namespace

const char* device_stage_name(DeviceStage s) {
    static const char* n[] = {"fill", "seal", "press", "vacuum", "load", "done"};
    return n[int(s)];
}

DeviceDef load_device(const std::string& path, const std::vector<std::string>& overrides) {
    const toml::table root = cfg::load(path, overrides);
    DeviceDef d;
    d.path = path;
    Section top(&root, "");

    Section sim = top.table("simulation");
    const scene::TimeStep step = scene::read_dt(sim, "dt", cfg::keys::dt.def);
    d.dt = step.automatic ? 0.0 : step.dt;
    read_numbers(sim, "simulation", d);
    d.gravity = sim.vec3("gravity", cfg::keys::gravity.def3);
    d.seed = cfg::read_seed(sim, "seed", int64_t(cfg::keys::seed.def));
    d.threads = cfg::read_threads(sim, "threads", int64_t(cfg::keys::threads.def));
    sim.finish();

    Section mem = top.table("membrane");
    read_shape(mem, d.membrane_shape, false);
    FoilDef& f = d.membrane.foil;
    f.young = positive(mem, "young", 2e6);
    f.thickness = positive(mem, "thickness", 5e-4);
    f.particle_radius = positive(mem, "particle_radius", 5e-4);
    // The grains' properties (scene/shared_keys.h) of the membrane's particles.
    f.density = cfg::check_real(mem, "density", mem.number("density", 1000.0), cfg::keys::density.limits);
    f.friction = mem.non_negative("friction", mem.number("friction", 0.5));
    f.stiffness_ratio = cfg::check_real(mem, "stiffness_ratio", mem.number("stiffness_ratio", 0.5),
                                        cfg::keys::stiffness_ratio.limits);
    d.membrane.spacing = mem.non_negative("spacing", mem.number("spacing", 0.0));
    d.membrane.vacancies = mem.boolean("vacancies", false);
    d.membrane.stiffness_factor = positive(mem, "stiffness_factor", 1.0);
    // A bag built stretched (a filled balloon): its tension squeezes the grains before any load.
    d.membrane.prestrain = cfg::check_real(mem, "prestrain", mem.number("prestrain", 0.0),
                                           {.check = cfg::Check::Range, .lo = 0.0, .hi = 0.5, .allowed = "must be in [0, 0.5] (a strain of the built membrane)"});
    // The bonds' shear springs at the bond point by default: a remeshed membrane's bonds are
    // 0.45-1.27 diameters long, and with the full radii a rigid rotation would load them
    // (docs/energy.md, "Bonds"); "radius" keeps the damper's lattice convention.
    {
        const std::optional<dem::BondArm> arm = dem::bond_arm_from_name(mem.string("bond_arm", "bond_point"));
        if (!arm) mem.fail("bond_arm", "must be \"bond_point\" or \"radius\"");
        f.bond_arm = *arm;
    }
    d.clamp_tool = mem.string("clamp_tool", "");
    read_numbers(mem, "membrane", d);
    if (!d.clamp_tool.empty() && !(d.clamp_height > 0.0))
        mem.fail("clamp_height", "must be > 0 [m] when membrane.clamp_tool names a tool (the height of the clamped top)");
    mem.finish();

    Section gr = top.table("grains");
    read_numbers(gr, "grains", d);
    d.lattice = gr.string("lattice", "cubic");
    if (d.lattice != "cubic" && d.lattice != "fcc")
        gr.fail("lattice", "must be \"cubic\" or \"fcc\" (the fill lattice)");
    d.fill_mode = gr.string("fill_mode", "lattice");
    if (d.fill_mode != "lattice" && d.fill_mode != "pour")
        gr.fail("fill_mode", "must be \"lattice\" (grains placed inside the closed membrane) or \"pour\" (poured through "
                             "an opening at its top, then sealed)");
    if (d.fill_mode == "pour") {
        // Required, no default: the opening and the amount poured are the pour's design.
        if (!gr.node("opening_height"))
            gr.fail("opening_height", "is required with grains.fill_mode = \"pour\": the height [m] below the membrane's top "
                                      "whose membrane particles form the opening");
        d.opening_height = gr.positive("opening_height", gr.number("opening_height", 0.0));
        if (!gr.node("pour_count"))
            gr.fail("pour_count", "is required with grains.fill_mode = \"pour\": the number of grains poured (>= 1)");
        d.pour_count = gr.integer("pour_count", 0);
        if (d.pour_count < 1 || d.pour_count > 10000000)
            gr.fail("pour_count", "must be an integer in [1, 10000000]: the number of grains poured");
    } else {
        // A pour key with the lattice fill would be silently ignored: refused instead.
        for (const char* k : {"opening_height", "pour_count"})
            if (gr.node(k)) gr.fail(k, "applies to grains.fill_mode = \"pour\" only (the fill mode is \"lattice\")");
    }
    gr.finish();

    Section st = top.table("stages");
    read_numbers(st, "stages", d);
    if (d.fill_min_time > d.fill_time) st.fail("fill_min_time", "must be at most stages.fill_time");
    st.finish();

    Section air = top.table("air");
    const std::optional<PressureModel> model = from_word<PressureModel>(air.string("model", word_of(PressureModel::Constant)));
    if (!model) air.fail("model", "must be \"constant\" (dp held at stages.underpressure) or \"pump\" (a sealed gas pumped down)");
    d.air.model = *model;
    d.air.line.speed = air.non_negative("pump_speed", air.number("pump_speed", 5.6e-4));
    d.air.line.bleed = air.non_negative("bleed_rate", air.number("bleed_rate", 0.0));
    d.air.line.leak = air.non_negative("leak_rate", air.number("leak_rate", 0.0));
    d.air.line.p_atm = kAtmosphericPressure;
    if (d.air.model == PressureModel::Pump && d.underpressure > 0.0 && !(d.air.line.speed > 0.0))
        air.fail("pump_speed", "must be > 0 [m^3/s] with air.model = \"pump\" and an underpressure");
    air.finish();

    // [suction] (vpp/device/suction.h): the seal between the membrane and result.object.
    Section suc = top.table("suction");
    d.suction.enabled = suc.boolean("enabled", false);
    d.suction.gap = suc.number("gap", d.suction.gap);
    // A film thinner than a molecule or thicker than the membrane's particles is no seal's.
    // The bounds by the membrane only where the seal is on (a foil of fine particles with the
    // suction off is not refused for the suction's defaults).
    const double r_f = d.suction.enabled ? d.membrane.foil.particle_radius : 1e300;
    if (!(d.suction.gap >= 1e-9 && d.suction.gap <= r_f))
        suc.fail("gap", "must be in [1e-9, membrane.particle_radius] [m]: the air film between membrane and object where they lie together");
    d.suction.ambient = suc.number("ambient", kAtmosphericPressure);
    if (!(d.suction.ambient > (d.suction.enabled ? d.underpressure : 0.0) && d.suction.ambient <= 1e7))
        suc.fail("ambient", "must be above stages.underpressure and at most 1e7 [Pa]: the surroundings' absolute pressure");
    d.suction.capture = suc.number("capture", 0.0);
    if (!(d.suction.capture >= 0.0 && d.suction.capture <= r_f))
        suc.fail("capture", "must be in [0, membrane.particle_radius] [m]: how far off the object a membrane particle's surface may be and still seal");
    d.suction.viscosity = suc.number("viscosity", d.suction.viscosity);
    if (!(d.suction.viscosity > 0.0 && d.suction.viscosity <= 1.0))
        suc.fail("viscosity", "must be in (0, 1] [Pa s]: the gas's dynamic viscosity (air 1.8e-5), which sets the leak through the seal's rim");
    suc.finish();

    Section out = top.table("output");
    read_numbers(out, "output", d);
    d.energy = out.boolean("energy", true);
    d.vtk = out.boolean("vtk", true);
    out.finish();

    Section res = top.table("result");
    d.object = res.string("object", "");
    d.cycle_tool = res.string("cycle_tool", "");
    read_numbers(res, "result", d);
    res.finish();

    std::vector<Section> tools = top.array_of_tables("tools");
    std::set<std::string> names;
    for (Section& t : tools) {
        DeviceTool tool;
        tool.name = t.string("name");
        if (tool.name.empty() || !names.insert(tool.name).second) t.fail("name", "must be a name no other tool has");
        read_shape(t, tool.shape, true);
        tool.young = positive(t, "young", 1e9);
        tool.friction = t.non_negative("friction", t.number("friction", 0.5));
        tool.stiffness_ratio = cfg::check_real(t, "stiffness_ratio", t.number("stiffness_ratio", 0.5),
                                               cfg::keys::stiffness_ratio.limits);
        int32_t last = 0;
        std::vector<Section> prog = t.array_of_tables("program");
        for (Section& p : prog) {
            tool.program.push_back(read_segment(p));
            if (tool.program.back().stage < last)
                p.fail("stage", "must not come before the stage of the segment above it (segments are listed in stage "
                                "order: press, vacuum, load)");
            last = tool.program.back().stage;
        }
        t.finish();
        d.tools.push_back(std::move(tool));
    }
    if (!d.clamp_tool.empty() && !names.count(d.clamp_tool))
        mem.fail("clamp_tool", "must name one of the [[tools]]");
    if (!d.object.empty() && !names.count(d.object)) res.fail("object", "must name one of the [[tools]]");
    if (d.suction.enabled && d.object.empty())
        res.fail("object", "must name the tool the membrane seals on when suction.enabled = true");
    if (!d.cycle_tool.empty()) {
        const DeviceTool* ct = nullptr;
        for (const DeviceTool& t : d.tools)
            if (t.name == d.cycle_tool) ct = &t;
        bool cycles = false;
        if (ct)
            for (const dem::ToolSegment& s : ct->program)
                cycles = cycles || (s.stage == int32_t(DeviceStage::Load) && s.kind == dem::SegmentKind::Cycle);
        if (!cycles) res.fail("cycle_tool", "must name one of the [[tools]] with a cycle segment in the \"load\" stage");
    }
    top.finish();

    // The meshes are read and checked now, so that a bad one is refused before anything is built;
    // then the sizes, the foil and the tools' motion against them (vpp/device/size_checks.h), so
    // that a device too large for the machine or a run that would never end is refused too.
    const std::string base = std::filesystem::path(path).parent_path().string();
    const dem::SurfaceMesh membrane = device_surface(d.membrane_shape, "membrane", base);
    std::vector<dem::SurfaceMesh> tool_surfaces(d.tools.size());
    for (std::size_t k = 0; k < d.tools.size(); ++k)
        if (d.tools[k].shape.kind != "none")
            tool_surfaces[k] = device_surface(d.tools[k].shape, "tools[" + std::to_string(k) + "]", base);
    check_device_inputs(d, membrane, tool_surfaces);
    return d;
}

dem::SurfaceMesh device_surface(const DeviceShape& s, const std::string& key, const std::string& base_dir) {
    dem::SurfaceMesh m;
    if (s.kind == "sphere") {
        m = dem::make_icosphere(s.radius, s.resolution, s.center);
    } else if (s.kind == "box") {
        m = dem::make_box_mesh(s.center - 0.5 * s.size, s.center + 0.5 * s.size, s.resolution);
    } else if (s.kind == "cylinder") {
        m = dem::make_cylinder_mesh(s.radius, s.height, 8 * s.resolution, std::max(1, s.resolution), s.center.z);
        for (dem::Vec3& v : m.vertices) v += dem::Vec3{s.center.x, s.center.y, 0.0};
    } else if (s.kind == "mesh") {
        std::filesystem::path p(s.file);
        if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
        try {
            dem::MeshReadOptions o;
            o.scale = s.scale;
            m = dem::read_closed_surface(p.string(), o);
        } catch (const std::runtime_error& e) {
            throw cfg::ConfigError("config key '" + key + ".file' = \"" + s.file + "\": " + e.what() +
                                   " (a closed, outward-wound surface is needed)");
        }
        for (dem::Vec3& v : m.vertices) v += s.offset;
        return m;
    } else {
        throw cfg::ConfigError("config key '" + key + ".shape': \"" + s.kind + "\" has no surface");
    }
    return m;
}

std::vector<std::pair<std::string, std::string>> device_inputs(const DeviceDef& d) {
    std::vector<std::pair<std::string, std::string>> in;
    in.emplace_back("file", json_string(d.path));
    in.emplace_back("simulation.dt", d.dt > 0 ? json_number(d.dt) : "\"auto\"");
    in.emplace_back("simulation.gravity", json_vec(d.gravity));
    in.emplace_back("simulation.seed", json_number(double(d.seed)));
    for (const NumberKey& k : number_keys()) in.emplace_back(k.key, json_number(d.*k.field));
    auto shape = [&](const std::string& key, const DeviceShape& sh) {
        in.emplace_back(key + ".shape", json_string(sh.kind));
        if (sh.kind == "none") return;
        if (sh.kind == "mesh") {
            in.emplace_back(key + ".file", json_string(sh.file));
            in.emplace_back(key + ".scale", json_number(sh.scale));
            in.emplace_back(key + ".offset", json_vec(sh.offset));
            return;
        }
        in.emplace_back(key + ".center", json_vec(sh.center));
        if (sh.kind == "box") in.emplace_back(key + ".size", json_vec(sh.size));
        else in.emplace_back(key + ".radius", json_number(sh.radius));
        if (sh.kind == "cylinder") in.emplace_back(key + ".height", json_number(sh.height));
        in.emplace_back(key + ".resolution", json_number(sh.resolution));
    };
    shape("membrane", d.membrane_shape);
    in.emplace_back("membrane.young", json_number(d.membrane.foil.young));
    in.emplace_back("membrane.thickness", json_number(d.membrane.foil.thickness));
    in.emplace_back("membrane.particle_radius", json_number(d.membrane.foil.particle_radius));
    in.emplace_back("membrane.friction", json_number(d.membrane.foil.friction));
    in.emplace_back("membrane.clamp_tool", json_string(d.clamp_tool));
    in.emplace_back("air.model", json_string(word_of(d.air.model)));
    in.emplace_back("result.object", json_string(d.object));
    in.emplace_back("result.cycle_tool", json_string(d.cycle_tool));
    in.emplace_back("grains.lattice", json_string(d.lattice));
    // The pour's keys only with the pour, so that a lattice fill's inputs (and so its checkpoints'
    // identity, DeviceRun's inputs_text) are those of the builds before the pour existed.
    if (d.fill_mode == "pour") {
        in.emplace_back("grains.fill_mode", json_string(d.fill_mode));
        in.emplace_back("grains.opening_height", json_number(d.opening_height));
        in.emplace_back("grains.pour_count", json_number(double(d.pour_count)));
    }
    in.emplace_back("membrane.density", json_number(d.membrane.foil.density));
    in.emplace_back("membrane.stiffness_ratio", json_number(d.membrane.foil.stiffness_ratio));
    in.emplace_back("membrane.spacing", json_number(d.membrane.spacing));
    in.emplace_back("membrane.vacancies", d.membrane.vacancies ? "true" : "false");
    in.emplace_back("membrane.stiffness_factor", json_number(d.membrane.stiffness_factor));
    in.emplace_back("membrane.bond_arm", json_string(dem::bond_arm_name(d.membrane.foil.bond_arm)));
    // Only when set: the inputs of the runs before it (their checkpoints' identity) unchanged.
    if (d.membrane.prestrain > 0) in.emplace_back("membrane.prestrain", json_number(d.membrane.prestrain));
    in.emplace_back("air.pump_speed", json_number(d.air.line.speed));
    in.emplace_back("air.bleed_rate", json_number(d.air.line.bleed));
    in.emplace_back("air.leak_rate", json_number(d.air.line.leak));
    in.emplace_back("output.energy", d.energy ? "true" : "false");
    // The suction's keys only with the suction on (the inputs of the runs before it, and so their
    // checkpoints' identity, unchanged).
    if (d.suction.enabled) {
        in.emplace_back("suction.enabled", "true");
        in.emplace_back("suction.gap", json_number(d.suction.gap));
        in.emplace_back("suction.ambient", json_number(d.suction.ambient));
        in.emplace_back("suction.capture", json_number(d.suction.capture));
        in.emplace_back("suction.viscosity", json_number(d.suction.viscosity));
    }
    static const char* kinds[] = {"move", "hold", "force", "cycle", "force_hold"};
    for (const DeviceTool& t : d.tools) {
        const std::string key = "tools." + t.name;
        shape(key, t.shape);
        in.emplace_back(key + ".young", json_number(t.young));
        in.emplace_back(key + ".friction", json_number(t.friction));
        in.emplace_back(key + ".stiffness_ratio", json_number(t.stiffness_ratio));
        std::string prog = "[";
        for (const dem::ToolSegment& g : t.program) {
            prog += std::string(prog.size() > 1 ? ", " : "") + "{\"stage\": " +
                    json_string(device_stage_name(DeviceStage(g.stage))) + ", \"kind\": " + json_string(kinds[int(g.kind)]) +
                    ", \"to\": " + json_number(g.to) + ", \"speed\": " + json_number(g.speed) +
                    ", \"duration\": " + json_number(g.duration) + ", \"force\": " + json_number(g.force) +
                    ", \"max_travel\": " + json_number(g.max_travel) + ", \"amplitude\": " + json_number(g.amplitude) +
                    ", \"cycles\": " + json_number(g.cycles) + "}";
        }
        in.emplace_back(key + ".program", prog + "]");
    }
    return in;
}

}  // namespace vpp

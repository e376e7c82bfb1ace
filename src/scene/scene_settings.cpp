#include "scene/scene_settings.h"

#include <stdexcept>

#include "dem/core/material.h"
#include "dem/io/json.h"
#include "scene/shared_keys.h"

namespace scene {

namespace {

using T = cfg::SettingType;
using C = cfg::Check;

// A body's collision mask: the bits it shares with another body decide whether they interact.
constexpr cfg::Limits kMask{.check = C::Range, .lo = 1, .hi = 4294967295.0,
                            .allowed = "must be a positive 32-bit bit mask (an integer 1 ... 4294967295)"};

// Keys every entry of a group has in the same sense.
SceneSetting material_row(const std::string& g, const char* doc) {
    return {.key = g + ".material", .type = T::String, .unit = "", .required = true,
            .limits = {.allowed = "the name of a [[materials]] entry"}, .doc = doc};
}
SceneSetting mask_row(const std::string& g) {
    return {.key = g + ".mask", .type = T::Integer, .unit = "", .def = 1, .limits = kMask,
            .doc = "collision mask: two bodies interact when their masks share a bit (docs/scene.md#masks)"};
}
SceneSetting flag_row(const std::string& g, const char* name, bool def, const char* doc) {
    return {.key = g + "." + name, .type = T::Boolean, .unit = "", .def = def ? 1.0 : 0.0, .doc = doc};
}
SceneSetting vec_row(const std::string& g, const char* name, const char* unit, const char* doc) {
    return {.key = g + "." + name, .type = T::Vec3, .unit = unit, .def3 = {}, .doc = doc};
}
SceneSetting required_vec_row(const std::string& g, const char* name, const char* unit, const char* doc) {
    return {.key = g + "." + name, .type = T::Vec3, .unit = unit, .required = true, .doc = doc};
}
// A wall's motion: a constant velocity or a displacement history (docs/scene.md#planes).
SceneSetting wall_velocity_row(const std::string& g) {
    return vec_row(g, "velocity", "m/s", "constant translation");
}
SceneSetting displacement_row(const std::string& g, const char* doc) {
    return {.key = g + ".displacement", .type = T::Rows, .unit = "s, m", .default_text = "none",
            .limits = {.allowed = "rows [t, dx, dy, dz], t strictly increasing; not with velocity"}, .doc = doc};
}
SceneSetting positive_row(const std::string& g, const char* name, const char* unit, const char* doc) {
    return {.key = g + "." + name, .type = T::Real, .unit = unit, .required = true,
            .limits = {.check = C::Positive}, .doc = doc};
}

// A row of a key declared once for every table (scene/shared_keys.h). A material property has
// the scene's key (`key`: "materials[].young") and says whose it is (`doc`).
SceneSetting declared(const cfg::KeyDecl& k, const std::string& key = "", const char* doc = nullptr) {
    return {.key = key.empty() ? std::string(k.key) : key, .type = k.type, .unit = k.unit, .def = k.def,
            .def3 = k.def3, .default_text = k.default_text, .limits = k.limits, .doc = doc ? doc : k.doc};
}

std::vector<SceneSetting> build_table() {
    namespace keys = cfg::keys;
    const dem::Material& material = keys::kCoreMaterial;  // the core's defaults are the table's
    std::vector<SceneSetting> t = {
        // [simulation]
        // A fixed 1e-7 s by default, not "auto": what a scene file without dt has always run at.
        declared(cfg::with_default(keys::dt, 1e-7)),
        declared(keys::dt_safety),
        {.key = "simulation.duration", .type = T::Real, .unit = "s", .def = 1e-3, .limits = {.check = C::Positive},
         .doc = "simulated time; the run makes round(duration / dt) steps"},
        declared(keys::gravity),
        declared(keys::local_damping),
        declared(keys::threads),
        {.key = "simulation.output_interval", .type = T::Real, .unit = "s", .def = 1e-6,
         .limits = {.check = C::Positive},
         .doc = "time between rows of tracked.csv, walls.csv and energy.csv; an interval <= dt writes every step"},
        declared(keys::skin),
        {.key = "simulation.max_initial_overlap", .type = T::Real, .unit = "-", .def = 0.01,
         .limits = {.check = C::NonNegative},
         .doc = "largest overlap at t = 0 as a fraction of the smaller radius (the sphere's for a wall); more is "
                "refused (docs/scene.md#initial-overlaps)"},
        // [output]
        {.key = "output.vtk_interval", .type = T::Real, .unit = "s", .def = 0.0, .limits = {.check = C::NonNegative},
         .doc = "time between VTK frames in vtk/; 0: no VTK output"},
        {.key = "output.energy", .type = T::Boolean, .unit = "", .def = 0.0,
         .doc = "keep the energy ledger and write energy.csv at the output times (docs/energy.md)"},
        // [[materials]]: the grains' properties (scene/shared_keys.h) at the core's defaults.
        {.key = "materials[].name", .type = T::String, .unit = "", .required = true,
         .limits = {.allowed = "a name no other material has"},
         .doc = "what material = \"...\" of a body refers to"},
        declared(cfg::with_default(keys::density, material.density), "materials[].density", "mass density of the spheres"),
        declared(cfg::with_default(keys::young, material.young), "materials[].young",
                 "E; a sphere's side of a contact is a spring E r, the two in series (Yade's FrictPhys)"),
        declared(cfg::with_default(keys::stiffness_ratio, material.stiffness_ratio), "materials[].stiffness_ratio",
                 "ks/kn (Yade's \"poisson\"; not a Poisson ratio)"),
        declared(cfg::with_default(keys::friction, material.friction), "materials[].friction",
                 "Coulomb coefficient mu (not an angle)"),
        declared(cfg::with_default(keys::restitution, material.restitution), "materials[].restitution",
                 "normal coefficient of restitution; 1: no viscous damping"),
    };
    auto add = [&](SceneSetting s) { t.push_back(std::move(s)); };
    // [[spheres]]
    const std::string sp = "spheres[]";
    add(material_row(sp, "material of the sphere"));
    add(positive_row(sp, "radius", "m", "radius"));
    add(required_vec_row(sp, "position", "m", "centre at t = 0"));
    add(vec_row(sp, "velocity", "m/s", "initial velocity, taken as the leapfrog's v(-dt/2); with prescribed: kept"));
    add(vec_row(sp, "angular_velocity", "rad/s", "initial angular velocity, v(-dt/2) like velocity"));
    add(mask_row(sp));
    add(flag_row(sp, "fixed", false, "never moves; velocities are set to zero"));
    add(flag_row(sp, "prescribed", false,
                 "moves at its velocity whatever the forces (no rotation), pushing others as an infinite mass"));
    add(displacement_row(sp, "prescribed motion along this piecewise-linear history from position (implies "
                             "prescribed)"));
    add(flag_row(sp, "track", false, "write this sphere to tracked.csv"));
    // [[sphere_files]]
    const std::string sf = "sphere_files[]";
    add({.key = sf + ".path", .type = T::String, .unit = "", .required = true,
         .limits = {.allowed = "a CSV file with columns x,y,z,r [m]"},
         .doc = "one sphere per row; a relative path is relative to the TOML file's folder"});
    add(material_row(sf, "material of every row"));
    add(vec_row(sf, "velocity", "m/s", "initial velocity of every row"));
    add(mask_row(sf));
    add(flag_row(sf, "fixed", false, "every row never moves"));
    add(flag_row(sf, "track", false, "write every row to tracked.csv"));
    // [[clumps]]
    const std::string cl = "clumps[]";
    add(material_row(cl, "material of the clump (its density sets the mass)"));
    add({.key = cl + ".shape", .type = T::String, .unit = "", .required = true,
         .limits = {.allowed = "one of sphere, dimer, trimer, tetrahedron, pellet, template"},
         .doc = "a built-in shape (docs/scene.md#clumps) or \"template\": the spheres of `template`"});
    add({.key = cl + ".template", .type = T::String, .unit = "", .default_text = "none",
         .limits = {.allowed = "a CSV file with columns x,y,z,r [m], the members in the grain's frame"},
         .doc = "the members of shape = \"template\"; a relative path is relative to the TOML file's folder"});
    add({.key = cl + ".radius", .type = T::Real, .unit = "m", .default_text = "the template as given",
         .limits = {.check = C::Positive},
         .doc = "volume-equivalent radius: the shape is scaled to the volume of a sphere of this radius "
                "(required for a built-in shape)"});
    add(required_vec_row(cl, "position", "m", "centre of mass at t = 0"));
    add(vec_row(cl, "orientation", "rad", "rotation vector (axis times angle) from the principal frame"));
    add(vec_row(cl, "velocity", "m/s", "initial velocity of the centre, taken as v(-dt/2)"));
    add(vec_row(cl, "angular_velocity", "rad/s", "initial angular velocity (world frame), taken as w(-dt/2)"));
    add(mask_row(cl));
    // [[planes]]
    const std::string pl = "planes[]";
    add(material_row(pl, "material of the plane"));
    add(required_vec_row(pl, "point", "m", "a point of the plane at t = 0"));
    add({.key = pl + ".normal", .type = T::Vec3, .unit = "-", .required = true,
         .limits = {.check = C::Custom, .allowed = "must not be the zero vector"},
         .doc = "normal, normalised on reading"});
    add(flag_row(pl, "one_sided", false, "bounds the half-space on the +normal side (a centre behind is pushed back)"));
    add(mask_row(pl));
    add(wall_velocity_row(pl));
    add(displacement_row(pl, "translation history from point, held before the first and after the last row"));
    // [[facets]]
    const std::string fa = "facets[]";
    add(material_row(fa, "material of the triangle"));
    add({.key = fa + ".vertices", .type = T::Rows, .unit = "m", .required = true,
         .limits = {.check = C::Custom, .allowed = "must be 3 points [[x,y,z],[x,y,z],[x,y,z]] with a non-zero area"},
         .doc = "corners at t = 0; normal (v1 - v0) x (v2 - v0)"});
    add(flag_row(fa, "one_sided", false, "only spheres whose centre is on the +normal side touch it"));
    add(mask_row(fa));
    add(wall_velocity_row(fa));
    add(displacement_row(fa, "translation history from vertices, as for planes"));
    // [[facet_sets]]: one mesh, reported as one wall; the keys after displacement belong to types.
    const std::string fs = "facet_sets[]";
    add({.key = fs + ".type", .type = T::Choice, .unit = "", .required = true,
         .limits = {.check = C::Custom, .allowed = "must be \"cylinder\", \"funnel\" or \"stl\""},
         .doc = "the mesh: a z-axis cylinder's side, a z-axis cone frustum's side, or an STL file; keys of "
                "another type are unknown keys"});
    add(material_row(fs, "material of every triangle"));
    add(flag_row(fs, "one_sided", false, "as for facets, every triangle"));
    add(mask_row(fs));
    add(wall_velocity_row(fs));
    add(displacement_row(fs, "translation history of every triangle, as for planes"));
    add(vec_row(fs, "base", "m", "cylinder, funnel: centre of the bottom circle"));
    add(positive_row(fs, "radius", "m", "cylinder (required): radius"));
    add(positive_row(fs, "bottom_radius", "m", "funnel (required): radius at base.z"));
    add(positive_row(fs, "top_radius", "m", "funnel (required): radius at base.z + height"));
    add(positive_row(fs, "height", "m", "cylinder, funnel (required): height up from base"));
    add({.key = fs + ".segments", .type = T::Integer, .unit = "", .def = 72,
         // At most 10^5: that polygon is within 5e-10 of its radius from the circle; more only
         // costs memory (10^9 asked for 2e9 triangles and ran out: fuzz/regressions/scene).
         .limits = {.check = C::Range, .lo = 3, .hi = 100000, .allowed = "must be an integer 3 ... 100000"},
         .doc = "cylinder, funnel: flat segments around (2 triangles each)"});
    add(flag_row(fs, "inward", true, "cylinder, funnel: triangle normals point to the axis (matters with one_sided)"));
    add({.key = fs + ".path", .type = T::String, .unit = "", .required = true,
         .limits = {.allowed = "a binary or ASCII STL file"},
         .doc = "stl (required): the file, relative to the TOML file's folder; its winding gives the normals"});
    add({.key = fs + ".scale", .type = T::Real, .unit = "-", .def = 1.0, .limits = {.check = C::Positive},
         .doc = "stl: factor on the file's coordinates (1e-3 for a file in mm)"});
    return t;
}

}  // namespace

const std::vector<SceneSetting>& scene_settings() {
    static const std::vector<SceneSetting> table = build_table();
    return table;
}

const SceneSetting* find_scene_setting(const std::string& key) {
    for (const SceneSetting& s : scene_settings())
        if (s.key == key) return &s;
    return nullptr;
}

const SceneSetting& SceneSection::row(const std::string& key) const {
    const SceneSetting* r = find_scene_setting(group_ + "." + key);
    if (!r) throw std::logic_error("scene reader: '" + group_ + "." + key + "' is not in the settings table");
    return *r;
}

double SceneSection::real(const std::string& key) {
    const SceneSetting& r = row(key);
    const double v = cfg::check_real(s_, key, r.required ? s_.number(key) : s_.number(key, r.def), r.limits);
    record(key, dem::json_double(v));
    return v;
}

int64_t SceneSection::integer(const std::string& key) {
    const SceneSetting& r = row(key);
    if (r.required && !s_.has(key)) s_.fail(key, "is required (an integer)");
    const int64_t v = cfg::check_integer(s_, key, s_.integer(key, int64_t(r.def)), r.limits);
    record(key, std::to_string(v));
    return v;
}

bool SceneSection::flag(const std::string& key) {
    const bool v = s_.boolean(key, row(key).def != 0.0);
    record(key, v ? "true" : "false");
    return v;
}

dem::Vec3 SceneSection::vec3(const std::string& key) {
    const SceneSetting& r = row(key);
    const dem::Vec3 v = r.required ? s_.vec3(key) : s_.vec3(key, r.def3);
    std::string text = "[";  // appended, not "[" + ...: GCC 12 warns falsely on the sum (its bug 105329)
    text.append(dem::json_double(v.x)).append(", ").append(dem::json_double(v.y)).append(", ");
    text.append(dem::json_double(v.z)).append("]");
    record(key, text);
    return v;
}

std::string SceneSection::string(const std::string& key) {
    const SceneSetting& r = row(key);
    const std::string v = r.required ? s_.string(key) : s_.string(key, r.default_text);
    record(key, dem::json_string(v));
    return v;
}

const toml::node* SceneSection::node(const std::string& key) {
    const SceneSetting& r = row(key);
    const toml::node* n = s_.node(key);
    if (!n && r.required) s_.fail(key, "is required");
    return n;
}

std::string scene_reference_markdown() {
    std::string md =
        "## `vppdem scene`\n\n"
        "Every key of a generic scene file (docs/scene.md), from the scene runner's settings table\n"
        "(src/scene/scene_settings.cpp). A key of an array of tables is written `group[].key` here and named\n"
        "`group[index].key` (0-based) in messages. Unknown keys are refused; \"required\" keys have no default.\n";
    std::string group;
    for (const SceneSetting& s : scene_settings()) {
        if (s.group() != group) {
            group = s.group();
            const bool array = group.ends_with("[]");
            const std::string name = array ? group.substr(0, group.size() - 2) : group;
            md += "\n### Scene `" + std::string(array ? "[[" : "[") + name + (array ? "]]" : "]") + "`\n\n";
            md += "| key | type | default | unit | allowed | description |\n|---|---|---|---|---|---|\n";
        }
        std::string def;
        if (s.required) def = "required";
        else if (*s.default_text) def = s.default_text;
        else if (s.type == cfg::SettingType::Boolean) def = s.def != 0.0 ? "true" : "false";
        else if (s.type == cfg::SettingType::Vec3)
            def = "[" + cfg::number_text(s.def3.x) + ", " + cfg::number_text(s.def3.y) + ", " +
                  cfg::number_text(s.def3.z) + "]";
        else def = cfg::number_text(s.def);
        md += "| `" + s.name() + "` | " + cfg::type_name(s.type) + " | " + cfg::markdown_cell(def) + " | " +
              cfg::markdown_cell(s.unit) + " | " + cfg::markdown_cell(cfg::allowed_text(s.type, s.limits)) + " | " +
              cfg::markdown_cell(s.doc) + " |\n";
    }
    return md;
}

}  // namespace scene

// The device file against its sizes and its run (vpp/device/size_checks.h).
#include "vpp/device/size_checks.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include "scene/config.h"
#include "scene/setting.h"

namespace vpp {

namespace {

using dem::Vec3;

std::string num(double v) { return cfg::number_text(v); }
std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}
std::string vec_text(const Vec3& v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }
std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// "value (a = 1, b = 2)": a value with the keys that go with it ("" left out).
std::string with_keys(const std::string& value, const std::vector<std::string>& others) {
    std::string w;
    for (const std::string& o : others)
        if (!o.empty()) w += (w.empty() ? "" : ", ") + o;
    return w.empty() ? value : value + " (" + w + ")";
}

[[noreturn]] void refuse(const std::string& key, const std::string& value, const std::string& what) {
    throw cfg::ConfigError("config key '" + key + "' = " + value + ": " + what);
}

double sphere_mass(double density, double r) { return density * 4.0 / 3.0 * std::numbers::pi * r * r * r; }
// dem::harmonic_stiffness, 2 a b / (a + b), in a form that does not overflow for moduli of 1e300.
double harmonic(double a, double b) { return 2.0 / (1.0 / a + 1.0 / b); }

// [N/m] A membrane bond's kn on an equilateral network of edge L: MatchFoil's c E_f t_f A_e / L^2
// with A_e = sqrt(3)/2 L^2 (its two triangles), c = (3 + a) / (3 (1 + a)) (vpp/membrane/membrane.h).
double equilateral_bond_kn(const MembraneDef& m) {
    const double a = m.foil.stiffness_ratio, c = (3.0 + a) / (3.0 * (1.0 + a));
    return m.stiffness_factor * c * m.foil.young * m.foil.thickness * std::sqrt(3.0) / 2.0;
}

// The keys that size a shape: the one that scales its surface (sphere: radius; box: size;
// cylinder: the larger of radius and height; mesh: scale) and the one that places it.
struct ShapeKeys {
    std::string size, size_value, place, place_value;
    std::string with;  // the mesh's file ("prefix.file = ..."), named beside its scale
};
ShapeKeys shape_keys(const DeviceShape& s, const std::string& prefix) {
    ShapeKeys k;
    if (s.kind == "mesh") {
        k.size = prefix + ".scale", k.size_value = num(s.scale), k.with = prefix + ".file = " + quoted(s.file);
        k.place = prefix + ".offset", k.place_value = vec_text(s.offset);
        return k;
    }
    k.place = prefix + ".center", k.place_value = vec_text(s.center);
    if (s.kind == "box") k.size = prefix + ".size", k.size_value = vec_text(s.size);
    else if (s.kind == "cylinder" && s.height > s.radius) k.size = prefix + ".height", k.size_value = num(s.height);
    else k.size = prefix + ".radius", k.size_value = num(s.radius);
    return k;
}

Vec3 bbox_lo(const dem::SurfaceMesh& m) {
    Vec3 lo{1e300, 1e300, 1e300};
    for (const Vec3& v : m.vertices) lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    return lo;
}
Vec3 bbox_hi(const dem::SurfaceMesh& m) {
    Vec3 hi{-1e300, -1e300, -1e300};
    for (const Vec3& v : m.vertices) hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    return hi;
}
double largest_extent(const dem::SurfaceMesh& m) {
    const Vec3 e = bbox_hi(m) - bbox_lo(m);
    return std::max({e.x, e.y, e.z});
}

// [m] The integral of the mean curvature over a closed, outward mesh: half of every edge's length
// times its exterior dihedral angle (> 0 where the surface is convex there): 4 pi R on a sphere,
// pi (a + b + c) on a box. Steiner's formula's M: the body shrunk by c has the volume
// V - A c + M c^2 - 4 pi c^3 / 3 (exact for a convex body whose curvature radii exceed c).
double mean_curvature_integral(const dem::SurfaceMesh& m) {
    std::unordered_map<uint64_t, std::array<int64_t, 2>> faces;  // edge -> its two triangles
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
            const uint64_t key = a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
            const auto it = faces.try_emplace(key, std::array<int64_t, 2>{-1, -1}).first;
            it->second[it->second[0] < 0 ? 0 : 1] = int64_t(t);
        }
    double M = 0.0;
    for (const auto& [key, f] : faces) {
        if (f[0] < 0 || f[1] < 0) continue;  // not closed there (the meshes are checked closed)
        const Vec3 a = m.vertices[key >> 32], b = m.vertices[key & 0xffffffffu];
        const Vec3 n1 = normalized(dem::area_vector(m, std::size_t(f[0]))), n2 = normalized(dem::area_vector(m, std::size_t(f[1])));
        const double angle = std::acos(std::clamp(dot(n1, n2), -1.0, 1.0));
        // Convex where the second triangle's far corner lies behind the first one's plane.
        Vec3 far = a;
        for (uint32_t v : m.triangles[std::size_t(f[1])])
            if (m.vertices[v] != a && m.vertices[v] != b) far = m.vertices[v];
        M += 0.5 * norm(b - a) * (dot(n1, far - a) <= 0.0 ? angle : -angle);
    }
    return M;
}

// A mesh file read as metres that looks like millimetres: more than a metre across, and with the
// grains still fitting four times across it read as millimetres (mm-sized grains in a bag drawn
// in mm). Then the message says what `scale` fixes it. "" when it does not look so.
std::string millimetre_hint(const DeviceShape& s, const dem::SurfaceMesh& m, const std::string& prefix, double grain_radius) {
    if (s.kind != "mesh" || s.scale != 1.0) return "";
    const double across = largest_extent(m);
    if (!(across > 1.0) || !(across * 1e-3 > 4.0 * grain_radius)) return "";
    return "; the mesh " + quoted(s.file) + " is " + fmt("%.4g", across) + " m across: if the file is in millimetres, " +
           prefix + ".scale = 1e-3 reads it as " + fmt("%.4g", across) + " mm";
}

// ---- sizes

void check_sizes(const DeviceDef& d, const dem::SurfaceMesh& membrane, const DeviceSizeEstimate& e) {
    const ShapeKeys mk = shape_keys(d.membrane_shape, "membrane");
    const std::string mm = millimetre_hint(d.membrane_shape, membrane, "membrane", d.grain_radius);
    const std::string bound = "allowed: at most " + fmt("%.0e", kMaxDeviceParticles) +
                              " particles in the device, membrane and grains (about " +
                              fmt("%.2g", kMaxDeviceParticles * kDeviceBytesPerParticle * 1e-9) +
                              " GB; a fixed bound: past it a device run takes months)";
    const double gb = e.bytes * 1e-9;
    if (!(e.membrane_particles <= kMaxDeviceParticles)) {
        // The count is the area over the site area: the slip is the size, unless the spacing is
        // far finer than the grains (a tenth of their radius).
        const bool spacing_slip = mm.empty() && e.membrane_spacing < 0.1 * d.grain_radius;
        const std::string spacing_key = d.membrane.spacing > 0.0 ? "membrane.spacing" : "membrane.particle_radius";
        const std::string spacing_value = d.membrane.spacing > 0.0 ? num(d.membrane.spacing) : num(d.membrane.foil.particle_radius);
        const double shrink = std::sqrt(e.membrane_particles / kMaxDeviceParticles);  // [-] across
        const std::string what =
            "the membrane would have about " + fmt("%.3g", e.membrane_particles) + " particles (its surface of " +
            fmt("%.3g", e.membrane_area) + " m^2 at the site density 2 / (sqrt(3) L^2) of the spacing L = " +
            fmt("%.3g", e.membrane_spacing) + " m" + (d.membrane.spacing > 0.0 ? "" : ", 2 membrane.particle_radius") +
            "), about " + fmt("%.3g", gb) + " GB; " + bound + ": a surface of at most " +
            fmt("%.3g", e.membrane_area / (shrink * shrink)) + " m^2 at this spacing (" + mk.size + ": this one " +
            fmt("%.3g", shrink) + " times smaller across), or a spacing of at least " + fmt("%.3g", e.membrane_spacing * shrink) +
            " m (" + spacing_key + ")" + mm;
        if (spacing_slip) refuse(spacing_key, spacing_value, what);
        refuse(mk.size, with_keys(mk.size_value, {mk.with}), what);
    }
    if (!(e.membrane_particles + e.grains <= kMaxDeviceParticles)) {
        const double room = kMaxDeviceParticles - e.membrane_particles;  // [-] grains the bound leaves
        if (d.fill_mode == "pour")
            refuse("grains.pour_count", std::to_string(d.pour_count),
                   "with the membrane's about " + fmt("%.3g", e.membrane_particles) + " particles the device would have " +
                       fmt("%.0f", e.membrane_particles + e.grains) + "; " + bound + ": grains.pour_count at most " +
                       fmt("%.0f", std::floor(room)) + " here");
        const double grow = std::cbrt(e.grains / room);  // [-] the grains' radius to bring them within it
        const std::string what =
            "the fill would place about " + fmt("%.3g", e.grains) + " grains (grains.fill = " + num(d.fill) + " of the " +
            d.lattice + " lattice's sites " + num(d.lattice_spacing) + " radii apart in the " +
            fmt("%.3g", e.fill_volume) + " m^3 the membrane's clearance leaves), with the membrane's " +
            fmt("%.3g", e.membrane_particles) + " particles about " + fmt("%.3g", gb) + " GB; " + bound +
            ": grains.radius at least " + fmt("%.3g", d.grain_radius * grow) + " m here, or a smaller membrane (" + mk.size +
            ")" + mm;
        if (!mm.empty()) refuse(mk.size, with_keys(mk.size_value, {mk.with}), what);
        refuse("grains.radius", num(d.grain_radius), what);
    }
}

// ---- tools

// A tool whose closed surface holds membrane surface points: the membrane's particles would
// start inside a rigid body (and, held whole, the fill finds no site and blamed grains.radius).
// Up to 511 of the surface's vertices, evenly strided, are tested (winding numbers: O(points x
// the tool's triangles) for the points inside the tool's bounding box).
void check_tools(const DeviceDef& d, const dem::SurfaceMesh& membrane, const std::vector<dem::SurfaceMesh>& tools) {
    const std::size_t n = membrane.vertices.size();
    const std::size_t stride = std::max<std::size_t>(1, n / 256);
    for (std::size_t k = 0; k < d.tools.size() && k < tools.size(); ++k) {
        if (tools[k].triangles.empty()) continue;
        // A point outside the tool's bounding box is outside the tool: the winding number only
        // for the others (a tool away from the membrane costs nothing, whatever its facets).
        const Vec3 lo = bbox_lo(tools[k]), hi = bbox_hi(tools[k]);
        std::size_t tested = 0, held = 0;
        for (std::size_t i = 0; i < n; i += stride, ++tested) {
            const Vec3& p = membrane.vertices[i];
            const bool in_box = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
            held += in_box && dem::winding_number(tools[k], p) > 0.5;
        }
        if (held == 0) continue;
        const std::string prefix = "tools[" + std::to_string(k) + "]";
        const ShapeKeys tk = shape_keys(d.tools[k].shape, prefix);
        const std::string mm = millimetre_hint(d.tools[k].shape, tools[k], prefix, d.grain_radius);
        const std::string whole = held == tested ? "the whole membrane lies inside it" : "it cuts into the membrane";
        const std::string what = "the tool '" + d.tools[k].name + "' (" + fmt("%.3g", largest_extent(tools[k])) +
                                 " m across) holds " + std::to_string(held) + " of " + std::to_string(tested) +
                                 " points of the membrane's surface tested: " + whole +
                                 "; allowed: a tool outside the membrane (its particles would start inside a rigid "
                                 "surface, and the fill finds no room for the grains there)" + mm;
        // Held whole: the tool's size is the slip (a 1 km object); in part: where it stands.
        if (held == tested || !mm.empty())
            refuse(tk.size, with_keys(tk.size_value, {tk.with, tk.place + " = " + tk.place_value}), what);
        refuse(tk.place, with_keys(tk.place_value, {tk.size + " = " + tk.size_value, tk.with}), what);
    }
}

// ---- the foil

void check_foil(const DeviceDef& d, const DeviceSizeEstimate& e) {
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius, L = e.membrane_spacing;
    // The holes: a grain passes between the membrane's particles where a hole's centre lies more
    // than r + r_f from every particle around it. A triangle of sites L apart has its centre
    // L / sqrt(3) from its corners; a vacant site's hole is its ring of neighbours, about L from
    // its centre. The remeshed edges reach 1.29 L (docs/membrane.md: 0.46-1.29 L), so the largest
    // holes reach 1.29 L / sqrt(3) (1.29 L with vacancies). Measured on the example gripper (1 mm
    // grains, r_f = 0.5 mm, bound 2.01 mm): membrane.spacing = 0.002 holds its grains through the
    // vacuum and the lift; 0.0025 and 0.003 let them out in the vacuum, and the air model stopped
    // the run ("the gas volume inside the membrane is -0.000000 m^3"), no key named.
    constexpr double kLongestEdge = 1.29;  // [-] the remeshed edges' largest over their mean L
    const bool vac = d.membrane.vacancies;
    const double k = (vac ? 1.0 : std::sqrt(3.0)) / kLongestEdge;  // [-] the spacing allowed per r + r_f
    const double most = k * (r + rf);
    if (!(L <= most)) {
        const std::string why =
            std::string("a grain (grains.radius = ") + num(r) + " m) would pass between the membrane's particles (r_f = " +
            num(rf) + " m): " +
            (vac ? "a vacancy's hole (membrane.vacancies) reaches about the longest edges, 1.29 L = "
                 : "a triangle of the longest edges, 1.29 L, has its centre 1.29 L / sqrt(3) = ") +
            fmt("%.3g", kLongestEdge * L * (vac ? 1.0 : 1.0 / std::sqrt(3.0))) + " m from " +
            (vac ? "its centre" : "its corners") + " (L = " + fmt("%.3g", L) + " m the sites' mean spacing), more than r + r_f = " +
            fmt("%.3g", r + rf) + " m; allowed: a spacing L of at most " + (vac ? "(r + r_f) / 1.29" : "sqrt(3) (r + r_f) / 1.29") +
            " = " + fmt("%.3g", most) + " m here";
        if (d.membrane.spacing > 0.0) refuse("membrane.spacing", num(d.membrane.spacing), why);
        // L = 2 r_f: 2 r_f <= k (r + r_f), r_f at most k r / (2 - k).
        refuse("membrane.particle_radius", num(rf),
               why + " (L = 2 membrane.particle_radius: at most " + fmt("%.3g", k * r / (2.0 - k)) +
                   " m, or a membrane.spacing)");
    }
    // The foil's stiffness against the load: under the underpressure dp (or, before the vacuum,
    // the weight of the grains' column, rho g H) a membrane particle is pressed over its site's
    // area, sqrt(3)/2 L^2, into the grain behind it, whose contact has the stiffness
    // harmonic(E_f t_f, E r) (E_f t_f: the foil particle's E_s r_f, vpp/membrane/foil.h). Past
    // half its radius the particle sits in the grain and the linear law means nothing (the
    // damper's bound on the grains' overlap); far past it the grains leave through the membrane
    // (membrane.thickness = 1e-9: the bag swelled to 2.7 times its volume in the fill).
    const double g = norm(d.gravity), H = e.hi.z - e.lo.z;
    const double weight = d.grain_density * g * H;             // [Pa]
    const double load = std::max(d.underpressure, weight);     // [Pa]
    const double force = load * std::sqrt(3.0) / 2.0 * L * L;  // [N] on one membrane particle
    const double need = force / (0.5 * rf);                    // [N/m] the contact stiffness that holds it
    const double b = d.grain_young * r;                        // [N/m] the grain's E r
    const double a = d.membrane.foil.young * d.membrane.foil.thickness;  // [N/m] the foil particle's E_s r_f
    if (!(force > 0.0) || harmonic(a, b) >= need) return;
    const std::string by = weight > d.underpressure ? "under the grains' weight rho g H = " + fmt("%.4g", weight) +
                                                          " Pa (grains.density, the membrane's height " + fmt("%.3g", H) + " m)"
                                                    : "under stages.underpressure = " + num(d.underpressure) + " Pa";
    const std::string overlap = fmt("%.3g", force / harmonic(a, b) / rf);
    if (!(2.0 * b > need))  // no foil is stiff enough: the grains themselves are too soft
        refuse("grains.young", num(d.grain_young),
               by + " a membrane particle would press into a grain by at least " + overlap + " of its radius r_f (its load " +
                   fmt("%.3g", force) + " N over the contact's stiffness, at most 2 E r = " + fmt("%.3g", 2.0 * b) +
                   " N/m); allowed: grains.young at least " + fmt("%.3g", need / (2.0 * r)) + " Pa here");
    const double a_min = need * b / (2.0 * b - need);  // [N/m] harmonic(a_min, b) = need
    // The key farther from its default (in decades) is named: a slip is in one of them.
    const double off_t = std::abs(std::log10(d.membrane.foil.thickness / 5e-4));
    const double off_e = std::abs(std::log10(d.membrane.foil.young / 2e6));
    const bool thickness = off_t >= off_e;
    const std::string what =
        by + " a membrane particle would press into the grain behind it by " + overlap + " of its radius r_f (its load " +
        "over its site, sqrt(3)/2 L^2 = " + fmt("%.3g", force) + " N, over the contact's stiffness 2 a b / (a + b), a = E_f t_f = " +
        fmt("%.3g", a) + " N/m, b = E r of a grain = " + fmt("%.3g", b) + " N/m); allowed: E_f t_f at least " +
        fmt("%.3g", a_min) + " N/m here (an overlap of at most half r_f), membrane." +
        (thickness ? "thickness at least " + fmt("%.3g", a_min / d.membrane.foil.young) + " m"
                   : "young at least " + fmt("%.3g", a_min / d.membrane.foil.thickness) + " Pa");
    const std::string t = num(d.membrane.foil.thickness), y = num(d.membrane.foil.young);
    if (thickness) refuse("membrane.thickness", t + " (membrane.young = " + y + ")", what);
    refuse("membrane.young", y + " (membrane.thickness = " + t + ")", what);
}

// ---- the motion

// The time step's estimate and where it comes from, for the messages.
struct StepSource {
    double dt = 0;         // [s]
    std::string text;      // "simulation.dt = ..." or how the estimate was made
    std::string key, value;  // the key a step far too short is blamed on
};

StepSource step_source(const DeviceDef& d) {
    StepSource s;
    s.dt = estimate_device_dt(d);
    if (d.dt > 0.0) {
        s.text = "simulation.dt = " + num(d.dt);
        s.key = "simulation.dt", s.value = num(d.dt);
        return s;
    }
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius;
    const double grain = std::sqrt(sphere_mass(d.grain_density, r) / (d.grain_young * r));
    const bool foil = !(grain * d.dt_safety <= s.dt * (1.0 + 1e-12));  // the membrane's particles set the step
    s.text = "about simulation.dt_safety = " + num(d.dt_safety) + " times sqrt(m/k) of " +
             (foil ? "a membrane particle (membrane.particle_radius, density, young, thickness)"
                   : "a grain (grains.radius, density, young)");
    // Of the keys that set that sqrt(m/k), the one given farthest from its default, in decades.
    struct Part {
        const char* key;
        double value, def;
    };
    const std::vector<Part> parts =
        foil ? std::vector<Part>{{"membrane.young", d.membrane.foil.young, 2e6},
                                 {"membrane.thickness", d.membrane.foil.thickness, 5e-4},
                                 {"membrane.density", d.membrane.foil.density, 1000.0},
                                 {"membrane.particle_radius", rf, 5e-4},
                                 {"membrane.stiffness_factor", d.membrane.stiffness_factor, 1.0}}
             : std::vector<Part>{{"grains.young", d.grain_young, 1e8},
                                 {"grains.density", d.grain_density, 1500.0},
                                 {"grains.radius", r, 1e-3}};
    double most = -1.0;
    for (const Part& p : parts) {
        const double off = std::abs(std::log10(p.value / p.def));
        if (off > most) most = off, s.key = p.key, s.value = num(p.value);
    }
    return s;
}

// [m/s] The speed at which a tool's impact overlaps a particle of `radius` [m] and mass `m` [kg]
// by half its radius through a contact of stiffness `k` [N/m]: v sqrt(m / k) = radius / 2 (the
// linear contact's largest overlap at an impact of speed v).
double impact_speed(double radius, double m, double k) { return 0.5 * radius * std::sqrt(k / m); }

void check_motion(const DeviceDef& d, const std::vector<dem::SurfaceMesh>& tools, const DeviceSizeEstimate& e) {
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius;
    const double mg = sphere_mass(d.grain_density, r), mf = sphere_mass(d.membrane.foil.density, rf);
    const double H = e.hi.z - e.lo.z;  // [m] the device's height along the tools' axis
    const StepSource step = step_source(d);

    auto duration = [&](const std::string& key, const std::string& value, double T, const std::string& what,
                        const std::string& allowed) {
        const double steps = T / step.dt;
        if (steps <= kMaxDeviceSteps) return;
        // A step far too short is the slip rather than the duration (as the damper's check_steps):
        // below a nanosecond and farther out, in decades, than the duration past 1000 s.
        const bool blame_step = std::log10(1e-9 / step.dt) > std::log10(T / 1e3);
        const std::string text = what + " would take " + fmt("%.3g", T) + " s, " + fmt("%.3g", steps) +
                                 " steps of " + fmt("%.3g", step.dt) + " s (" + step.text + "); allowed: at most " +
                                 fmt("%.0e", kMaxDeviceSteps) + " steps (months of a run): ";
        if (blame_step)
            refuse(step.key, step.value, text + "a time step of at least " + fmt("%.3g", T / kMaxDeviceSteps) + " s");
        refuse(key, value, text + allowed);
    };
    const std::string most_time = "at most " + fmt("%.3g", kMaxDeviceSteps * step.dt) + " s here";
    duration("stages.fill_time", num(d.fill_time), d.fill_time, "the fill", most_time);
    duration("stages.ramp_time", num(d.ramp_time), d.ramp_time, "the vacuum's ramp", most_time);
    duration("stages.vacuum_hold", num(d.vacuum_hold), d.vacuum_hold, "the vacuum's hold", most_time);

    for (std::size_t k = 0; k < d.tools.size(); ++k) {
        const DeviceTool& tool = d.tools[k];
        const bool surface = k < tools.size() && !tools[k].triangles.empty();
        const bool clamp = tool.name == d.clamp_tool;
        // The fastest the tool may go: its impact on a grain or a membrane particle (its surface),
        // the pull on the clamped particles' bonds (the clamp), half a radius of overlap (or of a
        // bond's stretch) at once; a tool that touches nothing (no surface, no clamp) has no bound.
        double vmax = std::numeric_limits<double>::infinity();
        std::string vwhy;
        auto bound = [&](double v, const std::string& why) {
            if (v < vmax) vmax = v, vwhy = why;
        };
        if (surface) {
            bound(impact_speed(r, mg, harmonic(tool.young * r, d.grain_young * r)), "overlap a grain it meets");
            bound(impact_speed(rf, mf, harmonic(tool.young * rf, d.membrane.foil.young * d.membrane.foil.thickness)),
                  "overlap a membrane particle it meets");
        }
        if (clamp) bound(impact_speed(rf, mf, equilateral_bond_kn(d.membrane)), "stretch the bonds of the membrane particles it pulls");
        // The stroke's bound: the device's height twice over beyond the tool's gap to it along z.
        double gap = 0.0;
        if (surface) {
            const Vec3 lo = bbox_lo(tools[k]), hi = bbox_hi(tools[k]);
            gap = std::max({0.0, lo.z - e.hi.z, e.lo.z - hi.z});
        }
        const double reach = gap + 2.0 * H;
        double z_lo = 0.0, z_hi = 0.0;  // [m] where the tool may stand at the segment's start (a press may stop anywhere)
        for (std::size_t m = 0; m < tool.program.size(); ++m) {
            const dem::ToolSegment& s = tool.program[m];
            const std::string key = "tools[" + std::to_string(k) + "].program[" + std::to_string(m) + "].";
            const bool moves = s.kind != dem::SegmentKind::Hold;
            if (moves && !vwhy.empty() && !(s.speed <= vmax))
                refuse(key + "speed", num(s.speed),
                       "the tool '" + tool.name + "' would " + vwhy + " by " + fmt("%.3g", 0.5 * s.speed / vmax) +
                           " particle radii at once (v sqrt(m/k): a linear spring's largest excursion when one end starts "
                           "at speed v); allowed: at most " + fmt("%.3g", vmax) + " m/s here (half a radius: past it the "
                           "linear law means nothing)");
            auto stroke = [&](const char* name, double value, double travel) {
                if (travel <= reach) return;
                refuse(key + name, num(value),
                       "a stroke of " + fmt("%.3g", travel) + " m, " + fmt("%.3g", travel / H) + " times the device's height H = " +
                           fmt("%.3g", H) + " m (the membrane's extent along z, the tools' axis); allowed: at most the tool's "
                           "gap to the membrane along z (" + fmt("%.3g", gap) + " m) plus 2 H, " + fmt("%.3g", reach) +
                           " m here: further down the tool has passed through the whole device, further up it has left it "
                           "or stretched the clamped membrane to three times its height");
            };
            const std::string speed_value = num(s.speed);
            auto at_least = [&](double length) {
                return "a speed of at least " + fmt("%.3g", length / (kMaxDeviceSteps * step.dt)) + " m/s here";
            };
            switch (s.kind) {
            case dem::SegmentKind::Move: {
                stroke("to", s.to, std::abs(s.to));
                const double travel = std::max(std::abs(s.to - z_lo), std::abs(s.to - z_hi));
                duration(key + "speed", speed_value, travel / s.speed, "the move to " + num(s.to) + " m", at_least(travel));
                z_lo = z_hi = s.to;
                break;
            }
            case dem::SegmentKind::Hold:
                duration(key + "duration", num(s.duration), s.duration, "the hold", most_time);
                break;
            case dem::SegmentKind::ForceHold:
                // Where the servo leaves the tool is left out: it follows the sample's creep, and
                // its largest excursion (speed x duration) would blame the next move for a hold's
                // length. A move's time is then at most underestimated, never refused wrongly.
                duration(key + "duration", num(s.duration), s.duration, "the force hold", most_time);
                break;
            case dem::SegmentKind::Force:
                stroke("max_travel", s.max_travel, s.max_travel);
                duration(key + "speed", speed_value, s.max_travel / s.speed,
                         "the press (its max_travel " + num(s.max_travel) + " m)", at_least(s.max_travel));
                if (s.force > 0.0) z_lo -= s.max_travel;
                else z_hi += s.max_travel;
                break;
            case dem::SegmentKind::Cycle: {
                stroke("amplitude", s.amplitude, std::abs(s.amplitude));
                const double path = 2.0 * std::abs(s.amplitude) * double(s.cycles);  // [m]
                duration(key + "speed", speed_value, path / s.speed,
                         "the " + std::to_string(s.cycles) + " cycles of " + num(s.amplitude) + " m", at_least(path));
                break;
            }
            }
        }
    }
}

}  // namespace

DeviceSizeEstimate estimate_device_size(const DeviceDef& d, const dem::SurfaceMesh& membrane) {
    DeviceSizeEstimate e;
    e.lo = bbox_lo(membrane), e.hi = bbox_hi(membrane);
    e.membrane_area = dem::surface_area(membrane);
    e.membrane_spacing = d.membrane.spacing > 0.0 ? d.membrane.spacing : 2.0 * d.membrane.foil.particle_radius;
    // The remesher makes the mean edge L (dem/mesh/remesh.h, match_mean), so the sites cover the
    // surface at 2 / (sqrt(3) L^2); the vacancies leave out about 24% (docs/membrane.md: 23-24% drawn).
    e.membrane_particles = 2.0 * e.membrane_area / (std::sqrt(3.0) * e.membrane_spacing * e.membrane_spacing);
    if (d.membrane.vacancies) e.membrane_particles *= 1.0 - 0.24;
    e.enclosed_volume = dem::enclosed_volume(membrane);
    // The lattice's sites lie at least the clearance c = r + r_f + 0.1 r inside the surface
    // (DeviceRun::add_grains): the body shrunk by c, by Steiner's formula.
    const double r = d.grain_radius, c = r + d.membrane.foil.particle_radius + 0.1 * r;
    // The shrunk volume only falls as c grows: the cubic's least value over [0, c] (past the
    // body's half-width along one axis a box's cubic turns up again), and not below 0.
    const double V = e.enclosed_volume, A = e.membrane_area, M = mean_curvature_integral(membrane);
    auto shrunk = [&](double s) { return V - A * s + M * s * s - 4.0 / 3.0 * std::numbers::pi * s * s * s; };
    double least = V;
    for (int k = 1; k <= 64; ++k) least = std::min(least, shrunk(c * k / 64.0));
    e.fill_volume = std::max(0.0, least);
    const bool fcc = d.lattice == "fcc";
    const double a = d.lattice_spacing * r * (fcc ? std::numbers::sqrt2 : 1.0);  // [m] the cell's edge
    const double per_cell = fcc ? 4.0 : 1.0;
    e.grains = d.fill_mode == "pour" ? double(d.pour_count) : d.fill * e.fill_volume * per_cell / (a * a * a);
    e.bytes = (e.membrane_particles + e.grains) * kDeviceBytesPerParticle;
    return e;
}

double estimate_device_dt(const DeviceDef& d) {
    if (d.dt > 0.0) return d.dt;
    // dem::critical_dt: per free particle sqrt(m / kn), kn the stiffer of its stiffest contact
    // (harmonic(E r, E' r') with the stiffest partner: at least a grain's E r) and its stiffest bond.
    const double r = d.grain_radius, rf = d.membrane.foil.particle_radius;
    const double er = d.grain_young * r;
    const double grain = std::sqrt(sphere_mass(d.grain_density, r) / er);
    const double foil_kn = std::max(harmonic(d.membrane.foil.young * d.membrane.foil.thickness, er), equilateral_bond_kn(d.membrane));
    const double foil = std::sqrt(sphere_mass(d.membrane.foil.density, rf) / foil_kn);
    return d.dt_safety * std::min(grain, foil);
}

void check_device_inputs(const DeviceDef& d, const dem::SurfaceMesh& membrane, const std::vector<dem::SurfaceMesh>& tools) {
    const DeviceSizeEstimate e = estimate_device_size(d, membrane);
    check_sizes(d, membrane, e);
    check_tools(d, membrane, tools);
    check_foil(d, e);
    check_motion(d, tools, e);
}

}  // namespace vpp

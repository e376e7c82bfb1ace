// The device's scene (device/scene.h): built from the device file, and its measures.
#include "vpp/device/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "scene/time_step.h"
#include "vpp/device/fill_sites.h"
#include "vpp/membrane/foil.h"

namespace vpp::device_detail {

using dem::Vec3;

namespace {

// The tools of the device file in `w`: each shaped tool's facets with a material of its own
// (after the grains', so that the materials' order is the file's); the surfaces of the shaped
// tools into `surfaces` (the fill keeps clear of them).
std::vector<dem::Tool> build_tools(const DeviceDef& d, const std::string& base, dem::World& w,
                                   std::vector<dem::SurfaceMesh>& surfaces) {
    std::vector<dem::Tool> tools;
    for (std::size_t k = 0; k < d.tools.size(); ++k) {
        const DeviceTool& t = d.tools[k];
        dem::Tool tool;
        tool.name = t.name;
        tool.program = t.program;
        if (t.shape.kind != "none") {
            dem::Material tm;
            tm.name = "tool " + t.name;
            tm.young = t.young;
            tm.friction = t.friction;
            tm.stiffness_ratio = t.stiffness_ratio;
            const uint32_t mat = w.add_material(tm);
            surfaces.push_back(device_surface(t.shape, "tools[" + std::to_string(k) + "]", base));
            const dem::SurfaceMesh& s = surfaces.back();
            std::vector<dem::Facet> facets;
            for (const auto& tri : s.triangles) {
                dem::Facet f;
                f.vertices = {s.vertices[tri[0]], s.vertices[tri[1]], s.vertices[tri[2]]};
                f.material = mat;
                f.mask = kMaskGrainFoil;  // grains and membrane; the grains' mask shares the bit
                facets.push_back(f);
            }
            dem::add_tool_facets(w, tool, facets);
        }
        tools.push_back(std::move(tool));
    }
    return tools;
}

// The membrane's particles within membrane.clamp_height of its top follow membrane.clamp_tool.
void clamp_membrane(const DeviceDef& d, dem::World& w, const Membrane& m, std::vector<dem::Tool>& tools) {
    if (d.clamp_tool.empty()) return;
    double z_top = -1e300;
    for (uint32_t i : m.particles) z_top = std::max(z_top, w.particles.pos[i].z);
    std::vector<uint32_t> clamp;
    for (uint32_t i : m.particles)
        if (w.particles.pos[i].z >= z_top - d.clamp_height) clamp.push_back(i);
    for (dem::Tool& t : tools)
        if (t.name == d.clamp_tool) dem::clamp_to_tool(w, t, clamp);
}

}  // namespace

DeviceScene::DeviceScene(const DeviceDef& d) : def(d) {
    const std::string base = std::filesystem::path(d.path).parent_path().string();  // the meshes' folder
    const dem::SurfaceMesh surface = device_surface(def.membrane_shape, "membrane", base);
    MembraneDef md = def.membrane;
    md.seed = def.seed == 0 ? 1 : def.seed;
    membrane = build_membrane(world, md, surface);  // the foil's material is 0

    dem::Material gm;
    gm.name = "grains";
    gm.density = def.grain_density;
    gm.young = def.grain_young;
    gm.friction = def.fill_friction;  // grains.friction from the seal on
    gm.stiffness_ratio = def.grain_stiffness_ratio;
    grain_mat = world.add_material(gm);

    std::vector<dem::SurfaceMesh> tool_surfaces;
    tools = build_tools(def, base, world, tool_surfaces);
    clamp_membrane(def, world, membrane, tools);

    pour = def.fill_mode == "pour";
    if (pour) opening = open_membrane(def, world, membrane);
    first_grain = uint32_t(world.particles.size());
    add_grains(*this, surface, tool_surfaces);
    end_grain = uint32_t(world.particles.size());
    grain_volume = active_grain_volume();

    world.params.gravity = def.gravity;
    world.params.local_damping = def.local_damping;
    world.params.threads = def.threads;
    world.params.dt = scene::time_step({.automatic = def.dt == 0.0, .dt = def.dt, .safety = def.dt_safety}, world);
    if (!(world.params.dt > 0.0) || !std::isfinite(world.params.dt))
        throw std::runtime_error("device: no usable time step (" + std::to_string(world.params.dt) + " s)");
}

std::size_t DeviceScene::active_grains() const {
    std::size_t n = 0;
    for (uint32_t i = first_grain; i < end_grain; ++i) n += active_grain(i);
    return n;
}

double DeviceScene::active_grain_volume() const {
    double v = 0.0;
    for (uint32_t i = first_grain; i < end_grain; ++i)
        if (active_grain(i)) v += 4.0 / 3.0 * std::numbers::pi * std::pow(world.particles.radius[i], 3);
    return v;
}

void DeviceScene::retire_grain(uint32_t i) {
    world.set_fixed(i);
    world.particles.mask[i] = 0;
}

double DeviceScene::largest_membrane_overlap() const {
    const dem::Particles& p = world.particles;
    double worst = 0.0;
    for (uint32_t i = first_grain; i < end_grain; ++i) {
        if (!active_grain(i)) continue;
        for (uint32_t k : membrane.particles) worst = std::max(worst, p.radius[i] + p.radius[k] - norm(p.pos[i] - p.pos[k]));
    }
    return worst;
}

double DeviceScene::grains_kinetic_energy() const {
    return dem::kinetic_energy(world.particles, first_grain, end_grain).translation;
}

double DeviceScene::membrane_z_min() const {
    double z_min = 1e300;
    for (uint32_t i : membrane.particles) z_min = std::min(z_min, world.particles.pos[i].z);
    return z_min;
}

}  // namespace vpp::device_detail

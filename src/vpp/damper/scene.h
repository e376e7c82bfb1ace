// The damper's scene: its World and the parts in it (foil, end rings, grains, caps, funnel), built
// from its definition (the Config), and what can be asked of or done to them with nothing but the
// scene: the grains' sizes, tops, volume and level, the foil's enclosed volume, the pressure on
// it. The stages (damper/stages.h) act on it; the run (damper/run.h) owns it. A plain aggregate:
// the stages read and move its parts directly. Internal to vpp/damper_*.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene/size_distribution.h"
#include "dem/world/world.h"
#include "vpp/settings/config.h"
#include "vpp/membrane/foil.h"
#include "vpp/membrane/membrane.h"

namespace vpp::damper_detail {

using dem::Vec3;

// Material indices in the damper world (the foil is built first, so its material is 0).
constexpr uint32_t kFoilMat = 0, kGrainMat = 1, kCapMat = 2, kFunnelMat = 3;
constexpr uint32_t kBottomCap = 0, kTopCap = 1;  // plane indices

struct DamperScene {
    // The foil from the definition `c`, and what the grains are drawn from (sizes, shape); no
    // grains yet: pour() them, or load a checkpoint's World (its sample holds its radii and
    // clumps, so a sieve curve or a clump template is read only when given).
    explicit DamperScene(const Config& c);
    DamperScene(const DamperScene&) = delete;
    DamperScene& operator=(const DamperScene&) = delete;

    // A fresh sample: the materials (grain, cap, funnel), the fixed end rings, n grains on a
    // jittered lattice in the foil and a funnel above it, the caps and the funnel's facets.
    // Returns the funnel's height [m] (the re-fills place their grains in the same funnel).
    double pour(std::size_t n);
    // Sites for n more grains above the grains in (the re-fill `stream`, 1, 2, ...) in the funnel
    // of height funnel_height [m]: as many of n as fit.
    std::vector<Vec3> refill_sites(std::size_t n, double funnel_height, uint64_t stream) const;
    // Grains at these centres [m] with these (volume-equivalent) radii [m]: spheres, or clumps
    // of grains.shape in random orientations from stream `stream` (0: the pour, k: re-fill k);
    // end_grain follows.
    void add_grains(const std::vector<Vec3>& pos, const std::vector<double>& radii, uint64_t stream);
    // n radii [m] from the size distribution's stream `stream` (0: the pour, k: re-fill k).
    std::vector<double> draw_radii(std::size_t n, uint64_t stream) const;
    // The run settings (contacts, foil stiffness, damping, threads, skin) of `config` applied to
    // the prepared sample's World (the geometry is the sample's; the caller checked it).
    void apply_run_settings();
    // The pressure's nodes (lattice) or fans (mesh) on the foil, from the vacuum on.
    void set_foil_pressure();

    // The foil's builder (foil.builder): the lattice (lattice, the paper's) or the mesh membrane.
    bool mesh_foil() const { return config.damper.foil_builder == FoilBuilder::Mesh; }
    // The mesh foil's definition from the config: the paper's rules carried to the membrane
    // (docs/membrane.md, "A cylinder given as a mesh").
    MembraneDef membrane_def() const;
    bool clumps() const { return config.grains.shape != GrainShape::Sphere; }
    // Grains in the world: clumps, or the spheres first_grain .. end_grain.
    std::size_t grain_count_now() const {
        return clumps() ? world.clumps().size() : std::size_t(end_grain - first_grain);
    }
    // The reach of a grain of volume-equivalent radius r [m] from its centre [m] (r for spheres).
    double grain_reach(double r) const { return clumps() ? r * shape.bounding_radius : r; }
    // Per grain: its volume-equivalent radius [m], its top (highest point) [m].
    std::vector<double> grain_radii() const;
    std::vector<double> grain_tops() const;
    // The grains' volume [m^3] and mass [kg] as they stand.
    double grains_volume_now() const;
    double grains_mass() const;
    // [m^3] grains_volume_now() summed once: the grains are fixed after the preparation, and the
    // air asks every step.
    double grain_volume() const;
    // [m] the mean top of the grains' highest layer (the level of their surface).
    double fill_level() const;
    // [m] the highest point of any grain.
    double highest_grain_top() const;
    // [-] the grains' volume over a cylinder of this inner radius [m] and height [m].
    double packing_fraction(double inner_radius, double height) const;
    // [m^3] volume enclosed by the foil closed by flat caps through its end rings.
    double foil_volume() const;
    // [m^2] area of the polygon of the top ring's particle centres (on which dp pushes the lid).
    double lid_area() const;
    // [N] z force on the top ring's particles (the foil's on the testing machine).
    double top_ring_force_z() const;
    // [J] energy scale of the rest criteria: every grain lifted by one diameter, N m g 2 r_k.
    // With a size distribution: the grains' total mass, the mean diameter.
    double settle_energy_scale() const {
        if (sizes.kind == scene::SizeDistribution::Kind::Single)
            return double(grain_count_now()) * world.particles.mass[first_grain] * 9.81 * 2.0 * config.grains.radius;
        return grains_mass() * 9.81 * 2.0 * config.grains.radius;
    }

    Config config;                   // the definition (a checkpoint's geometry and settings adopted)
    scene::SizeDistribution sizes;   // what the fill and re-fills draw the radii from
    dem::ClumpShape shape;           // clumps(): the clump at a volume-equivalent radius of 1 m
    dem::World world;
    // The lattice foil; with the mesh foil only its radius, spacing, material and particles are
    // set (rows and cols 0), which the grains, funnel and checks read alike.
    FoilLattice lattice;
    Membrane membrane;                 // the mesh foil (foil.builder = "mesh"); empty otherwise
    std::vector<uint32_t> bottom_ring; // the foil's end ring on the base (fixed)
    std::vector<uint32_t> top_ring;    // the foil's end ring under the top cap (moves with it)
    std::vector<uint32_t> free_foil;   // the foil's particles off both end rings
    uint32_t first_grain = 0, end_grain = 0;  // the grains' particle range (clumps: their members)
    double z_top = 0;                  // [m] top ring / cap height after preparation

private:
    void build_foil();
    mutable double grain_volume_ = 0;  // [m^3] grain_volume()'s sum, once the grains are final
};

}  // namespace vpp::damper_detail

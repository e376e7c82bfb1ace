// The foil membrane: a square grid of bonded spheres with 25% vacancies (paper section 3.2).
//
// Sites (row k, column c) sit 2 r_f apart. The site with k odd and c odd is empty, so even rows
// and even columns are continuous chains; particles at (even, even) are 'intersection'
// particles, the only ones loaded by pressure. Bonds join chain neighbours only (never
// diagonal). Stiffness convention (docs/foil.md): E_s = 2 E_f t_f / (2 r_f) as the paper, and
// a bond is a bar of modulus E_s, section (2 r_f)^2 and length 2 r_f: kn = 2 E_s r_f = 2 E_f t_f,
// which gives the strip the tensile stiffness E_f t_f w of the real foil.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/world/world.h"

namespace vpp {

struct FoilDef {
    double young{};               // [Pa] E_f, the real foil
    double thickness{};           // [m] t_f, the real foil
    double particle_radius{};     // [m] r_f
    double density{};             // [kg/m^3] foil particle density (paper)
    double friction{};            // [-] foil particles are frictionless
    double stiffness_ratio{};     // [-] ks/kn of bonds and foil contacts
    // Where the bonds' shear springs are driven from: the full radii, the paper's convention, or
    // the bond point, where the torques act (dem/bonds/bond_list.h).
    dem::BondArm bond_arm = dem::BondArm::kRadius;
};

// E_s = 2 E_f t_f / (2 r_f) [Pa]: only every second chain carries load (factor 2) and the
// lattice is 2 r_f thick instead of t_f (paper eq. 1).
inline double particle_modulus(const FoilDef& f) {
    return 2.0 * f.young * f.thickness / (2.0 * f.particle_radius);
}
// Axial bond stiffness [N/m]: a bar of modulus E_s, cross-section (2 r_f)^2, length 2 r_f.
inline double bond_normal_stiffness(const FoilDef& f) { return 2.0 * particle_modulus(f) * f.particle_radius; }
// The same bar rule for a lattice whose sites are `along` [m] apart in the bond's direction and
// `across` [m] apart across it (a cylinder at its exact radius: the row bonds are the chord, not
// 2 r_f): a bar of modulus E_s, thickness 2 r_f, width `across`, length `along`, kn = E_s 2 r_f
// across / along. A chain then carries E_s 2 r_f across per unit strain, and the lattice keeps
// E_f t_f per unit width in both directions whatever the two pitches (docs/foil.md). On the
// square grid (both 2 r_f) it is bond_normal_stiffness; that path keeps its own expression.
inline double lattice_bond_stiffness(const FoilDef& f, double along, double across) {
    return particle_modulus(f) * 2.0 * f.particle_radius * across / along;
}

// Flags stored in World::particles.flags above the core's bits.
enum FoilFlag : uint32_t {
    kFoil = 1u << 8,          // foil particle
    kIntersection = 1u << 9,  // at an (even row, even column) site
};

// Collision masks (Yade convention: bodies interact when masks share a bit).
constexpr uint32_t kMaskGrainFoil = 1u << 0;  // grains with grains, grains with foil, foil with foil
constexpr uint32_t kMaskCap = 1u << 1;        // grains with caps and funnel; never foil
constexpr uint32_t kGrainMask = kMaskGrainFoil | kMaskCap;
constexpr uint32_t kFoilMask = kMaskGrainFoil;

// One bond of a lattice: its index in the World's bonds, the site (row k, column c) it starts at
// and whether it runs along the row (to column c + 1) or along the column (to row k + 1).
struct LatticeBond {
    uint32_t index = 0;
    int k = 0, c = 0;
    bool along_row = false;
};

// A foil lattice placed in a World.
struct FoilLattice {
    int rows = 0;                 // site rows (k)
    int cols = 0;                 // site columns (c); around the cylinder for tubes
    bool closed = false;          // columns wrap around (cylinder)
    double radius = 0.0;          // [m] cylinder: radius of the site circle
    double spacing = 0.0;         // [m] 2 r_f
    // [m] distance between the sites of neighbouring columns: spacing, except on a cylinder built
    // at its exact radius (the chord 2 R sin(pi / cols)); the row bonds' rest length.
    double column_pitch = 0.0;
    uint32_t material = 0;
    std::vector<int32_t> site;    // (k * cols + c) -> particle index, -1 for a vacancy
    std::vector<uint32_t> particles;  // all foil particle indices
    std::vector<uint32_t> intersections;
    std::vector<LatticeBond> bonds;   // every bond of the lattice, in the order they were added
    int32_t at(int k, int c) const { return site[std::size_t(k) * cols + c]; }
    // Particles of site row k (cylinder end rings: first and last row).
    std::vector<uint32_t> row(int k) const;
    // Particles of site column c (strip edges).
    std::vector<uint32_t> column(int c) const;
};

// Adds the foil material to the world (E_s, density, friction) and returns its index.
uint32_t add_foil_material(dem::World& w, const FoilDef& f);

// Flat strip in the xy plane, columns along x (pulling direction), rows along y, first site at
// the origin. `rows` x `cols` sites (the paper's tension test: 12 x 37).
FoilLattice build_strip(dem::World& w, const FoilDef& f, int rows, int cols);

// Cylinder about the z axis, base ring at z = z0. Chooses the even column count whose radius
// r_f / sin(pi/n) is closest to `radius`, and the odd row count whose height is closest to
// `height`, so both end rings are full rings. The sites then lie on that circle (neighbours 2 r_f
// apart), or with exact_radius on the circle of `radius` itself: the row bonds' rest length is
// then the chord 2 radius sin(pi / n) (column_pitch), and every bond's stiffness follows from the
// bar rule with the two pitches (lattice_bond_stiffness), so the foil keeps E_f t_f per unit
// width both ways; the particles keep r_f (neighbours in a row overlap or part by the chord's
// difference from 2 r_f: at most 1.3% of it on the paper's radii).
FoilLattice build_cylinder(dem::World& w, const FoilDef& f, double radius, double height, double z0 = 0.0,
                           bool exact_radius = false);

// Axial stiffness [N/m] of lattice bond b of L (bond_normal_stiffness on the square grid; the bar
// rule with L's pitches where its columns are not 2 r_f apart).
double lattice_bond_kn(const FoilDef& f, const FoilLattice& L, const LatticeBond& b);

// Even column count and odd row count that build_cylinder would choose.
int choose_columns(double radius, double r_f);
int choose_rows(double height, double r_f);

// Pressure nodes of a cylinder: intersection particles not on the first or last row, with
// neighbours in the order +theta, +z, -theta, -z (A points outward).
std::vector<dem::PressureNode> cylinder_pressure_nodes(const FoilLattice& L);

// Volume enclosed by a cylinder lattice closed by flat caps through its end rings [m^3]: the
// polyhedron spanned by the full rings, triangulated, by the divergence theorem.
double enclosed_volume(const FoilLattice& L, const std::vector<dem::Vec3>& pos);

// Smallest surface gap between two foil particles that are not bonded, in units of r_f
// (negative: overlap).
double min_nonbonded_gap(const FoilLattice& L, const dem::World& w);

}  // namespace vpp

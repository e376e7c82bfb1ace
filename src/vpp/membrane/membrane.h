// A foil membrane on any closed surface (issue 47): the paper's foil rules (section 3.2,
// docs/foil.md) carried from the cylinder's square grid to a triangulation of the surface.
//
//   sites      the vertices of the surface remeshed to edges of the spacing (2 r_f by default,
//              the cylinder's chain spacing: neighbours touch), dem/mesh/remesh.h;
//   particles  one foil particle of radius r_f per site, less the vacancies;
//   bonds      the triangulation's edges between particles (an edge to a vacancy is none);
//   stiffness  kn per bond from E_f, t_f (MembraneStiffness below), ks = stiffness_ratio kn;
//   vacancies  optional: a seeded random ~25% of the sites, no two adjacent and every
//              particle keeping at least 3 bonds (the cylinder's fixed pattern has no analogue
//              on an irregular triangulation);
//   pressure   a fan per particle over the closed triangulation of the particles (each
//              vacancy's hole filled by a fan of its ring), A = a third of each adjacent
//              triangle's area vector (dem::PressureFans): zero net force under uniform dp;
//   volume     the divergence theorem over the same triangulation (the air model's V).
//
// The built-in cylinder (vpp/membrane/foil.h) is untouched: this is a second builder, not a
// replacement, so the paper's damper keeps its lattice bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dem/core/pressure.h"
#include "dem/mesh/surface_mesh.h"
#include "dem/world/world.h"
#include "vpp/membrane/foil.h"

namespace vpp {

// How a bond's kn follows from the real foil (E_f, t_f). Both give ks = stiffness_ratio kn.
enum class MembraneStiffness : int {
    // kn = c E_f t_f A_e / L_e^2, A_e the area of the bond's two triangles, L_e its length,
    // c = (3 + a) / (3 (1 + a)), a = ks/kn: on an equilateral network the in-plane Young
    // modulus (times thickness) is then E_f t_f, as the cylinder's rule gives its strip.
    // (van Gelder's area rule, corrected for the bonds' shear springs; see docs/membrane.md.)
    MatchFoil = 0,
    // The cylinder's bar, kn = E_s (2 r_f)^2 / L_e (= 2 E_f t_f at L_e = 2 r_f): the same
    // formula per bond, but a triangulated network of such bonds is 3x stiffer than the foil
    // (3 bonds per site instead of the grid's load-carrying every second chain).
    PaperBar = 1,
};

struct MembraneDef {
    FoilDef foil;                   // E_f, t_f, r_f, density, friction, ks/kn (as the cylinder's)
    double spacing = 0.0;           // [m] target bond length; 0: 2 r_f (the cylinder's)
    MembraneStiffness stiffness = MembraneStiffness::MatchFoil;
    // [-] multiplies every kn. The rules above hold for the full triangulation; the vacancies
    // (~24% drawn) halve its biaxial stiffness (measured strain ratio 2.05 over 3 seeds,
    // docs/membrane.md), which about 2.05 restores (2.1 gives a strain ratio of 0.977).
    double stiffness_factor = 1.0;
    // [-] every bond's rest length is its built length / (1 + prestrain): the membrane is built
    // stretched by this strain, as a balloon filled past its rest size, so that its tension
    // squeezes what it holds before any load (0: built at rest, the damper's foil).
    double prestrain = 0.0;
    bool vacancies = false;         // leave out ~vacancy_fraction of the sites
    double vacancy_fraction = 0.25; // [-] the paper's 25%
    uint64_t seed = 1;              // [-] the vacancies' draw
    int remesh_iterations = 12;     // [-] see dem::RemeshOptions
    double feature_angle = 35.0;    // [deg] input edges sharper than this stay sharp
};

struct Membrane {
    dem::SurfaceMesh sites;            // the remeshed surface: vertex = site, edge = bond candidate
    std::vector<uint8_t> site_feature; // per site: 0 smooth, 1 on a feature line, 2 corner
    std::vector<int32_t> particle;     // site -> particle index in the World, -1 a vacancy
    std::vector<uint32_t> particles;   // the foil particles, in site order
    // Closed, outward triangulation of the particles (World indices): the sites' triangles
    // without vacancies, each hole fan-filled. Pressure fans and the enclosed volume use it.
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<uint32_t> bonds;       // the World's bond indices of the membrane
    uint32_t material = 0;
    double spacing = 0.0;              // [m] the target bond length
    std::size_t vacancies = 0;         // sites left empty
    double min_edge = 0, max_edge = 0, mean_edge = 0;  // [m] of the site triangulation
    // An open membrane (membrane_tube_sites: a tube whose ends the caps hold): the loops of its
    // boundary, as site indices (boundary_sites) and, once placed, particle indices (boundary),
    // each loop in the direction of its outward triangles' boundary edges. Empty when closed.
    // The boundary sites are never vacant; the caps close the surface there, so the pressure
    // (membrane_pressure_fans) loads the other particles only, and the enclosed volume closes
    // each loop by a flat fan from its centroid.
    std::vector<std::vector<uint32_t>> boundary_sites;
    std::vector<std::vector<uint32_t>> boundary;
    // Per bond of `bonds`: its rest length [m] and the area of its two triangles [m^2], from which
    // membrane_bond_stiffness gives kn again for other foil values (a run from a prepared sample).
    std::vector<double> bond_length, bond_area;
    bool open() const { return !boundary_sites.empty(); }
};

// Builds the membrane on `surface` (closed, outward, checked: dem::check_closed_surface),
// adding the foil material, particles (flags kFoil, mask kFoilMask) and bonds to `w`. Pressure is
// not switched on: set w.pressure.fans = membrane_pressure_fans(m) and w.pressure.dp.
// Throws std::invalid_argument for a bad definition, std::runtime_error for a bad surface.
Membrane build_membrane(dem::World& w, const MembraneDef& d, const dem::SurfaceMesh& surface);

// build_membrane in two steps, so that runs over seeds remesh once: membrane_sites checks and
// remeshes (the sites only, nothing placed; seconds for ~10^4 sites), place_membrane draws the
// vacancies (d.seed) and adds the particles and bonds to `w` (milliseconds). Place a copy.
Membrane membrane_sites(const MembraneDef& d, const dem::SurfaceMesh& surface);
void place_membrane(dem::World& w, const MembraneDef& d, Membrane& m);

// The lateral surface of a z-axis cylinder of `radius` and `height` [m] from z = z0 as an open
// membrane's sites (place it with place_membrane): the closed cylinder (flat end discs, `segments`
// around) is remeshed as membrane_sites does, with its rims as feature lines on which sites only
// slide, and the discs' sites and triangles are dropped. The rims' sites become the two boundary
// loops (bottom first): the tube's end rings, which a damper's base and cap hold. Throws
// std::invalid_argument for a bad definition or size.
Membrane membrane_tube_sites(const MembraneDef& d, double radius, double height, double z0 = 0.0, int segments = 256);

// kn [N/m] of a bond of length `length` [m] whose two triangles have the area `area` [m^2].
double membrane_bond_stiffness(const MembraneDef& d, double length, double area);

// Closed forms for an equilateral network of bonds kn, ks = a kn (docs/membrane.md):
// in-plane Young modulus times thickness [N/m], its Poisson ratio [-], and the biaxial stiffness
// N / eps under equal strain both ways [N/m] (= E/(1 - nu) = sqrt(3) kn, free of ks).
double network_young(double kn, double a);
double network_poisson(double a);
double network_biaxial(double kn);

// The vacancies: a seeded random set of about fraction * sites, no two adjacent, every
// remaining site keeping >= 3 neighbours. 1 = vacant, per site.
std::vector<uint8_t> choose_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed);
// The same over the sites marked in `eligible` (1: may be vacant) only, about fraction * their
// count; `sites` may be open (a tube), its boundary sites then never eligible. The draw is the
// same permutation of all sites as above, skipping the others.
std::vector<uint8_t> choose_vacancies(const dem::SurfaceMesh& sites, double fraction, uint64_t seed,
                                      const std::vector<uint8_t>& eligible);

// Pressure fans of the membrane's particles (counter-clockwise rings seen from outside: A
// points out, dp > 0 pushes in). An open membrane: the particles off its boundary only (the
// boundary's particles are held by the walls that close it, which carry the pressure there).
dem::PressureFans membrane_pressure_fans(const Membrane& m);

// Volume enclosed by the membrane's particle triangulation at positions `pos` [m^3]; an open
// membrane closed by a flat fan over each boundary loop from the loop's centroid (the caps).
double enclosed_volume(const Membrane& m, const std::vector<dem::Vec3>& pos);

// Saves `w` (dem::save_checkpoint) without its pressure fans, which the checkpoint format does not
// carry yet: for callers that rebuild the fans from their membrane when they load. The fans are
// back in `w` afterwards, also when the save throws.
void save_checkpoint_without_fans(const std::string& path, dem::World& w, const std::string& blob);

}  // namespace vpp

#include "vpp/settings/settings.h"

#include <cstring>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "scene/config.h"
#include "scene/shared_keys.h"
#include "scene/time_step.h"

namespace vpp {

namespace {

using T = SettingType;
using A = Acts;
using C = Check;
namespace keys = cfg::keys;

// The key within its section ("process.velocity" -> "velocity").
// A fingerprint of a file's numbers (FNV-1a over their bytes), exact in a double (52 bits): the
// geometry check of a file a prepared sample was drawn from (a sieve curve, a clump template).
double fingerprint(const std::vector<double>& values) {
    uint64_t h = 14695981039346656037ull;
    for (double x : values) {
        uint64_t b;
        std::memcpy(&b, &x, 8);
        for (int i = 0; i < 8; ++i) h = (h ^ ((b >> (8 * i)) & 0xffu)) * 1099511628211ull;
    }
    return double(h >> 12);
}

std::string short_key(const Setting& s) {
    const std::string k = s.key;
    return k.substr(k.find('.') + 1);
}

// An enumerated key (vpp/settings/choices.h): its word in the file, `def` where the file has none;
// another word is refused with the row's `allowed`.
template <class E>
E read_word(cfg::Section& s, const Setting& r, E def) {
    const std::string k = short_key(r);
    const std::optional<E> v = from_word<E>(s.string(k, word_of(def)));
    if (!v) s.fail(k, r.allowed);
    return *v;
}

// A row of a key declared once for every table (scene/shared_keys.h): its type, unit, default,
// range and doc from there; `row` gives what this table adds (what it acts on, where it is
// recorded, its field, a note on what it does in these commands). `key` and `doc`: another key
// of the same property (the foil's stiffness ratio is the grains' property).
// A row may restate its key and default where a reader of this file's text needs them here (the
// time step's, below); they must be the declaration's.
Setting declared(const cfg::KeyDecl& k, Setting row, const char* key = nullptr, const char* doc = nullptr) {
    if ((*row.key && std::string(row.key) != k.key) || (!std::isnan(row.def) && row.def != k.def))
        throw std::logic_error(std::string("settings: the row of ") + k.key + " restates its key or default otherwise "
                               "than its declaration (scene/shared_keys.h)");
    row.key = key ? key : k.key;
    row.type = k.type;
    row.unit = k.unit;
    row.def = k.def;
    row.default_text = k.default_text;
    row.check = k.limits.check;
    row.lo = k.limits.lo;
    row.hi = k.limits.hi;
    row.lo_open = k.limits.lo_open;
    row.hi_open = k.limits.hi_open;
    row.allowed = k.limits.allowed;
    row.doc = doc ? doc : k.doc;
    return row;
}

#define FIELD(f)                                                    \
    .get = [](const Config& c) { return double(c.f); },             \
    .set = [](Config& c, double v) { c.f = decltype(c.f)(v); }
#define FLAG(f)                                                     \
    .get = [](const Config& c) { return c.f ? 1.0 : 0.0; },         \
    .set = [](Config& c, double v) { c.f = v != 0.0; }

// Rows in the order the reader reads them; sections must stay together (one [table] each).
// Sharing a preparation (shares_preparation): only what does not act before the end of the
// preparation (prepared.ckpt) may differ between the cases of one preparation; everything else
// would give a case a sample it did not ask for.
// - grains.friction, damper.cap_friction: the fill and the cap's compression are frictionless
//   (the grain, cap and funnel materials have friction 0 until DamperScene::apply_run_settings()
//   in vpp/damper/scene.cpp gives them the config's);
// - process.*: the vacuum and the cycles come after prepared.ckpt;
// - simulation.threads (results do not depend on it), output.* (files only), analysis.*
//   (post-processing).
// Not shared, because they act while the grains fall and the cap compresses them: grain and foil
// stiffnesses (grains.young, grains.stiffness_ratio, foil.*: contact stiffness, time step,
// bonds), simulation.local_damping, dt, dt_safety, skin, and the geometry. Test
// Study.SharedKeysLeaveThePreparedSampleBitwiseUnchanged.
// A function's static, not a global: other files' globals (damper.cpp's key lists) are built
// from it during static initialization, in an order between files that C++ leaves open.
const std::vector<Setting>& table() {
    static const std::vector<Setting> rows = {
        // [grains]
        declared(keys::grain_radius, {.acts = A::Geometry, .geometry = 1, .summary = 1, FIELD(grains.radius)}),
        {.key = "grains.radius_distribution", .type = T::Choice, .unit = "", .def = Setting::kUnset,
         .default_text = "\"single\"", .check = C::Custom,
         .allowed = "must be \"single\", \"uniform\", \"lognormal\" or \"sieve\"", .acts = A::Geometry,
         .geometry = 10,
         .doc = "grain radii: \"single\": every grain grains.radius (the paper); \"uniform\": in grains.radius (1 +- "
                "grains.radius_spread); \"lognormal\": ln r with sd grains.radius_spread, cut at 3 sd, mean "
                "grains.radius; \"sieve\": from the sieve curve grains.sieve_curve (docs/damper.md, \"Grain sizes\")",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             c.grains.radius_distribution = read_word(s, r, RadiusDistribution::Single);
         },
         FIELD(grains.radius_distribution), .legacy = 0.0},  // an older vppdem's grains had one radius
        {.key = "grains.radius_spread", .type = T::Real, .unit = "-", .def = 0.0, .check = C::Range, .lo = 0.0,
         .hi = 1.0, .hi_open = true,
         .allowed = "must be in [0, 1): the half-width of the uniform distribution over grains.radius, or the "
                    "standard deviation of ln r (at most 0.5)",
         .acts = A::Geometry, .geometry = 11,
         .doc = "width of the size distribution: uniform, radii in grains.radius (1 +- spread); lognormal, the sd of ln r",
         FIELD(grains.radius_spread), .legacy = 0.0},
        {.key = "grains.sieve_curve", .type = T::String, .unit = "", .def = Setting::kUnset, .default_text = "none",
         .check = C::Custom,
         .allowed = "must be a CSV file with the columns size (sieve opening [m]) and passing (mass fraction, or %), "
                    "sizes ascending",
         .acts = A::Geometry, .geometry = 12,
         .doc = "a measured sieve curve (CSV: size [m], passing) for grains.radius_distribution = \"sieve\"; a path "
                "relative to the working folder",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             c.grains.sieve_curve = s.string(k, "");
             c.grains.sieve_curve_id = 0.0;
             if (c.grains.sieve_curve.empty()) return;
             try {
                 const scene::SizeDistribution d = scene::SizeDistribution::sieve_curve(c.grains.sieve_curve);
                 // A run from a prepared sample must use the sample's curve.
                 std::vector<double> v = d.sieve_radius;
                 v.insert(v.end(), d.sieve_passing.begin(), d.sieve_passing.end());
                 c.grains.sieve_curve_id = fingerprint(v);
             } catch (const std::runtime_error& e) {
                 s.fail(k, std::string(r.allowed) + " (" + e.what() + ")");
             }
         },
         .get = [](const Config& c) { return c.grains.sieve_curve_id; },
         .set = [](Config&, double) {}, .legacy = 0.0},
        {.key = "grains.shape", .type = T::Choice, .unit = "", .def = Setting::kUnset, .default_text = "\"sphere\"",
         .check = C::Custom,
         .allowed = "must be \"sphere\", \"dimer\", \"trimer\", \"tetrahedron\", \"pellet\" or \"template\"",
         .acts = A::Geometry, .geometry = 13,
         .doc = "grain shape: spheres (the paper) or rigid clumps of overlapping spheres with the volume of the "
                "sphere of the grain's radius, in random orientations (docs/scene.md#clumps: dimer, trimer, "
                "tetrahedron, pellet; \"template\": grains.clump_template)",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             c.grains.shape = read_word(s, r, GrainShape::Sphere);
         },
         FIELD(grains.shape), .legacy = 0.0},  // an older vppdem's grains were spheres
        {.key = "grains.clump_template", .type = T::String, .unit = "", .def = Setting::kUnset, .default_text = "none",
         .check = C::Custom,
         .allowed = "must be a CSV file with columns x, y, z, r [m]: member spheres that all touch one another",
         .acts = A::Geometry, .geometry = 14,
         .doc = "the members of grains.shape = \"template\" in the grain's frame, scaled to the grain's volume; a "
                "path relative to the working folder",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             c.grains.clump_template = s.string(k, "");
             c.grains.clump_template_id = 0.0;
             if (c.grains.clump_template.empty()) return;
             try {
                 const dem::ClumpShape shape = clump_template_shape(c.grains.clump_template);
                 // The members in the principal frame.
                 std::vector<double> v;
                 for (const dem::ClumpMember& m : shape.members)
                     v.insert(v.end(), {m.center.x, m.center.y, m.center.z, m.radius});
                 c.grains.clump_template_id = fingerprint(v);
             } catch (const std::exception& e) {
                 s.fail(k, std::string(r.allowed) + " (" + e.what() + ")");
             }
         },
         .get = [](const Config& c) { return c.grains.clump_template_id; },
         .set = [](Config&, double) {}, .legacy = 0.0},
        declared(keys::density, {.acts = A::Geometry, .geometry = 3, .summary = 2, FIELD(grains.density)}),
        declared(keys::young, {.acts = A::ContactPhysics, .run = 2, .summary = 3, FIELD(grains.young)}),
        declared(keys::friction, {.acts = A::ContactPhysics, .shares_preparation = true, .run = 1, .summary = 4,
                                  FIELD(grains.friction)}),
        declared(keys::stiffness_ratio, {.acts = A::ContactPhysics, .run = 3, .summary = 5, FIELD(grains.stiffness_ratio)}),
        {.key = "grains.volume_fraction", .type = T::Real, .unit = "-", .def = 0.54, .check = C::Range, .lo = 0.0,
         .hi = 0.74, .lo_open = true, .hi_open = true,
         .allowed = "must be in (0, 0.74) (0.74 is the densest sphere packing)", .acts = A::Geometry, .geometry = 2,
         .summary = 6,
         .doc = "phi: the pour's N = round(phi pi r_p^2 H_p / (4/3 pi r_k^3)) grains; with damper.refill more follow "
                "(docs/damper.md)",
         FIELD(grains.volume_fraction)},
        declared(keys::restitution, {.acts = A::ContactPhysics, .shares_preparation = true, .run = 30, .summary = 32,
                                     FIELD(grains.restitution), .legacy = 1.0}),
        // [foil]
        {.key = "foil.young", .type = T::Real, .unit = "Pa", .def = 122.18e6, .check = C::Positive,
         .acts = A::ContactPhysics, .run = 4, .summary = 7, .doc = "E_f of the real foil (bond and foil contact stiffness)",
         FIELD(foil.young)},
        {.key = "foil.thickness", .type = T::Real, .unit = "m", .def = 0.15e-3, .check = C::Positive,
         .acts = A::ContactPhysics, .run = 5, .summary = 8, .doc = "t_f of the real foil (bond stiffness)",
         FIELD(foil.thickness)},
        {.key = "foil.particle_radius", .type = T::Real, .unit = "m", .def = Setting::kUnset,
         .default_text = "grains.radius/3", .check = C::Positive, .acts = A::Geometry, .geometry = 4, .summary = 9,
         .doc = "r_f, radius of the foil particles",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             const double v = s.number(k, c.grains.radius / 3.0);
             // Unset, it is grains.radius / 3: a radius of 5e-324 m leaves 0, which must name grains.radius.
             if (!(v >= std::numeric_limits<double>::min()) && !s.node(k))
                 s.fail(k, "is grains.radius / 3 unless given, here " + cfg::number_text(v) + " m from grains.radius = " +
                               cfg::number_text(c.grains.radius) + " m: must be > 0 and finite (a grain radius of "
                               "real grains)");
             c.foil.particle_radius = s.positive(k, v);
         },
         FIELD(foil.particle_radius)},
        {.key = "foil.density", .type = T::Real, .unit = "kg/m^3", .def = 151.77, .check = C::Range, .lo = 0.0,
         .hi = 1e6, .lo_open = true,
         .allowed = "must be in (0, 1e6] kg/m^3 (44 times osmium's 22,590: room for mass scaling; 1e300 gave a foil "
                    "that never comes to rest)",
         .acts = A::Geometry, .geometry = 5, .summary = 10, .doc = "density of the foil particles", FIELD(foil.density)},
        {.key = "foil.friction", .type = T::Real, .unit = "-", .def = 0.0, .check = C::NonNegative,
         .acts = A::ContactPhysics, .run = 6, .summary = 11, .doc = "friction of foil contacts", FIELD(foil.friction)},
        // The grains' property (scene/shared_keys.h) for the foil's particles and bonds.
        declared(keys::stiffness_ratio, {.acts = A::ContactPhysics, .run = 7, FIELD(foil.stiffness_ratio)},
                 "foil.stiffness_ratio", "ks/kn of bonds and foil contacts"),
        {.key = "foil.bond_arm", .type = T::Choice, .unit = "", .def = Setting::kUnset, .default_text = "\"radius\"",
         .check = C::Custom, .allowed = "must be \"radius\" or \"bond_point\"", .acts = A::ContactPhysics, .run = 32,
         .summary = 35,
         .doc = "where the bonds' shear springs are driven from: \"radius\", the relative velocity at the full radii "
                "as a contact's (Yade's convention, the paper's); \"bond_point\", at the bond point where the torques "
                "act (a rigid rotation loads no spring; the energy ledger closes on bonds longer than 2 r_f; the "
                "device files' default). The lattice's bonds are 2 r_f long and the two differ by the foil's strain "
                "(docs/energy.md, \"Bonds\")",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             const std::optional<dem::BondArm> a = dem::bond_arm_from_name(s.string(k, "radius"));
             if (!a) s.fail(k, r.allowed);
             c.foil.bond_arm = *a;
         },
         FIELD(foil.bond_arm), .legacy = 0.0},  // an older vppdem's bonds used the full radii
        // The mesh foil is the damper's (its run builds, loads and checkpoints it); the tension
        // strip and the envelope are the lattice's own checks.
        {.key = "foil.builder", .type = T::Choice, .unit = "", .def = Setting::kUnset, .default_text = "\"lattice\"",
         .check = C::Custom, .allowed = "must be \"lattice\" or \"mesh\"",
         .acts = A::Geometry, .geometry = 16,
         .doc = "the damper's foil: \"lattice\", the paper's square grid with 25% vacancies (docs/foil.md); \"mesh\", "
                "the membrane builder on the same cylinder (radius and height of the lattice's rings): the lateral "
                "surface remeshed to bonds of 2 r_f, seeded vacancies (simulation.seed, about 24%), MatchFoil "
                "stiffness times 2.05, the end rings held by base and cap (docs/membrane.md, \"A cylinder given as a "
                "mesh\")",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet commands) {
             c.damper.foil_builder = read_word(s, r, FoilBuilder::Lattice);
             if (c.damper.foil_builder == FoilBuilder::Mesh && commands == CommandSet::Foil)
                 s.fail(short_key(r), "must be \"lattice\" for the tension and envelope commands: they check the lattice "
                                      "foil (docs/foil.md); \"mesh\" is the damper's (damper, sweep, calibrate)");
         },
         FIELD(damper.foil_builder), .legacy = 0.0},  // an older vppdem's foil was the lattice
        {.key = "foil.exact_radius", .type = T::Boolean, .unit = "", .def = 0.0, .acts = A::Geometry, .geometry = 17,
         .summary = 36,
         .doc = "false: the foil's sites lie on the circle of chord 2 r_f for the even column count closest to "
                "damper.radius (the paper's rule: 20.77 / 25.80 / 30.21 mm for 20.5 / 25.5 / 30.5 mm); true: on the "
                "circle of damper.radius itself, the same column count, the row bonds as long as the sites' chord and "
                "every bond's stiffness from the bar rule with the two pitches, so the foil keeps E_f t_f per unit "
                "width both ways (docs/foil.md, \"At the exact radius\"); the lattice, the mesh foil and the envelope",
         FLAG(damper.foil_exact_radius), .legacy = 0.0},  // an older vppdem's foil took the chord's circle
        // [damper]; radius and height are also checked against the foil (vpp/settings/config.cpp).
        {.key = "damper.radius", .type = T::Real, .unit = "m", .def = 0.0255, .check = C::Positive,
         .allowed = "must be at least 4 foil particle radii", .acts = A::Geometry, .geometry = 6, .summary = 12,
         .doc = "r_p (the foil takes the even column count closest to it); at least 4 foil particle radii",
         FIELD(damper.radius)},
        {.key = "damper.height", .type = T::Real, .unit = "m", .def = 0.100, .check = C::Positive,
         .allowed = "must be at least 4 foil particle radii", .acts = A::Geometry, .geometry = 7, .summary = 13,
         .doc = "H_p (the foil takes the odd row count closest to it); at least 4 foil particle radii",
         FIELD(damper.height)},
        {.key = "damper.cap_friction", .type = T::Real, .unit = "-", .def = Setting::kUnset,
         .default_text = "grains.friction", .check = C::Custom, .allowed = "must be >= 0", .acts = A::ContactPhysics,
         .shares_preparation = true, .run = 8, .doc = "grain-cap friction",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             c.damper.cap_friction = s.number(k, -1.0);  // < 0: the grains' friction
             if (s.has(k) && !(c.damper.cap_friction >= 0.0)) s.fail(k, r.allowed);
         },
         FIELD(damper.cap_friction)},
        {.key = "damper.refill", .type = T::Boolean, .unit = "", .def = 1.0, .acts = A::Geometry, .geometry = 9,
         .summary = 23,
         .doc = "re-fill after the pour until the grains stand above H_p, so that the cap compresses them to H_p; "
                "false: the pour's N only, the cap may end above the grains (warned)",
         FLAG(damper.refill), .legacy = 0.0},  // samples of an older vppdem were poured once
        {.key = "damper.packing_target", .type = T::Real, .unit = "-", .def = 0.0, .check = C::Range, .lo = 0.0,
         .hi = 0.74, .hi_open = true,
         .allowed = "must be 0 (off: re-fill up to the damper height) or in (0, 0.74) (0.74 is the densest sphere "
                    "packing)",
         .acts = A::Geometry, .geometry = 15, .summary = 34,
         .doc = "0: the re-fills stop when the grains stand at H_p; otherwise they add grains until these fill this "
                "fraction of the foil's interior (pi r_in^2 H_p), the same packing in every geometry; needs "
                "damper.refill (docs/damper.md)",
         FIELD(damper.packing_target), .legacy = 0.0},  // samples of an older vppdem had no target
        // [process]
        {.key = "process.underpressure", .type = T::Real, .unit = "Pa", .def = 0.06e6, .def_foil = 0.01e6,
         .check = C::Range, .lo = 0.0, .hi = kAtmosphericPressure,
         .allowed = "must be a pressure difference in [0, 101325] Pa (0.101325 MPa, a perfect vacuum): atmospheric "
                    "minus the pressure inside the foil",
         .acts = A::Process, .shares_preparation = true, .run = 9, .summary = 14,
         .doc = "dp = atmospheric minus inside pressure (a perfect vacuum at most)",
         // A negative dp would blow the foil up, and NaN or inf would run to the end with NaN forces;
         // an integer is taken too, and a non-number gets the range's message.
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet commands) {
             const std::string k = short_key(r);
             c.process.underpressure = r.default_for(commands);
             if (const toml::node* n = s.node(k)) {
                 const auto v = n->value<double>();
                 if (!v || !(*v >= r.lo && *v <= r.hi)) s.fail(k, r.allowed);
                 c.process.underpressure = *v;
             }
         },
         FIELD(process.underpressure)},
        {.key = "process.ramp_time", .type = T::Real, .unit = "s", .def = 0.02, .check = C::Positive, .acts = A::Process,
         .shares_preparation = true, .run = 10, .doc = "dp rises linearly from 0 over this time", FIELD(process.ramp_time)},
        {.key = "process.hold_time", .type = T::Real, .unit = "s", .def = 0.08, .check = C::NonNegative,
         .acts = A::Process, .shares_preparation = true, .doc = "envelope: time held at full dp after the ramp",
         FIELD(process.hold_time)},
        {.key = "process.amplitude", .type = T::Real, .unit = "m", .def = 0.010, .check = C::Positive, .acts = A::Process,
         .shares_preparation = true, .run = 11, .summary = 15, .doc = "dz, the cap's displacement amplitude",
         FIELD(process.amplitude)},
        {.key = "process.velocity", .type = T::Real, .unit = "m/s", .def = 3.33e-4, .check = C::Positive,
         .acts = A::Process, .shares_preparation = true, .run = 12, .summary = 16, .doc = "v_z, the cap's speed",
         FIELD(process.velocity)},
        {.key = "process.start_offset", .type = T::Real, .unit = "m", .def = 0.0, .acts = A::Process,
         .shares_preparation = true, .run = 13,
         .doc = "the cap (and top ring) first move down by this (up if negative), then cycling starts there",
         FIELD(process.start_offset)},
        {.key = "process.direction", .type = T::Choice, .unit = "", .def = Setting::kUnset,
         .default_text = "\"compression\"", .check = C::Custom, .allowed = "must be \"compression\" or \"extension\"",
         .acts = A::Process, .shares_preparation = true, .run = 14,
         .doc = "\"compression\": down first; \"extension\": up first",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             const std::string dir = s.string(k, "compression");
             if (dir != "compression" && dir != "extension") s.fail(k, r.allowed);
             c.process.compression_first = dir == "compression";
         },
         .get = [](const Config& c) { return c.process.compression_first ? 0.0 : 1.0; },
         .set = [](Config& c, double v) { c.process.compression_first = v == 0.0; }},
        // Bounded: the run counts cycles and samples in int, and a value past 2^31 wrapped round
        // (2147483648 ran 0 cycles, 4294967297 one, samples_per_cycle 4294967300 four rows).
        // A million cycles or samples per cycle is far past any run (4 cycles take hours).
        {.key = "process.cycles", .type = T::Integer, .unit = "", .def = 4, .check = C::Range, .lo = 1, .hi = 1e6,
         .allowed = "must be an integer in 1..1000000", .acts = A::Process, .shares_preparation = true, .run = 15, .summary = 17,
         .doc = "loading cycles (raised when resuming a run.ckpt, the run goes on with the further cycles)", FIELD(process.cycles)},
        {.key = "process.samples_per_cycle", .type = T::Integer, .unit = "", .def = 500, .check = C::Range, .lo = 4,
         .hi = 1e6, .allowed = "must be an integer in 4..1000000 (and a sample at most every time step)", .acts = A::Process, .shares_preparation = true, .run = 16, .summary = 18,
         .doc = "rows of forces.csv per cycle", FIELD(process.samples_per_cycle)},
        {.key = "process.sample_window", .type = T::Real, .unit = "s", .def = 2e-4, .check = C::Positive,
         .acts = A::Process, .shares_preparation = true, .run = 17, .summary = 19,
         .doc = "each force is averaged over this window before its sample time", FIELD(process.sample_window)},
        {.key = "process.pressure_model", .type = T::Choice, .unit = "", .def = Setting::kUnset,
         .default_text = "\"constant\"", .check = C::Custom, .allowed = "must be \"constant\" or \"pump\"",
         .acts = A::Process, .shares_preparation = true, .run = 23, .summary = 25,
         .doc = "\"constant\": dp held at process.underpressure (the paper); \"pump\": the air inside as an "
                "isothermal gas in the foil's pores, drawn by a pump through a regulator set to process.underpressure, "
                "with a leak (docs/damper.md, \"The air inside\")",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             c.process.pressure_model = read_word(s, r, PressureModel::Constant);
         },
         FIELD(process.pressure_model), .legacy = 0.0},  // an older vppdem held dp constant
        {.key = "process.pump_speed", .type = T::Real, .unit = "m^3/s", .def = 2.0 / 3600.0, .check = C::NonNegative,
         .allowed = "must be a volumetric speed >= 0 m^3/s (2 m^3/h = 5.6e-4 m^3/s)", .acts = A::Process,
         .shares_preparation = true, .run = 24, .summary = 26,
         .doc = "pump model: S, the pump's volumetric speed at the inside pressure (2 m^3/h: a small rotary-vane "
                "pump); 0 with process.bleed_rate = 0: sealed as cycling starts",
         FIELD(process.pump_speed), .legacy = 2.0 / 3600.0},
        {.key = "process.bleed_rate", .type = T::Real, .unit = "m^3/s", .def = 2.0 / 3600.0, .check = C::NonNegative,
         .allowed = "must be a conductance >= 0 m^3/s", .acts = A::Process, .shares_preparation = true, .run = 25,
         .summary = 27,
         .doc = "pump model: B, the regulator's bleed valve: below the set pressure it lets air in at B (p_atm - "
                "p_inside), up to the set pressure; 0: a one-way regulator (only leaks raise the pressure)",
         FIELD(process.bleed_rate), .legacy = 2.0 / 3600.0},
        {.key = "process.leak_rate", .type = T::Real, .unit = "m^3/s", .def = 0.0, .check = C::NonNegative,
         .allowed = "must be a conductance >= 0 m^3/s", .acts = A::Process, .shares_preparation = true, .run = 26,
         .summary = 28, .doc = "pump model: C, the leak's conductance: air enters at C (p_atm - p_inside)",
         FIELD(process.leak_rate), .legacy = 0.0},
        {.key = "process.pump_down", .type = T::Boolean, .unit = "", .def = 0.0, .acts = A::Process,
         .shares_preparation = true, .run = 27, .summary = 29,
         .doc = "pump model: the vacuum stage draws the gas down from atmospheric pressure with the pump (time "
                "constant gas volume / process.pump_speed; summary.json start_of_cycling \"pump_down_time\"); false: along "
                "the constant model's ramp, as a sample evacuated long before its test, and the pump acts from the "
                "start of cycling",
         FLAG(process.pump_down), .legacy = 0.0},
        {.key = "process.waveform", .type = T::Choice, .unit = "", .def = Setting::kUnset,
         .default_text = "\"triangle\"", .check = C::Custom, .allowed = "must be \"triangle\" or \"sine\"",
         .acts = A::Process, .shares_preparation = true, .run = 28, .summary = 30,
         .doc = "the stroke's shape: \"triangle\" (constant speed, the paper) or \"sine\" (d = A (1 - cos 2 pi t / T) / "
                "2, peak speed pi A / T), period T from process.frequency or process.velocity",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             c.process.waveform = read_word(s, r, Waveform::Triangle);
         },
         FIELD(process.waveform), .legacy = 0.0},
        {.key = "process.frequency", .type = T::Real, .unit = "Hz", .def = 0.0, .check = C::NonNegative,
         .allowed = "must be a frequency >= 0 Hz (0: the period 2 amplitude / velocity)", .acts = A::Process,
         .shares_preparation = true, .run = 29, .summary = 31,
         .doc = "cycles per second; 0: the period is 2 process.amplitude / process.velocity (the triangle at that speed)",
         FIELD(process.frequency), .legacy = 0.0},
        {.key = "process.local_damping", .type = T::RealOrAuto, .unit = "-", .def = Setting::kUnset,
         .default_text = "\"auto\"", .check = C::Custom,
         .allowed = "must be in [0, 0.9] or \"auto\" (simulation.local_damping; above 0.9 the damping, not the grains, "
                    "dissipates)", .acts = A::Process,
         .shares_preparation = true, .run = 31, .summary = 33,
         .doc = "local damping from the vacuum on; \"auto\": simulation.local_damping throughout. 0 with "
                "grains.restitution: a dynamic run from the usual preparation (docs/damper.md, \"Waveforms and "
                "frequency\")",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
             const std::string k = short_key(r);
             c.process.local_damping = -1.0;  // the default, "auto"
             if (const toml::node* n = s.node(k)) {
                 if (auto str = n->as_string()) {
                     if (str->get() != "auto") s.fail(k, r.allowed);
                 } else if (auto v = n->value<double>(); v && *v >= 0.0 && *v <= 0.9) {
                     c.process.local_damping = *v;
                 } else {
                     s.fail(k, r.allowed);
                 }
             }
         },
         // Recorded as the value in force (a run's summary and checkpoint say what it ran with);
         // a checkpoint without the key ran with simulation.local_damping throughout.
         .get = [](const Config& c) { return cycling_local_damping(c); },
         .set = [](Config& c, double v) { c.process.local_damping = v; }, .legacy = -1.0},
        // [tension]: the tension command's strip.
        {.key = "tension.sites_along", .type = T::Integer, .unit = "", .def = 37, .check = C::AtLeast, .lo = 3,
         .allowed = "must be an integer >= 3", .acts = A::Geometry,
         .doc = "tension: sites in the pulling direction (paper: 37)", FIELD(tension.sites_along)},
        {.key = "tension.sites_across", .type = T::Integer, .unit = "", .def = 12, .check = C::AtLeast, .lo = 1,
         .allowed = "must be an integer >= 1", .acts = A::Geometry, .doc = "tension: sites across (paper: 12)",
         FIELD(tension.sites_across)},
        {.key = "tension.strain", .type = T::Real, .unit = "-", .def = 0.02, .check = C::Range, .lo = 0.0, .hi = 0.5,
         .lo_open = true, .hi_open = true, .allowed = "must be in (0, 0.5)", .acts = A::Process,
         .doc = "tension: final engineering strain", FIELD(tension.strain)},
        {.key = "tension.speed", .type = T::Real, .unit = "m/s", .def = 0.05, .check = C::Positive, .acts = A::Process,
         .doc = "tension: pulling speed (quasi-static: well below the bond wave speed, about 500 m/s)",
         FIELD(tension.speed)},
        // [simulation]
        declared(keys::dt,
                 {.acts = A::Simulation, .run = 19,
                  .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
                      const scene::TimeStep t = scene::read_dt(s, short_key(r), r.def);
                      c.simulation.dt_auto = t.automatic;
                      c.simulation.dt = t.dt;
                  },
                  .get = [](const Config& c) { return c.simulation.dt_auto ? 0.0 : c.simulation.dt; },
                  .set = [](Config& c, double v) {
                      c.simulation.dt_auto = v == 0.0;
                      c.simulation.dt = v;
                  }}),
        // The default 0.3 (the declaration's) is the foil's checks' too; the paper's studies ran at
        // 0.45; which level the data support: docs/paper_comparison.md, "Time step decided by
        // intervals" (its report reads the default from docs/config.md, this table's reference).
        declared(keys::dt_safety, {.acts = A::Simulation, .run = 20, FIELD(simulation.dt_safety)}),
        // Default 0.2: the preparation is frictionless and has no dashpot, only the damping brings
        // its pour to rest (0 is refused for a new sample, vpp/damper/checks.cpp). Above 0.5 is
        // warned there too.
        declared(cfg::with_default(keys::local_damping, 0.2),
                 {.acts = A::Simulation, .run = 18, .summary = 20,
                  .note = "the preparation's, and the run's unless process.local_damping is given; 0 only from a "
                          "prepared sample (the preparation needs it)",
                  FIELD(simulation.local_damping)}),
        // Default 0, the free cores, for the damper's commands (the sweep's cases share them); one
        // thread for the foil's small checks.
        declared(cfg::with_default(keys::threads, 0),
                 {.def_foil = 1, .acts = A::Simulation, .shares_preparation = true, .summary = 21,
                  .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet commands) {
                      c.simulation.threads = cfg::read_threads(s, short_key(r), int64_t(r.default_for(commands)));
                  },
                  FIELD(simulation.threads)}),
        declared(keys::seed, {.acts = A::Geometry, .geometry = 8, .summary = 22,
                              .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet) {
                                  c.simulation.seed = cfg::read_seed(s, short_key(r), int64_t(r.def));
                              },
                              FIELD(simulation.seed)}),
        declared(keys::skin, {.acts = A::Simulation, .run = 21, FIELD(simulation.skin)}),
        // [output]
        {.key = "output.interval", .type = T::Real, .unit = "s", .def = 0.0, .check = C::NonNegative, .acts = A::Output,
         .shares_preparation = true, .doc = "tension, envelope: rows of the time series; 0: the command's default",
         FIELD(output.interval)},
        {.key = "output.vtk_interval", .type = T::Real, .unit = "s", .def = 0.0, .check = C::NonNegative,
         .acts = A::Output, .shares_preparation = true,
         .doc = "VTK frames during cycling (frames at each stage end are always written); 0: the command's default",
         FIELD(output.vtk_interval)},
        {.key = "output.energy", .type = T::Boolean, .unit = "", .def = 1.0, .acts = A::Output,
         .shares_preparation = true, .run = 22,
         .doc = "energy ledger during cycling: energy.csv and the dissipation split in cycles.csv; about 25% slower",
         FLAG(output.energy)},
        {.key = "output.air", .type = T::Boolean, .unit = "", .def = 0.0, .acts = A::Output, .shares_preparation = true,
         .doc = "damper: the air's columns in forces.csv (enclosed_volume, gas_volume, pressure_inside, underpressure, "
                "force_lid, force_machine_zeroed) with the constant model too; the pump model always writes them",
         FLAG(output.air)},
        // [analysis]: post-processing of the recorded loops; never needs a new run.
        {.key = "analysis.settle_tolerance", .type = T::Real, .unit = "-", .def = 0.03, .check = C::Range, .lo = 0.0,
         .hi = 1.0, .lo_open = true, .hi_open = true,
         .allowed = "must be a fraction in (0, 1), e.g. 0.03 for 3% (the relative scatter of W from cycle to cycle "
                    "in a stationary loop)",
         .acts = A::Analysis, .shares_preparation = true, .summary = 24,
         .doc = "relative scatter of one cycle's W in a stationary loop (sd / mean; 2.7% measured on the paper's "
                "damper): W is stationary from the first of the last cycles (at least 3) that show no trend or jump "
                "beyond it at 95%",
         FIELD(analysis.settle_tolerance)},
        {.key = "analysis.event_threshold", .type = T::Real, .unit = "-", .def = 0.0, .check = C::Custom,
         .allowed = "must be 0 (no split) or a number above 1 up to 1e9, e.g. 3 (a record is in a rearrangement event "
                    "where its kinetic energy exceeds this many times the cycle's median)",
         .acts = A::Analysis, .shares_preparation = true,
         .doc = "the dissipation split into rearrangement events and the creep between them, per cycle (cycles.csv: "
                "events, event_fraction, friction_in_events, damping_in_events, viscous_in_events; needs output.energy; "
                "the detector: vpp/analysis/events.h); 0: no split",
         .read = [](cfg::Section& s, const Setting& r, Config& c, CommandSet commands) {
             const std::string k = short_key(r);
             const double v = s.number(k, r.default_for(commands));
             if (!(v == 0.0 || (v > 1.0 && v <= 1e9))) s.fail(k, r.allowed);
             c.analysis.event_threshold = v;
         },
         FIELD(analysis.event_threshold)},
    };
    return rows;
}
#undef FIELD
#undef FLAG

std::vector<Setting> ordered_by(int Setting::*position) {
    std::vector<Setting> out;
    for (const Setting& s : table())
        if (s.*position > 0) out.push_back(s);
    std::sort(out.begin(), out.end(), [&](const Setting& a, const Setting& b) { return a.*position < b.*position; });
    return out;
}

}  // namespace

std::string section_of(const std::string& key) { return key.substr(0, key.find('.')); }

const std::vector<Setting>& settings() { return table(); }

const Setting* find_setting(std::string_view key) {
    for (const Setting& s : table())
        if (key == s.key) return &s;
    return nullptr;
}

std::vector<Setting> geometry_settings() { return ordered_by(&Setting::geometry); }
std::vector<Setting> run_settings() { return ordered_by(&Setting::run); }
std::vector<Setting> summary_inputs() { return ordered_by(&Setting::summary); }
std::vector<Setting> preparation_settings() {
    std::vector<Setting> out;
    for (const Setting& s : table()) {
        const std::string sec = section_of(s.key);
        if (s.geometry == 0 && !s.shares_preparation &&
            (sec == "grains" || sec == "foil" || sec == "damper" || sec == "simulation"))
            out.push_back(s);
    }
    return out;
}

bool may_share_preparation(const std::string& key) {
    if (const Setting* s = find_setting(key)) return s->shares_preparation;
    const std::string section = section_of(key);
    if (section.size() == key.size()) return false;  // not a dotted key
    bool any = false;
    for (const Setting& s : table()) {
        if (section_of(s.key) != section) continue;
        if (!s.shares_preparation) return false;
        any = true;
    }
    return any;
}


const char* acts_name(Acts a) {
    switch (a) {
    case Acts::Geometry: return "geometry";
    case Acts::ContactPhysics: return "contact physics";
    case Acts::Process: return "process";
    case Acts::Output: return "output";
    case Acts::Analysis: return "analysis";
    case Acts::Simulation: return "simulation";
    }
    return "?";
}

// The checks that weigh keys against each other and against the built damper (vpp/damper/checks.cpp,
// check_process, check_steps and check_sampling; vpp/damper/record.cpp), which a single key's range cannot say.
std::string limits_markdown() {
    return "### Limits from the physics\n\n"
           "A value inside its key's range may still ask for something the damper cannot do. These are\n"
           "refused (exit 2, naming the key, its value and the limit) or run with a warning (on stderr, also\n"
           "with `--quiet`, and in summary.json `warnings`):\n\n"
           "- **Stroke** (`process.amplitude`, `process.start_offset`, `process.direction`), against the\n"
           "  sample's height H: a poured packing (about 0.6) reaches the densest packing of spheres (0.74)\n"
           "  at a compression of 1 - 0.6/0.74 = 19% of its height. A cap moving more than 20% of H below\n"
           "  its start is warned (the grains' overlaps, not the packing, carry the stroke); 50% of H or\n"
           "  more is refused (the grains would overlap by about their own size). Upwards the foil is\n"
           "  stretched by the same fraction: warned above 20%, refused from 50% (a torn foil).\n"
           "- **Local damping** (`simulation.local_damping`, `process.local_damping`): Yade's local\n"
           "  damping removes the fraction lambda of each force's power; at lambda = 0.5 an oscillation\n"
           "  already loses most of its amplitude each half period, beyond that more damping only holds\n"
           "  the grains back (0.999999 gave W 125,099 J/m^2 against 388, all of it damping). Allowed:\n"
           "  [0, 0.9]; above 0.5 is warned. The preparation is frictionless and has no dashpot, so\n"
           "  `simulation.local_damping` = 0 is refused for a new sample (it never comes to rest; the step\n"
           "  diverged); from a prepared sample it is a dynamic run, as `process.local_damping` = 0.\n"
           "- **Time step** (`simulation.dt_safety`): the critical step sqrt(m/k) is that of one contact; a\n"
           "  grain with several contacts, and the foil's bonds, need a smaller one: allowed (0, 0.5] (0.7\n"
           "  diverged on the small damper). A fixed `simulation.dt` has the same bound: at most half the\n"
           "  critical step. A run whose positions stop being finite numbers ends with an error naming the\n"
           "  step and these keys. A step that is not a positive finite number (a modulus of 1e300 or\n"
           "  DBL_MAX) is refused naming the key farthest from its default.\n"
           "- **Run length**: more than 1e12 steps from the vacuum on (the cycles, `process.ramp_time` and\n"
           "  `process.hold_time` over the step; 33,000 of the paper's cycles of 3e7 steps) is refused,\n"
           "  naming the period's key (`process.velocity`, `process.frequency`), `process.cycles`, the\n"
           "  ramp or hold, or the step's key, whichever lies farther outside a damper run (1000 s of\n"
           "  simulated time, a step of 1 ns).\n"
           "- **Contacts against the load**: the underpressure dp (without it the column's weight rho g H)\n"
           "  presses a grain over its cross-section (2r)^2 into contacts of stiffness about E r / 2: an\n"
           "  overlap of 8 dp / E radii. `grains.young` below 16 dp (an overlap of half the radius) is\n"
           "  refused (5e-324 Pa gave NaN). The foil under dp stretches by the hoop strain dp R / (E_f t_f):\n"
           "  `foil.young` x `foil.thickness` giving more than 50% is refused (a torn foil).\n"
           "- **Neighbour skin** (`simulation.skin`): at most ten times the largest grain radius (a few\n"
           "  tenths saves list rebuilds; 1e300 m overflowed the cell grid).\n"
           "- **Tangential stiffness** (`grains.stiffness_ratio`, `foil.stiffness_ratio`): ks/kn of elastic\n"
           "  spheres is 2(1 - nu)/(2 - nu), 0.67 to 1 for Poisson ratios 0.5 to 0, and the step is sized on\n"
           "  kn: allowed [0.01, 1] (0 left a contact without tangential stiffness, and the run gave NaN).\n"
           "- **Counts** (`process.cycles`, `process.samples_per_cycle`): at most 1,000,000 (larger values\n"
           "  wrapped round in the run's counters). A sample every time step at most: more samples per cycle\n"
           "  than the cycle has steps is refused, on a new sample and a branch from a prepared one alike (a\n"
           "  resumed run keeps its checked settings). A run that still records\n"
           "  fewer cycles than asked says so in `warnings` and exits 1 (a study's case fails).\n"
           "- **process.sample_window** longer than the samples' spacing (period / samples_per_cycle):\n"
           "  warned, each force is averaged over the spacing only.\n"
           "- **process.velocity** given with `process.frequency` > 0: warned, the frequency sets the\n"
           "  period and the start offset's speed, the velocity is not used.\n"
           "- **Pump model**: a pump-down (`process.pump_down`) whose 5 V / S (gas volume over\n"
           "  `process.pump_speed`) exceeds 60 s of simulated time is refused with the estimate; a cycle\n"
           "  whose dp falls below half `process.underpressure` is warned.\n";
}

std::string settings_reference_markdown() {
    std::string md =
        "## VPP commands\n\n"
        "Every key of the config of the VPP commands (damper, sweep, calibrate, tension, envelope), in a file\n"
        "or as `--set section.key=value`. Unknown keys and values outside the allowed range are refused with a\n"
        "message that names the key, the value and what is allowed; every number must be finite, every\n"
        "integer at most 2^53 in magnitude.\n\n"
        "- **default**: the damper's, the sweep's and calibrate's; tension and envelope differ where noted.\n"
        "- **acts on**: geometry (the prepared sample), contact physics, process (loading), simulation,\n"
        "  output (files only) or analysis (post-processing, never a new run).\n"
        "- **shares a preparation**: cases of a study that differ only in such keys share one prepared\n"
        "  sample (docs/studies.md); they do not act before prepared.ckpt.\n"
        "- **recorded**: geometry: stored with the prepared sample, a run from it must match the keys it gives;\n"
        "  run: a resumed run keeps the value it started with; summary: written to summary.json \"inputs\".\n\n"
        "| key | type | default | unit | allowed | acts on | shares a preparation | recorded | description |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
    for (const Setting& s : table()) {
        std::string def;
        if (s.type == SettingType::Boolean) def = s.def != 0.0 ? "true" : "false";
        else if (std::isnan(s.def)) def = s.default_text;
        else def = cfg::number_text(s.def);
        if (!std::isnan(s.def_foil)) def += " (tension, envelope: " + cfg::number_text(s.def_foil) + ")";
        std::string recorded;
        if (s.geometry) recorded += "geometry";
        if (s.run) recorded += std::string(recorded.empty() ? "" : ", ") + "run";
        if (s.summary) recorded += std::string(recorded.empty() ? "" : ", ") + "summary";
        const std::string doc = *s.note ? std::string(s.doc) + "; " + s.note : std::string(s.doc);
        md += "| `" + std::string(s.key) + "` | " + cfg::type_name(s.type) + " | " + cfg::markdown_cell(def) + " | " +
              cfg::markdown_cell(s.unit) + " | " + cfg::markdown_cell(cfg::allowed_text(s.type, s.limits())) + " | " +
              acts_name(s.acts) + " | " + (s.shares_preparation ? "yes" : "no") + " | " + recorded + " | " +
              cfg::markdown_cell(doc) + " |\n";
    }
    md += "\n" + limits_markdown();
    return md;
}

}  // namespace vpp

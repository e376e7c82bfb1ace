// Contract tests of `vppdem scene` (docs/scene.md): they run the real binary on small TOML
// scenes and read back tracked.csv, walls.csv, summary.json and the VTK frames.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#ifndef VPPDEM_BINARY
#error "VPPDEM_BINARY must name the built vppdem executable"
#endif

#include "../physics/cli_helpers.h"

namespace fs = std::filesystem;

namespace {

using cli_test::json_number;
using cli_test::quote;
using Result = cli_test::RunResult;
using cli_test::run_vppdem;
using cli_test::write_file;
const auto& read_file = cli_test::slurp;

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

// A fresh directory per test, removed at the end.
class TempDir {
public:
    TempDir() {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() /
                ("vppdem_scene_cli_" + std::string(info->name()) + "_" + std::to_string(::getpid()) + "_" +
                 std::to_string(counter++));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    const fs::path& path() const { return path_; }
    fs::path operator/(const std::string& name) const { return path_ / name; }

private:
    fs::path path_;
};

// Runs `vppdem scene FILE --out OUT --quiet EXTRA`.
Result run_scene(const fs::path& file, const fs::path& out, const std::string& extra = "") {
    return run_vppdem("scene " + quote(file) + " --out " + quote(out) + " --quiet " + extra);
}

std::string header_line(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    return line;
}

struct Csv {
    std::string header;
    std::vector<std::vector<double>> rows;
};

Csv read_csv(const fs::path& p) {
    Csv c;
    std::ifstream in(p);
    std::getline(in, c.header);
    for (std::string line; std::getline(in, line);) {
        if (line.empty()) continue;
        std::vector<double> row;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
        c.rows.push_back(row);
    }
    return c;
}

// Rows of walls.csv at the last output time, indexed by the wall column.
std::map<int, std::vector<double>> last_wall_rows(const Csv& walls) {
    std::map<int, std::vector<double>> out;
    if (walls.rows.empty()) return out;
    const double t_end = walls.rows.back()[0];
    for (const auto& r : walls.rows)
        if (r[0] == t_end) out[int(r[1])] = r;
    return out;
}

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        names.insert(fs::relative(e.path(), dir).string());
    return names;
}

double sphere_mass(double density, double r) { return density * 4.0 / 3.0 * kPi * r * r * r; }

const char* kGlass = R"(
[[materials]]
name = "glass"
density = 2800.0
young = 4.8e10
stiffness_ratio = 0.5
friction = 0.35
restitution = 1.0
)";

// A damped material so that spheres settle quickly on walls.
const char* kSoftDamped = R"(
[[materials]]
name = "grain"
density = 2000.0
young = 1.0e9
stiffness_ratio = 0.5
friction = 0.5
restitution = 0.2

[[materials]]
name = "steel"
density = 7800.0
young = 2.0e11
stiffness_ratio = 0.5
friction = 0.5
restitution = 0.2
)";

// A scene file from its blocks (docs/scene.md), so that each test writes only what it varies.
// [simulation]: dt, duration and output interval as written in TOML; `more`: further lines
// (gravity by default).
std::string simulation_block(const std::string& dt, const std::string& duration, const std::string& interval,
                             const std::string& more = "gravity = [0.0, 0.0, -9.81]\n") {
    return "\n[simulation]\ndt = " + dt + "\nduration = " + duration + "\n" + more + "output_interval = " + interval +
           "\n";
}
// A [[spheres]] entry; `more`: further lines (track = true, velocity = [...], ...).
std::string sphere_block(const std::string& material, const std::string& radius, const std::string& position,
                         const std::string& more = "") {
    return "[[spheres]]\nmaterial = \"" + material + "\"\nradius = " + radius + "\nposition = " + position + "\n" + more;
}
// A [[planes]] entry: by default the floor z = 0, normal +z.
std::string plane_block(const std::string& material, const std::string& point = "[0.0, 0.0, 0.0]",
                        const std::string& normal = "[0.0, 0.0, 1.0]") {
    return "[[planes]]\nmaterial = \"" + material + "\"\npoint = " + point + "\nnormal = " + normal + "\n";
}

// One free sphere in space, tracked, with a few steps.
std::string tiny_scene() {
    return simulation_block("1.0e-6", "2.0e-5", "1.0e-5") + kGlass +
           sphere_block("glass", "0.01", "[0.0, 0.0, 1.0]", "track = true\n") + plane_block("glass");
}

}  // namespace

TEST(SceneCli, HeadersAreExact) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    EXPECT_EQ(header_line(d / "out/tracked.csv"), "time,id,x,y,z,vx,vy,vz,wx,wy,wz");
    const std::string wh = header_line(d / "out/walls.csv");
    EXPECT_EQ(wh.rfind("time,wall,fx,fy,fz", 0), 0u) << wh;  // the contract: this prefix
    EXPECT_EQ(wh, "time,wall,fx,fy,fz,tx,ty,tz");             // our implementation
    EXPECT_TRUE(fs::exists(d / "out/summary.json"));
    EXPECT_FALSE(fs::exists(d / "out/vtk"));  // no [output] vtk_interval: no VTK files
    // No leftovers of the atomic writes.
    for (const auto& name : listing(d / "out")) EXPECT_EQ(name.find(".part"), std::string::npos) << name;
}

TEST(SceneCli, TrackedIdsFollowInputOrder) {
    TempDir d;
    std::string s = simulation_block("1e-6", "1e-5", "5e-6", "") + kGlass;
    const char* track[] = {"true", "false", "true"};
    for (int k = 0; k < 3; ++k) {
        const std::string at = std::to_string(k);  // x = the sphere's index
        s += sphere_block("glass", "0.01", "[" + at + ".0, 0.0, 0.0]", std::string("track = ") + track[k] + "\n");
    }
    write_file(d / "s.toml", s);
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    const Csv c = read_csv(d / "out/tracked.csv");
    ASSERT_EQ(c.rows.size(), 3u * 2u);  // t = 0, 5e-6, 1e-5; ids 0 and 2
    for (std::size_t k = 0; k < c.rows.size(); ++k) {
        const double id = k % 2 == 0 ? 0.0 : 2.0;
        EXPECT_EQ(c.rows[k][1], id);
        EXPECT_EQ(c.rows[k][2], id);  // x0 = id: the row really is that sphere
        EXPECT_EQ(c.rows[k].size(), 11u);
    }
}

TEST(SceneCli, RowTimesAreMultiplesOfOutputInterval) {
    TempDir d;
    const double interval = 1e-5;
    write_file(d / "s.toml", simulation_block("1.0e-6", "1.0e-4", "1.0e-5", "") + kGlass +
                                 sphere_block("glass", "0.01", "[0.0, 0.0, 0.5]", "track = true\n") +
                                 sphere_block("glass", "0.01", "[0.5, 0.0, 0.5]", "track = true\n") +
                                 plane_block("glass") + R"(
[[facets]]
material = "glass"
vertices = [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [0.0, 1.0, -1.0]]
)");
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    for (const char* file : {"tracked.csv", "walls.csv"}) {
        SCOPED_TRACE(file);
        const Csv c = read_csv(d / "out" / file);
        ASSERT_EQ(c.rows.size(), 11u * 2u);  // 11 times (0 ... 1e-4) x 2 spheres or 2 walls
        for (std::size_t k = 0; k < c.rows.size(); ++k) {
            const double t = c.rows[k][0];
            const double expected = double(k / 2) * interval;
            EXPECT_NEAR(t, expected, 1e-9 * interval) << "row " << k;
            EXPECT_NEAR(t / interval, std::round(t / interval), 1e-9) << "row " << k;
        }
    }
}

TEST(SceneCli, FreeFallMatchesConstantAcceleration) {
    TempDir d;
    const double z0 = 2.0, vx = 0.5, dt = 1e-5;
    write_file(d / "s.toml", simulation_block("1.0e-5", "0.02", "1.0e-3") + kGlass +
                                 sphere_block("glass", "0.01", "[0.0, 0.0, 2.0]", "velocity = [0.5, 0.0, 0.0]\ntrack = true\n"));
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    const Csv c = read_csv(d / "out/tracked.csv");
    ASSERT_EQ(c.rows.size(), 21u);
    for (const auto& row : c.rows) {
        const double t = row[0];
        const double z_exact = z0 - 0.5 * kG * t * t;
        EXPECT_NEAR(row[4], z_exact, 1e-6 * std::abs(z_exact)) << "t = " << t;
        // Leapfrog is exact for a constant acceleration up to the half-step offset of the
        // initial velocity: |z - z_exact| <= g t dt / 2.
        EXPECT_LE(std::abs(row[4] - z_exact), 0.5 * kG * t * dt * (1 + 1e-6) + 1e-14) << "t = " << t;
        EXPECT_NEAR(row[2], vx * t, 1e-12) << "t = " << t;  // no horizontal force
        EXPECT_EQ(row[3], 0.0);
    }
    EXPECT_NEAR(c.rows.back()[0], 0.02, 1e-12);
}

TEST(SceneCli, RestingSpherePushesPlaneDownWithItsWeight) {
    // walls.csv holds the force the particles exert ON the wall: a sphere resting on a floor
    // with normal +z pushes it along -z with its weight, fz = -m g.
    TempDir d;
    const double r = 0.01, x = 0.1;
    write_file(d / "s.toml", simulation_block("2.0e-6", "4.0e-3", "1.0e-3") + kSoftDamped +
                                 sphere_block("grain", "0.01", "[0.1, 0.0, 0.01]", "track = true\n") + plane_block("steel"));
    const Result res = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(res.rc, 0) << res.output;
    const double m = sphere_mass(2000.0, r), w = m * kG;
    const auto last = last_wall_rows(read_csv(d / "out/walls.csv"));
    ASSERT_EQ(last.size(), 1u);
    const auto& f = last.at(0);
    EXPECT_NEAR(f[4], -w, 1e-6 * w);  // fz: points along -normal
    EXPECT_NEAR(f[2], 0.0, 1e-9 * w);
    EXPECT_NEAR(f[3], 0.0, 1e-9 * w);
    // Torque about the origin of the force at the contact point (x, 0, ~0): (0, x m g, 0).
    EXPECT_NEAR(f[5], 0.0, 1e-9 * w);
    EXPECT_NEAR(f[6], x * w, 1e-6 * x * w);
    EXPECT_NEAR(f[7], 0.0, 1e-9 * w);
    // Contact stiffness: each side a spring E*r (the wall counts as a sphere of the particle's
    // radius), in series: kn = 2 E1 r E2 r / (E1 r + E2 r). Overlap at rest = m g / kn.
    const double e1 = 1.0e9 * r, e2 = 2.0e11 * r, kn = 2.0 * e1 * e2 / (e1 + e2);
    const Csv tr = read_csv(d / "out/tracked.csv");
    const double overlap = r - tr.rows.back()[4];
    EXPECT_NEAR(overlap, w / kn, 1e-4 * w / kn);
    EXPECT_NEAR(tr.rows.back()[7], 0.0, 1e-9);  // at rest
}

TEST(SceneCli, WallsArePlanesThenFacetsThenFacetSetsInInputOrder) {
    // Four spheres of different weights, each resting on its own wall; the facets come first in
    // the file, but walls.csv lists planes first, then facets, then facet sets.
    TempDir d;
    const double radii[4] = {0.010, 0.012, 0.014, 0.016};  // on plane 0, plane 1, facet 0, facet 1
    write_file(d / "s.toml", simulation_block("2.0e-6", "4.0e-3", "1.0e-3") + kSoftDamped + R"(
[[facets]]
material = "steel"
vertices = [[-0.1, -0.1, 0.0], [0.1, -0.1, 0.0], [0.0, 0.1, 0.0]]
[[facets]]
material = "steel"
vertices = [[-0.1, -0.1, 1.0], [0.1, -0.1, 1.0], [0.0, 0.1, 1.0]]
[[facet_sets]]
type = "cylinder"
material = "steel"
base = [5.0, 5.0, -3.0]
radius = 0.1
height = 0.5
segments = 12
)" + plane_block("steel", "[0.0, 0.0, -1.0]") + plane_block("steel", "[0.0, 0.0, -2.0]") +
                                 sphere_block("grain", "0.010", "[0.0, 0.0, -0.990]") +
                                 sphere_block("grain", "0.012", "[0.0, 0.0, -1.988]") +
                                 sphere_block("grain", "0.014", "[0.0, 0.0, 0.014]") +
                                 sphere_block("grain", "0.016", "[0.0, 0.0, 1.016]"));
    const Result res = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(res.rc, 0) << res.output;
    const Csv walls = read_csv(d / "out/walls.csv");
    // Every output time lists walls 0..4 in order.
    ASSERT_EQ(walls.rows.size() % 5, 0u);
    for (std::size_t k = 0; k < walls.rows.size(); ++k) EXPECT_EQ(walls.rows[k][1], double(k % 5));
    const auto last = last_wall_rows(walls);
    ASSERT_EQ(last.size(), 5u);
    for (int k = 0; k < 4; ++k) {
        const double w = sphere_mass(2000.0, radii[k]) * kG;
        EXPECT_NEAR(last.at(k)[4], -w, 1e-6 * w) << "wall " << k;
    }
    for (int c = 2; c < 8; ++c) EXPECT_EQ(last.at(4)[c], 0.0);  // the cylinder: untouched
    const std::string summary = read_file(d / "out/summary.json");
    EXPECT_NE(summary.find(R"("walls": ["planes[0]", "planes[1]", "facets[0]", "facets[1]", "facet_sets[0]"])"),
              std::string::npos)
        << summary;
    EXPECT_EQ(json_number(summary, "facets"), 2.0 + 24.0);  // 12 segments: 24 triangles
}

TEST(SceneCli, SphereFilesWithAndWithoutHeaderAndRelativePaths) {
    TempDir d;
    write_file(d / "scene/data/with_header.csv", "x,y,z,r\n1.0,0.0,0.0,0.01\n2.0,0.0,0.0,0.02\n");
    write_file(d / "scene/data/plain.csv", "# a comment line\n3.0, 0.0, 0.0, 0.03\r\n4.0,0.0,0.0,0.04\n");
    write_file(d / "scene/s.toml", simulation_block("1.0e-6", "2.0e-6", "1.0e-6", "gravity = [0.0, 0.0, 0.0]\n") +
                                       "[output]\nvtk_interval = 1.0e-6\n" + kGlass +
                                       sphere_block("glass", "0.01", "[0.0, 0.0, 0.0]") + R"(
[[sphere_files]]
path = "data/with_header.csv"
material = "glass"
track = true
[[sphere_files]]
path = "data/plain.csv"
material = "glass"
velocity = [0.0, 0.0, 1.0]
track = true
)");
    // Relative paths are resolved against the scene file's folder, not the working directory.
    fs::create_directories(d / "elsewhere");
    const Result r = run_vppdem("scene ../scene/s.toml --out out --quiet", d / "elsewhere");
    ASSERT_EQ(r.rc, 0) << r.output;
    const fs::path out = d / "elsewhere/out";
    EXPECT_EQ(json_number(read_file(out / "summary.json"), "particles"), 5.0);
    const Csv c = read_csv(out / "tracked.csv");
    ASSERT_EQ(c.rows.size(), 3u * 4u);  // 3 times x 4 tracked spheres
    // ids: [[spheres]] first (id 0), then the rows of each [[sphere_files]] entry in order.
    for (std::size_t k = 0; k < c.rows.size(); ++k) {
        const double id = double(1 + k % 4);
        EXPECT_EQ(c.rows[k][1], id) << "row " << k;
        EXPECT_EQ(c.rows[k][2], id) << "row " << k;  // x from the file
        EXPECT_EQ(c.rows[k][7], id >= 3 ? 1.0 : 0.0) << "row " << k;  // velocity of the entry
    }
    EXPECT_NEAR(c.rows.back()[4], 2e-6, 1e-15);  // id 4 moved with the entry's velocity
    // The r column is the radius: the VTK radius field lists 0.01 (the [[spheres]]) then the files.
    const std::string vtk = read_file(out / "vtk/particles_000000.vtk");
    const std::string field = "SCALARS radius double 1\nLOOKUP_TABLE default\n";
    const auto k = vtk.find(field);
    ASSERT_NE(k, std::string::npos) << vtk;
    std::istringstream radii(vtk.substr(k + field.size()));
    for (double expected : {0.01, 0.01, 0.02, 0.03, 0.04}) {
        double v = 0;
        radii >> v;
        EXPECT_EQ(v, expected);
    }
}

TEST(SceneCli, DtAutoIsReportedInSummary) {
    TempDir d;
    write_file(d / "s.toml", simulation_block("\"auto\"", "1.0e-4", "1.0e-12", "dt_safety = 0.25\n") + kGlass +
                                 sphere_block("glass", "0.01", "[0.0, 0.0, 0.0]", "track = true\n"));
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    const std::string s = read_file(d / "out/summary.json");
    EXPECT_NE(s.find("\"dt_auto\": true"), std::string::npos) << s;
    const double dt = json_number(s, "dt"), crit = json_number(s, "critical_dt");
    ASSERT_GT(dt, 0.0) << s;
    EXPECT_NEAR(dt, 0.25 * crit, 1e-8 * dt);
    // Glass sphere, r = 1 cm, no walls: critical step sqrt(m / (E r)).
    const double m = sphere_mass(2800.0, 0.01);
    EXPECT_NEAR(crit, std::sqrt(m / (4.8e10 * 0.01)), 1e-8 * crit);
    // An interval below dt writes every step: the rows are dt apart.
    const Csv c = read_csv(d / "out/tracked.csv");
    ASSERT_GE(c.rows.size(), 3u);
    EXPECT_EQ(double(c.rows.size() - 1), json_number(s, "steps"));
    EXPECT_NEAR(c.rows[2][0] - c.rows[1][0], dt, 1e-8 * dt);

    // The bare word auto also works from --set.
    const Result r2 = run_scene(d / "s.toml", d / "out2", "--set simulation.dt=1e-6 --set simulation.dt=auto");
    ASSERT_EQ(r2.rc, 0) << r2.output;
    EXPECT_NE(read_file(d / "out2/summary.json").find("\"dt_auto\": true"), std::string::npos);
}

TEST(SceneCli, ErrorsNameTheKeyAndWriteNothing) {
    const std::string sphere = sphere_block("glass", "0.01", "[0.0, 0.0, 0.0]");
    const std::string ok = std::string(kGlass) + sphere;
    struct Case {
        const char* name;
        std::string toml;
        std::string args;      // extra command-line arguments
        std::string expected;  // substring of the message
    };
    const std::vector<Case> cases = {
        {"malformed TOML", "[simulation\ndt = 1e-6\n" + ok, "", "line 1"},
        {"malformed value", "[simulation]\ndt = 1e-6 1e-7\n" + ok, "", "line 2"},
        {"unknown top-level key", "colour = 1\n" + ok, "", "'colour'"},
        {"unknown key in [simulation]", "[simulation]\ndtt = 1e-6\n" + ok, "", "simulation.dtt"},
        {"unknown key in [[spheres]]", ok + "colour = \"red\"\n", "", "spheres[0].colour"},
        {"unknown key in [[materials]]", "[[materials]]\nname = \"glass\"\npoisson = 0.3\n" + sphere, "",
         "materials[0].poisson"},
        {"unknown key in [output]", "[output]\nvtk = 1e-3\n" + ok, "", "output.vtk"},
        {"unknown material", kGlass + sphere_block("steel", "0.01", "[0.0, 0.0, 0.0]"), "", "spheres[0].material"},
        {"negative radius", kGlass + sphere_block("glass", "-0.01", "[0.0, 0.0, 0.0]"), "", "spheres[0].radius"},
        {"dt = 0", "[simulation]\ndt = 0.0\n" + ok, "", "simulation.dt"},
        {"dt = -1", "[simulation]\ndt = -1\n" + ok, "", "simulation.dt"},
        {"dt = fast", "[simulation]\ndt = \"fast\"\n" + ok, "", "simulation.dt"},
        {"dt = inf", "[simulation]\ndt = inf\n" + ok, "", "simulation.dt"},
        {"duration = inf", "[simulation]\nduration = inf\n" + ok, "", "simulation.duration"},
        {"output_interval = 0", "[simulation]\noutput_interval = 0.0\n" + ok, "", "simulation.output_interval"},
        {"gravity of 2 numbers", "[simulation]\ngravity = [0.0, -9.81]\n" + ok, "", "simulation.gravity"},
        {"threads = 1025", "[simulation]\nthreads = 1025\n" + ok, "", "simulation.threads"},
        {"dt_safety = 0.6", "[simulation]\ndt_safety = 0.6\n" + ok, "",
         "config key 'simulation.dt_safety' = 0.6: must be in (0, 0.5]"},
        {"missing position", std::string(kGlass) + "[[spheres]]\nmaterial = \"glass\"\nradius = 0.01\n", "",
         "spheres[0].position"},
        {"missing radius", std::string(kGlass) + "[[spheres]]\nmaterial = \"glass\"\nposition = [0.0, 0.0, 0.0]\n",
         "", "spheres[0].radius"},
        {"missing material name", "[[materials]]\ndensity = 1000.0\n" + sphere, "", "materials[0].name"},
        {"missing plane normal", ok + "[[planes]]\nmaterial = \"glass\"\npoint = [0.0, 0.0, 0.0]\n", "",
         "planes[0].normal"},
        {"zero mask", ok + "mask = 0\n", "", "spheres[0].mask"},
        {"restitution 0", "[[materials]]\nname = \"glass\"\nrestitution = 0.0\n" + sphere, "",
         "materials[0].restitution"},
        {"facet of zero area", ok + "[[facets]]\nmaterial = \"glass\"\nvertices = [[0,0,0],[1,0,0],[2,0,0]]\n", "",
         "facets[0].vertices"},
        {"unknown facet set type", ok + "[[facet_sets]]\ntype = \"cone\"\nmaterial = \"glass\"\n", "",
         "facet_sets[0].type"},
        {"missing sphere file", ok + "[[sphere_files]]\npath = \"nope.csv\"\nmaterial = \"glass\"\n", "",
         "sphere_files[0].path"},
        {"no spheres", std::string(kGlass), "", "no spheres"},
        {"dt auto with only fixed spheres", "[simulation]\ndt = \"auto\"\n" + ok + "fixed = true\n", "",
         "simulation.dt"},
        // Bad --set overrides.
        {"--set without =", ok, "--set simulation.dt", "--set"},
        {"--set index out of range", ok, "--set spheres.3.radius=0.02", "spheres.3.radius"},
        {"--set non-index into array", ok, "--set spheres.first.radius=0.02", "spheres.first.radius"},
        {"--set unknown key", ok, "--set simulation.dtt=1e-6", "simulation.dtt"},
        {"--set bad value", ok, "--set simulation.dt=fast", "simulation.dt"},
        {"--set negative radius", ok, "--set spheres.0.radius=-1", "spheres[0].radius"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        TempDir d;
        write_file(d / "s.toml", c.toml);
        const Result r = run_scene(d / "s.toml", d / "out", c.args);
        EXPECT_NE(r.rc, 0) << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << "message: " << r.output;
        EXPECT_NE(r.output.find("error"), std::string::npos) << "message: " << r.output;
        // One message, no traceback: a single line.
        EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(d / "out")) << "an output directory was created";
        EXPECT_EQ(listing(d.path()), std::set<std::string>{"s.toml"});
    }
}

TEST(SceneCli, OverlapsAndNonFiniteNumbersAreRefusedBeforeAnythingIsWritten) {
    // Spheres that start inside each other or a wall are thrown out at thousands of m/s; NaN or
    // inf in a number runs on NaN or fails deep inside. All are refused up front, naming the
    // bodies (or the key) and the overlap, exit status 2, one line, nothing written.
    auto sphere = [](double x, double y, double z, double r = 0.01) {
        std::ostringstream radius, at;
        radius << r;
        at << "[" << x << ", " << y << ", " << z << "]";
        return sphere_block("glass", radius.str(), at.str());
    };
    const std::string floor = plane_block("glass");
    const std::string cylinder = "[[facet_sets]]\ntype = \"cylinder\"\nmaterial = \"glass\"\nradius = 0.05\n"
                                 "height = 0.2\nsegments = 12\n";
    const std::string files = "[[sphere_files]]\npath = \"g.csv\"\nmaterial = \"glass\"\n";
    struct Case {
        const char* name;
        std::string toml, csv, expected, also;
    };
    const std::vector<Case> cases = {
        {"overlapping pair", sphere(0, 0, 1) + sphere(0.01, 0, 1), "", "spheres[0] and spheres[1] overlap by 0.01 m",
         "100% of the smaller radius"},
        {"identical centres", sphere(0, 0, 1) + sphere(0, 0, 1, 0.005), "", "spheres[0] and spheres[1]", "300%"},
        {"sphere in the floor", sphere(0, 0, 0.004) + floor, "", "spheres[0] and planes[0] overlap by 0.006 m",
         "max_initial_overlap"},
        {"sphere in a facet set", sphere(0.045, 0, 0.1) + cylinder, "", "spheres[0] and facet_sets[0] triangle",
         "overlap by"},
        {"sphere file row on a sphere", sphere(0, 0, 1) + files, "0.5,0,1,0.01\n0.005,0,1,0.01\n",
         "spheres[0] and sphere_files[0] row 2 of", "g.csv"},
        {"nan in a sphere file", sphere(0, 0, 1) + files, "x,y,z,r\n0.5,nan,1,0.01\n", "sphere_files[0].path",
         "finite"},
        {"nan velocity", sphere(0, 0, 1) + "velocity = [nan, 0.0, 0.0]\n", "", "spheres[0].velocity", "finite"},
        {"inf position", sphere(0, 0, 1) + sphere_block("glass", "0.01", "[inf, 0.0, 1.0]"), "", "spheres[1].position",
         "finite"},
        {"nan gravity", "[simulation]\ngravity = [0.0, 0.0, nan]\n" + sphere(0, 0, 1), "", "simulation.gravity", "finite"},
        {"nan in a displacement history", sphere(0, 0, 1) + "displacement = [[0.0, 0.0, 0.0, 0.0], [1.0, nan, 0.0, 0.0]]\n",
         "", "spheres[0].displacement", "finite"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        TempDir d;
        write_file(d / "s.toml", std::string(kGlass) + c.toml);
        if (!c.csv.empty()) write_file(d / "g.csv", c.csv);
        const Result r = run_scene(d / "s.toml", d / "out");
        EXPECT_EQ(r.rc, 2) << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(c.also), std::string::npos) << r.output;
        EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(d / "out"));
    }
    // An overlap on purpose: allowed by raising the tolerance.
    TempDir d;
    write_file(d / "s.toml", std::string(kGlass) + "[simulation]\ngravity = [0.0, 0.0, 0.0]\nduration = 1e-6\n" +
                                 sphere(0, 0, 1) + sphere(0.019, 0, 1));
    EXPECT_NE(run_scene(d / "s.toml", d / "out").rc, 0);
    const Result ok = run_scene(d / "s.toml", d / "out", "--set simulation.max_initial_overlap=0.2");
    EXPECT_EQ(ok.rc, 0) << ok.output;
}

TEST(SceneCli, MissingSceneFileFails) {
    TempDir d;
    const Result r = run_scene(d / "nope.toml", d / "out");
    EXPECT_NE(r.rc, 0);
    EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(SceneCli, ExistingNonEmptyOutDirIsRefusedAndUntouched) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    write_file(d / "out/tracked.csv", "old results\n");
    write_file(d / "out/notes.txt", "keep me\n");
    const auto before = listing(d / "out");
    const auto mtime = fs::last_write_time(d / "out/tracked.csv");
    const Result r = run_scene(d / "s.toml", d / "out");
    EXPECT_NE(r.rc, 0);
    EXPECT_NE(r.output.find("--overwrite"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
    EXPECT_EQ(listing(d / "out"), before);
    EXPECT_EQ(read_file(d / "out/tracked.csv"), "old results\n");
    EXPECT_EQ(read_file(d / "out/notes.txt"), "keep me\n");
    EXPECT_EQ(fs::last_write_time(d / "out/tracked.csv"), mtime);

    // --out naming an existing file is refused too, and the file is kept.
    write_file(d / "file", "x");
    const Result r2 = run_scene(d / "s.toml", d / "file");
    EXPECT_NE(r2.rc, 0);
    EXPECT_EQ(read_file(d / "file"), "x");

    // An existing empty directory is fine.
    fs::create_directories(d / "empty");
    const Result r3 = run_scene(d / "s.toml", d / "empty");
    EXPECT_EQ(r3.rc, 0) << r3.output;
    EXPECT_TRUE(fs::exists(d / "empty/tracked.csv"));
}

TEST(SceneCli, OverwriteReplacesOutputs) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    // A first run with VTK frames, then a rerun without: no stale frames may remain.
    const Result r1 = run_scene(d / "s.toml", d / "out", "--set output.vtk_interval=1e-5");
    ASSERT_EQ(r1.rc, 0) << r1.output;
    ASSERT_TRUE(fs::exists(d / "out/vtk/particles_000002.vtk"));
    write_file(d / "out/tracked.csv", "old results\n");
    write_file(d / "out/notes.txt", "keep me\n");
    const Result r2 = run_scene(d / "s.toml", d / "out", "--overwrite");
    ASSERT_EQ(r2.rc, 0) << r2.output;
    EXPECT_EQ(header_line(d / "out/tracked.csv"), "time,id,x,y,z,vx,vy,vz,wx,wy,wz");
    EXPECT_EQ(read_csv(d / "out/tracked.csv").rows.size(), 3u);
    EXPECT_EQ(read_file(d / "out/notes.txt"), "keep me\n");  // files vppdem does not write stay
    EXPECT_FALSE(fs::exists(d / "out/vtk/particles_000000.vtk"));
    EXPECT_FALSE(fs::exists(d / "out/vtk/walls_000002.vtk"));
}

TEST(SceneCli, SetOverridesKeys) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    const Result r = run_scene(d / "s.toml", d / "out",
                               "--set simulation.dt=2e-7 --set spheres.0.radius=0.02 "
                               "--set 'simulation.gravity=[0.0, 0.0, 0.0]' --set output.vtk_interval=1e-5");
    ASSERT_EQ(r.rc, 0) << r.output;
    const std::string s = read_file(d / "out/summary.json");
    EXPECT_DOUBLE_EQ(json_number(s, "dt"), 2e-7) << s;
    EXPECT_EQ(json_number(s, "steps"), 100.0) << s;
    // No gravity: the sphere stays put.
    for (const auto& row : read_csv(d / "out/tracked.csv").rows) EXPECT_EQ(row[4], 1.0);
    // [output] did not exist: --set created it; frames at t = 0, 1e-5, 2e-5.
    for (int k = 0; k < 3; ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "vtk/particles_%06d.vtk", k);
        EXPECT_TRUE(fs::exists(d / "out" / name)) << name;
        std::snprintf(name, sizeof name, "vtk/walls_%06d.vtk", k);
        EXPECT_TRUE(fs::exists(d / "out" / name)) << name;
    }
    EXPECT_FALSE(fs::exists(d / "out/vtk/particles_000003.vtk"));
    // The radius override reached the particle: the VTK radius field.
    const std::string vtk = read_file(d / "out/vtk/particles_000000.vtk");
    const std::string field = "SCALARS radius double 1\nLOOKUP_TABLE default\n";
    const auto k = vtk.find(field);
    ASSERT_NE(k, std::string::npos) << vtk;
    EXPECT_EQ(std::strtod(vtk.c_str() + k + field.size(), nullptr), 0.02);
}

TEST(SceneCli, VtkFilesHaveTheLegacyHeader) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene() + "[output]\nvtk_interval = 1.0e-5\n");
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    int n = 0;
    for (const auto& e : fs::directory_iterator(d / "out/vtk")) {
        ++n;
        EXPECT_EQ(e.path().extension(), ".vtk");
        EXPECT_EQ(header_line(e.path()).rfind("# vtk DataFile Version", 0), 0u) << e.path();
    }
    EXPECT_EQ(n, 6);  // particles_ and walls_ at t = 0, 1e-5, 2e-5
}

TEST(SceneCli, PrescribedSpheresFollowTheirMotionAndPushOthers) {
    // A prescribed sphere keeps its velocity under gravity and while it pushes a free sphere
    // ahead of it; a sphere with a displacement history follows it exactly.
    TempDir d;
    write_file(d / "s.toml",
               simulation_block("1.0e-6", "0.02", "1.0e-3") + kGlass +
                   sphere_block("glass", "0.01", "[0.0, 0.0, 0.0]",
                                "velocity = [1.0, 0.0, 0.0]\nprescribed = true\ntrack = true\n") +
                   sphere_block("glass", "0.01", "[0.0205, 0.0, 0.0]", "track = true\n") +
                   sphere_block("glass", "0.01", "[0.0, 0.5, 0.0]",
                                "displacement = [[0.0, 0.0, 0.0, 0.0], [0.01, 0.0, 0.0, 0.002], [0.02, 0.0, 0.0, 0.0]]\n"
                                "track = true\n"));
    const Result r = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(r.rc, 0) << r.output;
    const Csv c = read_csv(d / "out/tracked.csv");
    double pushed_x_end = 0;
    for (const auto& row : c.rows) {
        const double t = row[0];
        if (row[1] == 0) {  // prescribed: x = v t, no fall
            EXPECT_NEAR(row[2], 1.0 * t, 1e-9) << "t = " << t;
            EXPECT_EQ(row[4], 0.0);
            EXPECT_NEAR(row[5], 1.0, 1e-12);
        } else if (row[1] == 1) {
            pushed_x_end = row[2];
        } else {  // displacement history: up 2 mm at t = 0.01 s, back at 0.02 s
            const double dz = t <= 0.01 ? 0.2 * t : 0.2 * (0.02 - t);
            EXPECT_NEAR(row[4], dz, 1e-9) << "t = " << t;
        }
    }
    // The free sphere was pushed ahead (it started 0.5 mm away and the pusher moved 20 mm).
    EXPECT_GT(pushed_x_end, 0.0205 + 0.015);
}

// [[clumps]] (docs/scene.md#clumps): a built-in dimer lying on the floor and a template clump
// of three spheres (scaled to a volume-equivalent radius) standing on it; at rest the floor
// carries both weights, each mass the density times the shape's volume (4/3 pi r^3 for both,
// by the scaling). Members of one clump overlap by design and are not refused as an initial
// overlap; a template with a wrong row, a built-in without radius and an unknown shape are
// refused naming the key.
TEST(SceneCli, ClumpsRestOnAPlaneWithTheirWeight) {
    TempDir d;
    write_file(d / "pellet.csv", "x,y,z,r\n0,0,0,0.004\n0.004,0,0,0.004\n0,0.004,0,0.004\n");
    const std::string head = simulation_block("2.0e-6", "0.3", "0.05", "gravity = [0.0, 0.0, -9.81]\nlocal_damping = 0.4\n") +
                             kSoftDamped + plane_block("steel");
    write_file(d / "s.toml", head + R"(
[[clumps]]
material = "grain"
shape = "dimer"
radius = 0.005
position = [0.0, 0.0, 0.0045]
[[clumps]]
material = "grain"
shape = "template"
template = "pellet.csv"
radius = 0.005
position = [0.05, 0.0, 0.006]
orientation = [0.0, 0.0, 0.5]
)");
    const Result res = run_scene(d / "s.toml", d / "out");
    ASSERT_EQ(res.rc, 0) << res.output;
    const double w = 2.0 * 2000.0 * 4.0 / 3.0 * kPi * 0.005 * 0.005 * 0.005 * kG;
    const auto last = last_wall_rows(read_csv(d / "out/walls.csv"));
    ASSERT_EQ(last.size(), 1u);
    EXPECT_NEAR(last.at(0)[4], -w, 1e-5 * w);

    const auto refused = [&](const std::string& entry, const std::string& expect) {
        write_file(d / "bad.toml", head + entry);
        const Result r = run_scene(d / "bad.toml", d / "bad_out");
        EXPECT_NE(r.rc, 0) << entry;
        EXPECT_NE(r.output.find(expect), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(d / "bad_out/summary.json"));
    };
    refused("[[clumps]]\nmaterial = \"grain\"\nshape = \"cube\"\nradius = 0.005\nposition = [0, 0, 0.01]\n",
            "clumps[0].shape");
    refused("[[clumps]]\nmaterial = \"grain\"\nshape = \"dimer\"\nposition = [0, 0, 0.01]\n", "clumps[0].radius");
    write_file(d / "apart.csv", "x,y,z,r\n0,0,0,0.004\n0.1,0,0,0.004\n");
    refused("[[clumps]]\nmaterial = \"grain\"\nshape = \"template\"\ntemplate = \"apart.csv\"\nposition = [0, 0, 0.01]\n",
            "do not all touch");
}

// Issue 48, a full disk: CsvWriter ignored fflush and fclose, so a cut-short tracked.csv was
// renamed into place (and a throw from a destructor aborted the run, exit 134). tracked.csv's
// temporary file is a link to /dev/full, where every write fails with ENOSPC: the run ends with
// exit 2 and a message naming the file, and nothing lies under the final name.
TEST(SceneCli, AFullDiskIsAClearErrorAndLeavesNoFileUnderItsFinalName) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    fs::create_directories(d / "out");
    fs::create_symlink("/dev/full", d / "out/tracked.csv.part");
    const Result r = run_scene(d / "s.toml", d / "out", "--overwrite");
    EXPECT_EQ(r.rc, 2) << r.output;
    EXPECT_NE(r.output.find("tracked.csv"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(fs::symlink_status(d / "out/tracked.csv"))) << "a file under the final name";
}

// Issue 48: a .vppdem.lock that is a symbolic link was followed, and the file it points to
// truncated and overwritten. Refused with exit 2, the target kept.
TEST(SceneCli, ALockFileThatIsALinkIsRefusedAndItsTargetKept) {
    TempDir d;
    write_file(d / "s.toml", tiny_scene());
    write_file(d / "precious.txt", "the user's data\n");
    fs::create_directories(d / "out");
    fs::create_symlink(d / "precious.txt", d / "out/.vppdem.lock");
    const Result r = run_scene(d / "s.toml", d / "out", "--overwrite");
    EXPECT_EQ(r.rc, 2) << r.output;
    EXPECT_NE(r.output.find("is a symbolic link"), std::string::npos) << r.output;
    EXPECT_EQ(read_file(d / "precious.txt"), "the user's data\n");
}

// Issue 48: every refusal of the command line exits 2 (CLI11's own codes were 105 a failed
// check, 106 a missing option, 109 an excluded one), "nan" is no positive number
// (--checkpoint-every nan rewrote the checkpoint 189,028 times in 5 minutes), a bound is written
// as a number (CLI11 printed DBL_MAX with 309 digits), and --seeds 0 is refused, not ignored.
TEST(SceneCli, CommandLineRefusalsExitTwoAndSayTheBoundShortly) {
    TempDir d;
    write_file(d / "study.toml", "[grid]\n\"grains.friction\" = [0.3]\n");
    const std::string study = quote((d / "study.toml").string());
    struct Case {
        std::string args, must_mention;
    };
    const std::vector<Case> cases = {
        {"damper --out " + quote((d / "o1").string()) + " --checkpoint-every nan", "must be a finite number > 0"},
        {"damper --out " + quote((d / "o2").string()) + " --checkpoint-every -1e308", "must be a finite number > 0"},
        {"damper --out " + quote((d / "o3").string()) + " --checkpoint-every inf", "--checkpoint-every"},
        {"damper", "--out"},                                                     // 106 before
        {"sweep " + study + " --out " + quote((d / "o4").string()) + " --seeds 0", "--seeds"},
        {"sweep " + study + " --out " + quote((d / "o5").string()) + " --list --report-only", "excludes"},  // 109
        {"sweep " + study + " --out " + quote((d / "o6").string()) + " --jobs -2", "must be a finite number >= 0"},
        {"nosuchcommand", "unknown command"},
    };
    for (const Case& c : cases) {
        const Result r = run_vppdem(c.args);
        EXPECT_EQ(r.rc, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.must_mention), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(r.output.find("17976931348623157"), std::string::npos) << c.args << "\n" << r.output;
    }
    EXPECT_FALSE(fs::exists(d / "o1"));
    EXPECT_EQ(run_vppdem("--help").rc, 0);
}

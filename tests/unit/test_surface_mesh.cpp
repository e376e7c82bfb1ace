// The surface-mesh reader, the closed-surface checks, the enclosed volume and the remesher
// (dem/mesh): every defect refused with the file and the defect named; volumes of meshed
// spheres and boxes against their closed forms.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "dem/mesh/mesh_checks.h"
#include "dem/mesh/mesh_read.h"
#include "dem/mesh/mesh_shapes.h"
#include "dem/mesh/remesh.h"

namespace {

using dem::SurfaceMesh;
using dem::Vec3;

std::string temp_path(const std::string& name) {
    const auto dir = std::filesystem::path(::testing::TempDir()) / "vppdem_mesh_tests";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

// Writes a binary STL of the mesh's triangles (floats, as real files are).
void write_binary_stl(const std::string& path, const SurfaceMesh& m) {
    std::ofstream out(path, std::ios::binary);
    char header[80] = {};
    out.write(header, 80);
    const uint32_t n = uint32_t(m.triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);  // the test hosts are little-endian
    for (const auto& t : m.triangles) {
        float rec[12] = {};
        for (int k = 0; k < 3; ++k) {
            const Vec3& v = m.vertices[t[k]];
            rec[3 + 3 * k] = float(v.x), rec[4 + 3 * k] = float(v.y), rec[5 + 3 * k] = float(v.z);
        }
        out.write(reinterpret_cast<const char*>(rec), 48);
        const char attr[2] = {};
        out.write(attr, 2);
    }
}

// The message of the std::runtime_error that f throws ("" when none).
template <class F> std::string error_of(F&& f) {
    try {
        f();
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

SurfaceMesh tetra() {
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

}  // namespace

TEST(SurfaceMesh, ShapesAreClosedAndOutward) {
    for (const SurfaceMesh& m : {tetra(), dem::make_icosphere(1.0, 3), dem::make_box_mesh({0, 0, 0}, {1, 2, 3}, 4),
                                 dem::make_cylinder_mesh(0.5, 1.0, 24, 3), dem::make_torus(1.0, 0.3, 24, 12)})
        EXPECT_EQ(dem::find_mesh_defect(m), "");
    EXPECT_NEAR(dem::enclosed_volume(tetra()), 1.0 / 6.0, 1e-15);
}

TEST(SurfaceMesh, SphereVolumeConvergesToClosedForm) {
    // Inscribed polyhedra: the volume error falls as h^2, a quarter per doubling of s.
    const double R = 0.02, exact = 4.0 / 3.0 * std::numbers::pi * R * R * R;
    double prev = 1.0;
    for (int s : {2, 4, 8, 16, 32}) {
        const SurfaceMesh m = dem::make_icosphere(R, s);
        const double err = std::abs(dem::enclosed_volume(m) / exact - 1.0);
        const double area_err = std::abs(dem::surface_area(m) / (4 * std::numbers::pi * R * R) - 1.0);
        std::printf("icosphere s=%d: %zu triangles, volume error %.3e, area error %.3e\n", s, m.triangles.size(), err,
                    area_err);
        EXPECT_LT(err, 0.35 * prev);  // about a quarter per halving of h
        prev = err;
    }
    EXPECT_LT(prev, 1e-3);
}

TEST(SurfaceMesh, BoxVolumeIsExact) {
    for (int n : {1, 3, 10}) {
        const SurfaceMesh m = dem::make_box_mesh({-0.01, 0.02, 0.0}, {0.03, 0.05, 0.1}, n);
        const double exact = 0.04 * 0.03 * 0.1;
        EXPECT_NEAR(dem::enclosed_volume(m) / exact, 1.0, 1e-12) << n;
        EXPECT_NEAR(dem::surface_area(m), 2 * (0.04 * 0.03 + 0.04 * 0.1 + 0.03 * 0.1), 1e-15) << n;
    }
}

TEST(SurfaceMesh, ReadsBinaryAsciiStlAndObjAlike) {
    const SurfaceMesh src = dem::make_icosphere(10.0, 3);  // a file in mm
    const std::string bin = temp_path("sphere_bin.stl"), asc = temp_path("sphere_ascii.stl"),
                      obj = temp_path("sphere.obj");
    write_binary_stl(bin, src);
    dem::write_surface_mesh(asc, src);
    dem::write_surface_mesh(obj, src);
    dem::MeshReadOptions o;
    o.scale = 1e-3;
    for (const std::string& p : {bin, asc, obj}) {
        const SurfaceMesh m = dem::read_closed_surface(p, o);
        EXPECT_EQ(m.vertices.size(), src.vertices.size()) << p;  // welded back to shared vertices
        EXPECT_EQ(m.triangles.size(), src.triangles.size()) << p;
        EXPECT_NEAR(dem::enclosed_volume(m) / (dem::enclosed_volume(src) * 1e-9), 1.0, 1e-6) << p;
    }
}

TEST(SurfaceMesh, ObjPolygonsAreFanTriangulated) {
    const std::string p = temp_path("cube_quads.obj");
    std::ofstream(p) << "# unit cube of quads\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4/1 1/2 5/3 8/4\n";
    const SurfaceMesh m = dem::read_closed_surface(p);
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_NEAR(dem::enclosed_volume(m), 1.0, 1e-15);
}

TEST(SurfaceMesh, BadMeshesAreRefusedWithFileAndDefectNamed) {
    const SurfaceMesh good = dem::make_icosphere(1.0, 2);
    struct Case {
        std::string name, defect;
        SurfaceMesh mesh;
    };
    std::vector<Case> cases;
    {  // open: one triangle removed
        SurfaceMesh m = good;
        m.triangles.pop_back();
        cases.push_back({"open.stl", "open", m});
    }
    {  // inverted: every triangle wound the other way
        SurfaceMesh m = good;
        for (auto& t : m.triangles) std::swap(t[1], t[2]);
        cases.push_back({"inverted.stl", "normals point inward", m});
    }
    {  // inconsistent: one triangle flipped
        SurfaceMesh m = good;
        std::swap(m.triangles[5][1], m.triangles[5][2]);
        cases.push_back({"flipped.obj", "inconsistent orientation", m});
    }
    {  // degenerate: a vertex k inserted on edge a-b of a box, one side split at k, the
       // other left whole, and the gap closed by the zero-area sliver (a, b, k)
        SurfaceMesh m = dem::make_box_mesh({0, 0, 0}, {1, 1, 1}, 2);
        const auto t = m.triangles[0];
        const uint32_t a = t[0], b = t[1], c = t[2];
        m.vertices.push_back(0.5 * (m.vertices[a] + m.vertices[b]));
        const uint32_t k = uint32_t(m.vertices.size() - 1);
        m.triangles[0] = {a, k, c};
        m.triangles.push_back({k, b, c});
        m.triangles.push_back({a, b, k});
        cases.push_back({"degenerate.stl", "degenerate triangle", m});
    }
    {  // not a manifold: two tetrahedra sharing one vertex
        SurfaceMesh m = tetra();
        SurfaceMesh b = tetra();
        for (Vec3& v : b.vertices) v = -1.0 * v;  // point reflection, winding reversed to stay outward
        for (auto& t : b.triangles) std::swap(t[1], t[2]);
        const uint32_t off = uint32_t(m.vertices.size());
        for (std::size_t i = 1; i < b.vertices.size(); ++i) m.vertices.push_back(b.vertices[i]);
        auto map = [&](uint32_t i) { return i == 0 ? 0u : off + i - 1; };
        for (const auto& t : b.triangles) m.triangles.push_back({map(t[0]), map(t[1]), map(t[2])});
        cases.push_back({"bowtie.obj", "not a manifold", m});
    }
    {  // not a manifold: an edge shared by four triangles (two tetrahedra glued on an edge)
        SurfaceMesh m = tetra();
        SurfaceMesh b = tetra();
        for (Vec3& v : b.vertices) v = Vec3{v.x, -v.y, -v.z};  // rotation by pi about x: keeps edge 0-1
        m.vertices.push_back(b.vertices[2]);
        m.vertices.push_back(b.vertices[3]);
        auto map = [&](uint32_t i) { return i < 2 ? i : i + 2; };
        for (const auto& t : b.triangles) m.triangles.push_back({map(t[0]), map(t[1]), map(t[2])});
        cases.push_back({"edge4.stl", "not a manifold", m});
    }
    {  // self-intersecting: a sphere with one vertex pushed through the far side
        SurfaceMesh m = dem::make_icosphere(1.0, 4);
        m.vertices[0] = -1.3 * m.vertices[0];
        cases.push_back({"spike.stl", "self-intersecting", m});
    }
    {  // several surfaces: two disjoint spheres
        SurfaceMesh m = good;
        const SurfaceMesh b = dem::make_icosphere(1.0, 2, {5, 0, 0});
        const uint32_t off = uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
        for (const auto& t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
        cases.push_back({"two.obj", "several surfaces", m});
    }
    for (const Case& c : cases) {
        const std::string path = temp_path(c.name);
        dem::write_surface_mesh(path, c.mesh);
        const std::string msg = error_of([&] { dem::read_closed_surface(path); });
        std::printf("%s: %s\n", c.name.c_str(), msg.c_str());
        EXPECT_NE(msg.find(path), std::string::npos) << msg;
        EXPECT_NE(msg.find(c.defect), std::string::npos) << c.name << ": " << msg;
    }
    // Unreadable files name the file too.
    EXPECT_NE(error_of([&] { dem::read_surface_mesh(temp_path("missing.stl")); }).find("missing.stl"), std::string::npos);
    const std::string junk = temp_path("junk.stl");
    std::ofstream(junk) << "this is not an STL file at all";
    EXPECT_NE(error_of([&] { dem::read_surface_mesh(junk); }).find("junk.stl"), std::string::npos);
}

TEST(SurfaceMesh, TriangleIntersection) {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    EXPECT_TRUE(dem::triangles_intersect(a, b, c, {0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.3, 0.3, 1}));  // pierced
    EXPECT_FALSE(dem::triangles_intersect(a, b, c, {2, 2, -1}, {2, 2, 1}, {3, 3, 1}));
    EXPECT_FALSE(dem::triangles_intersect(a, b, c, {0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}));          // parallel
    EXPECT_TRUE(dem::triangles_intersect(a, b, c, {0.1, 0.1, 0}, {2, 0.1, 0}, {0.1, 2, 0}));         // coplanar overlap
    EXPECT_FALSE(dem::triangles_intersect(a, b, c, {1, 1, 0}, {2, 1, 0}, {1, 2, 0}));                // coplanar apart
}

TEST(SurfaceMesh, SelfIntersectionCheckIsFastOnLargeMeshes) {
    const SurfaceMesh m = dem::make_icosphere(1.0, 32);  // 20480 triangles
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(dem::find_mesh_defect(m), "");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("checks of %zu triangles: %.3f s\n", m.triangles.size(), s);
    EXPECT_LT(s, 5.0);
}

TEST(Remesh, EdgesCloseToTargetAndOnTheSurface) {
    // A coarse box (2 triangles per face) and a cylinder with fan caps, remeshed to L.
    const double L = 0.004;
    for (const SurfaceMesh& in : {dem::make_box_mesh({0, 0, 0}, {0.04, 0.03, 0.05}, 1),
                                  dem::make_cylinder_mesh(0.02, 0.05, 48, 1)}) {
        dem::RemeshOptions o;
        o.edge_length = L;
        const dem::RemeshResult r = dem::remesh_isotropic(in, o);
        EXPECT_EQ(dem::find_mesh_defect(r.mesh), "");
        const double v0 = dem::enclosed_volume(in), v1 = dem::enclosed_volume(r.mesh);
        std::printf("remesh: %zu -> %zu triangles, edges %.3f..%.3f L (mean %.3f), volume %+.2e\n", in.triangles.size(),
                    r.mesh.triangles.size(), r.min_edge / L, r.max_edge / L, r.mean_edge / L, v1 / v0 - 1);
        EXPECT_NEAR(r.mean_edge / L, 1.0, 0.1);
        EXPECT_LT(r.max_edge / L, 4.0 / 3.0 + 1e-9);
        EXPECT_GT(r.min_edge / L, 0.4);
        EXPECT_NEAR(v1 / v0, 1.0, 0.02);  // the corners and rims kept (features)
    }
}

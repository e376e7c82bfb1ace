#include "dem/walls/facet_sets.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dem;

namespace {


Vec3 facet_normal(const Facet& f) {
    return cross(f.vertices[1] - f.vertices[0], f.vertices[2] - f.vertices[0]);
}

double facet_area(const Facet& f) { return 0.5 * norm(facet_normal(f)); }

Vec3 centroid(const Facet& f) { return (f.vertices[0] + f.vertices[1] + f.vertices[2]) / 3.0; }

double radial_distance(const Vec3& p, const Vec3& axis_point) {
    return std::hypot(p.x - axis_point.x, p.y - axis_point.y);
}

// Horizontal unit vector from the z axis through axis_point toward p.
Vec3 radial_dir(const Vec3& p, const Vec3& axis_point) {
    return normalized(Vec3{p.x - axis_point.x, p.y - axis_point.y, 0.0});
}

double total_area(const std::vector<Facet>& fs) {
    double a = 0.0;
    for (const auto& f : fs) a += facet_area(f);
    return a;
}

// Unique per test so ctest may run tests in parallel.
std::string temp_path(const std::string& suffix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    return (std::filesystem::path(::testing::TempDir()) /
            (std::string("vppdem_") + info->name() + suffix))
        .string();
}

struct BinTri {
    float v[3][3];
};

// Hand-written binary STL (little-endian, as the format prescribes).
std::string binary_stl(const std::string& header, const std::vector<BinTri>& tris,
                       uint32_t count_override = UINT32_MAX) {
    std::string s(80, '\0');
    s.replace(0, header.size(), header);
    auto put_u32 = [&](uint32_t u) {
        for (int k = 0; k < 4; ++k) s.push_back(static_cast<char>((u >> (8 * k)) & 0xFF));
    };
    put_u32(count_override == UINT32_MAX ? static_cast<uint32_t>(tris.size()) : count_override);
    for (const auto& t : tris) {
        for (int k = 0; k < 3; ++k) put_u32(std::bit_cast<uint32_t>(0.0f));  // normal
        for (const auto& v : t.v)
            for (float c : v) put_u32(std::bit_cast<uint32_t>(c));
        s.push_back('\0');  // attribute byte count
        s.push_back('\0');
    }
    return s;
}

void write_file(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good());
}

// Runs f, expects std::runtime_error whose message contains `path`, returns the message.
template <class F>
std::string expect_runtime_error_naming(F&& f, const std::string& path) {
    try {
        f();
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path), std::string::npos) << msg;
        return msg;
    }
    ADD_FAILURE() << "expected std::runtime_error";
    return {};
}

const std::vector<BinTri> kTris = {
    {{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}},
    {{{0.5f, -0.25f, 2.0f}, {1.5f, 0.75f, 2.0f}, {0.5f, 1.0f, 3.125f}}},
};

}  // namespace

// ---------------------------------------------------------------------------------------
// Cylinder

TEST(FacetSets, CylinderCountRadiusAndHeight) {
    const Vec3 c{0.3, -1.2, 0.5};
    const double r = 0.07, h = 0.25;
    for (int n : {3, 8, 37}) {
        const auto fs = make_cylinder_facets(c, r, h, n);
        ASSERT_EQ(fs.size(), 2u * n);
        double zmin = 1e300, zmax = -1e300;
        for (const auto& f : fs) {
            for (const auto& v : f.vertices) {
                EXPECT_NEAR(radial_distance(v, c), r, 1e-12);
                zmin = std::min(zmin, v.z);
                zmax = std::max(zmax, v.z);
            }
        }
        EXPECT_DOUBLE_EQ(zmin, c.z);
        EXPECT_DOUBLE_EQ(zmax, c.z + h);
    }
}

TEST(FacetSets, CylinderNormalsInwardAndOutward) {
    const Vec3 c{1.0, 2.0, -0.5};
    for (bool inward : {true, false}) {
        const auto fs = make_cylinder_facets(c, 0.4, 1.1, 12, inward);
        for (const auto& f : fs) {
            const Vec3 n = normalized(facet_normal(f));
            const double radial = dot(n, radial_dir(centroid(f), c));
            if (inward)
                EXPECT_LT(radial, -0.9);  // close to -1: lateral faces are vertical
            else
                EXPECT_GT(radial, 0.9);
            EXPECT_NEAR(n.z, 0.0, 1e-12);
        }
    }
}

TEST(FacetSets, CylinderAreaEqualsPolygonalPrism) {
    const double r = 0.15, h = 0.6;
    for (int n : {3, 6, 50}) {
        const double exact = 2.0 * n * r * std::sin(std::numbers::pi / n) * h;
        for (bool inward : {true, false}) {
            const auto fs = make_cylinder_facets({0.1, 0.2, 0.3}, r, h, n, inward);
            EXPECT_NEAR(total_area(fs), exact, 1e-12 * exact);
        }
    }
}

TEST(FacetSets, CylinderLeavesAttributesDefault) {
    const auto fs = make_cylinder_facets({}, 1.0, 1.0, 4);
    const Facet def;
    for (const auto& f : fs) {
        EXPECT_EQ(f.material, def.material);
        EXPECT_EQ(f.mask, def.mask);
        EXPECT_EQ(f.one_sided, def.one_sided);
        EXPECT_TRUE(f.motion.is_static());
    }
}

TEST(FacetSets, CylinderRejectsBadArguments) {
    EXPECT_THROW(make_cylinder_facets({}, 0.0, 1.0, 8), std::invalid_argument);
    EXPECT_THROW(make_cylinder_facets({}, 1.0, -1.0, 8), std::invalid_argument);
    EXPECT_THROW(make_cylinder_facets({}, 1.0, 1.0, 2), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Funnel

TEST(FacetSets, FunnelCountRadiiAndHeight) {
    const Vec3 c{-0.2, 0.4, 1.0};
    const double rb = 0.02, rt = 0.1, h = 0.08;
    const int n = 16;
    const auto fs = make_funnel_facets(c, rb, rt, h, n);
    ASSERT_EQ(fs.size(), 2u * n);
    for (const auto& f : fs) {
        for (const auto& v : f.vertices) {
            const bool bottom = std::abs(v.z - c.z) < 1e-12;
            const bool top = std::abs(v.z - (c.z + h)) < 1e-12;
            ASSERT_TRUE(bottom || top) << v.z;
            EXPECT_NEAR(radial_distance(v, c), bottom ? rb : rt, 1e-12);
        }
    }
}

// Each segment is a planar isosceles trapezoid with parallel sides 2*r*sin(pi/n) (r = rb, rt)
// whose apothems differ by (rb - rt)*cos(pi/n) horizontally and h vertically, so
//   A = n * (rb + rt) * sin(pi/n) * sqrt(h^2 + (rb - rt)^2 * cos^2(pi/n)).
TEST(FacetSets, FunnelAreaEqualsPolygonalFrustum) {
    const double h = 0.3;
    for (auto [rb, rt] : {std::pair{0.05, 0.2}, std::pair{0.2, 0.05}, std::pair{0.1, 0.1}}) {
        for (int n : {3, 7, 64}) {
            const double cn = std::cos(std::numbers::pi / n);
            const double exact = n * (rb + rt) * std::sin(std::numbers::pi / n) *
                                 std::sqrt(h * h + (rb - rt) * (rb - rt) * cn * cn);
            const auto fs = make_funnel_facets({0.5, 0.5, 0.0}, rb, rt, h, n);
            EXPECT_NEAR(total_area(fs), exact, 1e-12 * exact) << rb << ' ' << rt << ' ' << n;
        }
    }
}

TEST(FacetSets, FunnelNormalsPointIntoInterior) {
    const Vec3 c{0.0, 0.0, 0.2};
    const double rb = 0.03, rt = 0.12, h = 0.1;  // hopper: wide at the top
    for (bool inward : {true, false}) {
        const auto fs = make_funnel_facets(c, rb, rt, h, 10, inward);
        for (const auto& f : fs) {
            const Vec3 n = normalized(facet_normal(f));
            const double radial = dot(n, radial_dir(centroid(f), c));
            if (inward) {
                EXPECT_LT(radial, 0.0);
                EXPECT_GT(n.z, 0.0);  // the hopper wall holds material up
            } else {
                EXPECT_GT(radial, 0.0);
                EXPECT_LT(n.z, 0.0);
            }
        }
    }
}

TEST(FacetSets, FunnelRejectsBadArguments) {
    EXPECT_THROW(make_funnel_facets({}, 0.0, 1.0, 1.0, 8), std::invalid_argument);
    EXPECT_THROW(make_funnel_facets({}, 1.0, 0.0, 1.0, 8), std::invalid_argument);
    EXPECT_THROW(make_funnel_facets({}, 1.0, 1.0, 0.0, 8), std::invalid_argument);
    EXPECT_THROW(make_funnel_facets({}, 1.0, 1.0, 1.0, 0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// STL

TEST(FacetSets, StlAsciiRoundTripIsExact) {
    const std::string path = temp_path(".stl");
    auto fs = make_cylinder_facets({0.1, -0.3, 0.7}, 0.123456789, 0.987654321, 9);
    const auto funnel = make_funnel_facets({0.0, 0.0, 2.0}, 0.01, 0.3, 0.2, 5, false);
    fs.insert(fs.end(), funnel.begin(), funnel.end());
    write_stl_ascii(path, fs);
    const auto back = read_stl(path);
    ASSERT_EQ(back.size(), fs.size());
    for (std::size_t i = 0; i < fs.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(back[i].vertices[k], fs[i].vertices[k]) << i;
    std::filesystem::remove(path);
}

TEST(FacetSets, StlAsciiScaleAndHandWrittenVariants) {
    const std::string path = temp_path(".stl");
    // Upper-case keywords, a name with spaces, '+' signs, exponents, CRLF, two solids.
    write_file(path,
               "solid my part 1\r\n"
               " FACET NORMAL 0 0 1\r\n  OUTER LOOP\r\n"
               "   VERTEX 0 0 0\r\n   VERTEX +1e3 0 0\r\n   VERTEX 0 1000.0 0\r\n"
               "  ENDLOOP\r\n ENDFACET\r\n"
               "endsolid my part 1\r\n"
               "solid second\n facet normal 0 0 0\n outer loop\n"
               " vertex 0 0 5\n vertex 0 0 6\n vertex 0 0 7\n"  // degenerate: skipped
               " endloop\n endfacet\nendsolid\n");
    const auto fs = read_stl(path, 1e-3);  // [mm] -> [m]
    ASSERT_EQ(fs.size(), 1u);
    EXPECT_EQ(fs[0].vertices[0], (Vec3{0, 0, 0}));
    EXPECT_EQ(fs[0].vertices[1], (Vec3{1e3 * 1e-3, 0, 0}));
    EXPECT_EQ(fs[0].vertices[2], (Vec3{0, 1000.0 * 1e-3, 0}));
    EXPECT_GT(facet_normal(fs[0]).z, 0.0);
    std::filesystem::remove(path);
}

TEST(FacetSets, StlBinaryWithSolidHeaderIsRead) {
    const std::string path = temp_path(".stl");
    write_file(path, binary_stl("solid exported by a careless CAD tool", kTris));
    for (double scale : {1.0, 0.5e-3}) {
        const auto fs = read_stl(path, scale);
        ASSERT_EQ(fs.size(), kTris.size());
        for (std::size_t i = 0; i < kTris.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const auto& v = kTris[i].v[k];
                EXPECT_EQ(fs[i].vertices[k],
                          (Vec3{double(v[0]) * scale, double(v[1]) * scale, double(v[2]) * scale}));
            }
    }
    std::filesystem::remove(path);
}

TEST(FacetSets, StlBinaryPlainHeaderSkipsDegenerate) {
    const std::string path = temp_path(".stl");
    auto tris = kTris;
    tris.insert(tris.begin() + 1, BinTri{{{1, 1, 1}, {2, 2, 2}, {3, 3, 3}}});  // collinear
    write_file(path, binary_stl("binary", tris));
    const auto fs = read_stl(path);
    ASSERT_EQ(fs.size(), 2u);
    EXPECT_EQ(fs[1].vertices[2], (Vec3{0.5, 1.0, 3.125}));
    std::filesystem::remove(path);
}

TEST(FacetSets, StlMissingFileThrowsNamingPath) {
    const std::string path = temp_path("_does_not_exist.stl");
    std::filesystem::remove(path);
    expect_runtime_error_naming([&] { read_stl(path); }, path);
}

TEST(FacetSets, StlTruncatedBinaryThrowsNamingPath) {
    const std::string path = temp_path(".stl");
    for (const std::string header : {"solid truncated", "binary truncated"}) {
        std::string bytes = binary_stl(header, kTris);
        bytes.resize(bytes.size() - 7);
        write_file(path, bytes);
        const std::string msg = expect_runtime_error_naming([&] { read_stl(path); }, path);
        EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
        // Shorter than the 84-byte header as well.
        write_file(path, bytes.substr(0, 40));
        expect_runtime_error_naming([&] { read_stl(path); }, path);
    }
    std::filesystem::remove(path);
}

TEST(FacetSets, StlMalformedOrEmptyThrowsNamingPath) {
    const std::string path = temp_path(".stl");
    const std::vector<std::string> bad = {
        "",                                                          // empty file
        "solid x\nendsolid x\n",                                     // zero triangles
        "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n"  // missing vertices
        " vertex 1 0 0\n endloop\n endfacet\nendsolid\n",
        "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 zero\n",  // bad number
        "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
        " vertex 0 1 0\n endloop\n endfacet\n",                     // missing endsolid
        "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 1 1\n"
        " vertex 2 2 2\n endloop\n endfacet\nendsolid\n",           // only degenerate
    };
    for (const auto& content : bad) {
        write_file(path, content);
        expect_runtime_error_naming([&] { read_stl(path); }, path);
    }
    write_file(path, binary_stl("binary", {}));  // binary with zero triangles
    expect_runtime_error_naming([&] { read_stl(path); }, path);
    std::filesystem::remove(path);
}

TEST(FacetSets, StlWriteToUnwritablePathThrows) {
    const std::string path = temp_path("_no_such_dir/out.stl");
    expect_runtime_error_naming([&] { write_stl_ascii(path, make_cylinder_facets({}, 1, 1, 3)); },
                                path);
}

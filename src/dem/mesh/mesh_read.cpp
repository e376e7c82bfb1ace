#include "dem/mesh/mesh_read.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace dem {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::runtime_error("mesh file '" + path + "': " + what);
}

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos) return "";
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

uint32_t u32_le(const char* p) {
    const auto* u = reinterpret_cast<const unsigned char*>(p);
    return uint32_t(u[0]) | (uint32_t(u[1]) << 8) | (uint32_t(u[2]) << 16) | (uint32_t(u[3]) << 24);
}

// Binary STL: 80-byte header, a count, then 50 bytes per triangle. Recognised by its exact
// size, since ASCII files may also start with "solid".
bool stl_binary(const std::string& s, std::vector<Vec3>& corners) {
    if (s.size() < 84) return false;
    const uint32_t n = u32_le(s.data() + 80);
    if (s.size() != 84 + 50 * uint64_t(n)) return false;
    corners.reserve(3 * std::size_t(n));
    for (uint32_t t = 0; t < n; ++t) {
        const char* p = s.data() + 84 + 50 * std::size_t(t) + 12;  // skip the stored normal
        for (int k = 0; k < 3; ++k, p += 12)
            corners.push_back({std::bit_cast<float>(u32_le(p)), std::bit_cast<float>(u32_le(p + 4)),
                               std::bit_cast<float>(u32_le(p + 8))});
    }
    return true;
}

// ASCII STL: only the 'vertex x y z' lines matter; 'facet'/'endloop' structure is checked by
// counting three vertices per 'endloop'.
void stl_ascii(const std::string& path, const std::string& s, std::vector<Vec3>& corners) {
    std::istringstream in(s);
    std::string line;
    int lineno = 0, in_loop = 0;
    while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ls(line);
        std::string w;
        if (!(ls >> w)) continue;
        if (w == "vertex") {
            Vec3 v;
            if (!(ls >> v.x >> v.y >> v.z)) fail(path, "line " + std::to_string(lineno) + ": a vertex needs 3 numbers");
            corners.push_back(v);
            ++in_loop;
        } else if (w == "endloop") {
            if (in_loop != 3) fail(path, "line " + std::to_string(lineno) + ": a facet needs exactly 3 vertices");
            in_loop = 0;
        }
    }
    if (corners.size() % 3 != 0) fail(path, "truncated ASCII STL (vertex count not a multiple of 3)");
}

// OBJ: 'v x y z' and 'f a b c ...' with 1-based or negative (relative) indices, each possibly
// 'a/t/n'. Polygons become fans from their first corner.
void obj(const std::string& path, const std::string& s, std::vector<Vec3>& corners) {
    std::vector<Vec3> v;
    std::istringstream in(s);
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ls(line);
        std::string w;
        if (!(ls >> w)) continue;
        if (w == "v") {
            Vec3 p;
            if (!(ls >> p.x >> p.y >> p.z)) fail(path, "line " + std::to_string(lineno) + ": 'v' needs 3 numbers");
            v.push_back(p);
        } else if (w == "f") {
            std::vector<std::size_t> poly;
            std::string tok;
            while (ls >> tok) {
                long k = 0;
                try {
                    k = std::stol(tok.substr(0, tok.find('/')));
                } catch (const std::exception&) {
                    fail(path, "line " + std::to_string(lineno) + ": bad face index '" + tok + "'");
                }
                const long idx = k > 0 ? k - 1 : long(v.size()) + k;
                if (k == 0 || idx < 0 || idx >= long(v.size()))
                    fail(path, "line " + std::to_string(lineno) + ": face index " + tok + " out of range");
                poly.push_back(std::size_t(idx));
            }
            if (poly.size() < 3) fail(path, "line " + std::to_string(lineno) + ": a face needs at least 3 corners");
            for (std::size_t k = 1; k + 1 < poly.size(); ++k)
                for (std::size_t c : {poly[0], poly[k], poly[k + 1]}) corners.push_back(v[c]);
        }
    }
}

}  // namespace

SurfaceMesh weld_triangles(const std::vector<Vec3>& corners, double tolerance) {
    SurfaceMesh m;
    // Hash grid of cell `tolerance`: a corner's match lies in its own or a neighbouring cell.
    const double cell = tolerance > 0 ? tolerance : 1.0;
    auto key = [](int64_t x, int64_t y, int64_t z) {
        return uint64_t(x * 73856093) ^ uint64_t(y * 19349663) ^ uint64_t(z * 83492791);
    };
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    std::vector<uint32_t> index(corners.size());
    for (std::size_t k = 0; k < corners.size(); ++k) {
        const Vec3& p = corners[k];
        const int64_t cx = int64_t(std::floor(p.x / cell)), cy = int64_t(std::floor(p.y / cell)),
                      cz = int64_t(std::floor(p.z / cell));
        int64_t found = -1;
        for (int64_t dz = -1; dz <= 1 && found < 0; ++dz)
            for (int64_t dy = -1; dy <= 1 && found < 0; ++dy)
                for (int64_t dx = -1; dx <= 1 && found < 0; ++dx) {
                    const auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second)
                        if (norm(m.vertices[j] - p) <= tolerance) {
                            found = j;
                            break;
                        }
                }
        if (found < 0) {
            found = int64_t(m.vertices.size());
            m.vertices.push_back(p);
            grid[key(cx, cy, cz)].push_back(uint32_t(found));
        }
        index[k] = uint32_t(found);
    }
    m.triangles.reserve(corners.size() / 3);
    for (std::size_t t = 0; t + 2 < corners.size(); t += 3) m.triangles.push_back({index[t], index[t + 1], index[t + 2]});
    return m;
}

SurfaceMesh read_surface_mesh(const std::string& path, const MeshReadOptions& opt) {
    if (!(opt.scale > 0) || !std::isfinite(opt.scale)) fail(path, "scale must be finite and > 0");
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "cannot open");
    std::stringstream buf;
    buf << f.rdbuf();
    const std::string s = buf.str();
    const std::string ext = lower_extension(path);
    std::vector<Vec3> corners;
    if (ext == "stl") {
        if (!stl_binary(s, corners)) {
            if (s.compare(0, 5, "solid") != 0) fail(path, "neither a binary STL (size does not match its count) nor ASCII");
            stl_ascii(path, s, corners);
        }
    } else if (ext == "obj") {
        obj(path, s, corners);
    } else {
        fail(path, "unknown extension '" + ext + "' (expected .stl or .obj)");
    }
    if (corners.empty()) fail(path, "no triangles");
    Vec3 lo = corners[0], hi = corners[0];
    for (Vec3& p : corners) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail(path, "a coordinate is not finite");
        p *= opt.scale;
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const double diag = norm(hi - lo);
    return weld_triangles(corners, opt.weld * (diag > 0 ? diag : 1.0));
}

void write_surface_mesh(const std::string& path, const SurfaceMesh& m) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error("mesh file '" + path + "': cannot write");
    if (lower_extension(path) == "obj") {
        for (const Vec3& v : m.vertices) std::fprintf(f, "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
        for (const auto& t : m.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    } else {
        std::fprintf(f, "solid mesh\n");
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const Vec3 a = area_vector(m, t);
            const double l = norm(a);
            const Vec3 n = l > 0 ? a / l : Vec3{};
            std::fprintf(f, "facet normal %.17g %.17g %.17g\nouter loop\n", n.x, n.y, n.z);
            for (uint32_t k : m.triangles[t]) {
                const Vec3& v = m.vertices[k];
                std::fprintf(f, "vertex %.17g %.17g %.17g\n", v.x, v.y, v.z);
            }
            std::fprintf(f, "endloop\nendfacet\n");
        }
        std::fprintf(f, "endsolid mesh\n");
    }
    if (std::fclose(f) != 0) throw std::runtime_error("mesh file '" + path + "': cannot write");
}

}  // namespace dem

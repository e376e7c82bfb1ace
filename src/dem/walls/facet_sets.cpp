#include "dem/walls/facet_sets.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace dem {

namespace {

// Ring of a surface of revolution around the z axis through `center`: quad i joins angles
// i and i+1 between heights z0 (radius r0) and z1 (radius r1). Angle index n maps back to
// 0 so the first and last quads share vertices exactly (a watertight seam).
std::vector<Facet> make_ring(const Vec3& center, double r0, double r1, double z0, double z1,
                             int segments, bool inward_normals) {
    std::vector<Facet> out;
    out.reserve(2 * static_cast<std::size_t>(segments));
    auto point = [&](int i, double r, double z) {
        const double a = 2.0 * std::numbers::pi * (i % segments) / segments;
        return Vec3{center.x + r * std::cos(a), center.y + r * std::sin(a), z};
    };
    for (int i = 0; i < segments; ++i) {
        const Vec3 p0 = point(i, r0, z0), p1 = point(i + 1, r0, z0);
        const Vec3 q0 = point(i, r1, z1), q1 = point(i + 1, r1, z1);
        // (p0, p1, q1) winds counter-clockwise seen from outside: tangent x up = outward.
        Facet a, b;
        if (inward_normals) {
            a.vertices = {p0, q1, p1};
            b.vertices = {p0, q0, q1};
        } else {
            a.vertices = {p0, p1, q1};
            b.vertices = {p0, q1, q0};
        }
        out.push_back(a);
        out.push_back(b);
    }
    return out;
}

void check_positive(double v, const char* what, const char* fn) {
    if (!(v > 0.0) || !std::isfinite(v))
        throw std::invalid_argument(std::string(fn) + ": " + what + " must be finite and > 0");
}

void check_segments(int segments, const char* fn) {
    if (segments < 3) throw std::invalid_argument(std::string(fn) + ": segments must be >= 3");
}

// Zero-area test relative to the triangle's size, so it does not depend on units.
bool is_degenerate(const Facet& f) {
    const Vec3 e0 = f.vertices[1] - f.vertices[0];
    const Vec3 e1 = f.vertices[2] - f.vertices[0];
    const Vec3 e2 = f.vertices[2] - f.vertices[1];
    const double l2 = std::max({norm2(e0), norm2(e1), norm2(e2)});
    return norm(cross(e0, e1)) <= 1e-12 * l2;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::runtime_error("STL file '" + path + "': " + what);
}

// STL binary is little-endian regardless of the host; assemble bytes explicitly.
uint32_t read_u32_le(const char* p) {
    const auto* u = reinterpret_cast<const unsigned char*>(p);
    return uint32_t(u[0]) | (uint32_t(u[1]) << 8) | (uint32_t(u[2]) << 16) | (uint32_t(u[3]) << 24);
}

float read_f32_le(const char* p) { return std::bit_cast<float>(read_u32_le(p)); }

struct AsciiError {
    std::string what;
};

// Minimal tokenizer over the whole file; tracks line numbers for error messages.
class Tokens {
public:
    explicit Tokens(std::string_view s) : s_(s) {}

    bool next(std::string_view& tok) {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) {
            if (s_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ >= s_.size()) return false;
        const std::size_t start = pos_;
        while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
        tok = s_.substr(start, pos_ - start);
        return true;
    }

    void skip_line() {  // solid names are free text up to the end of the line
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
    }

    [[noreturn]] void error(const std::string& what) const {
        throw AsciiError{"line " + std::to_string(line_) + ": " + what};
    }

    std::string_view word(const char* context) {
        std::string_view t;
        if (!next(t)) error(std::string("unexpected end of file, expected ") + context);
        return t;
    }

    void expect(const char* keyword) {
        const std::string_view t = word(keyword);
        if (!iequals(t, keyword))
            error("expected '" + std::string(keyword) + "', found '" + std::string(t) + "'");
    }

    double number() {
        const std::string_view t = word("a number");
        double v = 0.0;
        const char* first = t.data();
        if (!t.empty() && *first == '+') ++first;  // from_chars rejects a leading '+'
        const auto [ptr, ec] = std::from_chars(first, t.data() + t.size(), v);
        if (ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v))
            error("invalid number '" + std::string(t) + "'");
        return v;
    }

    static bool iequals(std::string_view a, std::string_view b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
                   return std::tolower(static_cast<unsigned char>(x)) ==
                          std::tolower(static_cast<unsigned char>(y));
               });
    }

private:
    std::string_view s_;
    std::size_t pos_ = 0;
    int line_ = 1;
};

// Parses all facets (degenerate ones included); several solids in one file are accepted.
std::vector<Facet> parse_ascii(std::string_view text, double scale) {
    Tokens tk(text);
    std::vector<Facet> out;
    std::string_view t;
    if (!tk.next(t) || !Tokens::iequals(t, "solid")) tk.error("expected 'solid'");
    tk.skip_line();
    bool in_solid = true;
    while (tk.next(t)) {
        if (in_solid && Tokens::iequals(t, "facet")) {
            tk.expect("normal");
            for (int k = 0; k < 3; ++k) tk.number();  // stored normal ignored: winding rules
            tk.expect("outer");
            tk.expect("loop");
            Facet f;
            for (auto& v : f.vertices) {
                tk.expect("vertex");
                v.x = tk.number() * scale;
                v.y = tk.number() * scale;
                v.z = tk.number() * scale;
            }
            tk.expect("endloop");
            tk.expect("endfacet");
            out.push_back(f);
        } else if (in_solid && Tokens::iequals(t, "endsolid")) {
            tk.skip_line();
            in_solid = false;
        } else if (!in_solid && Tokens::iequals(t, "solid")) {
            tk.skip_line();
            in_solid = true;
        } else {
            tk.error("unexpected '" + std::string(t) + "'");
        }
    }
    if (in_solid) tk.error("missing 'endsolid'");
    return out;
}

std::vector<Facet> parse_binary(const std::string& data, double scale) {
    const uint32_t n = read_u32_le(data.data() + 80);
    std::vector<Facet> out;
    out.reserve(n);
    for (uint32_t i = 0; i < n; ++i) {
        const char* rec = data.data() + 84 + 50 * static_cast<std::size_t>(i);
        Facet f;
        for (int k = 0; k < 3; ++k) {  // skip the 12-byte normal, then 3 vertices
            const char* p = rec + 12 + 12 * k;
            f.vertices[k] = Vec3{double(read_f32_le(p)), double(read_f32_le(p + 4)),
                                 double(read_f32_le(p + 8))} * scale;
        }
        out.push_back(f);
    }
    return out;
}

}  // namespace

std::vector<Facet> make_cylinder_facets(const Vec3& base_center, double radius, double height,
                                        int segments, bool inward_normals) {
    check_positive(radius, "radius", "make_cylinder_facets");
    check_positive(height, "height", "make_cylinder_facets");
    check_segments(segments, "make_cylinder_facets");
    return make_ring(base_center, radius, radius, base_center.z, base_center.z + height,
                     segments, inward_normals);
}

std::vector<Facet> make_funnel_facets(const Vec3& bottom_center, double bottom_radius,
                                      double top_radius, double height, int segments,
                                      bool inward_normals) {
    check_positive(bottom_radius, "bottom_radius", "make_funnel_facets");
    check_positive(top_radius, "top_radius", "make_funnel_facets");
    check_positive(height, "height", "make_funnel_facets");
    check_segments(segments, "make_funnel_facets");
    return make_ring(bottom_center, bottom_radius, top_radius, bottom_center.z,
                     bottom_center.z + height, segments, inward_normals);
}

std::vector<Facet> read_stl(const std::string& path, double scale) {
    if (!(scale > 0.0) || !std::isfinite(scale))
        fail(path, "scale must be finite and > 0");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file (missing or unreadable)");
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) fail(path, "read error");
    const std::string data = std::move(buf).str();
    if (data.empty()) fail(path, "file is empty");

    // Binary files may also start with "solid" (some exporters do this), so the size implied
    // by the binary triangle count decides first; only then is ASCII tried.
    const bool has_binary_header = data.size() >= 84;
    const uint64_t expected =
        has_binary_header ? 84 + 50 * uint64_t(read_u32_le(data.data() + 80)) : 0;
    const bool binary_size_ok = has_binary_header && data.size() == expected;
    const bool starts_solid = data.compare(0, 5, "solid") == 0;

    std::vector<Facet> facets;
    if (binary_size_ok) {
        facets = parse_binary(data, scale);
    } else {
        const std::string binary_problem =
            has_binary_header
                ? "binary triangle count implies " + std::to_string(expected) +
                      " bytes but the file has " + std::to_string(data.size()) +
                      (data.size() < expected ? " (truncated)" : " (trailing data)")
                : "file has " + std::to_string(data.size()) +
                      " bytes, shorter than the 84-byte binary header (truncated)";
        if (!starts_solid) fail(path, binary_problem);
        try {
            facets = parse_ascii(data, scale);
        } catch (const AsciiError& e) {
            fail(path, "malformed ASCII STL (" + e.what + "); as binary: " + binary_problem);
        }
    }
    if (facets.empty()) fail(path, "contains no triangles");
    for (const Facet& f : facets)
        for (const Vec3& v : f.vertices)
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
                fail(path, "non-finite vertex coordinate");

    std::erase_if(facets, is_degenerate);
    if (facets.empty()) fail(path, "all triangles are degenerate (zero area)");
    return facets;
}

void write_stl_ascii(const std::string& path, const std::vector<Facet>& facets) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("STL file '" + path + "': cannot open for writing");
    out << std::setprecision(17);  // round-trips doubles exactly
    out << "solid vppdem\n";
    for (const Facet& f : facets) {
        const Vec3& v0 = f.vertices[0];
        Vec3 n = cross(f.vertices[1] - v0, f.vertices[2] - v0);
        const double len = norm(n);
        n = len > 0.0 ? n / len : Vec3{};
        out << "  facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n    outer loop\n";
        for (const Vec3& v : f.vertices)
            out << "      vertex " << v.x << ' ' << v.y << ' ' << v.z << '\n';
        out << "    endloop\n  endfacet\n";
    }
    out << "endsolid vppdem\n";
    out.close();
    if (!out) throw std::runtime_error("STL file '" + path + "': write failed");
}

}  // namespace dem

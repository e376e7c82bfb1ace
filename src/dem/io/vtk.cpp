#include "dem/io/vtk.h"

#include "dem/io/csv.h"

namespace dem {

namespace {
void add_vec(std::string& s, const Vec3& v) {
    append_number(s, v.x);
    s += ' ';
    append_number(s, v.y);
    s += ' ';
    append_number(s, v.z);
    s += '\n';
}
}  // namespace

void write_particles_vtk(const std::string& path, const World& world, bool with_bonds,
                         const std::vector<uint32_t>* subset) {
    const Particles& p = world.particles;
    std::vector<uint32_t> all;
    if (!subset) {
        all.resize(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) all[i] = uint32_t(i);
        subset = &all;
    }
    const std::vector<uint32_t>& ids = *subset;
    const std::size_t n = ids.size();
    std::vector<int64_t> local(p.size(), -1);  // particle index -> point index in this file
    for (std::size_t k = 0; k < n; ++k) local[ids[k]] = int64_t(k);
    std::string s = "# vtk DataFile Version 3.0\nvppdem particles t=";
    append_number(s, world.time);
    s += "\nASCII\nDATASET POLYDATA\nPOINTS " + std::to_string(n) + " double\n";
    for (uint32_t i : ids) add_vec(s, p.pos[i]);
    s += "VERTICES " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
    for (std::size_t k = 0; k < n; ++k) s += "1 " + std::to_string(k) + "\n";
    if (with_bonds) {
        const BondList& b = world.bonds();
        std::string lines;
        std::size_t nl = 0;
        for (std::size_t k = 0; k < b.size(); ++k) {
            if (local[b.i[k]] < 0 || local[b.j[k]] < 0) continue;
            lines += "2 " + std::to_string(local[b.i[k]]) + " " + std::to_string(local[b.j[k]]) + "\n";
            ++nl;
        }
        s += "LINES " + std::to_string(nl) + " " + std::to_string(3 * nl) + "\n" + lines;
    }
    s += "POINT_DATA " + std::to_string(n) + "\nSCALARS radius double 1\nLOOKUP_TABLE default\n";
    for (uint32_t i : ids) {
        append_number(s, p.radius[i]);
        s += '\n';
    }
    s += "SCALARS id int 1\nLOOKUP_TABLE default\n";
    for (uint32_t i : ids) s += std::to_string(i) + "\n";
    s += "SCALARS material int 1\nLOOKUP_TABLE default\n";
    for (uint32_t i : ids) s += std::to_string(p.material[i]) + "\n";
    s += "VECTORS velocity double\n";
    for (uint32_t i : ids) add_vec(s, p.vel[i]);
    s += "VECTORS angular_velocity double\n";
    for (uint32_t i : ids) add_vec(s, p.angvel[i]);
    write_text_atomic(path, s);
}

void write_walls_vtk(const std::string& path, const World& world, double plane_size) {
    const std::size_t np = world.planes.size(), nf = world.facets.size();
    std::string s = "# vtk DataFile Version 3.0\nvppdem walls\nASCII\nDATASET POLYDATA\nPOINTS " +
                    std::to_string(4 * np + 3 * nf) + " double\n";
    for (std::size_t k = 0; k < np; ++k) {
        const Vec3 n = world.planes[k].normal;
        // Two in-plane axes orthogonal to n.
        const Vec3 helper = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
        const Vec3 u = normalized(cross(n, helper)) * plane_size, v = cross(n, u);
        const Vec3 c = world.plane_point(k);
        add_vec(s, c - u - v);
        add_vec(s, c + u - v);
        add_vec(s, c + u + v);
        add_vec(s, c - u + v);
    }
    for (std::size_t f = 0; f < nf; ++f)
        for (int v = 0; v < 3; ++v) add_vec(s, world.facet_vertices(f)[v]);
    s += "POLYGONS " + std::to_string(np + nf) + " " + std::to_string(5 * np + 4 * nf) + "\n";
    for (std::size_t k = 0; k < np; ++k) {
        const std::size_t b = 4 * k;
        s += "4 " + std::to_string(b) + " " + std::to_string(b + 1) + " " + std::to_string(b + 2) +
             " " + std::to_string(b + 3) + "\n";
    }
    for (std::size_t f = 0; f < nf; ++f) {
        const std::size_t b = 4 * np + 3 * f;
        s += "3 " + std::to_string(b) + " " + std::to_string(b + 1) + " " + std::to_string(b + 2) + "\n";
    }
    s += "CELL_DATA " + std::to_string(np + nf) + "\nSCALARS wall int 1\nLOOKUP_TABLE default\n";
    for (std::size_t k = 0; k < np + nf; ++k) s += std::to_string(k) + "\n";
    write_text_atomic(path, s);
}

}  // namespace dem

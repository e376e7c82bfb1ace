#include "dem/core/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "dem/detect/geometry.h"
#include "dem/integrate/leapfrog.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace dem {

namespace {
constexpr uint32_t kSideBit = 1u << 31;  // marks "this particle is body 2" in gather entries
}

uint32_t World::add_material(const Material& m) {
    materials.push_back(m);
    physics_dirty_ = true;
    return uint32_t(materials.size() - 1);
}

uint32_t World::add_sphere(const SphereDef& d) {
    if (!(d.radius > 0.0)) throw std::invalid_argument("sphere radius must be > 0");
    if (d.material >= materials.size()) throw std::invalid_argument("sphere material index out of range");
    Particles& p = particles;
    const double m = materials[d.material].density * 4.0 / 3.0 * std::numbers::pi * d.radius * d.radius * d.radius;
    const bool free = !(d.flags & (kFixed | kPrescribed));
    p.pos.push_back(d.position);
    p.vel.push_back(d.flags & kFixed ? Vec3{} : d.velocity);
    p.angvel.push_back(free ? d.angular_velocity : Vec3{});
    p.force.emplace_back();
    p.torque.emplace_back();
    p.ext_force.emplace_back();
    p.radius.push_back(d.radius);
    p.mass.push_back(m);
    p.inv_mass.push_back(free ? 1.0 / m : 0.0);
    p.inv_inertia.push_back(free ? 1.0 / (0.4 * m * d.radius * d.radius) : 0.0);
    p.material.push_back(d.material);
    p.mask.push_back(d.mask);
    p.flags.push_back(d.flags);
    p.motion.push_back(-1);
    p.ref_pos.push_back(d.position);
    candidates_dirty_ = true;
    return uint32_t(p.size() - 1);
}

uint32_t World::add_plane(const Plane& pl) {
    Plane q = pl;
    q.normal = normalized(pl.normal);
    planes.push_back(q);
    candidates_dirty_ = true;
    return uint32_t(planes.size() - 1);
}

uint32_t World::add_facet(const Facet& f) {
    facets.push_back(f);
    candidates_dirty_ = true;
    return uint32_t(facets.size() - 1);
}

uint32_t World::add_motion(const Motion& m) {
    motions.push_back(m);
    return uint32_t(motions.size() - 1);
}

void World::set_fixed(uint32_t i) {
    Particles& p = particles;
    p.flags[i] = (p.flags[i] | kFixed) & ~uint32_t(kPrescribed);
    p.inv_mass[i] = p.inv_inertia[i] = 0.0;
    p.vel[i] = p.angvel[i] = Vec3{};
    p.motion[i] = -1;
    physics_dirty_ = true;  // reduced masses of its contacts change
}

void World::set_prescribed(uint32_t i, uint32_t motion) {
    Particles& p = particles;
    p.flags[i] = (p.flags[i] | kPrescribed) & ~uint32_t(kFixed);
    p.inv_mass[i] = p.inv_inertia[i] = 0.0;
    p.angvel[i] = Vec3{};
    p.motion[i] = int32_t(motion);
    // The motion's displacement is measured from where the particle is at time 0 of the motion.
    p.ref_pos[i] = p.pos[i] - motions[motion].displacement(time);
    physics_dirty_ = true;
}

void World::clear_facets() {
    facets.clear();
    facet_now_.clear();
    // Drop the facet contacts now, so facets added later never inherit their history.
    std::vector<uint64_t> keep;
    for (uint64_t k : pw_.key)
        if (key_second(k) < planes.size()) keep.push_back(k);
    std::vector<uint8_t> existed;
    pw_.merge_from(keep, true, existed);
    candidates_dirty_ = true;
}

uint32_t World::add_bond(uint32_t i, uint32_t j, double kn, double ks, double rest_length) {
    if (i == j || i >= particles.size() || j >= particles.size())
        throw std::invalid_argument("bond between invalid particle indices");
    if (i > j) std::swap(i, j);
    bonds_.i.push_back(i);
    bonds_.j.push_back(j);
    const double L = rest_length >= 0.0 ? rest_length : norm(particles.pos[j] - particles.pos[i]);
    bonds_.phys.push_back({kn, ks, L});
    bonds_.hist.emplace_back();
    bonds_.force.emplace_back();
    bonds_.torque1.emplace_back();
    bonds_.torque2.emplace_back();
    bonds_dirty_ = candidates_dirty_ = true;
    return uint32_t(bonds_.size() - 1);
}

void World::build_bond_tables() {
    const std::size_t n = particles.size(), nb = bonds_.size();
    bond_start_.assign(n + 1, 0);
    for (std::size_t b = 0; b < nb; ++b) {
        ++bond_start_[bonds_.i[b] + 1];
        ++bond_start_[bonds_.j[b] + 1];
    }
    for (std::size_t i = 0; i < n; ++i) bond_start_[i + 1] += bond_start_[i];
    bond_entries_.resize(bond_start_.back());
    bonded_with_.resize(bond_start_.back());
    std::vector<uint32_t> fill(bond_start_.begin(), bond_start_.end() - 1);
    for (std::size_t b = 0; b < nb; ++b) {
        const uint32_t i = bonds_.i[b], j = bonds_.j[b];
        bonded_with_[fill[i]] = j;
        bond_entries_[fill[i]++] = uint32_t(b);
        bonded_with_[fill[j]] = i;
        bond_entries_[fill[j]++] = uint32_t(b) | kSideBit;
    }
    bonded_start_ = bond_start_;
    bonds_dirty_ = false;
}

double World::effective_skin() const {
    if (params.skin > 0.0) return params.skin;
    double rmin = std::numeric_limits<double>::max();
    for (double r : particles.radius) rmin = std::min(rmin, r);
    return particles.size() ? 0.5 * rmin : 1e-3;
}

double World::critical_dt() const {
    const Particles& p = particles;
    // Stiffest partner per material: E * r_max of that material's particles.
    std::vector<double> er_max(materials.size(), 0.0);
    for (std::size_t i = 0; i < p.size(); ++i)
        er_max[p.material[i]] = std::max(er_max[p.material[i]], materials[p.material[i]].young * p.radius[i]);
    double wall_e = 0.0;
    for (const Plane& pl : planes) wall_e = std::max(wall_e, materials[pl.material].young);
    for (const Facet& f : facets) wall_e = std::max(wall_e, materials[f.material].young);
    std::vector<double> kbond(p.size(), 0.0);
    for (std::size_t b = 0; b < bonds_.size(); ++b) {
        kbond[bonds_.i[b]] = std::max(kbond[bonds_.i[b]], bonds_.phys[b].kn);
        kbond[bonds_.j[b]] = std::max(kbond[bonds_.j[b]], bonds_.phys[b].kn);
    }
    double best = std::numeric_limits<double>::infinity();
    const double partner_er = *std::max_element(er_max.begin(), er_max.end());
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const double a = materials[p.material[i]].young * p.radius[i];
        const double b = std::max(partner_er, wall_e * p.radius[i]);
        const double kn = std::max(harmonic_stiffness(a, b), kbond[i]);
        best = std::min(best, std::sqrt(p.mass[i] / kn));
    }
    return best;
}

// ---------------------------------------------------------------- phases

void World::move_walls() {
    const std::size_t nw = wall_count();
    plane_point_.resize(planes.size());
    facet_now_.resize(facets.size());
    wall_vel_.resize(nw);
    // The velocity over the last step matches the particles' half-step velocity v(t - dt/2).
    const double t0 = time - params.dt, t1 = time;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        plane_point_[k] = planes[k].point + planes[k].motion.displacement(time);
        wall_vel_[k] = planes[k].motion.mean_velocity(t0, t1);
    }
    for (std::size_t k = 0; k < facets.size(); ++k) {
        const Vec3 d = facets[k].motion.displacement(time);
        for (int v = 0; v < 3; ++v) facet_now_[k][v] = facets[k].vertices[v] + d;
        wall_vel_[planes.size() + k] = facets[k].motion.mean_velocity(t0, t1);
    }
}

bool World::needs_rebuild() const {
    if (candidates_dirty_ || ref_pos_.size() != particles.size()) return true;
    const double skin = effective_skin();
    if (2.0 * max_disp_ > skin) return true;
    double wall_move = 0.0;
    for (std::size_t k = 0; k < planes.size(); ++k)
        wall_move = std::max(wall_move, norm(planes[k].motion.displacement(time) - wall_ref_disp_[k]));
    for (std::size_t k = 0; k < facets.size(); ++k)
        wall_move = std::max(wall_move,
                             norm(facets[k].motion.displacement(time) - wall_ref_disp_[planes.size() + k]));
    return max_disp_ + wall_move > skin;
}

void World::rebuild_candidates() {
    const Particles& p = particles;
    const std::size_t n = p.size();
    const double skin = effective_skin();
    if (bonds_dirty_ || bond_start_.size() != n + 1) build_bond_tables();
    double rmax = 0.0;
    for (double r : p.radius) rmax = std::max(rmax, r);
    grid_.build(p.pos, 2.0 * rmax + skin, std::max<int64_t>(int64_t(4 * n), 4096));

    // Facets are registered in every cell their box (grown by rmax + skin) touches, so a
    // particle only has to look at its own cell's list.
    std::vector<uint32_t> fstart(std::size_t(grid_.ncells() + 1), 0), fitems;
    if (!facets.empty()) {
        const double grow = rmax + skin;
        std::vector<std::array<int64_t, 6>> range(facets.size());
        std::vector<uint8_t> inside(facets.size(), 0);
        for (std::size_t f = 0; f < facets.size(); ++f) {
            Vec3 lo = facet_now_[f][0], hi = lo;
            for (int v = 1; v < 3; ++v)
                for (int d = 0; d < 3; ++d) {
                    lo[d] = std::min(lo[d], facet_now_[f][v][d]);
                    hi[d] = std::max(hi[d], facet_now_[f][v][d]);
                }
            bool ok = true;
            for (int d = 0; d < 3; ++d) {
                const double a = (lo[d] - grow - grid_.origin[d]) / grid_.cell;
                const double b = (hi[d] + grow - grid_.origin[d]) / grid_.cell;
                if (b < 0.0 || a >= double(grid_.dims[d])) ok = false;
                range[f][d] = std::clamp<int64_t>(int64_t(std::floor(a)), 0, grid_.dims[d] - 1);
                range[f][d + 3] = std::clamp<int64_t>(int64_t(std::floor(b)), 0, grid_.dims[d] - 1);
            }
            inside[f] = ok;
        }
        for (int pass = 0; pass < 2; ++pass) {
            std::vector<uint32_t> fill;
            if (pass == 1) {
                for (int64_t c = 0; c < grid_.ncells(); ++c) fstart[c + 1] += fstart[c];
                fitems.resize(fstart.back());
                fill.assign(fstart.begin(), fstart.end() - 1);
            }
            for (std::size_t f = 0; f < facets.size(); ++f) {
                if (!inside[f]) continue;
                const auto& r = range[f];
                for (int64_t z = r[2]; z <= r[5]; ++z)
                    for (int64_t y = r[1]; y <= r[4]; ++y)
                        for (int64_t x = r[0]; x <= r[3]; ++x) {
                            const int64_t c = grid_.index({x, y, z});
                            if (pass == 0) ++fstart[c + 1];
                            else fitems[fill[c]++] = uint32_t(f);
                        }
            }
        }
    }

    const int nt = std::max(1, params.threads);
    std::vector<std::vector<uint64_t>> pp_keys(nt), pw_keys(nt);
    const uint32_t nplanes = uint32_t(planes.size());
#pragma omp parallel num_threads(nt)
    {
#ifdef _OPENMP
        const int tid = omp_get_thread_num();
#else
        const int tid = 0;
#endif
        std::vector<uint32_t> local;
        // schedule(static) hands out contiguous blocks of i in thread order, so concatenating
        // the per-thread lists in thread order gives keys sorted by i for any thread count.
#pragma omp for schedule(static)
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 xi = p.pos[i];
            const double ri = p.radius[i];
            const auto c = grid_.coords(xi);
            local.clear();
            grid_.for_each_neighbour(c, [&](uint32_t j) {
                if (j <= i || !(p.mask[i] & p.mask[j])) return;
                if (p.inv_mass[i] == 0.0 && p.inv_mass[j] == 0.0) return;
                for (uint32_t b = bonded_start_[i]; b < bonded_start_[i + 1]; ++b)
                    if (bonded_with_[b] == j) return;
                const double reach = ri + p.radius[j] + skin;
                if (norm2(p.pos[j] - xi) < reach * reach) local.push_back(j);
            });
            std::sort(local.begin(), local.end());
            for (uint32_t j : local) pp_keys[tid].push_back(pair_key(uint32_t(i), j));

            if (p.inv_mass[i] == 0.0 && !(p.flags[i] & kPrescribed)) continue;  // fixed: no wall contacts
            for (uint32_t w = 0; w < nplanes; ++w) {
                if (!(planes[w].mask & p.mask[i])) continue;
                const double s = dot(xi - plane_point_[w], planes[w].normal);
                const bool near = planes[w].one_sided ? s < ri + skin : std::abs(s) < ri + skin;
                if (near) pw_keys[tid].push_back(pair_key(uint32_t(i), w));
            }
            if (!facets.empty()) {
                const int64_t cell = grid_.index(c);
                for (uint32_t k = fstart[cell]; k < fstart[cell + 1]; ++k) {
                    const uint32_t f = fitems[k];
                    if (!(facets[f].mask & p.mask[i])) continue;
                    const double reach = ri + skin;
                    if (distance2_to_triangle(xi, facet_now_[f]) < reach * reach)
                        pw_keys[tid].push_back(pair_key(uint32_t(i), nplanes + f));
                }
            }
        }
    }
    std::vector<uint64_t> all_pp, all_pw;
    for (int t = 0; t < nt; ++t) {
        all_pp.insert(all_pp.end(), pp_keys[t].begin(), pp_keys[t].end());
        all_pw.insert(all_pw.end(), pw_keys[t].begin(), pw_keys[t].end());
    }
    std::vector<uint8_t> existed_pp, existed_pw;
    pp_.merge_from(all_pp, false, existed_pp);
    pw_.merge_from(all_pw, true, existed_pw);
    refresh_physics(physics_dirty_, existed_pp, existed_pw);
    physics_dirty_ = false;

    build_gather_tables();

    ref_pos_ = p.pos;
    wall_ref_disp_.resize(wall_count());
    for (std::size_t k = 0; k < planes.size(); ++k) wall_ref_disp_[k] = planes[k].motion.displacement(time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        wall_ref_disp_[planes.size() + k] = facets[k].motion.displacement(time);
    max_disp_ = 0.0;
    candidates_dirty_ = false;
    ++rebuilds_;
}

void World::build_gather_tables() {
    const std::size_t n = particles.size();
    // Gather CSR: entries in contact order, so the summation order is fixed.
    pp_start_.assign(n + 1, 0);
    for (uint64_t k : pp_.key) {
        ++pp_start_[key_first(k) + 1];
        ++pp_start_[key_second(k) + 1];
    }
    for (std::size_t i = 0; i < n; ++i) pp_start_[i + 1] += pp_start_[i];
    pp_entries_.resize(pp_start_.back());
    {
        std::vector<uint32_t> fill(pp_start_.begin(), pp_start_.end() - 1);
        for (std::size_t c = 0; c < pp_.size(); ++c) {
            pp_entries_[fill[key_first(pp_.key[c])]++] = uint32_t(c);
            pp_entries_[fill[key_second(pp_.key[c])]++] = uint32_t(c) | kSideBit;
        }
    }
    pw_start_.assign(n + 1, 0);
    for (uint64_t k : pw_.key) ++pw_start_[key_first(k) + 1];
    for (std::size_t i = 0; i < n; ++i) pw_start_[i + 1] += pw_start_[i];
}

void World::rebuild_derived_tables() {
    // The bond tables only depend on the bond list; bonds_dirty_ keeps its restored value (a
    // pending rebuild builds them again, with the same result).
    const bool bonds_dirty = bonds_dirty_;
    build_bond_tables();
    bonds_dirty_ = bonds_dirty;
    build_gather_tables();
    // grid_ is scratch of rebuild_candidates(), rebuilt before every use.
    grid_ = CellGrid{};
}

void World::refresh_physics(bool all, const std::vector<uint8_t>& existed_pp,
                            const std::vector<uint8_t>& existed_pw) {
    const Particles& p = particles;
    for (std::size_t c = 0; c < pp_.size(); ++c) {
        if (!all && existed_pp[c]) continue;
        const uint32_t i = key_first(pp_.key[c]), j = key_second(pp_.key[c]);
        // Against a fixed or prescribed particle the moving one meets an infinite mass.
        double m_eff;
        if (p.inv_mass[i] == 0.0) m_eff = p.mass[j];
        else if (p.inv_mass[j] == 0.0) m_eff = p.mass[i];
        else m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
        pp_.phys[c] = make_contact_phys(materials[p.material[i]], p.radius[i],
                                        materials[p.material[j]], p.radius[j], m_eff);
    }
    for (std::size_t c = 0; c < pw_.size(); ++c) {
        if (!all && existed_pw[c]) continue;
        const uint32_t i = key_first(pw_.key[c]), w = key_second(pw_.key[c]);
        const uint32_t wm = w < planes.size() ? planes[w].material : facets[w - planes.size()].material;
        pw_.phys[c] = make_contact_phys(materials[wm], p.radius[i], materials[p.material[i]],
                                        p.radius[i], p.mass[i]);
    }
}

template <bool kEnergy>
void World::particle_contact_forces() {
    const Particles& p = particles;
    const double dt = params.dt;
    const int64_t nc = int64_t(pp_.size());
#pragma omp for schedule(static) nowait
    for (int64_t c = 0; c < nc; ++c) {
        const uint32_t i = key_first(pp_.key[c]), j = key_second(pp_.key[c]);
        ContactEnergyStep* es = nullptr;
        if constexpr (kEnergy) {
            es = &pp_energy_[c];
            *es = ContactEnergyStep{};
        }
        ContactGeom g;
        if (!sphere_sphere(p.pos[i], p.radius[i], p.pos[j], p.radius[j], g)) {
            if constexpr (kEnergy) {
                if (pp_.touching[c]) {  // opened this step: the shear spring's energy is lost
                    const Vec3 n = pp_.hist[c].prev_normal;
                    const Vec3 vrel = (p.vel[j] + cross(p.angvel[j], n * -p.radius[j])) -
                                      (p.vel[i] + cross(p.angvel[i], n * p.radius[i]));
                    es->release = shear_release_energy(pp_.phys[c], pp_.hist[c], vrel, dt);
                }
            }
            // An opened contact loses its shear spring (Yade deletes the interaction). A pair
            // that was not touching already holds zeros: most candidates, so no stores then.
            if (pp_.touching[c]) {
                pp_.hist[c] = ShearHistory{};
                pp_.force[c] = pp_.torque1[c] = pp_.torque2[c] = Vec3{};
                pp_.touching[c] = 0;
            }
            continue;
        }
        const Vec3& n = g.normal;
        // Relative velocity at the contact with the lever arms at the full radii (Yade's
        // avoidGranularRatcheting), body 2 relative to body 1.
        const Vec3 vrel = (p.vel[j] + cross(p.angvel[j], n * -p.radius[j])) -
                          (p.vel[i] + cross(p.angvel[i], n * p.radius[i]));
        const double spin_n = 0.5 * dot(n, p.angvel[i] + p.angvel[j]);
        const Vec3 f = linear_contact_force(pp_.phys[c], g, vrel, spin_n, dt, pp_.hist[c], es);
        const Vec3 nxf = cross(n, -f);
        pp_.force[c] = f;
        pp_.torque1[c] = nxf * g.arm1;
        pp_.torque2[c] = nxf * g.arm2;
        pp_.touching[c] = 1;
    }
}

template <bool kEnergy>
void World::wall_contact_forces() {
    const Particles& p = particles;
    const double dt = params.dt;
    const uint32_t nplanes = uint32_t(planes.size());
    const int64_t nc = int64_t(pw_.size());
#pragma omp for schedule(static) nowait
    for (int64_t c = 0; c < nc; ++c) {
        const uint32_t i = key_first(pw_.key[c]), w = key_second(pw_.key[c]);
        ContactEnergyStep* es = nullptr;
        if constexpr (kEnergy) {
            es = &pw_energy_[c];
            *es = ContactEnergyStep{};
        }
        ContactGeom g;
        bool touch;
        if (w < nplanes)
            touch = sphere_plane(p.pos[i], p.radius[i], plane_point_[w], planes[w].normal,
                                 planes[w].one_sided, g);
        else
            touch = sphere_facet(p.pos[i], p.radius[i], facet_now_[w - nplanes],
                                 facets[w - nplanes].one_sided, g);
        if (!touch) {
            if constexpr (kEnergy) {
                if (pw_.touching[c]) {  // opened this step
                    const Vec3 n = pw_.hist[c].prev_normal;
                    const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel_[w];
                    es->release = shear_release_energy(pw_.phys[c], pw_.hist[c], vrel, dt);
                }
            }
            if (pw_.touching[c]) {
                pw_.hist[c] = ShearHistory{};
                pw_.force[c] = pw_.torque2[c] = Vec3{};
                pw_.touching[c] = 0;
            }
            continue;
        }
        const Vec3& n = g.normal;  // from the wall to the sphere
        const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel_[w];
        const double spin_n = 0.5 * dot(n, p.angvel[i]);
        const Vec3 f = linear_contact_force(pw_.phys[c], g, vrel, spin_n, dt, pw_.hist[c], es);
        pw_.force[c] = f;
        pw_.torque2[c] = cross(n, -f) * g.arm2;
        pw_.point[c] = p.pos[i] - n * g.arm2;
        pw_.touching[c] = 1;
    }
}

template <bool kEnergy>
void World::bond_forces() {
    const Particles& p = particles;
    const double dt = params.dt;
    const int64_t nb = int64_t(bonds_.size());
#pragma omp for schedule(static) nowait
    for (int64_t b = 0; b < nb; ++b) {
        const uint32_t i = bonds_.i[b], j = bonds_.j[b];
        const Vec3 d = p.pos[j] - p.pos[i];
        const double dist = norm(d);
        const Vec3 n = d * (1.0 / dist);
        // Lever arms as for a contact: the bond point sits where the spheres would touch.
        const double half_gap = 0.5 * (p.radius[i] + p.radius[j] - dist);
        const Vec3 vrel = (p.vel[j] + cross(p.angvel[j], n * -p.radius[j])) -
                          (p.vel[i] + cross(p.angvel[i], n * p.radius[i]));
        const double spin_n = 0.5 * dot(n, p.angvel[i] + p.angvel[j]);
        double* elastic = nullptr;
        if constexpr (kEnergy) elastic = &bond_energy_[b];
        const Vec3 f = bond_force(bonds_.phys[b], n, dist, vrel, spin_n, dt, bonds_.hist[b], elastic);
        const Vec3 nxf = cross(n, -f);
        bonds_.force[b] = f;
        bonds_.torque1[b] = nxf * (p.radius[i] - half_gap);
        bonds_.torque2[b] = nxf * (p.radius[j] - half_gap);
    }
}

void World::apply_pressure() {
    const Particles& p = particles;
    const int64_t nn = int64_t(pressure.nodes.size());
    // Each node appears once in the list, so every iteration writes its own slot; the gather
    // adds the slots to the particles' forces.
#pragma omp for schedule(static)
    for (int64_t k = 0; k < nn; ++k) {
        const PressureNode& q = pressure.nodes[k];
        pressure_force_[q.node] = -(tributary_area(p.pos, q) * pressure.dp);
    }
}

void World::gather_forces(bool with_pressure) {
    Particles& p = particles;
    const int64_t n = int64_t(p.size());
#pragma omp for schedule(static)
    for (int64_t i = 0; i < n; ++i) {
        Vec3 f, t;
        // Candidates that do not touch hold zero force: skipping them reads one byte instead
        // of 48 (most candidates in loose packings), and leaves the sums bitwise the same.
        for (uint32_t k = pp_start_[i]; k < pp_start_[i + 1]; ++k) {
            const uint32_t e = pp_entries_[k];
            const uint32_t c = e & ~kSideBit;
            if (!pp_.touching[c]) continue;
            if (e & kSideBit) {
                f += pp_.force[c];
                t += pp_.torque2[c];
            } else {
                f -= pp_.force[c];
                t += pp_.torque1[c];
            }
        }
        for (uint32_t c = pw_start_[i]; c < pw_start_[i + 1]; ++c) {
            if (!pw_.touching[c]) continue;
            f += pw_.force[c];
            t += pw_.torque2[c];
        }
        for (uint32_t k = bond_start_[i]; k < bond_start_[i + 1]; ++k) {
            const uint32_t e = bond_entries_[k];
            const uint32_t b = e & ~kSideBit;
            if (e & kSideBit) {
                f += bonds_.force[b];
                t += bonds_.torque2[b];
            } else {
                f -= bonds_.force[b];
                t += bonds_.torque1[b];
            }
        }
        if (with_pressure) f += pressure_force_[i];
        p.force[i] = f;
        p.torque[i] = t;
    }
}

void World::sum_wall_reactions() {
    wall_force_.assign(wall_count(), Vec3{});
    wall_torque_.assign(wall_count(), Vec3{});
    for (std::size_t c = 0; c < pw_.size(); ++c) {
        if (!pw_.touching[c]) continue;
        const uint32_t w = key_second(pw_.key[c]);
        wall_force_[w] -= pw_.force[c];
        wall_torque_[w] += cross(pw_.point[c], -pw_.force[c]);
    }
}

void World::compute_forces() {
    profile_.start();
    move_walls();
    if (needs_rebuild()) rebuild_candidates();
    if (physics_dirty_) {
        refresh_physics(true, {}, {});
        physics_dirty_ = false;
    }
    profile_.lap(Phase::kNeighbour);
    const bool track = params.track_energy;
    const bool press = pressure.dp != 0.0 && !pressure.nodes.empty();
    if (track) {
        // Every slot is written by the kernels below.
        pp_energy_.resize(pp_.size());
        pw_energy_.resize(pw_.size());
        bond_energy_.resize(bonds_.size());
    }
    const bool pslots = press || track;  // the energy ledger reads the (zero) slots too
    if (pslots) pressure_force_.resize(particles.size());
    const bool prof = profile_.enabled();
    const int64_t n = int64_t(particles.size());
    // One parallel region for the whole force computation: the kernels write their own
    // slots and do not wait for each other; two barriers order pressure and gather after them.
#pragma omp parallel num_threads(params.threads)
    {
        if (pslots) {
#pragma omp for schedule(static) nowait
            for (int64_t i = 0; i < n; ++i) pressure_force_[i] = Vec3{};
        }
        if (track) {
            particle_contact_forces<true>();
            wall_contact_forces<true>();
        } else {
            particle_contact_forces<false>();
            wall_contact_forces<false>();
        }
        if (prof) {
#pragma omp barrier
#pragma omp master
            profile_.lap(Phase::kContacts);
        }
        if (track) bond_forces<true>();
        else bond_forces<false>();
#pragma omp barrier
        if (prof) {
#pragma omp master
            profile_.lap(Phase::kBonds);
        }
        if (press) apply_pressure();  // ends with a barrier
        if (prof) {
#pragma omp master
            profile_.lap(Phase::kPressure);
        }
        gather_forces(press);
    }
    energy_ready_ = track;
    sum_wall_reactions();
    profile_.lap(Phase::kGather);
}

Vec3 World::total_force(std::size_t i) const {
    const Particles& p = particles;
    return p.force[i] + p.ext_force[i] + params.gravity * p.mass[i];
}

Vec3 World::velocity_at_time(std::size_t i) const {
    const Particles& p = particles;
    if (p.inv_mass[i] == 0.0) return p.vel[i];
    const Vec3 a = damped_acceleration(total_force(i), p.inv_mass[i], p.vel[i], params.dt, params.local_damping);
    return p.vel[i] + a * (0.5 * params.dt);
}

Vec3 World::angular_velocity_at_time(std::size_t i) const {
    const Particles& p = particles;
    if (p.inv_inertia[i] == 0.0) return p.angvel[i];
    const Vec3 a = damped_angular_acceleration(p.torque[i], p.inv_inertia[i], p.angvel[i], params.local_damping);
    return p.angvel[i] + a * (0.5 * params.dt);
}

// Trapezoid rule per step interval: a force F_n acting at t_n does the work
// F_n . v(t_n - dt/2) dt/2 on [t_n - dt, t_n] ("back" half) and F_n . v(t_n + dt/2) dt/2 on
// [t_n, t_n + dt] ("forward" half). See docs/energy.md. Called by advance_particles<true>
// after particle i moved: v0, w0 the velocities before, v1, w1 after (passed rather than read
// back: reading a Vec3 just stored component by component stalls), a, al the accelerations.
[[gnu::always_inline]] inline World::ParticleEnergyStep World::particle_energy(std::size_t i, const Vec3& v0,
                                                                               const Vec3& w0, const Vec3& v1,
                                                                               const Vec3& w1, const Vec3& a,
                                                                               const Vec3& al) const {
    const Particles& p = particles;
    const double h = 0.5 * params.dt;
    const Vec3 fp = pressure_force_[i];
    ParticleEnergyStep e;
    if (p.flags[i] & kPrescribed) {
        // Work done by the prescribed particle on the others: minus the force they exert on it
        // (contacts and bonds, not the pressure it carries) times its displacement.
        const Vec3 fint = p.force[i] - fp;
        e.back[kBoundary] = -dot(fint, v0) * h;
        e.fwd[kBoundary] = -dot(fint, v1) * h;
        return e;
    }
    const Vec3 fg = params.gravity * p.mass[i];
    e.back[kGravity] = dot(fg, v0) * h;
    e.fwd[kGravity] = dot(fg, v1) * h;
    e.back[kPressure] = dot(fp, v0) * h;
    e.fwd[kPressure] = dot(fp, v1) * h;
    const Vec3 fx = p.ext_force[i];
    e.back[kExternal] = dot(fx, v0) * h;
    e.fwd[kExternal] = dot(fx, v1) * h;
    // Solid sphere I = 2/5 m r^2 (unless rotation was blocked by inv_inertia = 0).
    const double inertia = p.inv_inertia[i] > 0.0 ? 0.4 * p.mass[i] * p.radius[i] * p.radius[i] : 0.0;
    e.kinetic = 0.5 * p.mass[i] * dot(v0, v1) + 0.5 * inertia * dot(w0, w1);
    if (params.local_damping != 0.0) {
        // The damping force and torque the integrator removed: F - m a, T - I alpha
        // (= lambda sign(a_k v_k) F_k, see damped_acceleration).
        const Vec3 df = total_force(i) - a * p.mass[i];
        const Vec3 dq = inertia > 0.0 ? p.torque[i] - al * inertia : Vec3{};
        e.back[kDamping] = (dot(df, v0) + dot(dq, w0)) * h;
        e.fwd[kDamping] = (dot(df, v1) + dot(dq, w1)) * h;
    }
    return e;
}

template <bool kEnergy>
double World::advance_particles(double t1) {
    Particles& p = particles;
    const double dt = params.dt, lambda = params.local_damping;
    const int64_t n = int64_t(p.size());
    // Moves free particle i (prescribed: onto its motion); returns its energy terms of the step.
    const auto advance = [&](int64_t i) __attribute__((always_inline)) {
        ParticleEnergyStep e;
        const uint32_t fl = p.flags[i];
        [[maybe_unused]] const Vec3 v0 = p.vel[i], w0 = p.angvel[i];
        if (fl & kPrescribed) {
            const Motion& m = motions[p.motion[i]];
            p.vel[i] = m.mean_velocity(time, t1);
            p.pos[i] = p.ref_pos[i] + m.displacement(t1);
            if constexpr (kEnergy) e = particle_energy(size_t(i), v0, w0, m.mean_velocity(time, t1), w0, Vec3{}, Vec3{});
        } else {
            const Vec3 a = damped_acceleration(total_force(i), p.inv_mass[i], p.vel[i], dt, lambda);
            p.vel[i] += a * dt;
            p.pos[i] += p.vel[i] * dt;
            const Vec3 al = damped_angular_acceleration(p.torque[i], p.inv_inertia[i], p.angvel[i], lambda);
            p.angvel[i] += al * dt;
            if constexpr (kEnergy) e = particle_energy(size_t(i), v0, w0, v0 + a * dt, w0 + al * dt, a, al);
        }
        return e;
    };
    double max_d2 = 0.0;
    if constexpr (!kEnergy) {
#pragma omp parallel for num_threads(params.threads) schedule(static) reduction(max : max_d2)
        for (int64_t i = 0; i < n; ++i) {
            if (p.flags[i] & kFixed) continue;
            advance(i);
            max_d2 = std::max(max_d2, norm2(p.pos[i] - ref_pos_[i]));
        }
    } else {
        // The energy terms are summed here, per fixed block of kEnergyBlock particles in index
        // order (account_energy() adds the blocks in order): the same for any thread count, and
        // no per-particle record written and read back.
        const int64_t nblk = (n + kEnergyBlock - 1) / kEnergyBlock;
        particle_blocks_.assign(std::size_t(nblk * kParticleSums), 0.0);
#pragma omp parallel for num_threads(params.threads) schedule(static) reduction(max : max_d2)
        for (int64_t b = 0; b < nblk; ++b) {
            double s[kParticleSums] = {};  // local: stores through a pointer would alias p's arrays
            for (int64_t i = b * kEnergyBlock; i < std::min(n, (b + 1) * kEnergyBlock); ++i) {
                if (p.flags[i] & kFixed) continue;  // contributes nothing
                const ParticleEnergyStep e = advance(i);
                for (int k = 0; k < kTerms; ++k) {
                    s[k] += e.back[k];
                    s[kTerms + k] += e.fwd[k];
                }
                s[2 * kTerms] += e.kinetic;
                max_d2 = std::max(max_d2, norm2(p.pos[i] - ref_pos_[i]));
            }
            std::copy(s, s + kParticleSums, particle_blocks_.begin() + b * kParticleSums);
        }
    }
    return max_d2;
}

void World::integrate() {
    const double dt = params.dt;
    const double t1 = time + dt;
    const double t_n = time;
    const bool track = params.track_energy && energy_ready_;
    double max_d2;
    if (track) {
        max_d2 = advance_particles<true>(t1);
    } else {
        max_d2 = advance_particles<false>(t1);
    }
    max_disp_ = std::sqrt(max_d2);
    profile_.lap(Phase::kIntegration);
    // Rebase when dt changed or someone set the clock (e.g. a restart from a checkpoint).
    if (dt != dt_of_base_ || time != time_base_ + double(steps - step_base_) * dt_of_base_) {
        time_base_ = time;
        step_base_ = steps;
        dt_of_base_ = dt;
    }
    ++steps;
    time = time_base_ + double(steps - step_base_) * dt;
    if (track) {
        account_energy(t_n);
        profile_.lap(Phase::kEnergy);
    }
    energy_ready_ = false;
}

void World::account_energy(double t_n) {
    // Sums the step's per-particle, per-wall, per-contact and per-bond terms and books them:
    // back halves and the contacts' terms on [t_n - dt, t_n], forward halves pending until the
    // next step. The sums run in parallel over fixed blocks of kBlock indices, each summed in
    // index order, then the blocks in order: the same numbers for any thread count.
    const Particles& p = particles;
    const double dt = params.dt, h = 0.5 * dt;
    EnergyLedger& L = energy_;
    const bool first = L.steps == 0;

    // Walls translate: their work is the force on the particles times the wall's displacement.
    // The forward half uses the velocity the next step's move_walls() will compute.
    const std::size_t nw = wall_count();
    wall_vel_next_.resize(nw);
    std::vector<Vec3>& v_next = wall_vel_next_;
    for (std::size_t k = 0; k < planes.size(); ++k) v_next[k] = planes[k].motion.mean_velocity(time - dt, time);
    for (std::size_t k = 0; k < facets.size(); ++k)
        v_next[planes.size() + k] = facets[k].motion.mean_velocity(time - dt, time);

    constexpr int64_t kBlock = kEnergyBlock;
    constexpr int kPT = kParticleSums;   // particle terms, summed per block by advance_particles()
    constexpr int kCT = 5;               // contact terms: elastic, slip, release, viscous back, fwd
    const auto blocks = [](int64_t n) { return (n + kBlock - 1) / kBlock; };
    const int64_t npp = int64_t(pp_.size()), npw = int64_t(pw_.size()), nbd = int64_t(bond_energy_.size());
    const int64_t bp = int64_t(particle_blocks_.size()) / kPT, bpp = blocks(npp), bpw = blocks(npw),
                  bbd = blocks(nbd);
    energy_blocks_.assign(std::size_t((bpp + bpw) * kCT + bbd), 0.0);
    const double* const sp = particle_blocks_.data();
    double* const spp = energy_blocks_.data();
    double* const spw = spp + bpp * kCT;
    double* const sbd = spw + bpw * kCT;
#pragma omp parallel num_threads(params.threads)
    {
        // Contact terms; `vrel(c)`: velocity of body 2 relative to body 1 at t_n + dt/2, for
        // the dashpot's forward half.
        const auto contact_blocks = [&](const std::vector<ContactEnergyStep>& E, int64_t nc, int64_t nblk,
                                        double* out, auto&& vrel) {
#pragma omp for schedule(static) nowait
            for (int64_t b = 0; b < nblk; ++b) {
                double* s = out + b * kCT;
                for (int64_t c = b * kBlock; c < std::min(nc, (b + 1) * kBlock); ++c) {
                    const ContactEnergyStep& e = E[c];
                    s[0] += e.elastic;
                    s[1] += e.slip;
                    s[2] += e.release;
                    s[3] += e.viscous;
                    if (e.fv != Vec3{}) s[4] -= dot(e.fv, vrel(c)) * h;
                }
            }
        };
        contact_blocks(pp_energy_, npp, bpp, spp,
                       [&](int64_t c) { return p.vel[key_second(pp_.key[c])] - p.vel[key_first(pp_.key[c])]; });
        contact_blocks(pw_energy_, npw, bpw, spw,
                       [&](int64_t c) { return p.vel[key_first(pw_.key[c])] - v_next[key_second(pw_.key[c])]; });
#pragma omp for schedule(static) nowait
        for (int64_t b = 0; b < bbd; ++b)
            for (int64_t k = b * kBlock; k < std::min(nbd, (b + 1) * kBlock); ++k) sbd[b] += bond_energy_[k];
    }

    double back[kTerms] = {}, fwd[kTerms] = {}, kinetic = 0;
    for (int64_t b = 0; b < bp; ++b) {
        const double* s = sp + b * kPT;
        for (int k = 0; k < kTerms; ++k) {
            back[k] += s[k];
            fwd[k] += s[kTerms + k];
        }
        kinetic += s[2 * kTerms];
    }
    for (std::size_t w = 0; w < nw; ++w) {
        back[kBoundary] -= dot(wall_force_[w], wall_vel_[w]) * h;
        fwd[kBoundary] -= dot(wall_force_[w], v_next[w]) * h;
    }
    double cs[kCT] = {}, elastic_b = 0;
    for (int64_t b = 0; b < bpp + bpw; ++b)
        for (int k = 0; k < kCT; ++k) cs[k] += spp[b * kCT + k];  // pp blocks, then pw blocks
    for (int64_t b = 0; b < bbd; ++b) elastic_b += sbd[b];
    const double elastic_c = cs[0], slip = cs[1], release = cs[2], visc_back = cs[3], visc_fwd = cs[4];

    if (!first) {  // the back halves and the kernels' terms belong to [t_n - dt, t_n]
        L.boundary_work += L.pending_boundary + back[kBoundary];
        L.pressure_work += L.pending_pressure + back[kPressure];
        L.gravity_work += L.pending_gravity + back[kGravity];
        L.external_work += L.pending_external + back[kExternal];
        L.damping_dissipation += L.pending_damping + back[kDamping];
        L.viscous_dissipation += L.pending_viscous + visc_back;
        L.friction_slip += slip;
        L.shear_release += release;
    }
    L.pending_boundary = fwd[kBoundary];
    L.pending_pressure = fwd[kPressure];
    L.pending_gravity = fwd[kGravity];
    L.pending_external = fwd[kExternal];
    L.pending_damping = fwd[kDamping];
    L.pending_viscous = visc_fwd;
    L.kinetic = kinetic;
    L.elastic_contacts = elastic_c;
    L.elastic_bonds = elastic_b;
    L.time = t_n;
    if (first) {
        L.t0 = t_n;
        L.stored0 = L.stored();
    }
    ++L.steps;
}

void World::step() {
    compute_forces();
    integrate();
}

std::size_t World::contact_count() const { return pp_.count_touching() + pw_.count_touching(); }

}  // namespace dem

#include "dem/core/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "dem/core/kernels.h"
#include "dem/core/parallel.h"
#include "dem/detect/geometry.h"
#include "dem/integrate/leapfrog.h"

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
    candidates_dirty_ = prescribed_dirty_ = true;
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
    physics_dirty_ = prescribed_dirty_ = true;  // reduced masses of its contacts change
}

void World::set_prescribed(uint32_t i, uint32_t motion) {
    Particles& p = particles;
    p.flags[i] = (p.flags[i] | kPrescribed) & ~uint32_t(kFixed);
    p.inv_mass[i] = p.inv_inertia[i] = 0.0;
    p.angvel[i] = Vec3{};
    p.motion[i] = int32_t(motion);
    // The motion's displacement is measured from where the particle is at time 0 of the motion.
    p.ref_pos[i] = p.pos[i] - motions[motion].displacement(time);
    physics_dirty_ = prescribed_dirty_ = true;
}

void World::clear_facets() {
    // Drop the facet contacts now, so facets added later never inherit their history.
    for (std::size_t s = 0; s < walls_.size(); ++s)
        if (walls_.cand[s] != kNoSlot && walls_.j[s] >= planes.size()) {
            pw_cand_.slot[walls_.cand[s]] = kNoSlot;
            walls_.cand[s] = kNoSlot;
            walls_.force[s] = walls_.torque2[s] = Vec3{};
        }
    facets.clear();
    facet_now_.clear();
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
    bonds_.shear.emplace_back();
    bonds_.prev_normal.emplace_back();
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


ContactPhys World::pair_phys(uint32_t i, uint32_t j) const {
    const Particles& p = particles;
    // Against a fixed or prescribed particle the moving one meets an infinite mass.
    double m_eff;
    if (p.inv_mass[i] == 0.0) m_eff = p.mass[j];
    else if (p.inv_mass[j] == 0.0) m_eff = p.mass[i];
    else m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
    return make_contact_phys(materials[p.material[i]], p.radius[i], materials[p.material[j]], p.radius[j], m_eff);
}

ContactPhys World::wall_phys(uint32_t i, uint32_t w) const {
    const Particles& p = particles;
    const uint32_t wm = w < planes.size() ? planes[w].material : facets[w - planes.size()].material;
    return make_contact_phys(materials[wm], p.radius[i], materials[p.material[i]], p.radius[i], p.mass[i]);
}

void World::compact_contacts(bool refresh) {
    // Walks the candidates in order and copies each live contact into fresh stores, so slots
    // follow the candidate order (neighbouring pairs neighbouring in memory) and holes vanish.
    ActiveContacts nf, ns, nw;
    const auto copy = [](const ActiveContacts& src, uint32_t c, ActiveContacts& dst, uint32_t k,
                         const ContactPhys& ph, bool keep_shear) {
        const uint32_t t = dst.add(src.i[c], src.j[c], k, ph);
        if (keep_shear) {
            dst.shear[t] = src.shear[c];
            dst.prev_normal[t] = src.prev_normal[c];
        }
        dst.force[t] = src.force[c];
        dst.torque1[t] = src.torque1[c];
        dst.torque2[t] = src.torque2[c];
        dst.point[t] = src.point[c];
        dst.fv[t] = src.fv[c];
        return t;
    };
    // A frictional pair whose friction became zero loses its shear spring: the ledger books
    // the spring's energy as released.
    const auto dropped = [](const ActiveContacts& src, uint32_t c) {
        return src.phys[c].ks > 0.0 ? norm2(src.shear[c]) / (2.0 * src.phys[c].ks) : 0.0;
    };
    const std::size_t n = particles.size();
    for (std::size_t i = 0; i < n && !pp_cand_.start.empty(); ++i)
        for (uint32_t k = pp_cand_.start[i]; k < pp_cand_.start[i + 1]; ++k) {
            const uint32_t s = pp_cand_.slot[k];
            if (s == kNoSlot) continue;
            const bool was_smooth = s & kSmoothBit;
            const ActiveContacts& src = was_smooth ? smooth_ : fric_;
            const uint32_t c = s & ~kSmoothBit;
            const ContactPhys ph = refresh ? pair_phys(uint32_t(i), pp_cand_.other[k]) : src.phys[c];
            const bool smooth = ph.mu == 0.0;
            if (smooth && !was_smooth) dropped_shear_energy_ += dropped(src, c);
            const uint32_t t = copy(src, c, smooth ? ns : nf, k, ph, !smooth && !was_smooth);
            pp_cand_.slot[k] = t | (smooth ? kSmoothBit : 0u);
        }
    for (std::size_t i = 0; i < n && !pw_cand_.start.empty(); ++i)
        for (uint32_t k = pw_cand_.start[i]; k < pw_cand_.start[i + 1]; ++k) {
            const uint32_t s = pw_cand_.slot[k];
            if (s == kNoSlot) continue;
            const ContactPhys ph = refresh ? wall_phys(uint32_t(i), pw_cand_.other[k]) : walls_.phys[s];
            const bool keep = ph.mu != 0.0;
            if (!keep) dropped_shear_energy_ += dropped(walls_, s);
            pw_cand_.slot[k] = copy(walls_, s, nw, k, ph, keep);
        }
    fric_ = std::move(nf);
    smooth_ = std::move(ns);
    walls_ = std::move(nw);
}

void World::build_reverse_table() {
    const std::size_t n = particles.size();
    CandidateList& c = pp_cand_;
    c.rstart.assign(n + 1, 0);
    for (uint32_t j : c.other) ++c.rstart[j + 1];
    for (std::size_t i = 0; i < n; ++i) c.rstart[i + 1] += c.rstart[i];
    c.rentry.resize(c.other.size());
    std::vector<uint32_t> fill(c.rstart.begin(), c.rstart.end() - 1);
    for (uint32_t k = 0; k < c.other.size(); ++k) c.rentry[fill[c.other[k]]++] = k;
}

void World::rebuild_derived_tables() {
    // The bond tables only depend on the bond list; bonds_dirty_ keeps its restored value (a
    // pending rebuild builds them again, with the same result).
    const bool bonds_dirty = bonds_dirty_;
    build_bond_tables();
    bonds_dirty_ = bonds_dirty;
    if (!pp_cand_.start.empty()) build_reverse_table();
    prescribed_dirty_ = true;
    // grid_ is scratch of rebuild_candidates(), rebuilt before every use.
    grid_ = CellGrid{};
}

// ---------------------------------------------------------------- contacts open and close

void World::find_new_contacts() {
    // Inside the parallel region of compute_forces(). The same geometric tests as the force
    // kernels, so a pair found here is found touching there.
    const Particles& p = particles;
    const int64_t n = int64_t(p.size());
    const uint32_t nplanes = uint32_t(planes.size());
    const int tid = thread_id();
    std::vector<uint32_t>& npp = new_pp_[tid];
    std::vector<uint32_t>& npw = new_pw_[tid];
    npp.clear();
    npw.clear();
    const bool walls = !pw_cand_.other.empty();
#pragma omp for schedule(static)
    for (int64_t i = 0; i < n; ++i) {
        const Vec3 xi = p.pos[i];
        const double ri = p.radius[i];
        for (uint32_t k = pp_cand_.start[i]; k < pp_cand_.start[i + 1]; ++k) {
            if (pp_cand_.slot[k] != kNoSlot) continue;
            const uint32_t j = pp_cand_.other[k];
            const Vec3 d = p.pos[j] - xi;
            const double rs = ri + p.radius[j];
            if (norm2(d) < rs * rs) {
                npp.push_back(uint32_t(i));
                npp.push_back(k);
            }
        }
        if (!walls) continue;
        for (uint32_t k = pw_cand_.start[i]; k < pw_cand_.start[i + 1]; ++k) {
            if (pw_cand_.slot[k] != kNoSlot) continue;
            const uint32_t w = pw_cand_.other[k];
            ContactGeom g;
            const bool touch = w < nplanes
                                   ? sphere_plane(xi, ri, plane_point_[w], planes[w].normal, planes[w].one_sided, g)
                                   : sphere_facet(xi, ri, facet_now_[w - nplanes], facets[w - nplanes].one_sided, g);
            if (touch) {
                npw.push_back(uint32_t(i));
                npw.push_back(k);
            }
        }
    }
}

void World::activate_new_contacts() {
    // Serial, in candidate order (the per-thread lists hold consecutive particle ranges).
    for (const auto& list : new_pp_)
        for (std::size_t q = 0; q < list.size(); q += 2) {
            const uint32_t i = list[q], k = list[q + 1], j = pp_cand_.other[k];
            const ContactPhys ph = pair_phys(i, j);
            if (ph.mu == 0.0) pp_cand_.slot[k] = smooth_.add(i, j, k, ph) | kSmoothBit;
            else pp_cand_.slot[k] = fric_.add(i, j, k, ph);
        }
    for (const auto& list : new_pw_)
        for (std::size_t q = 0; q < list.size(); q += 2) {
            const uint32_t i = list[q], k = list[q + 1], w = pw_cand_.other[k];
            pw_cand_.slot[k] = walls_.add(i, w, k, wall_phys(i, w));
        }
}

void World::release_opened_contacts() {
    const auto release = [](ActiveContacts& a, CandidateList& cl, const std::vector<std::vector<uint32_t>>& opened) {
        for (const auto& list : opened)
            for (uint32_t s : list) {
                cl.slot[a.cand[s]] = kNoSlot;
                a.cand[s] = kNoSlot;
            }
    };
    release(fric_, pp_cand_, opened_fric_);
    release(smooth_, pp_cand_, opened_smooth_);
    release(walls_, pw_cand_, opened_walls_);
}

// ---------------------------------------------------------------- forces

template <bool kEnergy>
void World::wall_contact_forces() {
    // Few contacts (caps, funnel): scalar, over this thread's blocks of slots.
    const Particles& p = particles;
    const double dt = params.dt;
    const uint32_t nplanes = uint32_t(planes.size());
    const int64_t ns = int64_t(walls_.size());
    const auto [b0, b1] = thread_range(kernels::block_count(walls_.size()), thread_id(), thread_count());
    std::vector<uint32_t>& opened = opened_walls_[thread_id()];
    opened.clear();
    for (int64_t b = b0; b < b1; ++b) {
        double sum[kernels::kPairSums] = {};
        for (int64_t s = b * kernels::kBlock; s < std::min(ns, (b + 1) * kernels::kBlock); ++s) {
            if (walls_.cand[s] == kNoSlot) continue;
            const uint32_t i = walls_.i[s], w = walls_.j[s];
            const ContactPhys& ph = walls_.phys[s];
            ContactGeom g;
            const bool touch = w < nplanes
                                   ? sphere_plane(p.pos[i], p.radius[i], plane_point_[w], planes[w].normal,
                                                  planes[w].one_sided, g)
                                   : sphere_facet(p.pos[i], p.radius[i], facet_now_[w - nplanes],
                                                  facets[w - nplanes].one_sided, g);
            if (!touch) {
                if constexpr (kEnergy) {  // opened this step: the shear spring's energy is lost
                    const Vec3 n = walls_.prev_normal[s];
                    const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel_[w];
                    sum[kernels::kRelease] += shear_release_energy(ph.ks, walls_.shear[s], vrel, dt);
                }
                walls_.shear[s] = walls_.prev_normal[s] = walls_.force[s] = walls_.torque2[s] = walls_.fv[s] = Vec3{};
                opened.push_back(uint32_t(s));
                continue;
            }
            const Vec3& n = g.normal;  // from the wall to the sphere
            const Vec3 vrel = (p.vel[i] + cross(p.angvel[i], n * -p.radius[i])) - wall_vel_[w];
            ContactEnergyLanes<double> e;
            V3<double> f;
            if (ph.mu == 0.0) {
                f = normal_contact_force_lanes<kEnergy>(ph.kn, ph.cn, lanes(n), g.overlap, lanes(vrel), dt, &e);
                walls_.torque2[s] = Vec3{};
            } else {
                V3<double> fs = lanes(walls_.shear[s]), prev = lanes(walls_.prev_normal[s]);
                const double spin_n = 0.5 * dot(n, p.angvel[i]);
                f = linear_contact_force_lanes<kEnergy>(ph.kn, ph.ks, ph.mu, ph.cn, lanes(n), g.overlap, lanes(vrel),
                                                        spin_n, dt, fs, prev, &e);
                walls_.shear[s] = vec3(fs);
                walls_.prev_normal[s] = vec3(prev);
                walls_.torque2[s] = cross(n, -vec3(f)) * g.arm2;
            }
            walls_.force[s] = vec3(f);
            walls_.point[s] = p.pos[i] - n * g.arm2;
            if constexpr (kEnergy) {
                sum[kernels::kElastic] += e.elastic;
                sum[kernels::kSlip] += e.slip;
                sum[kernels::kViscous] += e.viscous;
                walls_.fv[s] = vec3(e.fv);
            }
        }
        if constexpr (kEnergy) std::copy(sum, sum + kernels::kPairSums, wall_energy_.begin() + b * kernels::kPairSums);
    }
}

void World::apply_pressure() {
    const Particles& p = particles;
    const auto [k0, k1] = thread_range(int64_t(pressure.nodes.size()), thread_id(), thread_count());
    // Each node appears once in the list, so every iteration writes its own slot; the gather
    // adds the slots to the particles' forces.
    for (int64_t k = k0; k < k1; ++k) {
        const PressureNode& q = pressure.nodes[k];
        pressure_force_[q.node] = -(tributary_area(p.pos, q) * pressure.dp);
    }
}

void World::gather_forces(bool with_pressure) {
    Particles& p = particles;
    const int64_t n = int64_t(p.size());
    const CandidateList& pc = pp_cand_;
    const CandidateList& wc = pw_cand_;
    const bool walls = !wc.other.empty();
#pragma omp for schedule(static)
    for (int64_t i = 0; i < n; ++i) {
        Vec3 f, t;
        // Particle i as body 1, then as body 2, each in candidate order: a fixed order.
        for (uint32_t k = pc.start[i]; k < pc.start[i + 1]; ++k) {
            const uint32_t s = pc.slot[k];
            if (s == kNoSlot) continue;
            if (s & kSmoothBit) {
                f -= smooth_.force[s & ~kSmoothBit];
            } else {
                f -= fric_.force[s];
                t += fric_.torque1[s];
            }
        }
        for (uint32_t e = pc.rstart[i]; e < pc.rstart[i + 1]; ++e) {
            const uint32_t s = pc.slot[pc.rentry[e]];
            if (s == kNoSlot) continue;
            if (s & kSmoothBit) {
                f += smooth_.force[s & ~kSmoothBit];
            } else {
                f += fric_.force[s];
                t += fric_.torque2[s];
            }
        }
        if (walls)
            for (uint32_t k = wc.start[i]; k < wc.start[i + 1]; ++k) {
                const uint32_t s = wc.slot[k];
                if (s == kNoSlot) continue;
                f += walls_.force[s];
                t += walls_.torque2[s];
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
    for (std::size_t s = 0; s < walls_.size(); ++s) {
        if (walls_.cand[s] == kNoSlot) continue;
        const uint32_t w = walls_.j[s];
        wall_force_[w] -= walls_.force[s];
        wall_torque_[w] += cross(walls_.point[s], -walls_.force[s]);
    }
}

void World::compute_forces() {
    profile_.start();
    move_walls();
    if (needs_rebuild()) rebuild_candidates();
    else if (physics_dirty_) compact_contacts(true);
    physics_dirty_ = false;
    profile_.lap(Phase::kNeighbour);

    const bool track = params.track_energy;
    const bool press = pressure.dp != 0.0 && !pressure.nodes.empty();
    const int nt = std::max(1, params.threads);
    for (auto* v : {&new_pp_, &new_pw_, &opened_fric_, &opened_smooth_, &opened_walls_}) v->resize(nt);
    // Pressure slots: only the nodes' entries are written each step, the others stay zero; so
    // the array is zeroed whenever the node list changes or the pressure is switched on or off.
    const bool pslots = press || track;  // the energy ledger reads the (zero) slots too
    if (pslots) {
        if (pressure_force_.size() != particles.size() || press != pressure_was_on_ || pressure.nodes.size() != pressure_seen_.size() ||
            (press && std::memcmp(pressure.nodes.data(), pressure_seen_.data(), pressure.nodes.size() * sizeof(PressureNode)) != 0)) {
            pressure_force_.assign(particles.size(), Vec3{});
            pressure_seen_ = pressure.nodes;
            pressure_was_on_ = press;
        }
    }
    const bool prof = profile_.enabled();
    const double dt = params.dt;
    // One parallel region for the whole force computation: the kernels write their own
    // slots and do not wait for each other; barriers order the contact bookkeeping before
    // them and the gather after them.
#pragma omp parallel num_threads(nt)
    {
        find_new_contacts();  // ends with a barrier
#pragma omp single
        {
            activate_new_contacts();
            if (track) {
                // Every block sum is written by the kernels below.
                fric_energy_.resize(kernels::block_count(fric_.size()) * kernels::kPairSums);
                smooth_energy_.resize(kernels::block_count(smooth_.size()) * kernels::kPairSums);
                wall_energy_.resize(kernels::block_count(walls_.size()) * kernels::kPairSums);
                bond_energy_.resize(kernels::block_count(bonds_.size()));
            }
        }  // ends with a barrier
        if (prof) {
#pragma omp master
            profile_.lap(Phase::kNeighbour);
        }
        const int tid = thread_id();
        const auto [f0, f1] = thread_range(kernels::block_count(fric_.size()), tid, nt);
        kernels::frictional_pairs({&particles, &fric_, dt, f0, f1, track ? fric_energy_.data() : nullptr,
                                   &(opened_fric_[tid] = {})});
        const auto [s0, s1] = thread_range(kernels::block_count(smooth_.size()), tid, nt);
        kernels::smooth_pairs({&particles, &smooth_, dt, s0, s1, track ? smooth_energy_.data() : nullptr,
                               &(opened_smooth_[tid] = {})});
        if (track) wall_contact_forces<true>();
        else wall_contact_forces<false>();
        if (prof) {
#pragma omp barrier
#pragma omp master
            profile_.lap(Phase::kContacts);
        }
        const auto [b0, b1] = thread_range(kernels::block_count(bonds_.size()), tid, nt);
        kernels::bonds({&particles, &bonds_, dt, b0, b1, track ? bond_energy_.data() : nullptr});
        if (prof) {
#pragma omp barrier
#pragma omp master
            profile_.lap(Phase::kBonds);
        }
        if (press) apply_pressure();
#pragma omp barrier
        if (prof) {
#pragma omp master
            profile_.lap(Phase::kPressure);
        }
        gather_forces(press);
    }
    sum_wall_reactions();
    release_opened_contacts();
    energy_ready_ = track;
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


void World::integrate() {
    Particles& p = particles;
    const double dt = params.dt;
    const double t1 = time + dt;
    const double t_n = time;
    const bool track = params.track_energy && energy_ready_;
    const int nt = std::max(1, params.threads);
    const int64_t nblk = kernels::block_count(p.size());
    if (track) particle_blocks_.assign(std::size_t(nblk * kernels::kParticleSums), 0.0);
    kernels::AdvanceArgs args;
    args.p = &p;
    args.ext_force = p.ext_force.data();
    args.pressure = track && !pressure_force_.empty() ? pressure_force_.data() : nullptr;
    args.ref_pos = ref_pos_.data();
    args.gravity = params.gravity;
    args.dt = dt;
    args.lambda = params.local_damping;
    args.energy = track ? particle_blocks_.data() : nullptr;
    double max_d2 = 0.0;
#pragma omp parallel num_threads(nt) reduction(max : max_d2)
    {
        kernels::AdvanceArgs a = args;
        std::tie(a.block_begin, a.block_end) = thread_range(nblk, thread_id(), thread_count());
        max_d2 = kernels::advance(a);
    }
    // Prescribed particles follow their motion (few: serial, in index order).
    if (prescribed_dirty_) {
        prescribed_.clear();
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p.flags[i] & kPrescribed) prescribed_.push_back(uint32_t(i));
        prescribed_dirty_ = false;
    }
    prescribed_energy_[0] = prescribed_energy_[1] = 0.0;
    for (uint32_t i : prescribed_) {
        const Motion& m = motions[p.motion[i]];
        const Vec3 v0 = p.vel[i];
        p.vel[i] = m.mean_velocity(time, t1);
        p.pos[i] = p.ref_pos[i] + m.displacement(t1);
        max_d2 = std::max(max_d2, norm2(p.pos[i] - ref_pos_[i]));
        if (track) {
            // Work done by the prescribed particle on the others: minus the force they exert
            // on it (contacts and bonds, not the pressure it carries) times its displacement.
            const double h = 0.5 * dt;
            const Vec3 fint = p.force[i] - pressure_force_[i];
            prescribed_energy_[0] -= dot(fint, v0) * h;
            prescribed_energy_[1] -= dot(fint, p.vel[i]) * h;
        }
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

void World::step() {
    compute_forces();
    integrate();
}

std::size_t World::contact_count() const { return particle_contact_count() + walls_.live_count(); }

}  // namespace dem

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
    if (!p.ext_force.empty()) p.ext_force.emplace_back();
    p.radius.push_back(d.radius);
    p.mass.push_back(m);
    p.inv_mass.push_back(free ? 1.0 / m : 0.0);
    p.inv_inertia.push_back(free ? 1.0 / (0.4 * m * d.radius * d.radius) : 0.0);
    p.material.push_back(d.material);
    p.mask.push_back(d.mask);
    p.flags.push_back(d.flags);
    p.motion.push_back(-1);
    if (!p.ref_pos.empty()) p.ref_pos.push_back(d.position);
    candidates_dirty_ = prescribed_dirty_ = true;
    return uint32_t(p.size() - 1);
}

void World::reserve(std::size_t n) {
    Particles& p = particles;
    for (auto* v : {&p.pos, &p.vel, &p.angvel, &p.force, &p.torque}) v->reserve(n);
    for (auto* v : {&p.radius, &p.mass, &p.inv_mass, &p.inv_inertia}) v->reserve(n);
    for (auto* v : {&p.material, &p.mask, &p.flags}) v->reserve(n);
    p.motion.reserve(n);
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
    packed_valid_ = false;
}

void World::set_prescribed(uint32_t i, uint32_t motion) {
    Particles& p = particles;
    p.flags[i] = (p.flags[i] | kPrescribed) & ~uint32_t(kFixed);
    p.inv_mass[i] = p.inv_inertia[i] = 0.0;
    p.angvel[i] = Vec3{};
    p.motion[i] = int32_t(motion);
    // The motion's displacement is measured from where the particle is at time 0 of the motion.
    if (p.ref_pos.size() != p.size()) p.ref_pos = p.pos;
    p.ref_pos[i] = p.pos[i] - motions[motion].displacement(time);
    physics_dirty_ = prescribed_dirty_ = true;
    packed_valid_ = false;
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
    bonds_dirty_ = false;
}

double World::effective_skin() const {
    if (params.skin > 0.0) return params.skin;
    const auto& r = particles.radius;
    return r.empty() ? 1e-3 : 0.5 * *std::min_element(r.begin(), r.end());
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

bool World::needs_rebuild() {
    if (candidates_dirty_ || ref_pos_.size() != particles.size()) return true;
    const double skin = skin_;  // the skin the candidates were found with
    if (2.0 * max_disp_ > skin) return true;
    double wall_move = 0.0;
    for (std::size_t k = 0; k < planes.size(); ++k)
        wall_move = std::max(wall_move, norm(planes[k].motion.displacement(time) - wall_ref_disp_[k]));
    for (std::size_t k = 0; k < facets.size(); ++k)
        wall_move = std::max(wall_move,
                             norm(facets[k].motion.displacement(time) - wall_ref_disp_[planes.size() + k]));
    wall_move_ = wall_move;
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
    holes_ = 0;
    build_interaction_lists();  // the slots moved
}

void World::build_interaction_lists() {
    using L = InteractionLists;
    const std::size_t n = particles.size();
    L& l = links_;
    // Each particle's region holds its bonds and live contacts plus some room for contacts
    // that start before the next rebuild (when a region is full, the lists are laid out anew).
    const auto each = [&](auto&& f) {
        for (std::size_t i = 0; i < n; ++i)
            for (uint32_t k = bond_start_[i]; k < bond_start_[i + 1]; ++k)
                f(uint32_t(i), L::make(L::kBond, bond_entries_[k] & kSideBit, bond_entries_[k] & ~kSideBit));
        for (std::size_t s = 0; s < fric_.size(); ++s)
            if (fric_.cand[s] != kNoSlot) {
                f(fric_.i[s], L::make(L::kFrictional, false, uint32_t(s)));
                f(fric_.j[s], L::make(L::kFrictional, true, uint32_t(s)));
            }
        for (std::size_t s = 0; s < smooth_.size(); ++s)
            if (smooth_.cand[s] != kNoSlot) {
                f(smooth_.i[s], L::make(L::kFrictionless, false, uint32_t(s)));
                f(smooth_.j[s], L::make(L::kFrictionless, true, uint32_t(s)));
            }
        for (std::size_t s = 0; s < walls_.size(); ++s)
            if (walls_.cand[s] != kNoSlot) f(walls_.i[s], L::make(L::kWall, true, uint32_t(s)));
    };
    l.count.assign(n, 0);
    each([&](uint32_t i, uint32_t) { ++l.count[i]; });
    l.start.assign(n, 0);
    l.cap.resize(n);
    uint32_t at = 0;
    for (std::size_t i = 0; i < n; ++i) {
        l.start[i] = at;
        l.cap[i] = l.count[i] + 2 + l.count[i] / 4;
        at += l.cap[i];
    }
    l.count.assign(n, 0);
    l.ref.assign(at, 0);
    each([&](uint32_t i, uint32_t r) { l.insert(i, r); });
}

void World::rebuild_derived_tables() {
    // The bond tables only depend on the bond list; bonds_dirty_ keeps its restored value (a
    // pending rebuild builds them again, with the same result).
    const bool bonds_dirty = bonds_dirty_;
    build_bond_tables();
    bonds_dirty_ = bonds_dirty;
    build_interaction_lists();
    prescribed_dirty_ = true;
    skin_ = effective_skin();
    // grid_ is scratch of rebuild_candidates(), rebuilt before every use.
    grid_ = CellGrid{};
}

// ---------------------------------------------------------------- work sharing

void World::assign_owners() {
    const Particles& p = particles;
    const int nt = std::max(1, params.threads);
    const int64_t n = int64_t(p.size()), nb = kernels::block_count(p.size());
    owners_for_ = nt;
    block_owner_.assign(std::size_t(nb), 0);
    if (nt > 1 && n > 0) {
        // Slabs along the longest extent of the packing, each with about 1/nt of the work
        // (a block's work: its particles plus their bonds and candidates).
        Vec3 lo = p.pos[0], hi = lo;
        for (const Vec3& x : p.pos)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], x[d]);
                hi[d] = std::max(hi[d], x[d]);
            }
        int axis = 0;
        for (int d = 1; d < 3; ++d)
            if (hi[d] - lo[d] > hi[axis] - lo[axis]) axis = d;
        std::vector<double> key(std::size_t(nb), 0.0), weight(std::size_t(nb), 0.0);
        for (int64_t i = 0; i < n; ++i) {
            key[i / kernels::kBlock] += p.pos[i][axis];
            // Integration, the gather (live interactions) and the candidate tests.
            weight[i / kernels::kBlock] +=
                4.0 + (links_.count.size() == std::size_t(n) ? double(links_.count[i]) : 0.0) +
                (pp_cand_.start.size() == std::size_t(n + 1) ? 0.5 * double(pp_cand_.start[i + 1] - pp_cand_.start[i]) : 0.0);
        }
        std::vector<int64_t> order(static_cast<std::size_t>(nb));
        for (int64_t b = 0; b < nb; ++b) {
            key[b] /= double(std::min(n, (b + 1) * kernels::kBlock) - b * kernels::kBlock);
            order[b] = b;
        }
        std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return key[a] < key[b]; });
        double total = 0.0;
        for (double w : weight) total += w;
        double before = 0.0;
        for (int64_t b : order) {
            block_owner_[b] = std::min(nt - 1, int((before + 0.5 * weight[b]) / total * nt));
            before += weight[b];
        }
    }
    particle_runs_ = runs_of(nb, nt, [&](int64_t b) { return block_owner_[b]; });
    bond_runs_ = runs_of(kernels::block_count(bonds_.size()), nt, [&](int64_t b) {
        return block_owner_[bonds_.i[b * kernels::kBlock] / kernels::kBlock];
    });
}

BlockRuns World::store_runs(const ActiveContacts& a) const {
    // A block of slots goes to the owner of its first slot's particle (slots are in particle
    // order after each rebuild; the few added since are wherever they fall).
    return runs_of(kernels::block_count(a.size()), owners_for_,
                   [&](int64_t b) { return block_owner_[a.i[b * kernels::kBlock] / kernels::kBlock]; });
}

// ---------------------------------------------------------------- contacts open and close

void World::find_new_contacts() {
    // Inside the parallel region of compute_forces(), over this thread's particles. The same
    // geometric tests as the force kernels, so a pair found here is found touching there.
    // Only candidates without a contact that could have closed their gap since the rebuild are
    // tested (CandidateList::gap); they are picked out by a vector filter, since a branch per
    // candidate would be mispredicted about every other time. The margin covers the rounding
    // of the gaps and of the moves.
    const Particles& p = particles;
    const int64_t n = int64_t(p.size());
    const uint32_t nplanes = uint32_t(planes.size());
    const int tid = thread_id();
    std::vector<uint32_t>& npp = new_pp_[tid];
    std::vector<uint32_t>& npw = new_pw_[tid];
    std::vector<uint32_t>& test = open_scratch_[tid];
    npp.clear();
    npw.clear();
    const double margin = 1e-9 * skin_;
    const auto scan = [&](const CandidateList& c, int64_t i0, int64_t i1, float reach, auto&& touches,
                          std::vector<uint32_t>& hits) {
        if (c.other.empty()) return;
        test.clear();
        kernels::filter_open_candidates(c.slot.data(), c.gap.data(), reach, c.start[i0], c.start[i1], test);
        int64_t i = i0;
        for (uint32_t k : test) {
            while (c.start[i + 1] <= k) ++i;  // the particle of candidate k
            if (touches(uint32_t(i), c.other[k])) {
                hits.push_back(uint32_t(i));
                hits.push_back(k);
            }
        }
    };
    // Particle pairs with packed records: the tests in SIMD on (i, j) lists.
    const auto scan_pairs = [&](int64_t i0, int64_t i1, float reach) {
        const CandidateList& c = pp_cand_;
        if (c.other.empty()) return;
        test.clear();
        kernels::filter_open_candidates(c.slot.data(), c.gap.data(), reach, c.start[i0], c.start[i1], test);
        std::vector<uint32_t>& is = pair_i_[tid];
        std::vector<uint32_t>& js = pair_j_[tid];
        is.resize(test.size());
        js.resize(test.size());
        int64_t i = i0;
        for (std::size_t q = 0; q < test.size(); ++q) {
            while (c.start[i + 1] <= test[q]) ++i;
            is[q] = uint32_t(i);
            js[q] = c.other[test[q]];
        }
        std::vector<uint32_t>& hits = pair_hits_[tid];
        hits.clear();
        kernels::touching_pairs(packed_.data(), is.data(), js.data(), test.size(), hits);
        for (uint32_t q : hits) {
            npp.push_back(is[q]);
            npp.push_back(test[q]);
        }
    };
    for (const auto& [b0, b1] : particle_runs_[tid]) {
        const int64_t i0 = b0 * kernels::kBlock, i1 = std::min(n, b1 * kernels::kBlock);
        if (!packed_.empty() && !packed_valid_) kernels::pack_particles(p, i0, i1, packed_.data());
        if (!packed_.empty()) scan_pairs(i0, i1, float(2.0 * max_disp_ + margin));
        else scan(pp_cand_, i0, i1, float(2.0 * max_disp_ + margin), [&](uint32_t i, uint32_t j) {
            const Vec3 d = p.pos[j] - p.pos[i];
            const double rs = p.radius[i] + p.radius[j];
            return norm2(d) < rs * rs;
        }, npp);
        scan(pw_cand_, i0, i1, float(max_disp_ + wall_move_ + margin), [&](uint32_t i, uint32_t w) {
            ContactGeom g;
            return w < nplanes ? sphere_plane(p.pos[i], p.radius[i], plane_point_[w], planes[w].normal, planes[w].one_sided, g)
                               : sphere_facet(p.pos[i], p.radius[i], facet_now_[w - nplanes], facets[w - nplanes].one_sided, g);
        }, npw);
    }
}

void World::activate_new_contacts() {
    // Serial, in candidate order: the threads' lists are merged and sorted first, so the slots
    // a new contact gets do not depend on which thread found it.
    const auto merged = [](std::vector<std::vector<uint32_t>>& lists) {
        std::vector<std::pair<uint32_t, uint32_t>> all;  // (candidate, particle)
        for (const auto& l : lists)
            for (std::size_t q = 0; q < l.size(); q += 2) all.emplace_back(l[q + 1], l[q]);
        std::sort(all.begin(), all.end());
        return all;
    };
    // New contacts fill the holes of opened ones, lowest first (in candidate order).
    std::size_t new_count = 0;
    for (const auto* lists : {&new_pp_, &new_pw_})
        for (const auto& l : *lists) new_count += l.size() / 2;
    std::size_t fric_cursor = 0, smooth_cursor = 0, wall_cursor = 0;
    const std::size_t before = fric_.size() + smooth_.size() + walls_.size();
    for (const auto& [k, i] : merged(new_pp_)) {
        const uint32_t j = pp_cand_.other[k];
        const ContactPhys ph = pair_phys(i, j);
        const bool smooth = ph.mu == 0.0;
        const uint32_t s = smooth ? smooth_.place(i, j, k, ph, &smooth_cursor) : fric_.place(i, j, k, ph, &fric_cursor);
        pp_cand_.slot[k] = s | (smooth ? kSmoothBit : 0u);
        const auto src = smooth ? InteractionLists::kFrictionless : InteractionLists::kFrictional;
        links_.insert(i, InteractionLists::make(src, false, s));
        links_.insert(j, InteractionLists::make(src, true, s));
    }
    for (const auto& [k, i] : merged(new_pw_)) {
        const uint32_t w = pw_cand_.other[k];
        pw_cand_.slot[k] = walls_.place(i, w, k, wall_phys(i, w), &wall_cursor);
        links_.insert(i, InteractionLists::make(InteractionLists::kWall, true, pw_cand_.slot[k]));
    }
    const std::size_t after = fric_.size() + smooth_.size() + walls_.size();
    const std::size_t filled = (new_count - (after - before));
    holes_ = holes_ > filled ? holes_ - filled : 0;
}


void World::release_opened_contacts() {
    using L = InteractionLists;
    const auto release = [&](ActiveContacts& a, CandidateList& cl, const std::vector<std::vector<uint32_t>>& opened,
                             L::Source src) {
        for (const auto& list : opened)
            for (uint32_t s : list) {
                cl.slot[a.cand[s]] = kNoSlot;
                a.cand[s] = kNoSlot;
                ++holes_;
                if (src == L::kWall) {
                    links_.erase(a.i[s], L::make(src, true, s));
                } else {
                    links_.erase(a.i[s], L::make(src, false, s));
                    links_.erase(a.j[s], L::make(src, true, s));
                }
            }
    };
    release(fric_, pp_cand_, opened_fric_, L::kFrictional);
    release(smooth_, pp_cand_, opened_smooth_, L::kFrictionless);
    release(walls_, pw_cand_, opened_walls_, L::kWall);
}

// ---------------------------------------------------------------- forces

template <bool kEnergy>
void World::wall_contact_forces() {
    // Few contacts (caps, funnel): scalar, over this thread's blocks of slots.
    const Particles& p = particles;
    const double dt = params.dt;
    const uint32_t nplanes = uint32_t(planes.size());
    const int64_t ns = int64_t(walls_.size());
    std::vector<uint32_t>& opened = opened_walls_[thread_id()];
    opened.clear();
    for (const auto& [b0, b1] : wall_runs_[thread_id()])
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
    using L = InteractionLists;
    // Force and torque tables by source (L::Source) and side (body 1, body 2). The
    // frictionless store's torques are never written and stay zero; a wall contact's
    // particle is always its body 2.
    const Vec3* const force[4] = {fric_.force.data(), smooth_.force.data(), walls_.force.data(), bonds_.force.data()};
    const Vec3* const torque[4][2] = {{fric_.torque1.data(), fric_.torque2.data()},
                                      {smooth_.torque1.data(), smooth_.torque2.data()},
                                      {walls_.torque2.data(), walls_.torque2.data()},
                                      {bonds_.torque1.data(), bonds_.torque2.data()}};
    for (const auto& [b0, b1] : particle_runs_[thread_id()])
    for (int64_t i = b0 * kernels::kBlock; i < std::min(n, b1 * kernels::kBlock); ++i) {
        // In list order (a fixed order), alternating between two partial sums so that the
        // chains of dependent additions are half as long (the gather is bound by them).
        const uint32_t* r = &links_.ref[links_.start[i]];
        const uint32_t m = links_.count[i];
        const auto add = [&](uint32_t ref, Vec3& f, Vec3& t) {
            const uint32_t src = ref >> 30, second = (ref & L::kSecond) ? 1 : 0, k = ref & L::kIndexMask;
            // Body 1 gets the opposite of the force on body 2: x - y and x + (-y) round alike.
            f += force[src][k] * (second ? 1.0 : -1.0);
            t += torque[src][second][k];
        };
        Vec3 fa, ta, fb, tb;
        uint32_t e = 0;
        for (; e + 1 < m; e += 2) {
            add(r[e], fa, ta);
            add(r[e + 1], fb, tb);
        }
        if (e < m) add(r[e], fa, ta);
        Vec3 fi = fa + fb;
        if (with_pressure) fi += pressure_force_[i];
        p.force[i] = fi;
        p.torque[i] = ta + tb;
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
    // Holes left by opened contacts are dropped at each rebuild; where contacts come and go
    // much faster than rebuilds happen (a collapsing column), also once they are a quarter of
    // the slots, so the kernels do not sweep mostly empty stores.
    if (needs_rebuild()) {
        rebuild_candidates();
        // The work moves with the particles (grains settle, contacts gather at the bottom): the
        // slabs are balanced again on the new candidates and contacts.
        owners_for_ = 0;
    } else if (physics_dirty_ || holes_ > (fric_.size() + smooth_.size() + walls_.size()) / 4 + 256) compact_contacts(physics_dirty_);
    physics_dirty_ = false;
    profile_.lap(Phase::kNeighbour);

    const bool track = params.track_energy;
    const bool press = pressure.dp != 0.0 && !pressure.nodes.empty();
    const int nt = std::max(1, params.threads);
    for (auto* v : {&new_pp_, &new_pw_, &open_scratch_, &pair_i_, &pair_j_, &pair_hits_, &opened_fric_, &opened_smooth_,
                    &opened_walls_})
        v->resize(nt);
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
    if (owners_for_ != nt || block_owner_.size() != std::size_t(kernels::block_count(particles.size())))
        assign_owners();
    const bool prof = profile_.enabled();
    const double dt = params.dt;
    // The packed particle state is only needed (and written) when pairs or bonds are computed;
    // a new contact always involves particles of an existing candidate, so candidates count.
    // The packed records exist while there are bonds or particle contacts (a free fall of
    // 1e5 grains needs none); the first contacts get them in activate_new_contacts().
    if (packed_.size() != particles.size() || (bonds_.i.empty() && fric_.size() + smooth_.size() == 0)) {
        packed_.clear();
        packed_valid_ = false;
    }
    // One parallel region for the whole force computation: the kernels write their own
    // slots and do not wait for each other; barriers order the contact bookkeeping before
    // them and the gather after them.
    team_->run(nt, [&](int tid) {
        find_new_contacts();
        team_->barrier();
        if (tid == 0) {
            activate_new_contacts();
            if (track) {
                // Every block sum is written by the kernels below.
                fric_energy_.resize(kernels::block_count(fric_.size()) * kernels::kPairSums);
                smooth_energy_.resize(kernels::block_count(smooth_.size()) * kernels::kPairSums);
                wall_energy_.resize(kernels::block_count(walls_.size()) * kernels::kPairSums);
                bond_energy_.resize(kernels::block_count(bonds_.size()));
            }
            if (packed_.empty() && (!bonds_.i.empty() || fric_.size() + smooth_.size() > 0)) {
                packed_.resize(particles.size());
                for (std::size_t i = 0; i < particles.size(); ++i) packed_[i] = kernels::pack(particles, i);
            }
            fric_runs_ = store_runs(fric_);
            smooth_runs_ = store_runs(smooth_);
            wall_runs_ = store_runs(walls_);
        }
        team_->barrier();
        if (prof && tid == 0) profile_.lap(Phase::kNeighbour);
        opened_fric_[tid].clear();
        opened_smooth_[tid].clear();
        for (const auto& [b0, b1] : fric_runs_[tid])
            kernels::frictional_pairs({&particles, packed_.data(), &fric_, dt, b0, b1,
                                       track ? fric_energy_.data() : nullptr, &opened_fric_[tid]});
        for (const auto& [b0, b1] : smooth_runs_[tid])
            kernels::smooth_pairs({&particles, packed_.data(), &smooth_, dt, b0, b1,
                                   track ? smooth_energy_.data() : nullptr, &opened_smooth_[tid]});
        if (track) wall_contact_forces<true>();
        else wall_contact_forces<false>();
        // With profiling on, a barrier after each phase so that its time is the slowest thread's.
        const auto lap = [&](Phase ph) {
            if (!prof) return;
            team_->barrier();
            if (tid == 0) profile_.lap(ph);
        };
        lap(Phase::kContacts);
        for (const auto& [b0, b1] : bond_runs_[tid])
            kernels::bonds({&particles, packed_.data(), &bonds_, dt, b0, b1, track ? bond_energy_.data() : nullptr});
        lap(Phase::kBonds);
        if (press) apply_pressure();
        team_->barrier();
        if (prof && tid == 0) profile_.lap(Phase::kPressure);
        gather_forces(press);
    });
    packed_valid_ = !packed_.empty();  // (integrate() keeps it so; invalidate_candidates() does not)
    sum_wall_reactions();
    release_opened_contacts();
    energy_ready_ = track;
    profile_.lap(Phase::kGather);
}

Vec3 World::total_force(std::size_t i) const {
    const Particles& p = particles;
    const Vec3 fx = p.ext_force.empty() ? Vec3{} : p.ext_force[i];
    return p.force[i] + fx + params.gravity * p.mass[i];
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
    if (!p.ext_force.empty() && p.ext_force.size() != p.size())
        throw std::logic_error("Particles::ext_force must be empty or hold one force per particle");
    args.ext_force = p.ext_force.empty() ? nullptr : p.ext_force.data();
    args.pressure = track && !pressure_force_.empty() ? pressure_force_.data() : nullptr;
    args.ref_pos = ref_pos_.data();
    args.gravity = params.gravity;
    args.dt = dt;
    args.lambda = params.local_damping;
    args.energy = track ? particle_blocks_.data() : nullptr;
    args.packed = packed_.size() == p.size() ? packed_.data() : nullptr;
    if (owners_for_ != nt || block_owner_.size() != std::size_t(nblk)) assign_owners();
    std::vector<double>& thread_max = thread_max_d2_;
    thread_max.assign(std::size_t(nt), 0.0);
    team_->run(nt, [&](int tid) {
        kernels::AdvanceArgs a = args;
        for (const auto& [b0, b1] : particle_runs_[tid]) {
            a.block_begin = b0;
            a.block_end = b1;
            thread_max[tid] = std::max(thread_max[tid], kernels::advance(a));
        }
    });
    double max_d2 = *std::max_element(thread_max.begin(), thread_max.end());
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
        if (args.packed) packed_[i] = kernels::pack(p, i);
        const FloatVec3 r = ref_pos_[i];
        max_d2 = std::max(max_d2, norm2(p.pos[i] - Vec3{r.x, r.y, r.z}));
        if (track) {
            // Work done by the prescribed particle on the others: minus the force they exert
            // on it (contacts and bonds, not the pressure it carries) times its displacement.
            const double h = 0.5 * dt;
            const Vec3 fint = p.force[i] - pressure_force_[i];
            prescribed_energy_[0] -= dot(fint, v0) * h;
            prescribed_energy_[1] -= dot(fint, p.vel[i]) * h;
        }
    }
    packed_valid_ = args.packed != nullptr;
    max_disp_ = std::sqrt(max_d2) + ref_round_;
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

#include "dem/world/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "dem/kernels/kernels.h"
#include "dem/integrate/critical_dt.h"
#include "dem/clumps/rigid_rotation.h"
#include "dem/core/parallel.h"
#include "dem/integrate/leapfrog.h"

namespace dem {

uint32_t World::add_material(const Material& m) {
    materials.push_back(m);
    physics_dirty_ = true;
    return uint32_t(materials.size() - 1);
}

uint32_t World::add_sphere(const SphereDef& d) {
    if (!(d.radius > 0.0)) throw std::invalid_argument("sphere radius must be > 0");
    if (d.material >= materials.size()) throw std::invalid_argument("sphere material index out of range");
    // Those flags need their partner data (a motion, a clump) that only set_prescribed() and
    // add_clump() give: a sphere with the flag alone would step into motions[-1].
    if (d.flags & (kPrescribed | kClumpMember))
        throw std::invalid_argument("add_sphere: flags kPrescribed and kClumpMember are set by set_prescribed() and "
                                    "add_clump(), not by the sphere's definition");
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
    if (!clumps_.owner.empty()) clumps_.owner.push_back(-1);
    contacts_.cover_particles(p.size());
    broad_.dirty = prescribed_dirty_ = true;
    return uint32_t(p.size() - 1);
}

uint32_t World::add_clump(const ClumpShape& shape, const ClumpDef& d) {
    if (shape.members.empty()) throw std::invalid_argument("clump shape without members");
    if (d.material >= materials.size()) throw std::invalid_argument("clump material index out of range");
    if (!(shape.volume > 0.0)) throw std::invalid_argument("clump shape volume must be > 0");
    Particles& p = particles;
    Clumps& c = clumps_;
    const double density = materials[d.material].density;
    const double m = density * shape.volume;
    const Vec3 inertia = shape.inertia_per_density * density;
    const Quat q = normalized(d.orientation);
    if (c.owner.empty()) c.owner.assign(p.size(), -1);
    const uint32_t k = uint32_t(c.size());
    for (const ClumpMember& mb : shape.members) {
        const Vec3 r = rotate(q, mb.center);
        c.member.push_back(uint32_t(p.size()));
        c.rel.push_back(mb.center);
        c.owner.push_back(int32_t(k));
        p.pos.push_back(d.position + r);
        p.vel.push_back(d.velocity + cross(d.angular_velocity, r));
        p.angvel.push_back(d.angular_velocity);
        p.force.emplace_back();
        p.torque.emplace_back();
        if (!p.ext_force.empty()) p.ext_force.emplace_back();
        p.radius.push_back(mb.radius);
        p.mass.push_back(m);  // the clump's: a contact's reduced mass is the bodies'
        p.inv_mass.push_back(0.0);  // moved by advance_clumps(), not by the particle integrator
        p.inv_inertia.push_back(0.0);
        p.material.push_back(d.material);
        p.mask.push_back(d.mask);
        p.flags.push_back(kClumpMember);
        p.motion.push_back(-1);
        if (!p.ref_pos.empty()) p.ref_pos.push_back(d.position + r);
    }
    c.start.push_back(uint32_t(c.member.size()));
    c.pos.push_back(d.position);
    c.vel.push_back(d.velocity);
    c.q.push_back(q);
    c.mom.push_back(rigid::momentum(q, d.angular_velocity, inertia));
    c.angvel.push_back(d.angular_velocity);
    c.inertia.push_back(inertia);
    c.mass.push_back(m);
    c.inv_mass.push_back(1.0 / m);
    contacts_.cover_particles(p.size());
    broad_.dirty = true;
    packed_valid_ = false;
    return k;
}

double World::clump_kinetic_energy(std::size_t k) const {
    const Clumps& c = clumps_;
    return 0.5 * c.mass[k] * norm2(c.vel[k]) + rigid::rotational_energy(c.q[k], c.mom[k], c.inertia[k]);
}

void World::reserve(std::size_t n) {
    Particles& p = particles;
    for (auto* v : {&p.pos, &p.vel, &p.angvel, &p.force, &p.torque}) v->reserve(n);
    for (auto* v : {&p.radius, &p.mass, &p.inv_mass, &p.inv_inertia}) v->reserve(n);
    for (auto* v : {&p.material, &p.mask, &p.flags}) v->reserve(n);
    p.motion.reserve(n);
}

uint32_t World::add_plane(const Plane& pl) {
    if (pl.material >= materials.size()) throw std::invalid_argument("plane material index out of range");
    Plane q = pl;
    q.normal = normalized(pl.normal);
    // Walls are numbered planes first, then facets: a plane added after facets moves every facet
    // up by one. Their live contacts, candidates and last reactions follow them, so that each
    // facet keeps its own shear history (the next broad phase matches contacts by wall index).
    const uint32_t k = uint32_t(planes.size());
    if (!facets.empty()) {
        contacts_.shift_walls_from(k);
        for (std::vector<Vec3>* v : {&walls_now_.velocity, &walls_now_.force, &walls_now_.torque})
            if (v->size() > k) v->insert(v->begin() + k, Vec3{});
    }
    planes.push_back(q);
    broad_.dirty = true;
    return k;
}

uint32_t World::add_facet(const Facet& f) {
    if (f.material >= materials.size()) throw std::invalid_argument("facet material index out of range");
    facets.push_back(f);
    broad_.dirty = true;
    return uint32_t(facets.size() - 1);
}

uint32_t World::add_motion(const Motion& m) {
    motions.push_back(m);
    return uint32_t(motions.size() - 1);
}

void World::require_particle(const char* caller, uint32_t i) const {
    if (i >= particles.size())
        throw std::invalid_argument(std::string(caller) + ": particle " + std::to_string(i) + " does not exist (" +
                                    std::to_string(particles.size()) + " particles)");
}

void World::set_fixed(uint32_t i) {
    require_particle("set_fixed", i);
    if (particles.flags[i] & kClumpMember)
        throw std::invalid_argument("set_fixed: particle " + std::to_string(i) + " is a clump member");
    Particles& p = particles;
    p.flags[i] = (p.flags[i] | kFixed) & ~uint32_t(kPrescribed);
    p.inv_mass[i] = p.inv_inertia[i] = 0.0;
    p.vel[i] = p.angvel[i] = Vec3{};
    p.motion[i] = -1;
    physics_dirty_ = prescribed_dirty_ = true;  // reduced masses of its contacts change
    packed_valid_ = false;
}

void World::set_prescribed(uint32_t i, uint32_t motion) {
    require_particle("set_prescribed", i);
    if (motion >= motions.size())
        throw std::invalid_argument("set_prescribed: motion " + std::to_string(motion) + " does not exist (" +
                                    std::to_string(motions.size()) + " motions)");
    if (particles.flags[i] & kClumpMember)
        throw std::invalid_argument("set_prescribed: particle " + std::to_string(i) + " is a clump member");
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
    contacts_.drop_wall_contacts_from(uint32_t(planes.size()));
    facets.clear();
    walls_now_.facet_now.clear();
    broad_.dirty = true;
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
    bonds_dirty_ = broad_.dirty = true;
    return uint32_t(bonds_.size() - 1);
}

double World::effective_skin() const {
    if (params.skin > 0.0) return params.skin;
    const auto& r = particles.radius;
    return r.empty() ? 1e-3 : 0.5 * *std::min_element(r.begin(), r.end());
}

double World::critical_dt() const { return dem::critical_dt(particles, materials, planes, facets, bonds_, clumps_); }

// ================================================================ the step

void World::step() {
    compute_forces();
    integrate();
}

void World::compute_forces() {
    move_walls();
    update_candidates();
    prepare_forces();
    // One parallel region for the force phases: the kernels write their own slots and do not
    // wait for each other; barriers order the contact bookkeeping before them and the gather
    // after them.
    team_->run(threads(), [&](int tid) {
        open_contacts(tid);
        contact_forces(tid);
        bond_forces(tid);
        pressure_forces(tid);
        gather_forces(tid);
    });
    wall_reactions();
    close_contacts();
    finish_forces();
}

void World::integrate() {
    const double t_n = time;
    const bool track = prepare_integration();
    // In this order (the clumps place their members after the free particles' kernel wrote its
    // records), not as arguments of one call, whose order C++ leaves open.
    const double moved_free = advance_free_particles(track);
    const double moved_clumps = advance_clumps(track);
    broad_.record_moves(std::max(std::max(moved_free, moved_clumps), follow_motions(track)));
    profile_.lap(Phase::kIntegration);
    advance_clock();
    if (track) account_energy(t_n);
    book_.ready = false;
}

// ---------------------------------------------------------------- forces at t

void World::move_walls() {
    profile_.start();  // the step's first phase
    walls_now_.move(planes, facets, time, params.dt);
}

void World::update_candidates() {
    const std::size_t n = particles.size();
    if (broad_.needs_rebuild(n, planes, facets, time)) {
        if (bonds_dirty_ || !bond_tables_.built_for(n)) {
            bond_tables_.build(n, bonds_);
            bonds_dirty_ = false;
        }
        BroadPhase::Scene scene;
        scene.p = &particles;
        scene.planes = &planes;
        scene.facets = &facets;
        scene.plane_point = &walls_now_.plane_point;
        scene.facet_now = &walls_now_.facet_now;
        scene.bonds = &bond_tables_;
        scene.owner = clumps_.owner.empty() ? nullptr : clumps_.owner.data();
        scene.skin = effective_skin();
        scene.time = time;
        scene.threads = threads();
        scene.team = &*team_;
        broad_.rebuild(scene, contacts_.pp, contacts_.pw);
        contacts_.reattach();  // the live contacts find their pairs again
        // Holes dropped, slots in candidate order.
        contacts_.compact(physics_dirty_, contact_physics(), bond_tables_, n);
        // The work moves with the particles (grains settle, contacts gather at the bottom): the
        // slabs are balanced again on the new candidates and contacts.
        work_.invalidate();
    } else if (physics_dirty_ || stores_need_compaction(contacts_.holes, contacts_.store_slots())) {
        // Where contacts come and go much faster than rebuilds happen (a collapsing column),
        // the holes of opened contacts are also dropped once they are a quarter of the slots,
        // so the kernels do not sweep mostly empty stores.
        contacts_.compact(physics_dirty_, contact_physics(), bond_tables_, n);
    }
    physics_dirty_ = false;
    profile_.lap(Phase::kNeighbour);
}

void World::prepare_forces() {
    const int nt = threads();
    contacts_.prepare_threads(nt);
    // The energy ledger reads the (zero) pressure slots too.
    pressure_forces_.prepare(pressure, particles.size(), pressure_on(), pressure_on() || params.track_energy);
    if (!work_.valid_for(nt, particles.size())) assign_work();
    // The packed particle records exist while there are bonds or particle contacts (a free
    // fall of 1e5 grains needs none); the first contacts get them in open_contacts().
    if (packed_.size() != particles.size() || (bonds_.i.empty() && contacts_.fric.size() + contacts_.smooth.size() == 0)) {
        packed_.clear();
        packed_valid_ = false;
    }
}

void World::assign_work() {
    work_.assign(threads(), particles.pos, contacts_.links.count, contacts_.pp.start, bonds_.i);
}

void World::lap(int tid, Phase phase) {
    if (!profile_.enabled()) return;
    team_->barrier();
    if (tid == 0) profile_.lap(phase);
}

void World::open_contacts(int tid) {
    // In parallel, over this thread's particles: candidates touching without a slot.
    ContactSet::FindArgs find;
    find.p = &particles;
    find.packed = packed_.empty() ? nullptr : packed_.data();
    find.repack = !packed_valid_;
    find.planes = &planes;
    find.facets = &facets;
    find.wall_now = &walls_now_.now;
    std::tie(find.pair_reach, find.wall_reach) = engine_reach();
    find.blocks = &work_.particles[tid];
    contacts_.find_new(find);
    team_->barrier();
    // Serial: slots in candidate order, then what the kernels need sized for them.
    if (tid == 0) {
        contacts_.activate_new(contact_physics());
        if (params.track_energy) book_.size_blocks(contacts_, bonds_.size());
        if (packed_.empty() && (!bonds_.i.empty() || contacts_.fric.size() + contacts_.smooth.size() > 0)) {
            packed_.resize(particles.size());
            for (std::size_t i = 0; i < particles.size(); ++i) packed_[i] = kernels::pack(particles, i);
        }
        work_.fric = work_.store_runs(contacts_.fric.i);
        work_.smooth = work_.store_runs(contacts_.smooth.i);
        work_.walls = work_.store_runs(contacts_.walls.i);
    }
    team_->barrier();
    if (profile_.enabled() && tid == 0) profile_.lap(Phase::kNeighbour);
}

void World::contact_forces(int tid) {
    const bool track = params.track_energy;
    const double dt = params.dt;
    contacts_.opened_fric[tid].clear();
    contacts_.opened_smooth[tid].clear();
    for (const auto& [b0, b1] : work_.fric[tid])
        kernels::frictional_pairs({&particles, packed_.data(), &contacts_.fric, dt, b0, b1,
                                   track ? book_.fric.data() : nullptr, &contacts_.opened_fric[tid]});
    for (const auto& [b0, b1] : work_.smooth[tid])
        kernels::smooth_pairs({&particles, packed_.data(), &contacts_.smooth, dt, b0, b1,
                               track ? book_.smooth.data() : nullptr, &contacts_.opened_smooth[tid]});
    kernels::WallPairArgs w;
    w.p = &particles;
    w.c = &contacts_.walls;
    w.now = &walls_now_.now;
    w.dt = dt;
    w.blocks = &work_.walls[tid];
    w.energy = track ? book_.walls.data() : nullptr;
    w.opened = &contacts_.opened_walls[tid];
    kernels::wall_pairs(w);
    lap(tid, Phase::kContacts);
}

void World::bond_forces(int tid) {
    for (const auto& [b0, b1] : work_.bonds[tid])
        kernels::bonds({&particles, packed_.data(), &bonds_, params.dt, b0, b1,
                        params.track_energy ? book_.bonds.data() : nullptr});
    lap(tid, Phase::kBonds);
}

void World::pressure_forces(int /*tid*/) {
    if (pressure_on()) pressure_forces_.apply(pressure, particles.pos);
}

void World::gather_forces(int tid) {
    team_->barrier();  // the gather reads every thread's forces
    if (profile_.enabled() && tid == 0) profile_.lap(Phase::kPressure);
    Particles& p = particles;
    const int64_t n = int64_t(p.size());
    const bool with_pressure = pressure_on();
    const ContactSet& c = contacts_;
    const GatherTables tb{{c.fric.force.data(), c.smooth.force.data(), c.walls.force.data(), bonds_.force.data()},
                          {{c.fric.torque1.data(), c.fric.torque2.data()},
                           {c.smooth.torque1.data(), c.smooth.torque2.data()},
                           {c.walls.torque2.data(), c.walls.torque2.data()},
                           {bonds_.torque1.data(), bonds_.torque2.data()}}};
    const Vec3* const pressure_force = pressure_forces_.force.data();
    for (const auto& [b0, b1] : work_.particles[tid])
    for (int64_t i = b0 * kernels::kBlock; i < std::min(n, b1 * kernels::kBlock); ++i) {
        Vec3 fi, ti;
        gather_particle(tb, &c.links.ref[c.links.start[i]], c.links.count[i], fi, ti);
        if (with_pressure) fi += pressure_force[i];
        p.force[i] = fi;
        p.torque[i] = ti;
    }
}

void World::wall_reactions() { walls_now_.sum_reactions(contacts_.walls, wall_count()); }

void World::close_contacts() { contacts_.release_opened(); }

void World::finish_forces() {
    packed_valid_ = !packed_.empty();  // (integrate() keeps it so; invalidate_candidates() does not)
    book_.ready = params.track_energy;
    profile_.lap(Phase::kGather);
}

// ---------------------------------------------------------------- motion to t + dt

bool World::prepare_integration() {
    Particles& p = particles;
    if (!p.ext_force.empty() && p.ext_force.size() != p.size())
        throw std::logic_error("Particles::ext_force must be empty or hold one force per particle");
    const bool track = params.track_energy && book_.ready;
    if (track) book_.particles.assign(std::size_t(kernels::block_count(p.size()) * kernels::kParticleSums), 0.0);
    if (!work_.valid_for(threads(), p.size())) assign_work();
    refresh_prescribed();
    return track;
}

void World::refresh_prescribed() {
    if (!prescribed_dirty_) return;
    prescribed_.clear();
    for (std::size_t i = 0; i < particles.size(); ++i)
        if (particles.flags[i] & kPrescribed) prescribed_.push_back(uint32_t(i));
    prescribed_dirty_ = false;
}

double World::advance_free_particles(bool track) {
    Particles& p = particles;
    kernels::AdvanceArgs args;
    args.p = &p;
    args.ext_force = p.ext_force.empty() ? nullptr : p.ext_force.data();
    args.pressure = track && !pressure_forces_.force.empty() ? pressure_forces_.force.data() : nullptr;
    args.ref_pos = broad_.ref_pos.data();
    args.gravity = params.gravity;
    args.dt = params.dt;
    args.lambda = params.local_damping;
    args.energy = track ? book_.particles.data() : nullptr;
    args.packed = packed_.size() == p.size() ? packed_.data() : nullptr;
    const int nt = threads();
    std::vector<double>& thread_max = thread_max_d2_;
    thread_max.assign(std::size_t(nt), 0.0);
    team_->run(nt, [&](int tid) {
        kernels::AdvanceArgs a = args;
        for (const auto& [b0, b1] : work_.particles[tid]) {
            a.block_begin = b0;
            a.block_end = b1;
            thread_max[tid] = std::max(thread_max[tid], kernels::advance(a));
        }
    });
    return *std::max_element(thread_max.begin(), thread_max.end());
}

double World::advance_clumps(bool track) {
    Clumps& c = clumps_;
    if (c.empty()) return 0.0;
    Particles& p = particles;
    const double dt = params.dt, h = 0.5 * dt, lambda = params.local_damping;
    const Vec3 g = params.gravity;
    const bool packed = packed_.size() == p.size();
    const Vec3* ext = p.ext_force.empty() ? nullptr : p.ext_force.data();
    const Vec3* pressure = track && pressure_forces_.force.size() == p.size() ? pressure_forces_.force.data() : nullptr;
    // Blocks of clumps, each block's energy terms summed in clump order: the same sums for any
    // number of threads (each clump writes only its own members).
    const int64_t nb = kernels::block_count(c.size());
    using kernels::kTerms;
    if (track) book_.clumps.assign(std::size_t(nb * kernels::kParticleSums), 0.0);
    const int nt = threads();
    std::vector<double>& thread_max = thread_max_d2_;
    thread_max.assign(std::size_t(nt), 0.0);
    team_->run(nt, [&](int tid) {
        const auto [b0, b1] = thread_range(nb, tid, nt);
        for (int64_t b = b0; b < b1; ++b)
        for (int64_t k = b * kernels::kBlock; k < std::min(int64_t(c.size()), (b + 1) * kernels::kBlock); ++k) {
            const Vec3 x0 = c.pos[k], v0 = c.vel[k], w0 = c.angvel[k], L0 = c.mom[k], I = c.inertia[k];
            const Quat q0 = c.q[k];
            const double m = c.mass[k];
            // The members' forces and torques about the centre of mass, in member order.
            Vec3 f, t, fx, tx, fp, tp;
            for (uint32_t e = c.start[k]; e < c.start[k + 1]; ++e) {
                const uint32_t i = c.member[e];
                const Vec3 r = p.pos[i] - x0;
                f += p.force[i];
                t += cross(r, p.force[i]) + p.torque[i];
                if (ext) {
                    fx += ext[i];
                    tx += cross(r, ext[i]);
                }
                if (pressure) {
                    fp += pressure[i];
                    tp += cross(r, pressure[i]);
                }
            }
            const Vec3 fg = g * m;
            // As the spheres (kernels::advance): total force, Yade's cundallDamp2nd, leapfrog.
            const Vec3 ftot = (f + fx) + fg;
            const Vec3 a = damped_acceleration(ftot, c.inv_mass[k], v0, dt, lambda);
            const Vec3 v1 = v0 + a * dt;
            const Vec3 x1 = x0 + v1 * dt;
            // Rotation: cundallDamp1st on the world-frame torque (sign of torque times angular
            // velocity), kick of the angular momentum, then the symplectic drift.
            const Vec3 ttot = t + tx;
            Vec3 td = ttot;
            if (lambda != 0.0)
                for (int d = 0; d < 3; ++d) td[d] *= 1.0 - lambda * sign(td[d] * w0[d]);
            const Vec3 L1 = L0 + td * dt;
            const Vec3 inv_i{1.0 / I.x, 1.0 / I.y, 1.0 / I.z};
            Quat q1 = q0;
            Vec3 pi0, pi1;
            rigid::drift(q1, L1, inv_i, dt, pi0, pi1);
            // The half step's angular velocity: the mean of the drift's two ends.
            const Vec3 w1 = (rigid::angular_velocity_of(q0, pi0, inv_i) + rigid::angular_velocity_of(q1, pi1, inv_i)) * 0.5;
            c.pos[k] = x1;
            c.vel[k] = v1;
            c.q[k] = q1;
            c.mom[k] = L1;
            c.angvel[k] = w1;
            double max_d2 = 0.0;
            const RotationMatrix rm(q1);
            for (uint32_t e = c.start[k]; e < c.start[k + 1]; ++e) {
                const uint32_t i = c.member[e];
                const Vec3 r = rm * c.rel[e];
                p.pos[i] = x1 + r;
                p.vel[i] = v1 + cross(w1, r);
                p.angvel[i] = w1;
                if (packed) packed_[i] = kernels::pack(p, i);
                const FloatVec3 rf = broad_.ref_pos[i];
                max_d2 = std::max(max_d2, norm2(p.pos[i] - Vec3{rf.x, rf.y, rf.z}));
            }
            thread_max[tid] = std::max(thread_max[tid], max_d2);
            if (track) {
                // The terms of kernels::advance for a rigid body (docs/energy.md): trapezoid
                // halves of each force's work, the kinetic energy at t, what the damping removed.
                double* s = &book_.clumps[std::size_t(b * kernels::kParticleSums)];
                s[kernels::kGravity] += dot(fg, v0) * h;
                s[kTerms + kernels::kGravity] += dot(fg, v1) * h;
                s[kernels::kPressure] += (dot(fp, v0) + dot(tp, w0)) * h;
                s[kTerms + kernels::kPressure] += (dot(fp, v1) + dot(tp, w1)) * h;
                s[kernels::kExternal] += (dot(fx, v0) + dot(tx, w0)) * h;
                s[kTerms + kernels::kExternal] += (dot(fx, v1) + dot(tx, w1)) * h;
                s[2 * kTerms] += 0.5 * m * dot(v0, v1) + 0.25 * (dot(w0, L1) + dot(w1, L0));
                if (lambda != 0.0) {
                    const Vec3 df = ftot - a * m, dq = ttot - td;
                    s[kernels::kDamping] += (dot(df, v0) + dot(dq, w0)) * h;
                    s[kTerms + kernels::kDamping] += (dot(df, v1) + dot(dq, w1)) * h;
                }
            }
        }
    });
    packed_valid_ = packed;
    return *std::max_element(thread_max.begin(), thread_max.end());
}

std::pair<Vec3, Vec3> World::prescribed_next(uint32_t i) const {
    const Placement at = placement_after_step(motions[particles.motion[i]].view(), particles.ref_pos[i], time, params.dt);
    return {at.pos, at.vel};
}

double World::follow_motions(bool track, const Vec3* pressure) {
    // Few particles: serial, in index order.
    Particles& p = particles;
    const bool packed = packed_.size() == p.size();
    double max_d2 = 0.0;
    book_.prescribed[0] = book_.prescribed[1] = 0.0;
    for (uint32_t i : prescribed_) {
        const Vec3 v0 = p.vel[i];
        std::tie(p.pos[i], p.vel[i]) = prescribed_next(i);
        if (packed) packed_[i] = kernels::pack(p, i);
        const FloatVec3 r = broad_.ref_pos[i];
        max_d2 = std::max(max_d2, norm2(p.pos[i] - Vec3{r.x, r.y, r.z}));
        if (track) {
            // Work done by the prescribed particle on the others: minus the force they exert
            // on it (contacts and bonds, not the pressure it carries) times its displacement.
            const Vec3 fint = p.force[i] - (pressure ? pressure[i] : pressure_forces_.force[i]);
            ledger::add_boundary_work(book_.prescribed[0], book_.prescribed[1], fint, v0, p.vel[i], 0.5 * params.dt);
        }
    }
    packed_valid_ = packed;
    return max_d2;
}

void World::advance_clock() { clock_.advance(time, steps, params.dt); }

void World::account_energy(double t_n) {
    EnergyBook::Step s;
    s.p = &particles;
    s.materials = &materials;
    s.planes = &planes;
    s.facets = &facets;
    s.walls = &walls_now_;
    s.contacts = &contacts_;
    s.time = time;
    s.dt = params.dt;
    s.t_n = t_n;
    book_.account(s);
    profile_.lap(Phase::kEnergy);
}

// ---------------------------------------------------------------- an engine's step

void World::engine_begin_forces() {
    move_walls();
    update_candidates();
    contacts_.prepare_threads(1);
    for (auto* l : {&contacts_.new_pp, &contacts_.new_pw, &contacts_.opened_fric, &contacts_.opened_smooth, &contacts_.opened_walls})
        (*l)[0].clear();
}

void World::engine_end_forces() {
    wall_reactions();
    close_contacts();
}

void World::engine_end_forces(const Vec3* force, const Vec3* torque) {
    const std::size_t nw = wall_count();
    walls_now_.force.assign(force, force + nw);
    walls_now_.torque.assign(torque, torque + nw);
    close_contacts();
}

std::pair<float, float> World::engine_reach() const {
    const Reaches r = touch_reaches(broad_.max_disp, broad_.wall_move, broad_.skin);
    return {r.pair, r.wall};
}

void World::engine_activate() {
    contacts_.activate_new(contact_physics());
    if (params.track_energy) book_.size_blocks(contacts_, bonds_.size());
}

double World::engine_follow_motions(const Vec3* pressure) {
    refresh_prescribed();
    return follow_motions(params.track_energy, pressure);
}

void World::engine_next_wall_velocities(std::vector<Vec3>& v) const {
    StepClock clock = clock_;  // the time engine_end_step() will move the clock to
    double t = time;
    uint64_t n = steps;
    clock.advance(t, n, params.dt);
    EnergyBook::next_wall_velocities(planes, facets, t, params.dt, v);
}

void World::engine_end_step(double max_d2) {
    const double t_n = time;
    broad_.record_moves(max_d2);
    advance_clock();
    if (params.track_energy) account_energy(t_n);
}

// ---------------------------------------------------------------- queries

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


void World::rebuild_derived_tables() {
    // The bond tables only depend on the bond list; bonds_dirty_ keeps its restored value (a
    // pending rebuild builds them again, with the same result).
    bond_tables_.build(particles.size(), bonds_);
    contacts_.build_interaction_lists(bond_tables_, particles.size());
    prescribed_dirty_ = true;
    broad_.skin = effective_skin();
    broad_.grid = CellGrid{};  // scratch of the broad phase, rebuilt before every use
}

}  // namespace dem

// The World's state as the checkpoint stores it (dem/io/checkpoint.h): World::serialize lists
// every field, section by section, for an archive that either writes (const World) or reads
// (World, Archive::kLoading). Included by the checkpoint code only. Older formats are read here
// too (version 1's contact lists are converted after reading).
#pragma once

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "dem/world/world.h"

namespace dem {

// A field added to one of these structs must also be added to the checkpoint (and the format
// version bumped); these asserts make that impossible to forget.
static_assert(sizeof(Particles) == 15 * sizeof(std::vector<int>), "update dem/world/world_io.h");
static_assert(sizeof(Clumps) == 12 * sizeof(std::vector<int>) && sizeof(Quat) == 32, "update dem/world/world_io.h");
static_assert(sizeof(CandidateList) == 4 * sizeof(std::vector<int>), "update dem/world/world_io.h");
static_assert(sizeof(ActiveContacts) == 11 * sizeof(std::vector<int>), "update dem/world/world_io.h");
static_assert(sizeof(BondList) == 8 * sizeof(std::vector<int>) + 8 && sizeof(BondArm) == 1, "update dem/world/world_io.h");
static_assert(sizeof(Material) == sizeof(std::string) + 5 * sizeof(double), "update dem/world/world_io.h");
static_assert(sizeof(Motion) == sizeof(Vec3) + sizeof(std::vector<int>), "update dem/world/world_io.h");
static_assert(sizeof(Plane) == 2 * sizeof(Vec3) + 16 + sizeof(Motion), "update dem/world/world_io.h");
static_assert(sizeof(Facet) == 3 * sizeof(Vec3) + 16 + sizeof(Motion), "update dem/world/world_io.h");
// The fans (3 vectors) are refused by the writer until the format carries them (section PRES).
static_assert(sizeof(MembranePressure) == 4 * sizeof(std::vector<int>) + 8, "update dem/world/world_io.h");
static_assert(sizeof(SimulationParams) == 4 * 8 + sizeof(Vec3) &&
                  offsetof(SimulationParams, track_energy) == 3 * 8 + sizeof(Vec3) + 4,
              "update dem/world/world_io.h");
static_assert(sizeof(EnergyLedger) == 21 * 8, "update dem/world/world_io.h");
static_assert(sizeof(PressureNode) == 20 && sizeof(DisplacementSample) == 32 &&
                  sizeof(ShearHistory) == 48 && sizeof(ContactPhys) == 32 && sizeof(BondPhys) == 24,
              "padding-free records expected");

namespace io {

// Field lists shared by saving (const objects) and loading.
template <class A, class M> void motion_io(A& a, M& m) {
    a.pod(m.velocity);
    a.vec(m.history);
}

template <class A, class M> void material_io(A& a, M& m) {
    a.str(m.name);
    a.pod(m.density);
    a.pod(m.young);
    a.pod(m.stiffness_ratio);
    a.pod(m.friction);
    a.pod(m.restitution);
}

template <class A, class P> void plane_io(A& a, P& p) {
    a.pod(p.point);
    a.pod(p.normal);
    a.pod(p.material);
    a.pod(p.mask);
    a.flag(p.one_sided);
    motion_io(a, p.motion);
}

template <class A, class F> void facet_io(A& a, F& f) {
    a.pod(f.vertices);
    a.pod(f.material);
    a.pod(f.mask);
    a.flag(f.one_sided);
    motion_io(a, f.motion);
}

template <class A, class P> void particles_io(A& a, P& p) {
    a.vec(p.pos);
    a.vec(p.vel);
    a.vec(p.angvel);
    a.vec(p.force);
    a.vec(p.torque);
    a.vec(p.ext_force);
    a.vec(p.radius);
    a.vec(p.mass);
    a.vec(p.inv_mass);
    a.vec(p.inv_inertia);
    a.vec(p.material);
    a.vec(p.mask);
    a.vec(p.flags);
    a.vec(p.motion);
    a.vec(p.ref_pos);
}

// Version 1 kept a bond's shear spring and previous normal as one record (ShearHistory).
template <class A, class B> void bonds_io(A& a, B& b, uint32_t version) {
    a.vec(b.i);
    a.vec(b.j);
    a.vec(b.phys);
    if (version >= 2) {
        a.vec(b.shear);
        a.vec(b.prev_normal);
    } else if constexpr (A::kLoading) {
        std::vector<ShearHistory> hist;
        a.vec(hist);
        for (const ShearHistory& h : hist) {
            b.shear.push_back(h.shear);
            b.prev_normal.push_back(h.prev_normal);
        }
    }
    a.vec(b.force);
    a.vec(b.torque1);
    a.vec(b.torque2);
}

template <class A, class C> void clumps_io(A& a, C& c) {
    a.vec(c.pos);
    a.vec(c.vel);
    a.vec(c.q);
    a.vec(c.mom);
    a.vec(c.angvel);
    a.vec(c.inertia);
    a.vec(c.mass);
    a.vec(c.inv_mass);
    a.vec(c.start);
    a.vec(c.member);
    a.vec(c.rel);
    a.vec(c.owner);
}

// Version 2: the light candidate lists and the stores of live contacts.
template <class A, class C> void candidates_io(A& a, C& c) {
    a.vec(c.start);
    a.vec(c.other);
    a.vec(c.slot);
    a.vec(c.gap);
}

template <class A, class C> void store_io(A& a, C& c) {
    a.vec(c.i);
    a.vec(c.j);
    a.vec(c.cand);
    a.vec(c.phys);
    a.vec(c.shear);
    a.vec(c.prev_normal);
    a.vec(c.force);
    a.vec(c.torque1);
    a.vec(c.torque2);
    a.vec(c.point);
    a.vec(c.fv);
}

inline uint32_t key_first(uint64_t k) { return uint32_t(k >> 32); }
inline uint32_t key_second(uint64_t k) { return uint32_t(k & 0xffffffffu); }

// Version 1 kept every candidate with its physics, history and forces, keyed i << 32 | j.
struct ContactListV1 {
    std::vector<uint64_t> key;
    std::vector<ContactPhys> phys;
    std::vector<ShearHistory> hist;
    std::vector<Vec3> force, torque1, torque2, point;
    std::vector<uint8_t> touching;
};

template <class A> void contacts_v1_io(A& a, ContactListV1& c) {
    a.vec(c.key);
    a.vec(c.phys);
    a.vec(c.hist);
    a.vec(c.force);
    a.vec(c.torque1);
    a.vec(c.torque2);
    a.vec(c.point);
    a.vec(c.touching);
}


// Version 1 contact lists, read before they are converted.
struct V1Contacts {
    ContactListV1 pp, pw;
};

// Version 1 contact lists -> candidate lists and stores (after the particles are read).
inline void convert_v1(ContactSet& cs, std::size_t n, const V1Contacts& v1_) {
    const auto convert = [&](const ContactListV1& c, CandidateList& cl, bool walls) {
        cl.start.assign(n + 1, 0);
        for (uint64_t k : c.key) {
            if (key_first(k) >= n) throw std::runtime_error("contact index out of range");
            ++cl.start[key_first(k) + 1];
        }
        for (std::size_t i = 0; i < n; ++i) cl.start[i + 1] += cl.start[i];
        cl.other.resize(c.key.size());
        cl.slot.assign(c.key.size(), kNoSlot);
        // Gaps unknown: every candidate is tested until the next rebuild.
        cl.gap.assign(c.key.size(), -std::numeric_limits<float>::infinity());
        for (std::size_t k = 0; k < c.key.size(); ++k) {
            cl.other[k] = key_second(c.key[k]);
            if (!c.touching[k]) continue;
            const uint32_t i = key_first(c.key[k]), j = key_second(c.key[k]);
            const ContactPhys& ph = c.phys[k];
            const bool smooth = !walls && ph.mu == 0.0;
            ActiveContacts& a = walls ? cs.walls : smooth ? cs.smooth : cs.fric;
            const uint32_t s = a.add(i, j, uint32_t(k), ph);
            if (ph.mu != 0.0) {
                a.shear[s] = c.hist[k].shear;
                a.prev_normal[s] = c.hist[k].prev_normal;
            }
            a.force[s] = c.force[k];
            a.torque1[s] = c.torque1[k];
            a.torque2[s] = c.torque2[k];
            if (walls) a.point[s] = c.point[k];
            cl.slot[k] = s | (smooth ? kSmoothBit : 0u);
        }
    };
    const std::size_t m = v1_.pp.key.size(), mw = v1_.pw.key.size();
    if (v1_.pp.phys.size() != m || v1_.pp.hist.size() != m || v1_.pp.touching.size() != m ||
        v1_.pp.force.size() != m || v1_.pp.torque1.size() != m || v1_.pp.torque2.size() != m ||
        v1_.pw.phys.size() != mw || v1_.pw.hist.size() != mw || v1_.pw.touching.size() != mw ||
        v1_.pw.force.size() != mw || v1_.pw.torque2.size() != mw || v1_.pw.point.size() != mw ||
        v1_.pw.torque1.size() != mw)
        throw std::runtime_error("contact arrays of different lengths");
    convert(v1_.pp, cs.pp, false);
    convert(v1_.pw, cs.pw, true);
}

}  // namespace io

template <class A, class W> void World::serialize(A& a, W& w, uint32_t version) {
    [[maybe_unused]] io::V1Contacts v1_lists, *v1 = &v1_lists;
    a.section("MATL", [&](A& s) { s.list(w.materials, [](A& x, auto& m) { io::material_io(x, m); }); });
    a.section("PART", [&](A& s) { io::particles_io(s, w.particles); });
    a.section("WALL", [&](A& s) {
        s.list(w.planes, [](A& x, auto& pl) { io::plane_io(x, pl); });
        s.list(w.facets, [](A& x, auto& f) { io::facet_io(x, f); });
    });
    a.section("MOTN", [&](A& s) { s.list(w.motions, [](A& x, auto& m) { io::motion_io(x, m); }); });
    a.section("PRES", [&](A& s) {
        // The fans of a triangulated membrane are not in the format yet: refuse rather than
        // resume without their pressure.
        if constexpr (!A::kLoading)
            if (!w.pressure.fans.empty())
                throw std::runtime_error("checkpoint: a World with pressure fans (a triangulated membrane) cannot be saved yet");
        s.vec(w.pressure.nodes);
        s.pod(w.pressure.dp);
    });
    a.section("PARM", [&](A& s) {
        s.pod(w.params.dt);
        s.pod(w.params.gravity);
        s.pod(w.params.local_damping);
        s.pod(w.params.skin);
        s.pod(w.params.threads);
    });
    a.section("CLCK", [&](A& s) {
        s.pod(w.time);
        s.pod(w.steps);
        s.pod(w.clock_.time_base);
        s.pod(w.clock_.dt_of_base);
        s.pod(w.clock_.step_base);
    });
    if (version >= 2) {
        a.section("CONT", [&](A& s) {
            io::candidates_io(s, w.contacts_.pp);
            io::candidates_io(s, w.contacts_.pw);
            io::store_io(s, w.contacts_.fric);
            io::store_io(s, w.contacts_.smooth);
            io::store_io(s, w.contacts_.walls);
        });
    } else if constexpr (A::kLoading) {
        a.section("CONT", [&](A& s) {
            io::contacts_v1_io(s, v1->pp);
            io::contacts_v1_io(s, v1->pw);
        });
    }
    a.section("BOND", [&](A& s) { io::bonds_io(s, w.bonds_, version); });
    // The bonds' arm, written only when it is not the default (older files, and files of worlds
    // that keep the paper's convention, have no such section and load as kRadius).
    if constexpr (A::kLoading) w.bonds_.arm = BondArm::kRadius;
    a.optional_section("BARM", w.bonds_.arm != BondArm::kRadius, [&](A& s) {
        uint8_t arm = uint8_t(w.bonds_.arm);
        s.pod(arm);
        if constexpr (A::kLoading) {
            if (arm > uint8_t(BondArm::kBondPoint)) io::corrupt(s.path(), "unknown bond arm " + std::to_string(arm));
            w.bonds_.arm = BondArm(arm);
        }
    });
    a.section("VRLT", [&](A& s) {
        if (version >= 2) {
            s.vec(w.broad_.ref_pos);
            s.pod(w.broad_.ref_round);
        } else if constexpr (A::kLoading) {
            std::vector<Vec3> ref;
            s.vec(ref);
            w.broad_.dirty = true;  // version 1: rebuild at the next step
        }
        s.vec(w.broad_.wall_ref_disp);
        s.pod(w.broad_.max_disp);
        if (version >= 2) s.pod(w.broad_.wall_move);
        s.pod(w.broad_.rebuilds);
        s.flag(w.broad_.dirty);
        s.flag(w.physics_dirty_);
        s.flag(w.bonds_dirty_);
    });
    // Results of the last compute_forces(): not needed by the next step (it recomputes
    // them), but restored so every query right after loading answers as before saving.
    a.section("LAST", [&](A& s) {
        s.vec(w.walls_now_.plane_point);
        s.vec(w.walls_now_.velocity);
        s.vec(w.walls_now_.facet_now);
        s.vec(w.walls_now_.force);
        s.vec(w.walls_now_.torque);
    });
    // Energy ledger: only in files of worlds that track energy, so other checkpoints are
    // unchanged (and version-1 files without it load with tracking off). The per-contact
    // terms are kept when the file was written between compute_forces() and integrate().
    a.optional_section("ENRG", w.params.track_energy, [&](A& s) {
        s.flag(w.params.track_energy);
        s.pod(w.book_.ledger);
        s.flag(w.book_.ready);
        if (version >= 2) {
            s.pod(w.contacts_.dropped_shear_energy);
            if (w.book_.ready) {
                s.vec(w.book_.fric);
                s.vec(w.book_.smooth);
                s.vec(w.book_.walls);
                s.vec(w.book_.bonds);
                s.vec(w.pressure_forces_.force);
            }
        } else if (w.book_.ready) {
            // Between compute_forces() and integrate(): the per-contact terms of version 1
            // have no counterpart here; such files come from a program's own tests only.
            throw std::runtime_error("a version 1 checkpoint written in the middle of a step cannot be converted");
        }
    });
    // Clumps: only in files of worlds that have them, so other checkpoints are unchanged.
    a.optional_section("CLMP", !w.clumps_.empty(), [&](A& s) { io::clumps_io(s, w.clumps_); });
    if constexpr (A::kLoading)
        if (version == 1) io::convert_v1(w.contacts_, w.particles.size(), v1_lists);
}

}  // namespace dem

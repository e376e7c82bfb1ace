#include "dem/io/checkpoint.h"

#include "dem/core/kernels.h"

#include <fcntl.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace dem {

static_assert(std::endian::native == std::endian::little,
              "checkpoints are written in host byte order and assume a little-endian host");

// A field added to one of these structs must also be added to the checkpoint (and the format
// version bumped); these asserts make that impossible to forget.
static_assert(sizeof(Particles) == 15 * sizeof(std::vector<int>), "update checkpoint.cpp");
static_assert(sizeof(CandidateList) == 4 * sizeof(std::vector<int>), "update checkpoint.cpp");
static_assert(sizeof(ActiveContacts) == 11 * sizeof(std::vector<int>), "update checkpoint.cpp");
static_assert(sizeof(BondList) == 8 * sizeof(std::vector<int>), "update checkpoint.cpp");
static_assert(sizeof(Material) == sizeof(std::string) + 5 * sizeof(double), "update checkpoint.cpp");
static_assert(sizeof(Motion) == sizeof(Vec3) + sizeof(std::vector<int>), "update checkpoint.cpp");
static_assert(sizeof(Plane) == 2 * sizeof(Vec3) + 16 + sizeof(Motion), "update checkpoint.cpp");
static_assert(sizeof(Facet) == 3 * sizeof(Vec3) + 16 + sizeof(Motion), "update checkpoint.cpp");
static_assert(sizeof(MembranePressure) == sizeof(std::vector<int>) + 8, "update checkpoint.cpp");
static_assert(sizeof(SimulationParams) == 4 * 8 + sizeof(Vec3) &&
                  offsetof(SimulationParams, track_energy) == 3 * 8 + sizeof(Vec3) + 4,
              "update checkpoint.cpp");
static_assert(sizeof(EnergyLedger) == 21 * 8, "update checkpoint.cpp");
static_assert(sizeof(PressureNode) == 20 && sizeof(DisplacementSample) == 32 &&
                  sizeof(ShearHistory) == 48 && sizeof(ContactPhys) == 32 && sizeof(BondPhys) == 24,
              "padding-free records expected");

namespace {

constexpr char kMagic[8] = {'V', 'P', 'P', 'D', 'E', 'M', 'C', 'K'};
constexpr std::size_t kHeader = 8 + 4 + 8;  // magic, version, payload size

uint64_t fnv1a(const char* p, std::size_t n) {
    uint64_t h = 14695981039346656037ull;
    for (std::size_t k = 0; k < n; ++k) {
        h ^= uint8_t(p[k]);
        h *= 1099511628211ull;
    }
    return h;
}

[[noreturn]] void corrupt(const std::string& path, const std::string& what) {
    throw std::runtime_error("checkpoint '" + path + "' is truncated or corrupt: " + what);
}

class Writer {
public:
    std::string buf;

    template <class T> void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    void flag(bool b) { pod(uint8_t(b)); }
    void str(const std::string& s) {
        pod(uint64_t(s.size()));
        buf.append(s);
    }
    template <class T> void vec(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        pod(uint64_t(v.size()));
        buf.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    template <class T, class F> void list(const std::vector<T>& v, F&& each) {
        pod(uint64_t(v.size()));
        for (const T& e : v) each(*this, e);
    }
    // A section that only some files have: written when `present`.
    template <class F> void optional_section(const char (&tag)[5], bool present, F&& body) {
        if (present) section(tag, body);
    }
    template <class F> void section(const char (&tag)[5], F&& body) {
        buf.append(tag, 4);
        const std::size_t at = buf.size();
        pod(uint64_t(0));
        body(*this);
        const uint64_t len = buf.size() - at - 8;
        std::memcpy(buf.data() + at, &len, 8);
    }
};

class Reader {
public:
    Reader(const char* p, std::size_t n, const std::string& path) : p_(p), end_(p + n), path_(path) {}

    template <class T> void pod(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        std::memcpy(&v, p_, sizeof(T));
        p_ += sizeof(T);
    }
    void flag(bool& b) {
        uint8_t v;
        pod(v);
        if (v > 1) corrupt(path_, "bad boolean");
        b = v;
    }
    void str(std::string& s) {
        const uint64_t n = count(1);
        s.assign(p_, n);
        p_ += n;
    }
    template <class T> void vec(std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const uint64_t n = count(sizeof(T));
        v.resize(n);
        if (n) std::memcpy(v.data(), p_, n * sizeof(T));
        p_ += n * sizeof(T);
    }
    template <class T, class F> void list(std::vector<T>& v, F&& each) {
        v.assign(count(1), T{});  // every element takes at least one byte
        for (T& e : v) each(*this, e);
    }
    template <class F> void section(const char (&tag)[5], F&& body) {
        need(12);
        if (std::memcmp(p_, tag, 4) != 0)
            corrupt(path_, "expected section '" + std::string(tag) + "', found '" + std::string(p_, 4) + "'");
        uint64_t len;
        std::memcpy(&len, p_ + 4, 8);
        p_ += 12;
        if (len > uint64_t(end_ - p_)) corrupt(path_, "section '" + std::string(tag) + "' overruns the file");
        Reader sub(p_, len, path_);
        body(sub);
        if (sub.p_ != sub.end_) corrupt(path_, "section '" + std::string(tag) + "' has unread bytes");
        p_ += len;
    }
    // Read when the next section has this tag.
    template <class F> void optional_section(const char (&tag)[5], bool /*present*/, F&& body) {
        if (end_ - p_ >= 4 && std::memcmp(p_, tag, 4) == 0) section(tag, body);
    }
    bool done() const { return p_ == end_; }

private:
    void need(std::size_t n) const {
        if (n > std::size_t(end_ - p_)) corrupt(path_, "record runs past the end of its section");
    }
    // Reads an element count and checks that count * size bytes are left.
    uint64_t count(std::size_t size) {
        uint64_t n;
        pod(n);
        if (n > uint64_t(end_ - p_) / size) corrupt(path_, "element count runs past the end of its section");
        return n;
    }

    const char* p_;
    const char* end_;
    const std::string& path_;
};

// Field lists shared by saving (A = Writer, const objects) and loading (A = Reader).
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

void contacts_v1_io(Reader& a, ContactListV1& c) {
    a.vec(c.key);
    a.vec(c.phys);
    a.vec(c.hist);
    a.vec(c.force);
    a.vec(c.torque1);
    a.vec(c.torque2);
    a.vec(c.point);
    a.vec(c.touching);
}

}  // namespace

void reseal_checkpoint_bytes(std::string& bytes) {
    if (bytes.size() < kHeader + 8) return;
    const uint64_t payload = bytes.size() - kHeader - 8;
    std::memcpy(bytes.data() + 12, &payload, 8);
    const uint64_t sum = fnv1a(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
}

struct WorldSerializer {
    // W is `const World` when saving and `World` when loading.
    // Version 1 contact lists, read before they are converted.
    struct V1Contacts {
        ContactListV1 pp, pw;
    };

    template <class A, class W> static void fields(A& a, W& w, uint32_t version, V1Contacts* v1 = nullptr) {
        a.section("MATL", [&](A& s) { s.list(w.materials, [](A& x, auto& m) { material_io(x, m); }); });
        a.section("PART", [&](A& s) {
            auto& p = w.particles;
            s.vec(p.pos);
            s.vec(p.vel);
            s.vec(p.angvel);
            s.vec(p.force);
            s.vec(p.torque);
            s.vec(p.ext_force);
            s.vec(p.radius);
            s.vec(p.mass);
            s.vec(p.inv_mass);
            s.vec(p.inv_inertia);
            s.vec(p.material);
            s.vec(p.mask);
            s.vec(p.flags);
            s.vec(p.motion);
            s.vec(p.ref_pos);
        });
        a.section("WALL", [&](A& s) {
            s.list(w.planes, [](A& x, auto& pl) { plane_io(x, pl); });
            s.list(w.facets, [](A& x, auto& f) { facet_io(x, f); });
        });
        a.section("MOTN", [&](A& s) { s.list(w.motions, [](A& x, auto& m) { motion_io(x, m); }); });
        a.section("PRES", [&](A& s) {
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
            s.pod(w.time_base_);
            s.pod(w.dt_of_base_);
            s.pod(w.step_base_);
        });
        if (version >= 2) {
            a.section("CONT", [&](A& s) {
                candidates_io(s, w.pp_cand_);
                candidates_io(s, w.pw_cand_);
                store_io(s, w.fric_);
                store_io(s, w.smooth_);
                store_io(s, w.walls_);
            });
        } else if constexpr (std::is_same_v<A, Reader>) {
            a.section("CONT", [&](A& s) {
                contacts_v1_io(s, v1->pp);
                contacts_v1_io(s, v1->pw);
            });
        }
        a.section("BOND", [&](A& s) {
            auto& b = w.bonds_;
            s.vec(b.i);
            s.vec(b.j);
            s.vec(b.phys);
            if (version >= 2) {
                s.vec(b.shear);
                s.vec(b.prev_normal);
            } else if constexpr (std::is_same_v<A, Reader>) {
                std::vector<ShearHistory> hist;
                s.vec(hist);
                for (const ShearHistory& h : hist) {
                    b.shear.push_back(h.shear);
                    b.prev_normal.push_back(h.prev_normal);
                }
            }
            s.vec(b.force);
            s.vec(b.torque1);
            s.vec(b.torque2);
        });
        a.section("VRLT", [&](A& s) {
            if (version >= 2) {
                s.vec(w.ref_pos_);
                s.pod(w.ref_round_);
            } else if constexpr (std::is_same_v<A, Reader>) {
                std::vector<Vec3> ref;
                s.vec(ref);
                w.candidates_dirty_ = true;  // version 1: rebuild at the next step
            }
            s.vec(w.wall_ref_disp_);
            s.pod(w.max_disp_);
            if (version >= 2) s.pod(w.wall_move_);
            s.pod(w.rebuilds_);
            s.flag(w.candidates_dirty_);
            s.flag(w.physics_dirty_);
            s.flag(w.bonds_dirty_);
        });
        // Results of the last compute_forces(): not needed by the next step (it recomputes
        // them), but restored so every query right after loading answers as before saving.
        a.section("LAST", [&](A& s) {
            s.vec(w.plane_point_);
            s.vec(w.wall_vel_);
            s.vec(w.facet_now_);
            s.vec(w.wall_force_);
            s.vec(w.wall_torque_);
        });
        // Energy ledger: only in files of worlds that track energy, so other checkpoints are
        // unchanged (and version-1 files without it load with tracking off). The per-contact
        // terms are kept when the file was written between compute_forces() and integrate().
        a.optional_section("ENRG", w.params.track_energy, [&](A& s) {
            s.flag(w.params.track_energy);
            s.pod(w.energy_);
            s.flag(w.energy_ready_);
            if (version >= 2) {
                s.pod(w.dropped_shear_energy_);
                if (w.energy_ready_) {
                    s.vec(w.fric_energy_);
                    s.vec(w.smooth_energy_);
                    s.vec(w.wall_energy_);
                    s.vec(w.bond_energy_);
                    s.vec(w.pressure_force_);
                }
            } else if (w.energy_ready_) {
                // Between compute_forces() and integrate(): the per-contact terms of version 1
                // have no counterpart here; such files come from a program's own tests only.
                throw std::runtime_error("a version 1 checkpoint written in the middle of a step cannot be converted");
            }
        });
    }

    // Version 1 contact lists -> candidate lists and stores (after the particles are read).
    static void convert_v1(World& w, const V1Contacts& v1_) {
        const std::size_t n = w.particles.size();
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
                ActiveContacts& a = walls ? w.walls_ : smooth ? w.smooth_ : w.fric_;
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
        convert(v1_.pp, w.pp_cand_, false);
        convert(v1_.pw, w.pw_cand_, true);
    }

    static void rebuild(World& w) { w.rebuild_derived_tables(); }

    // Index checks, so a file that passed the checksum but was written inconsistently cannot
    // make rebuild_derived_tables() or the next step read out of bounds.
    static void validate(const World& w, const std::string& path) {
        const Particles& p = w.particles;
        const std::size_t n = p.size(), nw = w.wall_count();
        auto bad = [&](const char* what) { corrupt(path, what); };
        if (!p.ext_force.empty() && p.ext_force.size() != n) bad("particle arrays of different lengths");
        if (!p.ref_pos.empty() && p.ref_pos.size() != n) bad("particle arrays of different lengths");
        for (std::size_t s : {p.vel.size(), p.angvel.size(), p.force.size(), p.torque.size(),
                              p.radius.size(), p.mass.size(), p.inv_mass.size(),
                              p.inv_inertia.size(), p.material.size(), p.mask.size(), p.flags.size(),
                              p.motion.size()})
            if (s != n) bad("particle arrays of different lengths");
        for (std::size_t i = 0; i < n; ++i) {
            if (p.material[i] >= w.materials.size()) bad("particle material out of range");
            if (p.motion[i] >= int64_t(w.motions.size()) || p.motion[i] < -1)
                bad("particle motion out of range");
            if ((p.flags[i] & kPrescribed) && (p.motion[i] < 0 || p.ref_pos.empty())) bad("prescribed particle without motion");
        }
        for (const Plane& pl : w.planes)
            if (pl.material >= w.materials.size()) bad("wall material out of range");
        for (const Facet& f : w.facets)
            if (f.material >= w.materials.size()) bad("wall material out of range");
        for (const PressureNode& q : w.pressure.nodes) {
            if (q.node >= n) bad("pressure node out of range");
            for (uint32_t r : q.ring)
                if (r >= n) bad("pressure ring out of range");
        }
        // Candidate lists: CSR shape, partners in range and ascending, slots pointing to live
        // entries of the right store that point back.
        auto check_candidates = [&](const CandidateList& c, std::size_t other_limit, bool walls) {
            if (c.start.empty() && c.other.empty()) return;
            if (c.start.size() != n + 1 || c.start[0] != 0 || c.start[n] != c.other.size() ||
                c.slot.size() != c.other.size() || c.gap.size() != c.other.size())
                bad("candidate list of the wrong shape");
            for (std::size_t i = 0; i < n; ++i) {
                // Each range within `other` before it is walked: start[n] == other.size() alone
                // let an earlier start[i + 1] above it send the loop past the end (found by
                // fuzz/fuzz_checkpoint.cpp).
                if (c.start[i] > c.start[i + 1] || c.start[i + 1] > c.other.size())
                    bad("candidate list of the wrong shape");
                for (uint32_t k = c.start[i]; k < c.start[i + 1]; ++k) {
                    if (c.other[k] >= other_limit || (!walls && c.other[k] <= i)) bad("contact index out of range");
                    if (k > c.start[i] && c.other[k] <= c.other[k - 1]) bad("candidates out of order");
                    const uint32_t s = c.slot[k];
                    if (s == kNoSlot) continue;
                    const ActiveContacts& a = walls ? w.walls_ : (s & kSmoothBit) ? w.smooth_ : w.fric_;
                    const uint32_t q = walls ? s : s & ~kSmoothBit;
                    if (q >= a.size() || a.cand[q] != k || a.i[q] != i || a.j[q] != c.other[k])
                        bad("contact slot does not match its candidate");
                }
            }
        };
        auto check_store = [&](const ActiveContacts& a, const CandidateList& c) {
            const std::size_t m = a.size();
            for (std::size_t s : {a.j.size(), a.cand.size(), a.phys.size(), a.shear.size(), a.prev_normal.size(),
                                  a.force.size(), a.torque1.size(), a.torque2.size(), a.point.size(), a.fv.size()})
                if (s != m) bad("contact arrays of different lengths");
            for (std::size_t q = 0; q < m; ++q)
                if (a.i[q] >= n || (a.cand[q] != kNoSlot && a.cand[q] >= c.size())) bad("contact index out of range");
        };
        check_store(w.fric_, w.pp_cand_);
        check_store(w.smooth_, w.pp_cand_);
        check_store(w.walls_, w.pw_cand_);
        check_candidates(w.pp_cand_, n, false);
        check_candidates(w.pw_cand_, nw, true);
        const BondList& b = w.bonds_;
        const std::size_t nb = b.size();
        if (b.j.size() != nb || b.phys.size() != nb || b.shear.size() != nb || b.prev_normal.size() != nb ||
            b.force.size() != nb || b.torque1.size() != nb || b.torque2.size() != nb)
            bad("bond arrays of different lengths");
        for (std::size_t k = 0; k < nb; ++k)
            if (b.i[k] >= n || b.j[k] >= n) bad("bond index out of range");
        if (!w.candidates_dirty_ && (w.ref_pos_.size() != n || w.wall_ref_disp_.size() != nw))
            bad("rebuild state does not match the particles and walls");
        using kernels::block_count, kernels::kPairSums;
        if (w.energy_ready_ &&
            (w.fric_energy_.size() != std::size_t(block_count(w.fric_.size()) * kPairSums) ||
             w.smooth_energy_.size() != std::size_t(block_count(w.smooth_.size()) * kPairSums) ||
             w.wall_energy_.size() != std::size_t(block_count(w.walls_.size()) * kPairSums) ||
             w.bond_energy_.size() != std::size_t(block_count(nb)) || w.pressure_force_.size() != n ||
             w.wall_force_.size() != nw || w.wall_vel_.size() != nw))
            bad("energy terms do not match the contacts, bonds and particles");
    }
};

void save_checkpoint(const std::string& path, const World& w, const std::string& app_state) {
    Writer out;
    out.buf.append(kMagic, 8);
    out.pod(kCheckpointVersion);
    out.pod(uint64_t(0));  // payload size, patched below
    WorldSerializer::fields(out, w, kCheckpointVersion);
    out.section("APPS", [&](Writer& s) { s.str(app_state); });
    const uint64_t payload = out.buf.size() - kHeader;
    std::memcpy(out.buf.data() + 12, &payload, 8);
    out.pod(fnv1a(out.buf.data(), out.buf.size()));

    const std::string tmp = path + ".part";
    auto fail = [&](const char* what, int fd) {
        const int err = errno;
        if (fd >= 0) ::close(fd);
        std::remove(tmp.c_str());
        throw std::runtime_error(std::string("cannot save checkpoint '") + path + "': " + what + " '" + tmp +
                                 "' failed (" + std::strerror(err) + ")");
    };
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail("creating", -1);
    for (std::size_t done = 0; done < out.buf.size();) {
        const ssize_t k = ::write(fd, out.buf.data() + done, out.buf.size() - done);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) fail("writing", fd);
        done += std::size_t(k);
    }
    if (::fsync(fd) != 0) fail("syncing", fd);
    if (::close(fd) != 0) fail("closing", -1);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot save checkpoint '" + path + "': renaming '" + tmp + "' failed (" +
                                 ec.message() + ")");
    }
    // Make the rename itself durable (best effort).
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

std::string load_checkpoint(const std::string& path, World& w) {
    std::string buf;
    {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw std::runtime_error("cannot open checkpoint '" + path + "': no such file");
        if (std::filesystem::is_directory(path, ec))
            throw std::runtime_error("cannot open checkpoint '" + path + "': is a directory");
        std::ifstream in(path, std::ios::binary);
        if (!in) throw std::runtime_error("cannot open checkpoint '" + path + "': not readable");
        buf.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (in.bad()) throw std::runtime_error("cannot read checkpoint '" + path + "'");
    }
    const std::size_t m = std::min<std::size_t>(buf.size(), 8);
    if (std::memcmp(buf.data(), kMagic, m) != 0)
        throw std::runtime_error("'" + path + "' is not a vppdem checkpoint (bad magic)");
    if (buf.size() < kHeader) corrupt(path, "file has only " + std::to_string(buf.size()) + " bytes");
    uint32_t version;
    std::memcpy(&version, buf.data() + 8, 4);
    if (version != kCheckpointVersion && version != 1)
        throw std::runtime_error("checkpoint '" + path + "' has format version " + std::to_string(version) +
                                 "; this build supports version " + std::to_string(kCheckpointVersion));
    uint64_t payload;
    std::memcpy(&payload, buf.data() + 12, 8);
    if (buf.size() < kHeader + 8 || buf.size() - kHeader - 8 != payload)
        corrupt(path, "size mismatch (file has " + std::to_string(buf.size()) + " bytes, header says " +
                          std::to_string(payload + kHeader + 8) + ")");
    uint64_t sum;
    std::memcpy(&sum, buf.data() + kHeader + payload, 8);
    if (sum != fnv1a(buf.data(), kHeader + payload)) corrupt(path, "checksum mismatch");

    Reader in(buf.data() + kHeader, payload, path);
    World restored;
    WorldSerializer::V1Contacts v1;
    WorldSerializer::fields(in, restored, version, &v1);
    if (version == 1) WorldSerializer::convert_v1(restored, v1);
    std::string app;
    in.section("APPS", [&](Reader& s) { s.str(app); });
    if (!in.done()) corrupt(path, "unexpected data after the last section");
    WorldSerializer::validate(restored, path);
    WorldSerializer::rebuild(restored);
    w = std::move(restored);
    return app;
}

}  // namespace dem

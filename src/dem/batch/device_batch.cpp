#include "dem/batch/device_batch.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

#include "dem/kernels/kernels.h"
#include "dem/core/parallel.h"

namespace dem::batch {

static_assert(dev::kBlock == kernels::kBlock && dev::kPairSums == kernels::kPairSums &&
              dev::kParticleSums == kernels::kParticleSums && dev::kNone == kNoSlot && dev::kSmooth == kSmoothBit);
static_assert(kernels::kElastic == 0 && kernels::kSlip == 1 && kernels::kRelease == 2 && kernels::kViscous == 3);

struct DeviceBatch::Sys {
    struct St {
        Buf i, j, cand, phys, shear, prev, force, torque1, torque2, point, fv, terms, opened, dterms, hole_bits;
        std::size_t cap = 0;  // slots of room
    };
    St st[3];  // frictional, frictionless, wall
    Buf pp_start, pp_other, pp_slot, pp_gap, pw_start, pw_other, pw_slot, pw_gap, found_pp, found_pw;
    std::size_t pp_size = 0, pw_size = 0;
    Buf link_start, link_count, link_cap, link_ref;
    Buf mats, zeta, wall_mat;
    uint32_t materials = 0;
    Buf ref_pos, pterms, bterms;
    // Chunks: [WallRef per wall | each wall's displacement at the rebuild | PrescRef per prescribed
    // particle | their velocities before the step | the motions' samples], byte offsets o_*.
    Buf refs;
    std::vector<char> h_refs;
    std::size_t o_wall_disp = 0, o_presc_ref = 0, o_presc_v0 = 0, o_probe = 0, probe_n = 0;
    std::size_t off_now = 0;  // this system's walls in the walls-now section
    // This system's parts of the outbox sections (entries of each).
    std::size_t off_reactions = 0;  // this system's walls in the reactions section
    std::size_t sum_fric = 0, sum_smooth = 0, sum_walls = 0, sum_bonds = 0, sum_particles = 0, sum_dashpots = 0;
    int track = 0;
    std::vector<Buf*> bufs() {
        std::vector<Buf*> v{&pp_start, &pp_other, &pp_slot, &pp_gap, &pw_start, &pw_other, &pw_slot, &pw_gap, &found_pp,
                            &found_pw, &link_start, &link_count, &link_cap, &link_ref, &mats, &zeta, &wall_mat,
                            &ref_pos, &pterms, &bterms, &refs};
        for (St& t : st)
            for (Buf* b : {&t.i, &t.j, &t.cand, &t.phys, &t.shear, &t.prev, &t.force, &t.torque1, &t.torque2, &t.point,
                           &t.fv, &t.terms, &t.opened, &t.dterms, &t.hole_bits})
                v.push_back(b);
        return v;
    }
};

namespace {
ActiveContacts& store_of(ContactSet& c, int k) { return k == 0 ? c.fric : k == 1 ? c.smooth : c.walls; }
// The host's copy of a store holds `size` slots (the device placed and freed them).
void resize_store(ActiveContacts& a, std::size_t size) {
    for (auto* v : {&a.i, &a.j, &a.cand}) v->resize(size);
    a.phys.resize(size);
    for (auto* v : {&a.shear, &a.prev_normal, &a.force, &a.torque1, &a.torque2, &a.point, &a.fv}) v->resize(size);
}
template <class T> T* at(DeviceBatch::Buf& b, std::size_t k) { return static_cast<T*>(b.p) + k; }
// The host thread of each() that runs this system (its staging area for download_contacts).
thread_local std::size_t host_thread = 0;
// Adds the wall time of its scope to a counter (host or total seconds of the timing report).
struct Lap {
    double& to;  // [s]
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    ~Lap() { to += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};
}  // namespace

DeviceBatch::DeviceBatch(std::unique_ptr<dev::Device> device, int threads)
    : dev_(std::move(device)), threads_(threads > 1 ? threads : 1) {
    if (!dev_) throw std::invalid_argument("batch: no device");
    stage_.resize(std::size_t(threads_) + 1);
}

template <class F> void DeviceBatch::each(std::size_t B, int part, F&& f) {
    Lap lap{host_s_};
    Lap split{part_s_[part]};
    const int nt = int(std::min<std::size_t>(std::size_t(threads_), std::max<std::size_t>(B, 1)));
    team_.run(nt, [&](int tid) {
        host_thread = std::size_t(tid);
        const auto [s0, s1] = thread_range(int64_t(B), tid, nt);
        for (int64_t s = s0; s < s1; ++s) f(std::size_t(s));
    });
}

DeviceBatch::~DeviceBatch() {
    free_all();
    for (Buf& b : stage_)
        if (b.p) dev_->host_release(b.p);
    if (h_sec_.p) dev_->host_release(h_sec_.p);
}

void DeviceBatch::free_all() {
    for (Sys& y : sys_)
        for (Buf* b : y.bufs())
            if (b->p) dev_->release(b->p);
    sys_.clear();
    for (Buf& b : globals_)
        if (b.p) dev_->release(b.p);
    globals_.clear();
    for (Buf* b : {&views_buf_, &in_, &presc_in_, &sec_})
        if (b->p) {
            dev_->release(b->p);
            *b = Buf{};
        }
    g_ = dev::Globals{};
    layout_dirty_ = true;
}

void DeviceBatch::ensure(Buf& b, std::size_t bytes) {
    if (bytes <= b.bytes && b.p) return;
    const std::size_t cap = std::max<std::size_t>({bytes, b.bytes + b.bytes / 2, 64});
    void* p = dev_->alloc(cap);
    if (b.p) dev_->release(b.p);
    b.p = p;
    b.bytes = cap;
}

void DeviceBatch::ensure_host(Buf& b, std::size_t bytes) {
    if (bytes <= b.bytes && b.p) return;
    const std::size_t cap = std::max<std::size_t>({bytes, b.bytes + b.bytes / 2, 64});
    if (b.p) dev_->host_release(b.p);
    b.p = dev_->host_alloc(cap);
    b.bytes = cap;
}

void DeviceBatch::send(void* dst, const void* src, std::size_t bytes) {
    dev_->put(dst, src, bytes);
    ++calls_;
    up_ += bytes;
}

void DeviceBatch::put(Buf& b, const void* src, std::size_t bytes) {
    ensure(b, bytes);
    send(b.p, src, bytes);
}

void DeviceBatch::get(void* dst, const void* src, std::size_t bytes) {
    dev_->get(dst, src, bytes);
    ++calls_;
    ++waits_;
    down_ += bytes;
}

void DeviceBatch::load(BatchSystems& b) {
    free_all();
    const auto up = [&](auto*& ptr, const auto& vec) {
        Buf buf;
        put(buf, vec.data(), vec.size() * sizeof(vec[0]));
        globals_.push_back(buf);
        ptr = static_cast<std::remove_reference_t<decltype(ptr)>>(buf.p);
    };
    up(g_.x, b.x);
    up(g_.v, b.v);
    up(g_.w, b.w);
    up(g_.f, b.f);
    up(g_.fx, b.fx);
    up(g_.t, b.t);
    up(g_.m, b.m);
    up(g_.inv_m, b.inv_m);
    up(g_.inv_i, b.inv_i);
    up(g_.r, b.r);
    up(g_.pressure_slot, b.pressure_slot);
    up(g_.bi, b.bi);
    up(g_.bj, b.bj);
    up(g_.kn, b.kn);
    up(g_.ks, b.ks);
    up(g_.rest, b.rest);
    up(g_.bshear, b.shear);
    up(g_.bprev, b.prev_normal);
    up(g_.bforce, b.bond_force);
    up(g_.btorque1, b.torque1);
    up(g_.btorque2, b.torque2);
    up(g_.node, b.node);
    {
        Buf buf;
        put(buf, b.ring.data(), b.ring.size() * sizeof(b.ring[0]));
        globals_.push_back(buf);
        g_.ring = static_cast<int64_t*>(buf.p);
    }
    up(g_.prescribed, b.prescribed);
    {
        std::vector<uint32_t> mat;
        mat.reserve(b.particles());
        for (std::size_t s = 0; s < b.systems(); ++s) {
            const std::vector<uint32_t>& m = b.world[s]->particles.material;
            if (int64_t(m.size()) != b.first[s + 1] - b.first[s]) throw std::logic_error("batch: a system's materials");
            mat.insert(mat.end(), m.begin(), m.end());
        }
        up(g_.mat, mat);
    }
    sys_.resize(b.systems());
    views_.assign(b.systems(), dev::SysView{});
    forces_on_.clear();
    life_.assign(b.systems(), dev::Life{});
    vnext_scratch_.assign(b.systems(), {});
    h_presc_.assign(2 * b.prescribed.size(), Vec3{});
    ensure(presc_in_, std::max<std::size_t>(h_presc_.size(), 1) * sizeof(Vec3));
    views_up_.clear();
    life_up_.assign(b.systems(), 1);
    for (std::size_t s = 0; s < b.systems(); ++s) {
        const std::size_t n = std::size_t(b.first[s + 1] - b.first[s]);
        Sys& y = sys_[s];
        upload_contacts(b, s);
        const std::vector<FloatVec3>& ref = b.world[s]->broad_phase().ref_pos;
        ensure(y.ref_pos, n * sizeof(FloatVec3));
        if (ref.size() == n) put(y.ref_pos, ref.data(), n * sizeof(FloatVec3));
        ensure(y.pterms, n * dev::kParticleSums * sizeof(double));
        ensure(y.bterms, std::size_t(b.bond_first[s + 1] - b.bond_first[s]) * sizeof(double));
    }
    layout_dirty_ = true;
    totals_ = b.systems() >= dev::kTotalsFrom;
    up_ = down_ = calls_ = waits_ = 0;
    host_s_ = total_s_ = 0;
    std::fill(std::begin(part_s_), std::end(part_s_), 0.0);
    relayouts_ = 0;
}

void DeviceBatch::ensure_stores(BatchSystems& b, std::size_t s) {
    // A store never holds more slots than its candidates: it appends only when it has no hole, so
    // then its size is its live contacts, one per candidate (and a layout drops the holes). With
    // that room the device places every contact between two layouts.
    ContactSet& c = b.world[s]->engine_contacts();
    Sys& y = sys_[s];
    for (int k = 0; k < 3; ++k) {
        Sys::St& t = y.st[k];
        const std::size_t need = std::max(store_of(c, k).size(), k == 2 ? c.pw.other.size() : c.pp.other.size());
        if (need <= t.cap && t.i.p) continue;
        const std::size_t cap = std::max<std::size_t>({need, t.cap + t.cap / 2, 256});
        for (Buf* bf : {&t.i, &t.j, &t.cand, &t.opened}) ensure(*bf, cap * 4);
        ensure(t.phys, cap * sizeof(ContactPhys));
        for (Buf* bf : {&t.shear, &t.prev, &t.force, &t.torque1, &t.torque2, &t.point, &t.fv}) ensure(*bf, cap * sizeof(Vec3));
        ensure(t.terms, cap * dev::kPairSums * sizeof(double));
        ensure(t.dterms, cap * sizeof(double));
        ensure(t.hole_bits, (cap / 64 + 1) * 8);
        t.cap = cap;
        layout_dirty_ = true;
    }
}

void DeviceBatch::upload_contacts(BatchSystems& b, std::size_t s) {
    World& wd = *b.world[s];
    ContactSet& c = wd.engine_contacts();
    Sys& y = sys_[s];
    const std::size_t n = std::size_t(b.first[s + 1] - b.first[s]);
    ensure_stores(b, s);
    dev::Life& life = life_[s];
    life = dev::Life{};
    for (int k = 0; k < 3; ++k) {
        const ActiveContacts& a = store_of(c, k);
        Sys::St& t = y.st[k];
        const std::size_t m = a.size();
        const auto up = [&](Buf& bf, const auto& vec) { send(bf.p, vec.data(), m * sizeof(vec[0])); };
        up(t.i, a.i);
        up(t.j, a.j);
        up(t.cand, a.cand);
        up(t.phys, a.phys);
        up(t.shear, a.shear);
        up(t.prev, a.prev_normal);
        up(t.force, a.force);
        up(t.torque1, a.torque1);
        up(t.torque2, a.torque2);
        up(t.point, a.point);
        up(t.fv, a.fv);
        // The holes' bits (none at or beyond the size: a placement at the end finds none there).
        std::vector<uint64_t> bits(t.cap / 64 + 1, 0);
        for (std::size_t q = 0; q < m; ++q)
            if (a.cand[q] == kNoSlot) bits[q / 64] |= uint64_t(1) << (q % 64);
        send(t.hole_bits.p, bits.data(), bits.size() * 8);
        life.size[k] = uint32_t(m);
        life.free[k] = uint32_t(m - a.live_count());
    }
    life.holes = c.holes;
    life_up_[s] = 1;
    const auto cands = [&](const CandidateList& cl, Buf& start, Buf& other, Buf& slot, Buf& gap, Buf& found, std::size_t& size) {
        size = cl.other.empty() || cl.start.size() != n + 1 ? 0 : cl.other.size();
        ensure(found, std::max<std::size_t>(size, 1) * 8);
        if (!size) return;
        put(start, cl.start.data(), (n + 1) * 4);
        put(other, cl.other.data(), size * 4);
        put(slot, cl.slot.data(), size * 4);
        put(gap, cl.gap.data(), size * sizeof(float));
    };
    std::size_t pp = y.pp_size, pw = y.pw_size;
    cands(c.pp, y.pp_start, y.pp_other, y.pp_slot, y.pp_gap, y.found_pp, y.pp_size);
    cands(c.pw, y.pw_start, y.pw_other, y.pw_slot, y.pw_gap, y.found_pw, y.pw_size);
    if (pp != y.pp_size || pw != y.pw_size) layout_dirty_ = true;
    // Each particle's list with room for its bonds and one entry per candidate it is in (its
    // content is World's; where it lies in ref does not change the gather).
    const InteractionLists& l = c.links;
    std::vector<uint32_t> room(n, 0), start(n, 0), count(n, 0), ref;
    const bool lists = l.start.size() == n && l.count.size() == n;
    for (std::size_t i = 0; i < n && lists; ++i)
        for (uint32_t e = 0; e < l.count[i]; ++e) room[i] += (l.ref[l.start[i] + e] >> 30) == InteractionLists::kBond;
    if (y.pp_size)
        for (std::size_t i = 0; i < n; ++i) {
            room[i] += c.pp.start[i + 1] - c.pp.start[i];
            for (uint32_t k = c.pp.start[i]; k < c.pp.start[i + 1]; ++k) ++room[c.pp.other[k]];
        }
    if (y.pw_size)
        for (std::size_t i = 0; i < n; ++i) room[i] += c.pw.start[i + 1] - c.pw.start[i];
    std::size_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        start[i] = uint32_t(total);
        total += room[i];
    }
    ref.assign(std::max<std::size_t>(total, 1), 0);
    for (std::size_t i = 0; i < n && lists; ++i) {
        if (l.count[i] > room[i]) throw std::logic_error("batch: a particle's list exceeds its candidates");
        count[i] = l.count[i];
        std::copy(l.ref.begin() + l.start[i], l.ref.begin() + l.start[i] + l.count[i], ref.begin() + start[i]);
    }
    const std::size_t nn = std::max<std::size_t>(n, 1);
    start.resize(nn);
    count.resize(nn);
    room.resize(nn);
    put(y.link_start, start.data(), nn * 4);
    put(y.link_count, count.data(), nn * 4);
    put(y.link_cap, room.data(), nn * 4);
    put(y.link_ref, ref.data(), ref.size() * 4);
    // The new contacts' coefficients: the materials, the pairs' damping ratios (the host's log),
    // the walls' materials, the particles' materials.
    const std::vector<Material>& mat = wd.materials;
    std::vector<dev::MatCoef> mc;
    std::vector<double> zeta;
    for (const Material& m : mat) mc.push_back({m.young, m.stiffness_ratio, m.friction});
    for (const Material& a : mat)
        for (const Material& q : mat) zeta.push_back(pair_damping_ratio(a, q));
    std::vector<uint32_t> wm;
    for (const Plane& p : wd.planes) wm.push_back(p.material);
    for (const Facet& f : wd.facets) wm.push_back(f.material);
    for (uint32_t m : wm)
        if (m >= mat.size()) throw std::logic_error("batch: a wall's material");
    for (uint32_t m : wd.particles.material)
        if (m >= mat.size()) throw std::logic_error("batch: a particle's material");
    mc.resize(std::max<std::size_t>(mc.size(), 1));
    zeta.resize(std::max<std::size_t>(zeta.size(), 1));
    wm.resize(std::max<std::size_t>(wm.size(), 1));
    put(y.mats, mc.data(), mc.size() * sizeof(dev::MatCoef));
    put(y.zeta, zeta.data(), zeta.size() * sizeof(double));
    put(y.wall_mat, wm.data(), wm.size() * 4);
    y.materials = uint32_t(mat.size());
    if (n) send(g_.mat + b.first[s], wd.particles.material.data(), n * 4);
}

void DeviceBatch::download_contacts(BatchSystems& b, std::size_t s, std::size_t slot, bool positions) {
    ContactSet& c = b.world[s]->engine_contacts();
    Sys& y = sys_[s];
    const dev::Life& life = life_[s];
    // What comes down: (World's array, the device's, bytes), each at its offset in the staging.
    struct Part {
        void* host;
        const void* device;
        std::size_t bytes;
    };
    std::vector<Part> parts;
    if (positions) {
        const int64_t base = b.first[s], n = b.first[s + 1] - base;
        parts.push_back({b.world[s]->particles.pos.data(), g_.x + base, std::size_t(n) * sizeof(Vec3)});
    }
    for (int k = 0; k < 3; ++k) {
        ActiveContacts& a = store_of(c, k);
        Sys::St& t = y.st[k];
        const std::size_t m = life.size[k];
        resize_store(a, m);
        parts.push_back({a.i.data(), t.i.p, m * 4});
        parts.push_back({a.j.data(), t.j.p, m * 4});
        parts.push_back({a.cand.data(), t.cand.p, m * 4});
        parts.push_back({a.phys.data(), t.phys.p, m * sizeof(ContactPhys)});
        for (auto [dst, bf] : {std::pair{&a.shear, &t.shear}, {&a.prev_normal, &t.prev}, {&a.force, &t.force},
                               {&a.torque1, &t.torque1}, {&a.torque2, &t.torque2}, {&a.point, &t.point}, {&a.fv, &t.fv}})
            parts.push_back({dst->data(), bf->p, m * sizeof(Vec3)});
    }
    if (y.pp_size) parts.push_back({c.pp.slot.data(), y.pp_slot.p, y.pp_size * 4});
    if (y.pw_size) parts.push_back({c.pw.slot.data(), y.pw_slot.p, y.pw_size * 4});
    std::vector<std::size_t> at_off(parts.size());
    std::size_t total = 0, data = 0;  // the staging's bytes (each part 16-aligned), the parts' own
    for (std::size_t e = 0; e < parts.size(); ++e) {
        at_off[e] = total;
        total += (parts[e].bytes + 15) / 16 * 16;
        data += parts[e].bytes;
    }
    Buf& st = stage_[slot];
    ensure_host(st, total);
    char* const area = static_cast<char*>(st.p);
    for (std::size_t e = 0; e < parts.size(); ++e) dev_->get_async(area + at_off[e], parts[e].device, parts[e].bytes);
    dev_->wait();
    ++calls_;
    ++waits_;
    down_ += data;
    for (std::size_t e = 0; e < parts.size(); ++e)
        if (parts[e].bytes) std::memcpy(parts[e].host, area + at_off[e], parts[e].bytes);
    c.holes = std::size_t(life.holes);
}

void DeviceBatch::put_life(std::size_t s) {
    if (!sec_.p) return;  // layout_outbox() puts them all
    send(static_cast<char*>(sec_.p) + o_life_ + s * sizeof(dev::Life), &life_[s], sizeof(dev::Life));
    life_up_[s] = 0;
}

void DeviceBatch::layout_outbox(BatchSystems& b) {
    std::size_t reactions = 0, sums = 0, msums = 0;
    for (std::size_t s = 0; s < sys_.size(); ++s) {
        Sys& y = sys_[s];
        const int64_t n = b.first[s + 1] - b.first[s], nb = b.bond_first[s + 1] - b.bond_first[s];
        y.off_reactions = reactions;
        reactions += 2 * (b.world[s]->planes.size() + b.world[s]->facets.size());
        y.sum_fric = sums;
        sums += std::size_t(dev::kPairSums * dev::blocks(int64_t(y.st[0].cap)));
        y.sum_smooth = sums;
        sums += std::size_t(dev::kPairSums * dev::blocks(int64_t(y.st[1].cap)));
        y.sum_walls = sums;
        sums += std::size_t(dev::kPairSums * dev::blocks(int64_t(y.st[2].cap)));
        y.sum_bonds = sums;
        sums += std::size_t(dev::blocks(nb));
        y.sum_particles = msums;
        msums += std::size_t(dev::kParticleSums * dev::blocks(n));
        y.sum_dashpots = msums;
        for (const Sys::St& t : y.st) msums += std::size_t(dev::blocks(int64_t(t.cap)));
    }
    o_pstate_ = 0;
    o_chunk_ = o_pstate_ + 2 * b.prescribed.size() * sizeof(Vec3);
    o_life_ = o_chunk_ + sys_.size() * sizeof(dev::Chunk);
    o_presc_ = o_life_ + sys_.size() * sizeof(dev::Life);
    o_reactions_ = o_presc_ + 2 * b.prescribed.size() * sizeof(Vec3);
    o_ftot_ = o_reactions_ + reactions * sizeof(Vec3);
    o_fsums_ = o_ftot_ + sys_.size() * dev::kForceTotals * sizeof(double);
    o_maxd2_ = o_fsums_ + sums * sizeof(double);
    o_mtot_ = o_maxd2_ + sys_.size() * 8;
    o_msums_ = o_mtot_ + sys_.size() * dev::kMotionTotals * sizeof(double);
    o_end_ = o_msums_ + msums * sizeof(double);
    ensure(sec_, std::max<std::size_t>(o_end_, 8));
    ++outbox_gen_;
    ensure_host(h_sec_, std::max<std::size_t>(o_end_, 8));
    layout_dirty_ = false;
    // The section moved: every system's lifecycle goes up again.
    if (!life_.empty()) send(static_cast<char*>(sec_.p) + o_life_, life_.data(), life_.size() * sizeof(dev::Life));
    std::fill(life_up_.begin(), life_up_.end(), 0);
}

void DeviceBatch::fill_view(BatchSystems& b, std::size_t s) {
    Sys& y = sys_[s];
    dev::SysView& v = views_[s];
    v.active = 1;
    v.track = y.track;
    v.base = b.first[s];
    v.n = b.first[s + 1] - b.first[s];
    v.bond0 = b.bond_first[s];
    v.bond1 = b.bond_first[s + 1];
    v.bond_point = b.bond_point[s];
    v.node0 = b.node_first[s];
    v.node1 = b.node_first[s + 1];
    v.presc0 = b.presc_first[s];
    v.presc1 = b.presc_first[s + 1];
    v.dt = b.dt[s];
    v.lambda = b.lambda[s];
    v.with_pressure = b.with_pressure(s);
    v.gravity = b.gravity[s];
    v.walls_n = uint32_t(b.world[s]->planes.size() + b.world[s]->facets.size());
    char* const in = static_cast<char*>(in_.p);
    v.in = reinterpret_cast<const dev::StepIn*>(in) + s;
    v.presc_in = at<Vec3>(presc_in_, 2 * std::size_t(b.presc_first[s]));
    v.wall_now = reinterpret_cast<const WallNow*>(in + o_in_now_) + y.off_now;
    v.wall_vnext = reinterpret_cast<const Vec3*>(in + o_in_vnext_) + y.off_now;
    const auto cands = [](dev::Cands& c, Buf& start, Buf& other, Buf& slot, Buf& gap, std::size_t size) {
        c.start = at<uint32_t>(start, 0);
        c.other = at<uint32_t>(other, 0);
        c.slot = at<uint32_t>(slot, 0);
        c.gap = at<float>(gap, 0);
        c.size = uint32_t(size);
    };
    cands(v.pp, y.pp_start, y.pp_other, y.pp_slot, y.pp_gap, y.pp_size);
    cands(v.pw, y.pw_start, y.pw_other, y.pw_slot, y.pw_gap, y.pw_size);
    for (int k = 0; k < 3; ++k) {
        Sys::St& t = y.st[k];
        dev::Store& d = k == 0 ? v.fric : k == 1 ? v.smooth : v.walls;
        d.i = at<uint32_t>(t.i, 0);
        d.j = at<uint32_t>(t.j, 0);
        d.cand = at<uint32_t>(t.cand, 0);
        d.phys = at<ContactPhys>(t.phys, 0);
        d.shear = at<Vec3>(t.shear, 0);
        d.prev = at<Vec3>(t.prev, 0);
        d.force = at<Vec3>(t.force, 0);
        d.torque1 = at<Vec3>(t.torque1, 0);
        d.torque2 = at<Vec3>(t.torque2, 0);
        d.point = at<Vec3>(t.point, 0);
        d.fv = at<Vec3>(t.fv, 0);
        d.terms = y.track ? at<double>(t.terms, 0) : nullptr;
        d.dterms = at<double>(t.dterms, 0);
        d.hole_bits = at<uint64_t>(t.hole_bits, 0);
        d.cap = uint32_t(t.cap);
        v.opened[k] = at<uint32_t>(t.opened, 0);
    }
    v.link_start = at<uint32_t>(y.link_start, 0);
    v.link_count = at<uint32_t>(y.link_count, 0);
    v.link_cap = at<uint32_t>(y.link_cap, 0);
    v.link_ref = at<uint32_t>(y.link_ref, 0);
    v.found_pp = at<uint32_t>(y.found_pp, 0);
    v.found_pw = at<uint32_t>(y.found_pw, 0);
    v.mats = at<dev::MatCoef>(y.mats, 0);
    v.zeta = at<double>(y.zeta, 0);
    v.materials = y.materials;
    v.wall_mat = at<uint32_t>(y.wall_mat, 0);
    v.ref_pos = at<FloatVec3>(y.ref_pos, 0);
    v.pterms = at<double>(y.pterms, 0);
    v.bterms = at<double>(y.bterms, 0);
    dev::Outbox& o = v.out;
    char* const sec = static_cast<char*>(sec_.p);
    o.life = reinterpret_cast<dev::Life*>(sec + o_life_) + s;
    o.max_d2 = reinterpret_cast<uint64_t*>(sec + o_maxd2_) + s;
    o.reactions = reinterpret_cast<Vec3*>(sec + o_reactions_) + y.off_reactions;
    o.presc = reinterpret_cast<Vec3*>(sec + o_presc_) + 2 * b.presc_first[s];
    double* const sums = reinterpret_cast<double*>(sec + o_fsums_);
    o.sum_fric = sums + y.sum_fric;
    o.sum_smooth = sums + y.sum_smooth;
    o.sum_walls = sums + y.sum_walls;
    o.sum_bonds = sums + y.sum_bonds;
    double* const msums = reinterpret_cast<double*>(sec + o_msums_);
    o.sum_particles = msums + y.sum_particles;
    o.sum_dashpots = msums + y.sum_dashpots;
    o.ftotals = totals_ ? reinterpret_cast<double*>(sec + o_ftot_) + s * dev::kForceTotals : nullptr;
    o.mtotals = totals_ ? reinterpret_cast<double*>(sec + o_mtot_) + s * dev::kMotionTotals : nullptr;
    if (!chunk_views_) {
        v.ck = nullptr;
        o.pstate = nullptr;
        return;
    }
    v.ck = reinterpret_cast<dev::Chunk*>(sec + o_chunk_) + s;
    o.pstate = reinterpret_cast<Vec3*>(sec + o_pstate_) + 2 * b.presc_first[s];
    char* const r = static_cast<char*>(y.refs.p);
    v.wall_ref = reinterpret_cast<const dev::WallRef*>(r);
    v.wall_ref_disp = reinterpret_cast<const Vec3*>(r + y.o_wall_disp);
    v.presc_ref = reinterpret_cast<const dev::PrescRef*>(r + y.o_presc_ref);
    v.presc_v0 = reinterpret_cast<Vec3*>(r + y.o_presc_v0);
    v.probe_particles = reinterpret_cast<const uint32_t*>(r + y.o_probe);
    v.probe_n = uint32_t(y.probe_n);
    v.in_w = reinterpret_cast<dev::StepIn*>(in) + s;
    v.wall_now_w = reinterpret_cast<WallNow*>(in + o_in_now_) + y.off_now;
    v.wall_vnext_w = reinterpret_cast<Vec3*>(in + o_in_vnext_) + y.off_now;
    v.presc_in_w = at<Vec3>(presc_in_, 2 * std::size_t(b.presc_first[s]));
}

void DeviceBatch::upload_views() {
    // Only when they changed (a layout, a system that joined the ledger or left): what changes
    // every step goes up with the walls (StepIn).
    const std::size_t bytes = views_.size() * sizeof(dev::SysView);
    if (views_up_.size() == bytes && std::memcmp(views_up_.data(), views_.data(), bytes) == 0) return;
    put(views_buf_, views_.data(), bytes);
    views_up_.assign(reinterpret_cast<const char*>(views_.data()), reinterpret_cast<const char*>(views_.data()) + bytes);
}

bool DeviceBatch::lay_out_if_due(BatchSystems& b, std::size_t s) {
    World& wd = *b.world[s];
    const bool rebuild = wd.engine_rebuild_due();
    if (!rebuild && !wd.engine_compaction_due()) return false;
    ++relayouts_;
    download_contacts(b, s, host_thread, rebuild);
    wd.engine_begin_forces();
    upload_contacts(b, s);
    if (rebuild) {
        const std::vector<FloatVec3>& ref = wd.broad_phase().ref_pos;
        if (ref.size() != std::size_t(b.first[s + 1] - b.first[s])) throw std::logic_error("batch: no rebuild positions");
        put(sys_[s].ref_pos, ref.data(), ref.size() * sizeof(FloatVec3));
    }
    return true;
}

void DeviceBatch::layout_in(BatchSystems& b) {
    // What goes up every step, in one copy: [StepIn per system | walls now | the walls' next
    // velocities] (the number of walls does not change in a step).
    const std::size_t B = b.systems();
    std::size_t walls_n = 0;
    for (std::size_t s = 0; s < B; ++s) {
        sys_[s].off_now = walls_n;
        walls_n += b.world[s]->planes.size() + b.world[s]->facets.size();
    }
    o_in_now_ = B * sizeof(dev::StepIn);
    o_in_vnext_ = o_in_now_ + walls_n * sizeof(WallNow);
    h_in_.resize(std::max<std::size_t>(o_in_vnext_ + walls_n * sizeof(Vec3), 8));
}

void DeviceBatch::forces(BatchSystems& b, const std::vector<bool>& skip, std::vector<std::exception_ptr>& err) {
    Lap lap{total_s_};
    const std::size_t B = b.systems();
    if (sys_.size() != B) throw std::logic_error("batch: the device holds another layout (load first)");
    const auto live = [&](std::size_t s) { return !(s < skip.size() && skip[s]) && !err[s]; };
    const auto fail = [&](std::size_t s) {
        err[s] = std::current_exception();
        views_[s].active = 0;
    };
    layout_in(b);
    const std::size_t walls_n = (o_in_vnext_ - o_in_now_) / sizeof(WallNow);
    chunk_views_ = false;
    std::vector<int> on(B, 0);
    // The walls' motion, the rebuild test and the broad phase, World's (its positions and
    // contacts from the device first when it rebuilds or compacts, all of them up again after).
    each(B, 0, [&](std::size_t s) {
        if (!live(s)) return;
        try {
            World& wd = *b.world[s];
            Sys& y = sys_[s];
            // The walls at t, and the candidates or the stores laid out anew where World does.
            if (!lay_out_if_due(b, s)) wd.engine_begin_forces();
            const WallState& walls = wd.wall_state();
            const std::size_t nw = wd.planes.size() + wd.facets.size();
            if (y.off_now + nw > walls_n) throw std::logic_error("batch: a system's walls changed in a step");
            if (walls.now.size() != nw) throw std::logic_error("batch: a system's walls were not moved");
            std::memcpy(h_in_.data() + o_in_now_ + y.off_now * sizeof(WallNow), walls.now.data(), nw * sizeof(WallNow));
            y.track = wd.params.track_energy ? 1 : 0;
            if (y.track) {
                // The ledger's dashpots take each wall's velocity over the next step.
                wd.engine_next_wall_velocities(vnext_scratch_[s]);
                if (vnext_scratch_[s].size() != nw) throw std::logic_error("batch: a system's walls' velocities");
                std::memcpy(h_in_.data() + o_in_vnext_ + y.off_now * sizeof(Vec3), vnext_scratch_[s].data(), nw * sizeof(Vec3));
            }
            dev::StepIn in;
            std::tie(in.pair_reach, in.wall_reach) = wd.engine_reach();
            b.dp[s] = world_underpressure(wd);
            in.dp = b.dp[s];
            std::memcpy(h_in_.data() + s * sizeof(dev::StepIn), &in, sizeof in);
            on[s] = 1;
        } catch (...) {
            fail(s);
        }
    });
    put(in_, h_in_.data(), h_in_.size());
    if (layout_dirty_) layout_outbox(b);
    for (std::size_t s = 0; s < B; ++s)
        if (life_up_[s]) put_life(s);
    bool any_track = false;
    for (std::size_t s = 0; s < B; ++s) {
        if (on[s]) fill_view(b, s);
        else views_[s].active = 0;
        any_track |= on[s] && sys_[s].track;
    }
    upload_views();
    // The systems of this forces half, its motion half's (whose views are made again: a chunk of
    // other systems may come between).
    forces_on_.resize(B);
    for (std::size_t s = 0; s < B; ++s) forces_on_[s] = views_[s].active != 0;
    forces_gen_ = outbox_gen_;
    // One launch: the touch test, the new contacts' slots, the forces, the reactions, the frees.
    dev_->forces(g_, static_cast<const dev::SysView*>(views_buf_.p), int(B));
    ++calls_;
    // The lifecycles, the prescribed particles' forces and the walls' reactions (with the ledger
    // also the block sums) in one copy.
    const std::size_t upto = !any_track ? o_ftot_ : totals_ ? o_fsums_ : o_maxd2_;
    get(hs() + o_life_, static_cast<const char*>(sec_.p) + o_life_, upto - o_life_);

    // World's part: the counts of its contacts (the device keeps them), the reactions, the ledger.
    each(B, 1, [&](std::size_t s) {
        if (!on[s]) return;
        try {
            World& wd = *b.world[s];
            Sys& y = sys_[s];
            ContactSet& c = wd.engine_contacts();
            dev::Life& life = life_[s];
            std::memcpy(&life, hs() + o_life_ + s * sizeof(dev::Life), sizeof(dev::Life));
            if (life.overflow)
                throw std::logic_error("batch: a store or an interaction list on the device had no room (a bug: docs/gpu.md)");
            for (int k = 0; k < 3; ++k) resize_store(store_of(c, k), life.size[k]);
            c.holes = std::size_t(life.holes);
            wd.engine_activate();  // nothing found here (the device placed them): the ledger's blocks sized
            if (y.track && totals_) {
                // account() adds each block from +0: the totals in the first block, +0 elsewhere
                // (x + 0 is x: a sum from +0 is never -0), the blocks' sizes World's.
                EnergyBook& book = wd.engine_book();
                const double* t = hd(o_ftot_) + s * dev::kForceTotals;
                for (std::vector<double>* v : {&book.fric, &book.smooth, &book.walls, &book.bonds})
                    std::fill(v->begin(), v->end(), 0.0);
                if (book.fric.size() < std::size_t(dev::kPairSums)) book.fric.assign(dev::kPairSums, 0.0);
                std::copy(t, t + dev::kPairSums, book.fric.begin());
                if (book.bonds.empty()) book.bonds.assign(1, 0.0);
                book.bonds[0] = t[dev::kPairSums];
            } else if (y.track) {
                EnergyBook& book = wd.engine_book();
                const auto sums = [&](std::vector<double>& to, std::size_t off) {
                    std::copy(hd(o_fsums_) + off, hd(o_fsums_) + off + to.size(), to.begin());
                };
                sums(book.fric, y.sum_fric);
                sums(book.smooth, y.sum_smooth);
                sums(book.walls, y.sum_walls);
                sums(book.bonds, y.sum_bonds);
            }
            // The walls' forces, then their torques (no opened list: the device freed them).
            const Vec3* r = hv(o_reactions_) + y.off_reactions;
            wd.engine_end_forces(r, r + wd.planes.size() + wd.facets.size());
            const int64_t base = b.first[s];
            for (int64_t q = b.presc_first[s]; q < b.presc_first[s + 1]; ++q) {
                const uint32_t i = b.prescribed[std::size_t(q)];
                wd.particles.force[i] = hv(o_presc_)[2 * q];
                b.pressure_slot[std::size_t(base + i)] = hv(o_presc_)[2 * q + 1];
            }
        } catch (...) {
            fail(s);
        }
    });
}

void DeviceBatch::motion(BatchSystems& b, const std::vector<bool>& skip, std::vector<std::exception_ptr>& err) {
    Lap lap{total_s_};
    const std::size_t B = b.systems();
    if (forces_on_.size() != B) throw std::logic_error("batch: a motion half without its forces half");
    // The forces half's systems, their views made again: a chunk of other systems in between may
    // have laid the outbox out anew (a store grown at a relayout).
    chunk_views_ = false;
    for (std::size_t s = 0; s < B; ++s) {
        if (forces_on_[s] && !(s < skip.size() && skip[s]) && !err[s]) fill_view(b, s);
        else views_[s].active = 0;
    }
    if (outbox_gen_ != forces_gen_) {
        // The largest moves' words moved with the outbox: zero, as the forces half left them.
        const std::vector<uint64_t> zero(B, 0);
        send(static_cast<char*>(sec_.p) + o_maxd2_, zero.data(), B * 8);
    }
    bool any_track = false;
    for (std::size_t s = 0; s < B; ++s) {
        any_track |= views_[s].active && views_[s].track;
    }
    // The prescribed particles where their motions put them at t + dt (World's, as
    // engine_follow_motions() will set them after the launch), up in one copy.
    if (!h_presc_.empty()) {
        each(B, 2, [&](std::size_t s) {
            if (!views_[s].active) return;
            const World& wd = *b.world[s];
            for (int64_t q = b.presc_first[s]; q < b.presc_first[s + 1]; ++q)
                std::tie(h_presc_[2 * std::size_t(q)], h_presc_[2 * std::size_t(q) + 1]) =
                    wd.engine_prescribed_next(b.prescribed[std::size_t(q)]);
        });
        put(presc_in_, h_presc_.data(), h_presc_.size() * sizeof(Vec3));
    }
    // The views are the forces half's unless a system dropped out since.
    upload_views();
    dev_->motion(g_, static_cast<const dev::SysView*>(views_buf_.p), int(B));
    ++calls_;
    // Each system's largest move (with the ledger also the block sums) in one copy.
    const std::size_t upto = !any_track ? o_mtot_ : totals_ ? o_msums_ : o_end_;
    get(hs() + o_maxd2_, static_cast<const char*>(sec_.p) + o_maxd2_, upto - o_maxd2_);
    each(B, 3, [&](std::size_t s) {
        if (!views_[s].active) return;
        try {
            World& wd = *b.world[s];
            Sys& y = sys_[s];
            const int64_t base = b.first[s], n = b.first[s + 1] - base;
            double max_d2;
            std::memcpy(&max_d2, hs() + o_maxd2_ + s * 8, 8);
            if (y.track && totals_) {
                EnergyBook& book = wd.engine_book();
                const double* t = hd(o_mtot_) + s * dev::kMotionTotals;
                book.particles.assign(std::max<std::size_t>(std::size_t(dev::blocks(n)), 1) * dev::kParticleSums, 0.0);
                std::copy(t, t + dev::kParticleSums, book.particles.begin());
                // account() takes each block away from +0: the one value is the sum negated.
                book.dashpot_blocks.assign(1, t[dev::kParticleSums]);
                book.dashpot_blocks_given = true;
            } else if (y.track) {
                EnergyBook& book = wd.engine_book();
                const std::size_t m = std::size_t(dev::blocks(n) * dev::kParticleSums);
                book.particles.assign(hd(o_msums_) + y.sum_particles, hd(o_msums_) + y.sum_particles + m);
                book.dashpot_blocks.clear();
                const double* from = hd(o_msums_) + y.sum_dashpots;
                for (int k = 0; k < 3; ++k) {
                    book.dashpot_blocks.insert(book.dashpot_blocks.end(), from, from + dev::blocks(life_[s].size[k]));
                    from += dev::blocks(int64_t(y.st[k].cap));
                }
                book.dashpot_blocks_given = true;
            }
            // World moves its prescribed particles (they go up with the next forces half).
            max_d2 = std::max(max_d2, wd.engine_follow_motions(b.pressure_slot.data() + base));
            wd.engine_end_step(max_d2);
        } catch (...) {
            err[s] = std::current_exception();
            views_[s].active = 0;
        }
    });
}

void DeviceBatch::step(BatchSystems& b, uint64_t steps) {
    std::vector<std::exception_ptr> err(b.systems());
    const std::vector<bool> skip;
    for (uint64_t k = 0; k < steps; ++k) {
        forces(b, skip, err);
        motion(b, skip, err);
        for (const auto& e : err)
            if (e) std::rethrow_exception(e);
    }
}

void DeviceBatch::pull(BatchSystems& b, std::size_t s) {
    if (s >= sys_.size()) throw std::invalid_argument("batch: no system " + std::to_string(s) + " on the device");
    const std::size_t base = std::size_t(b.first[s]), n = std::size_t(b.first[s + 1]) - base;
    for (auto [host, d] : {std::pair{&b.x, g_.x}, {&b.v, g_.v}, {&b.w, g_.w}, {&b.f, g_.f}, {&b.t, g_.t}})
        get(host->data() + base, d + base, n * sizeof(Vec3));

    const std::size_t b0 = std::size_t(b.bond_first[s]), nb = std::size_t(b.bond_first[s + 1]) - b0;
    for (auto [host, d] : {std::pair{&b.shear, g_.bshear}, {&b.prev_normal, g_.bprev}, {&b.bond_force, g_.bforce},
                           {&b.torque1, g_.btorque1}, {&b.torque2, g_.btorque2}})
        get(host->data() + b0, d + b0, nb * sizeof(Vec3));
    download_contacts(b, s, stage_.size() - 1, false);
    b.world[s]->engine_relink();
}

}  // namespace dem::batch

namespace dem::batch {

void DeviceBatch::upload_refs(BatchSystems& b, std::size_t s, const std::vector<uint32_t>* probe_particles) {
    const World& wd = *b.world[s];
    Sys& y = sys_[s];
    const std::size_t np = wd.planes.size(), nw = np + wd.facets.size();
    const int64_t q0 = b.presc_first[s], q1 = b.presc_first[s + 1];
    const std::size_t npr = std::size_t(q1 - q0);
    // The motions' samples: each wall's, then each prescribed particle's motion once.
    std::vector<const Motion*> motions;
    std::vector<std::size_t> first;  // each motion's first sample
    std::size_t samples = 0;
    const auto add = [&](const Motion& m) {
        for (std::size_t k = 0; k < motions.size(); ++k)
            if (motions[k] == &m) return k;
        motions.push_back(&m);
        first.push_back(samples);
        samples += m.history.size();
        return motions.size() - 1;
    };
    std::vector<std::size_t> wall_motion(nw), presc_motion(npr);
    for (std::size_t k = 0; k < np; ++k) wall_motion[k] = add(wd.planes[k].motion);
    for (std::size_t k = 0; k < wd.facets.size(); ++k) wall_motion[np + k] = add(wd.facets[k].motion);
    for (std::size_t e = 0; e < npr; ++e) {
        const uint32_t i = b.prescribed[std::size_t(q0) + e];
        presc_motion[e] = add(wd.motions.at(wd.particles.motion.at(i)));
    }
    y.o_wall_disp = nw * sizeof(dev::WallRef);
    y.o_presc_ref = y.o_wall_disp + nw * sizeof(Vec3);
    y.o_presc_v0 = y.o_presc_ref + npr * sizeof(dev::PrescRef);
    const std::size_t o_samples = y.o_presc_v0 + npr * sizeof(Vec3);
    y.o_probe = o_samples + samples * sizeof(DisplacementSample);
    y.probe_n = probe_particles ? probe_particles->size() : 0;
    const std::size_t n = std::size_t(b.first[s + 1] - b.first[s]);
    for (std::size_t k = 0; k < y.probe_n; ++k)
        if ((*probe_particles)[k] >= n)
            throw std::invalid_argument("batch: a probe's particle " + std::to_string((*probe_particles)[k]) + " of " + std::to_string(n));
    const std::size_t bytes = y.o_probe + y.probe_n * 4;
    ensure(y.refs, std::max<std::size_t>(bytes, 8));
    y.h_refs.assign(std::max<std::size_t>(bytes, 8), 0);
    char* const h = y.h_refs.data();
    const auto* dev_samples = reinterpret_cast<const DisplacementSample*>(static_cast<char*>(y.refs.p) + o_samples);
    auto* h_samples = reinterpret_cast<DisplacementSample*>(h + o_samples);
    for (std::size_t k = 0; k < motions.size(); ++k)
        std::copy(motions[k]->history.begin(), motions[k]->history.end(), h_samples + first[k]);
    const auto view = [&](std::size_t k) {
        const Motion& m = *motions[k];
        return MotionView{m.velocity, m.history.empty() ? nullptr : dev_samples + first[k], uint32_t(m.history.size())};
    };
    const BroadPhase& bp = wd.broad_phase();
    if (bp.wall_ref_disp.size() != nw) throw std::logic_error("batch: a system's walls changed since its rebuild");
    auto* refs = reinterpret_cast<dev::WallRef*>(h);
    auto* disp = reinterpret_cast<Vec3*>(h + y.o_wall_disp);
    for (std::size_t k = 0; k < nw; ++k) {
        dev::WallRef r;
        r.plane = k < np;
        if (r.plane) {
            r.point = wd.planes[k].point;
            r.normal = wd.planes[k].normal;
            r.one_sided = wd.planes[k].one_sided;
        } else {
            const Facet& f = wd.facets[k - np];
            r.v0 = f.vertices[0];
            r.v1 = f.vertices[1];
            r.v2 = f.vertices[2];
            r.one_sided = f.one_sided;
        }
        r.motion = view(wall_motion[k]);
        refs[k] = r;
        disp[k] = bp.wall_ref_disp[k];
    }
    auto* presc = reinterpret_cast<dev::PrescRef*>(h + y.o_presc_ref);
    for (std::size_t e = 0; e < npr; ++e) {
        const uint32_t i = b.prescribed[std::size_t(q0) + e];
        presc[e] = dev::PrescRef{wd.particles.ref_pos.at(i), view(presc_motion[e])};
    }
    if (y.probe_n) std::copy(probe_particles->begin(), probe_particles->end(), reinterpret_cast<uint32_t*>(h + y.o_probe));
    send(y.refs.p, h, bytes);
}

void DeviceBatch::run(BatchSystems& b, const std::vector<uint64_t>& until, int K, const std::vector<bool>& skip,
                      std::vector<std::exception_ptr>& err, std::vector<Probe>* probes) {
    while (run_chunk(b, until, K, skip, err, probes)) {
    }
}

bool DeviceBatch::run_chunk(BatchSystems& b, const std::vector<uint64_t>& until, int K, const std::vector<bool>& skip,
                            std::vector<std::exception_ptr>& err, std::vector<Probe>* probes) {
    const std::size_t B = b.systems();
    if (sys_.size() != B) throw std::logic_error("batch: the device holds another layout (load first)");
    if (until.size() != B || err.size() != B || (probes && probes->size() != B))
        throw std::invalid_argument("batch: run() takes one event, one error (and one probe) per system");
    if (K < 1) throw std::invalid_argument("batch: a chunk of " + std::to_string(K) + " steps (at least 1)");
    // The device books the ledger from its totals of the block sums (the host adds nothing).
    totals_ = true;
    h_chunks_.resize(B);
    const auto live = [&](std::size_t s) {
        return !(s < skip.size() && skip[s]) && !err[s] && b.world[s]->steps < until[s];
    };
    {
        Lap lap{total_s_};
        layout_in(b);
        std::vector<int> on(B, 0);
        // World's part first: a layout where World would make one (the device stopped there, or
        // the caller changed the system), then the chunk's state and the motions.
        each(B, 0, [&](std::size_t s) {
            if (!live(s)) return;
            try {
                World& wd = *b.world[s];
                Sys& y = sys_[s];
                lay_out_if_due(b, s);
                y.track = wd.params.track_energy ? 1 : 0;
                const World::EngineSteps e = wd.engine_steps();
                dev::Chunk& c = h_chunks_[s];
                c = dev::Chunk{};
                c.time = e.time;
                c.steps = e.steps;
                c.clock = e.clock;
                c.stop_at = until[s];
                c.max_disp = e.max_disp;
                c.wall_move = e.wall_move;
                c.skin = e.skin;
                c.ref_round = e.ref_round;
                c.dropped = wd.engine_contacts().dropped_shear_energy;
                c.ledger = wd.energy();
                for (const Material& m : wd.materials) c.dashpots |= m.restitution < 1.0;
                if (probes) c.probe = (*probes)[s].sums;
                upload_refs(b, s, probes ? &(*probes)[s].particles : nullptr);
                dev::StepIn in;
                b.dp[s] = world_underpressure(wd);
                in.dp = b.dp[s];
                std::memcpy(h_in_.data() + s * sizeof(dev::StepIn), &in, sizeof in);
                on[s] = 1;
            } catch (...) {
                err[s] = std::current_exception();
            }
        });
        if (std::find(on.begin(), on.end(), 1) == on.end()) return false;
        put(in_, h_in_.data(), h_in_.size());
        if (layout_dirty_) layout_outbox(b);
        for (std::size_t s = 0; s < B; ++s)
            if (life_up_[s]) put_life(s);
        send(static_cast<char*>(sec_.p) + o_chunk_, h_chunks_.data(), B * sizeof(dev::Chunk));
        chunk_views_ = true;
        for (std::size_t s = 0; s < B; ++s) {
            if (on[s]) fill_view(b, s);
            else views_[s].active = 0;
        }
        upload_views();
        dev_->chunk(g_, static_cast<const dev::SysView*>(views_buf_.p), int(B), K);
        ++calls_;
        ++chunks_;
        // Back in one copy: the prescribed particles, the chunks, the lifecycles, the prescribed
        // particles' forces, the walls' reactions.
        get(hs() + o_pstate_, static_cast<const char*>(sec_.p) + o_pstate_, o_ftot_ - o_pstate_);
        each(B, 1, [&](std::size_t s) {
            if (!on[s]) return;
            try {
                World& wd = *b.world[s];
                ContactSet& c = wd.engine_contacts();
                dev::Chunk ck;
                std::memcpy(&ck, hs() + o_chunk_ + s * sizeof(dev::Chunk), sizeof ck);
                dev::Life& life = life_[s];
                std::memcpy(&life, hs() + o_life_ + s * sizeof(dev::Life), sizeof(dev::Life));
                if (life.overflow)
                    throw std::logic_error("batch: a store or an interaction list on the device had no room (a bug: docs/gpu.md)");
                for (int k = 0; k < 3; ++k) resize_store(store_of(c, k), life.size[k]);
                c.holes = std::size_t(life.holes);
                const bool ran = ck.steps > wd.steps;
                World::EngineSteps e = wd.engine_steps();
                e.time = ck.time;
                e.steps = ck.steps;
                e.clock = ck.clock;
                e.max_disp = ck.max_disp;
                e.wall_move = ck.wall_move;
                wd.engine_set_steps(e);
                if (sys_[s].track) wd.engine_book().ledger = ck.ledger;
                c.dropped_shear_energy = ck.dropped;
                if (probes) (*probes)[s].sums = ck.probe;
                if (ran) {
                    wd.engine_activate();  // the ledger's blocks sized as World's
                    const Vec3* r = hv(o_reactions_) + sys_[s].off_reactions;
                    wd.engine_end_forces(r, r + wd.planes.size() + wd.facets.size());
                    const int64_t base = b.first[s];
                    for (int64_t q = b.presc_first[s]; q < b.presc_first[s + 1]; ++q) {
                        const uint32_t i = b.prescribed[std::size_t(q)];
                        wd.particles.force[i] = hv(o_presc_)[2 * q];
                        b.pressure_slot[std::size_t(base + i)] = hv(o_presc_)[2 * q + 1];
                        wd.particles.pos[i] = hv(o_pstate_)[2 * q];
                        wd.particles.vel[i] = hv(o_pstate_)[2 * q + 1];
                    }
                }
                // The device's rules are World's (rebuild_rule.h): World must see the stop too.
                if (ck.stop == dev::kRebuild && !wd.engine_rebuild_due())
                    throw std::logic_error("batch: the device stopped for a rebuild that World does not make (a bug: docs/gpu.md)");
                if (ck.stop == dev::kCompaction && !wd.engine_compaction_due())
                    throw std::logic_error("batch: the device stopped for a compaction that World does not make (a bug: docs/gpu.md)");
            } catch (...) {
                err[s] = std::current_exception();
                views_[s].active = 0;
            }
        });
    }
    return true;
}

void DeviceBatch::run(BatchSystems& b, uint64_t steps, int K) {
    std::vector<uint64_t> until(b.systems());
    for (std::size_t s = 0; s < b.systems(); ++s) until[s] = b.world[s]->steps + steps;
    std::vector<std::exception_ptr> err(b.systems());
    run(b, until, K, {}, err);
    for (const auto& e : err)
        if (e) std::rethrow_exception(e);
}

}  // namespace dem::batch

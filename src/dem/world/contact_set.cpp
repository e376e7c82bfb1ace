#include "dem/world/contact_set.h"

#include <algorithm>

#include "dem/core/parallel.h"
#include "dem/kernels/step_bodies.h"
#include "dem/detect/geometry.h"

namespace dem {

namespace {

// Slot of the candidate (i, j) in the list, or nullptr when the pair is no candidate.
uint32_t* find_slot(CandidateList& c, uint32_t i, uint32_t j) {
    const auto b = c.other.begin() + c.start[i], e = c.other.begin() + c.start[i + 1];
    const auto it = std::lower_bound(b, e, j);
    return it != e && *it == j ? &c.slot[std::size_t(it - c.other.begin())] : nullptr;
}

}  // namespace

void ContactSet::prepare_threads(int nt) {
    for (auto* v : {&new_pp, &new_pw, &scratch, &pair_i, &pair_j, &pair_hits, &opened_fric, &opened_smooth, &opened_walls})
        v->resize(std::size_t(nt));
}

void ContactSet::find_new(const FindArgs& a) {
    // The same geometric tests as the force kernels, so a pair found here is found touching
    // there. Only candidates without a contact that could have closed their gap since the
    // rebuild are tested (CandidateList::gap); they are picked out by a vector filter, since a
    // branch per candidate would be mispredicted about every other time.
    const Particles& p = *a.p;
    const int64_t n = int64_t(p.size());
    const int tid = thread_id();
    std::vector<uint32_t>& npp = new_pp[tid];
    std::vector<uint32_t>& npw = new_pw[tid];
    std::vector<uint32_t>& test = scratch[tid];
    npp.clear();
    npw.clear();
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
        const CandidateList& c = pp;
        if (c.other.empty()) return;
        test.clear();
        kernels::filter_open_candidates(c.slot.data(), c.gap.data(), reach, c.start[i0], c.start[i1], test);
        std::vector<uint32_t>& is = pair_i[tid];
        std::vector<uint32_t>& js = pair_j[tid];
        is.resize(test.size());
        js.resize(test.size());
        int64_t i = i0;
        for (std::size_t q = 0; q < test.size(); ++q) {
            while (c.start[i + 1] <= test[q]) ++i;
            is[q] = uint32_t(i);
            js[q] = c.other[test[q]];
        }
        std::vector<uint32_t>& hits = pair_hits[tid];
        hits.clear();
        kernels::touching_pairs(a.packed, is.data(), js.data(), test.size(), hits);
        for (uint32_t q : hits) {
            npp.push_back(is[q]);
            npp.push_back(test[q]);
        }
    };
    const std::vector<WallNow>& wall_now = *a.wall_now;
    for (const auto& [b0, b1] : *a.blocks) {
        const int64_t i0 = b0 * kernels::kBlock, i1 = std::min(n, b1 * kernels::kBlock);
        if (a.packed && a.repack) kernels::pack_particles(p, i0, i1, a.packed);
        if (a.packed) scan_pairs(i0, i1, a.pair_reach);
        else scan(pp, i0, i1, a.pair_reach, [&](uint32_t i, uint32_t j) {
            return spheres_touch_lanes(lanes(p.pos[i]), p.radius[i], lanes(p.pos[j]), p.radius[j]);
        }, npp);
        scan(pw, i0, i1, a.wall_reach, [&](uint32_t i, uint32_t w) {
            ContactGeom g;  // the touch test of the wall body (dem/kernels/step_bodies.h), the batch engine's too
            return wall_geometry(p.pos[i], p.radius[i], wall_now[w], g);
        }, npw);
    }
}

void ContactSet::activate_new(const ContactPhysics& phys) {
    // The threads' lists are merged and sorted first, so the slots a new contact gets do not
    // depend on which thread found it.
    const auto merged = [](std::vector<std::vector<uint32_t>>& lists) {
        std::vector<std::pair<uint32_t, uint32_t>> all;  // (candidate, particle)
        for (const auto& l : lists)
            for (std::size_t q = 0; q < l.size(); q += 2) all.emplace_back(l[q + 1], l[q]);
        std::sort(all.begin(), all.end());
        return all;
    };
    // New contacts fill the holes of opened ones, lowest first (in candidate order).
    std::size_t new_count = 0;
    for (const auto* lists : {&new_pp, &new_pw})
        for (const auto& l : *lists) new_count += l.size() / 2;
    std::size_t fric_cursor = 0, smooth_cursor = 0, wall_cursor = 0;
    const std::size_t before = store_slots();
    for (const auto& [k, i] : merged(new_pp)) {
        const uint32_t j = pp.other[k];
        const ContactPhys ph = phys.pair(i, j);
        const bool is_smooth = ph.mu == 0.0;
        const uint32_t s = is_smooth ? smooth.place(i, j, k, ph, &smooth_cursor) : fric.place(i, j, k, ph, &fric_cursor);
        pp.slot[k] = s | (is_smooth ? kSmoothBit : 0u);
        const auto src = is_smooth ? InteractionLists::kFrictionless : InteractionLists::kFrictional;
        links.insert(i, InteractionLists::make(src, false, s));
        links.insert(j, InteractionLists::make(src, true, s));
    }
    for (const auto& [k, i] : merged(new_pw)) {
        const uint32_t w = pw.other[k];
        pw.slot[k] = walls.place(i, w, k, phys.wall(i, w), &wall_cursor);
        links.insert(i, InteractionLists::make(InteractionLists::kWall, true, pw.slot[k]));
    }
    const std::size_t filled = new_count - (store_slots() - before);
    holes = holes > filled ? holes - filled : 0;
}

void ContactSet::release_opened() {
    using L = InteractionLists;
    const auto release = [&](ActiveContacts& a, CandidateList& cl, const std::vector<std::vector<uint32_t>>& opened,
                             L::Source src) {
        for (const auto& list : opened)
            for (uint32_t s : list) {
                cl.slot[a.cand[s]] = kNoSlot;
                a.cand[s] = kNoSlot;
                ++holes;
                if (src == L::kWall) {
                    links.erase(a.i[s], L::make(src, true, s));
                } else {
                    links.erase(a.i[s], L::make(src, false, s));
                    links.erase(a.j[s], L::make(src, true, s));
                }
            }
    };
    release(fric, pp, opened_fric, L::kFrictional);
    release(smooth, pp, opened_smooth, L::kFrictionless);
    release(walls, pw, opened_walls, L::kWall);
}

void ContactSet::compact(bool refresh, const ContactPhysics& phys, const BondTables& bonds, std::size_t n) {
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
    for (std::size_t i = 0; i < n && !pp.start.empty(); ++i)
        for (uint32_t k = pp.start[i]; k < pp.start[i + 1]; ++k) {
            const uint32_t s = pp.slot[k];
            if (s == kNoSlot) continue;
            const bool was_smooth = s & kSmoothBit;
            const ActiveContacts& src = was_smooth ? smooth : fric;
            const uint32_t c = s & ~kSmoothBit;
            const ContactPhys ph = refresh ? phys.pair(uint32_t(i), pp.other[k]) : src.phys[c];
            const bool is_smooth = ph.mu == 0.0;
            if (is_smooth && !was_smooth) dropped_shear_energy += dropped(src, c);
            const uint32_t t = copy(src, c, is_smooth ? ns : nf, k, ph, !is_smooth && !was_smooth);
            pp.slot[k] = t | (is_smooth ? kSmoothBit : 0u);
        }
    for (std::size_t i = 0; i < n && !pw.start.empty(); ++i)
        for (uint32_t k = pw.start[i]; k < pw.start[i + 1]; ++k) {
            const uint32_t s = pw.slot[k];
            if (s == kNoSlot) continue;
            const ContactPhys ph = refresh ? phys.wall(uint32_t(i), pw.other[k]) : walls.phys[s];
            const bool keep = ph.mu != 0.0;
            if (!keep) dropped_shear_energy += dropped(walls, s);
            pw.slot[k] = copy(walls, s, nw, k, ph, keep);
        }
    fric = std::move(nf);
    smooth = std::move(ns);
    walls = std::move(nw);
    holes = 0;
    build_interaction_lists(bonds, n);  // the slots moved
}

void ContactSet::build_interaction_lists(const BondTables& bonds, std::size_t n) {
    using L = InteractionLists;
    L& l = links;
    // Each particle's region holds its bonds and live contacts plus some room for contacts
    // that start before the next rebuild (when a region is full, the lists are laid out anew).
    const auto each = [&](auto&& f) {
        for (std::size_t i = 0; i < n; ++i)
            for (uint32_t k = bonds.start[i]; k < bonds.start[i + 1]; ++k)
                f(uint32_t(i), L::make(L::kBond, bonds.entries[k] & BondTables::kSideBit,
                                       bonds.entries[k] & ~BondTables::kSideBit));
        for (std::size_t s = 0; s < fric.size(); ++s)
            if (fric.cand[s] != kNoSlot) {
                f(fric.i[s], L::make(L::kFrictional, false, uint32_t(s)));
                f(fric.j[s], L::make(L::kFrictional, true, uint32_t(s)));
            }
        for (std::size_t s = 0; s < smooth.size(); ++s)
            if (smooth.cand[s] != kNoSlot) {
                f(smooth.i[s], L::make(L::kFrictionless, false, uint32_t(s)));
                f(smooth.j[s], L::make(L::kFrictionless, true, uint32_t(s)));
            }
        for (std::size_t s = 0; s < walls.size(); ++s)
            if (walls.cand[s] != kNoSlot) f(walls.i[s], L::make(L::kWall, true, uint32_t(s)));
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

void ContactSet::reattach() {
    // A touching pair is always within the skin, so it is found, unless its masks, bonds or
    // fixity changed since: then it is dropped with its history.
    const auto attach = [](ActiveContacts& a, CandidateList& cl, uint32_t bit) {
        for (std::size_t s = 0; s < a.size(); ++s) {
            if (a.cand[s] == kNoSlot) continue;
            uint32_t* slot = find_slot(cl, a.i[s], a.j[s]);
            if (!slot) {
                a.cand[s] = kNoSlot;
                continue;
            }
            *slot = uint32_t(s) | bit;
            a.cand[s] = uint32_t(slot - cl.slot.data());
        }
    };
    attach(fric, pp, 0u);
    attach(smooth, pp, kSmoothBit);
    attach(walls, pw, 0u);
}

void ContactSet::drop_wall_contacts_from(uint32_t first_wall) {
    for (std::size_t s = 0; s < walls.size(); ++s)
        if (walls.cand[s] != kNoSlot && walls.j[s] >= first_wall) {
            pw.slot[walls.cand[s]] = kNoSlot;
            walls.cand[s] = kNoSlot;
            walls.force[s] = walls.torque2[s] = Vec3{};
        }
    // The candidates with those walls go too; the others move down, and their live contacts
    // follow them. (The next broad phase builds the lists anew: nothing here changes a result.)
    if (pw.start.empty()) return;
    const std::size_t n = pw.start.size() - 1;
    uint32_t at = 0, begin = pw.start[0];
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t end = pw.start[i + 1];
        pw.start[i] = at;
        for (uint32_t k = begin; k < end; ++k) {
            if (pw.other[k] >= first_wall) continue;
            pw.other[at] = pw.other[k];
            pw.slot[at] = pw.slot[k];
            pw.gap[at] = pw.gap[k];
            if (pw.slot[at] != kNoSlot) walls.cand[pw.slot[at]] = at;
            ++at;
        }
        begin = end;
    }
    pw.start[n] = at;
    pw.other.resize(at);
    pw.slot.resize(at);
    pw.gap.resize(at);
}

void ContactSet::shift_walls_from(uint32_t first) {
    for (uint32_t& j : walls.j)
        if (j >= first) ++j;
    for (uint32_t& w : pw.other)
        if (w >= first) ++w;
}

void ContactSet::cover_particles(std::size_t n) {
    for (CandidateList* c : {&pp, &pw})
        if (!c->start.empty() && c->start.size() < n + 1) c->start.resize(n + 1, c->start.back());
}

const char* ContactSet::broken_rule(std::size_t n, std::size_t nw) const {
    // Candidate lists: CSR shape, partners in range and ascending, slots pointing to live
    // entries of the right store that point back.
    const auto check_candidates = [&](const CandidateList& c, std::size_t other_limit, bool wall) -> const char* {
        if (c.start.empty() && c.other.empty()) return nullptr;
        if (c.start.size() != n + 1 || c.start[0] != 0 || c.start[n] != c.other.size() ||
            c.slot.size() != c.other.size() || c.gap.size() != c.other.size())
            return "candidate list of the wrong shape";
        for (std::size_t i = 0; i < n; ++i) {
            // Each range within `other` before it is walked: start[n] == other.size() alone
            // let an earlier start[i + 1] above it send the loop past the end (found by
            // fuzz/fuzz_checkpoint.cpp).
            if (c.start[i] > c.start[i + 1] || c.start[i + 1] > c.other.size()) return "candidate list of the wrong shape";
            for (uint32_t k = c.start[i]; k < c.start[i + 1]; ++k) {
                if (c.other[k] >= other_limit || (!wall && c.other[k] <= i)) return "contact index out of range";
                if (k > c.start[i] && c.other[k] <= c.other[k - 1]) return "candidates out of order";
                const uint32_t s = c.slot[k];
                if (s == kNoSlot) continue;
                const ActiveContacts& a = wall ? walls : (s & kSmoothBit) ? smooth : fric;
                const uint32_t q = wall ? s : s & ~kSmoothBit;
                if (q >= a.size() || a.cand[q] != k || a.i[q] != i || a.j[q] != c.other[k])
                    return "contact slot does not match its candidate";
            }
        }
        return nullptr;
    };
    const auto check_store = [&](const ActiveContacts& a, const CandidateList& c) -> const char* {
        const std::size_t m = a.size();
        for (std::size_t s : {a.j.size(), a.cand.size(), a.phys.size(), a.shear.size(), a.prev_normal.size(),
                              a.force.size(), a.torque1.size(), a.torque2.size(), a.point.size(), a.fv.size()})
            if (s != m) return "contact arrays of different lengths";
        for (std::size_t q = 0; q < m; ++q)
            if (a.i[q] >= n || (a.cand[q] != kNoSlot && a.cand[q] >= c.size())) return "contact index out of range";
        return nullptr;
    };
    for (const char* why : {check_store(fric, pp), check_store(smooth, pp), check_store(walls, pw)})
        if (why) return why;
    if (const char* why = check_candidates(pp, n, false)) return why;
    return check_candidates(pw, nw, true);
}

}  // namespace dem

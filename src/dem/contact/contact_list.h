// Persistent contact list: every candidate pair found by the broad phase (within the skin),
// sorted by its 64-bit key. Forces are written per contact, then gathered per particle
// through CSR ranges in a fixed order, so results are independent of the thread count and no
// atomics are needed. History (the shear spring) follows its key across rebuilds.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/contact/linear_law.h"
#include "dem/core/vec3.h"

namespace dem {

inline uint64_t pair_key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | uint64_t(b); }
inline uint32_t key_first(uint64_t k) { return uint32_t(k >> 32); }
inline uint32_t key_second(uint64_t k) { return uint32_t(k & 0xffffffffu); }

// For particle-particle lists the key is (i << 32 | j) with i < j. For particle-wall lists it
// is (particle << 32 | wall), walls numbered planes first, then facets.
struct ContactList {
    std::vector<uint64_t> key;
    std::vector<ContactPhys> phys;
    std::vector<ShearHistory> hist;
    // Written every step by the force kernel:
    std::vector<Vec3> force;     // [N] on body 2 (body 1 gets the opposite)
    std::vector<Vec3> torque1;   // [N m] on body 1 (unused for walls)
    std::vector<Vec3> torque2;   // [N m] on body 2
    std::vector<Vec3> point;     // [m] contact point (wall lists only; for wall torques)
    std::vector<uint8_t> touching;  // 1 when the pair overlaps this step

    std::size_t size() const { return key.size(); }

    void resize(std::size_t n, bool with_points) {
        key.resize(n);
        phys.resize(n);
        hist.assign(n, ShearHistory{});
        force.assign(n, Vec3{});
        torque1.assign(n, Vec3{});
        torque2.assign(n, Vec3{});
        if (with_points) point.assign(n, Vec3{});
        touching.assign(n, 0);
    }

    // Replace the list by `new_keys` (sorted), keeping the history of pairs present in both.
    // Returns, for each new entry, whether it existed before (so physics can be reused).
    void merge_from(const std::vector<uint64_t>& new_keys, bool with_points,
                    std::vector<uint8_t>& existed) {
        ContactList next;
        next.resize(new_keys.size(), with_points);
        next.key = new_keys;
        existed.assign(new_keys.size(), 0);
        std::size_t a = 0;
        for (std::size_t b = 0; b < new_keys.size(); ++b) {
            while (a < key.size() && key[a] < new_keys[b]) ++a;
            if (a < key.size() && key[a] == new_keys[b]) {
                next.phys[b] = phys[a];
                next.hist[b] = hist[a];
                next.touching[b] = touching[a];
                existed[b] = 1;
            }
        }
        *this = std::move(next);
    }

    std::size_t count_touching() const {
        std::size_t n = 0;
        for (uint8_t t : touching) n += t;
        return n;
    }
};

}  // namespace dem

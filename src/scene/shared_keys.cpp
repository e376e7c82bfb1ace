#include "scene/shared_keys.h"

#include "scene/threads.h"

namespace cfg {

int read_threads(Section& s, const std::string& key, int64_t def) {
    const Limits& l = keys::threads.limits;
    const int64_t n = s.integer(key, def);
    if (n < int64_t(l.lo) || n > int64_t(l.hi)) s.fail(key, l.allowed);
    return n == 0 ? scene::default_threads() : int(n);
}

uint64_t read_seed(Section& s, const std::string& key, int64_t def) {
    const int64_t seed = s.integer(key, def);
    if (seed < int64_t(keys::seed.limits.lo)) s.fail(key, keys::seed.limits.allowed);
    return uint64_t(seed);
}

}  // namespace cfg

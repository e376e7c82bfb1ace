#include "scene/time_step.h"

#include <cmath>

namespace scene {

TimeStep read_dt(cfg::Section& s, const std::string& key, double def) {
    const char* allowed = cfg::keys::dt.limits.allowed;
    TimeStep t;
    t.automatic = std::isnan(def);
    t.dt = t.automatic ? 0.0 : def;
    if (const toml::node* n = s.node(key)) {
        if (auto word = n->as_string()) {
            if (word->get() != "auto") s.fail(key, allowed);
            t.automatic = true;
            t.dt = 0.0;
        } else if (auto v = n->value<double>()) {
            t.automatic = false;
            t.dt = s.positive(key, *v);
        } else {
            s.fail(key, allowed);
        }
    }
    return t;
}

double time_step(const TimeStep& t, const dem::World& w) { return t.automatic ? t.safety * w.critical_dt() : t.dt; }

}  // namespace scene

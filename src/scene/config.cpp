#include "scene/config.h"

#include <charconv>

#include <cmath>
#include <sstream>

namespace cfg {

std::string describe(const toml::node& n) {
    // Arrays on one line (toml++ may spread them over several): messages are one line.
    if (const toml::array* a = n.as_array()) {
        std::string out = "[";
        for (std::size_t k = 0; k < a->size(); ++k) out += (k ? ", " : "") + describe(*a->get(k));
        return out + "]";
    }
    // A float in its shortest form that reads back (0.7, not toml++'s 0.69999999999999996), a
    // ".0" kept on a whole number so that it still reads as a float.
    if (const auto* f = n.as_floating_point()) {
        char buf[40];
        const auto r = std::to_chars(buf, buf + sizeof buf, f->get());
        std::string out(buf, r.ptr);
        if (out.find_first_of(".eEn") == std::string::npos) out += ".0";  // not 1e+300, nan, inf
        return out;
    }
    std::ostringstream os;
    n.visit([&](const auto& v) { os << v; });
    return os.str();
}

toml::table parse_file(const std::string& path, const std::string& what) {
    try {
        return toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << "cannot parse " << what << " '" << path << "' at line " << e.source().begin.line << ", column "
           << e.source().begin.column << ": " << e.description();
        throw ConfigError(os.str());
    }
}

toml::table load(const std::string& path, const std::vector<std::string>& overrides) {
    toml::table root;
    if (!path.empty()) root = parse_file(path, "config");
    for (const auto& o : overrides) apply_override(root, o);
    return root;
}

void apply_override(toml::table& root, const std::string& assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        throw ConfigError("--set '" + assignment + "': expected key=value, e.g. simulation.dt=1e-6");
    const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
    toml::table parsed;
    try {
        parsed = toml::parse("v = " + text);
    } catch (const toml::parse_error&) {
        parsed = toml::table{};
        parsed.insert("v", text);  // a bare word: take it as a string
    }
    std::vector<std::string> parts;
    std::stringstream ss(key);
    for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
    toml::node* cur = &root;
    for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
        const std::string& p = parts[k];
        if (auto* t = cur->as_table()) {
            if (!t->contains(p)) t->insert(p, toml::table{});
            cur = t->get(p);
        } else if (auto* a = cur->as_array()) {
            std::size_t idx = 0;
            try {
                idx = std::stoul(p);
            } catch (...) {
                throw ConfigError("--set '" + assignment + "': '" + p + "' must be an index into the array");
            }
            if (idx >= a->size())
                throw ConfigError("--set '" + assignment + "': index " + p + " out of range (size " +
                                  std::to_string(a->size()) + ")");
            cur = a->get(idx);
        } else {
            throw ConfigError("--set '" + assignment + "': '" + p + "' is not a table");
        }
    }
    auto* t = cur->as_table();
    if (!t) throw ConfigError("--set '" + assignment + "': parent of the last key is not a table");
    t->insert_or_assign(parts.back(), *parsed.get("v"));
}

const toml::node* Section::get(const std::string& key) {
    used_.insert(key);
    return t_ ? t_->get(key) : nullptr;
}

bool Section::has(const std::string& key) const { return t_ && t_->contains(key); }

void Section::fail(const std::string& key, const std::string& what) const {
    std::string msg = "config key '" + name(key) + "'";
    if (t_ && t_->get(key)) msg += " = " + describe(*t_->get(key));
    throw ConfigError(msg + ": " + what);
}

double Section::number(const std::string& key, double def) {
    const toml::node* n = get(key);
    if (!n) return def;
    if (auto v = n->value<double>()) {  // integers convert too
        // TOML allows nan and inf; no key takes them (a NaN runs to the end with NaN forces).
        if (!std::isfinite(*v)) fail(key, "must be a finite number");
        return *v;
    }
    fail(key, "must be a number");
}

double Section::number(const std::string& key) {
    if (!has(key)) fail(key, "is required (a number)");
    return number(key, 0.0);
}

int64_t Section::integer(const std::string& key, int64_t def) {
    const toml::node* n = get(key);
    if (!n) return def;
    if (auto v = n->as_integer()) return v->get();
    fail(key, "must be an integer");
}

bool Section::boolean(const std::string& key, bool def) {
    const toml::node* n = get(key);
    if (!n) return def;
    if (auto v = n->as_boolean()) return v->get();
    fail(key, "must be true or false");
}

std::string Section::string(const std::string& key, const std::string& def) {
    const toml::node* n = get(key);
    if (!n) return def;
    if (auto v = n->as_string()) return v->get();
    fail(key, "must be a string");
}

std::string Section::string(const std::string& key) {
    if (!has(key)) fail(key, "is required (a string)");
    return string(key, "");
}

dem::Vec3 Section::vec3(const std::string& key, const dem::Vec3& def) {
    const toml::node* n = get(key);
    if (!n) return def;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) fail(key, "must be an array of 3 numbers");
    dem::Vec3 v;
    for (int k = 0; k < 3; ++k) {
        auto x = a->get(k)->value<double>();
        if (!x) fail(key, "must be an array of 3 numbers");
        if (!std::isfinite(*x)) fail(key, "must be an array of 3 finite numbers");
        v[k] = *x;
    }
    return v;
}

dem::Vec3 Section::vec3(const std::string& key) {
    if (!has(key)) fail(key, "is required (an array of 3 numbers)");
    return vec3(key, {});
}

const toml::node* Section::node(const std::string& key) { return get(key); }

Section Section::table(const std::string& key) {
    const toml::node* n = get(key);
    if (!n) return Section(nullptr, name(key));
    if (!n->as_table()) fail(key, "must be a table [" + name(key) + "]");
    return Section(n->as_table(), name(key));
}

std::vector<Section> Section::array_of_tables(const std::string& key) {
    std::vector<Section> out;
    const toml::node* n = get(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "must be an array of tables [[" + name(key) + "]]");
    for (std::size_t k = 0; k < a->size(); ++k) {
        const toml::table* t = a->get(k)->as_table();
        if (!t) fail(key, "must be an array of tables [[" + name(key) + "]]");
        out.emplace_back(t, name(key) + "[" + std::to_string(k) + "]");
    }
    return out;
}

double Section::positive(const std::string& key, double v) const {
    if (!(v > 0.0) || !std::isfinite(v)) fail(key, "must be > 0 and finite");
    return v;
}

double Section::non_negative(const std::string& key, double v) const {
    if (!(v >= 0.0) || !std::isfinite(v)) fail(key, "must be >= 0 and finite");
    return v;
}

void Section::finish() const {
    if (!t_) return;
    for (const auto& [k, v] : *t_) {
        const std::string key(k.str());
        if (!used_.count(key)) {
            std::string allowed;
            for (const auto& u : used_) allowed += (allowed.empty() ? "" : ", ") + u;
            throw ConfigError("unknown config key '" + name(key) + "' (allowed here: " + allowed + ")");
        }
    }
}

}  // namespace cfg

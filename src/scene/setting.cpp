#include "scene/setting.h"

#include <charconv>
#include <stdexcept>

namespace cfg {

double check_real(const Section& s, const std::string& key, double v, const Limits& l) {
    switch (l.check) {
    case Check::None: return v;
    case Check::Positive: return s.positive(key, v);
    case Check::NonNegative: return s.non_negative(key, v);
    case Check::Range: {
        const bool above = l.lo_open ? v > l.lo : v >= l.lo;
        const bool below = l.hi_open ? v < l.hi : v <= l.hi;
        if (!(above && below)) s.fail(key, l.allowed);
        return v;
    }
    case Check::AtLeast:
        if (!(v >= l.lo)) s.fail(key, l.allowed);
        return v;
    case Check::Custom: break;
    }
    throw std::logic_error("settings: '" + s.name(key) + "' has a check of its own and needs its own reader");
}

int64_t check_integer(const Section& s, const std::string& key, int64_t v, const Limits& l) {
    switch (l.check) {
    case Check::None: return v;
    case Check::AtLeast:
        if (v < int64_t(l.lo)) s.fail(key, l.allowed);
        return v;
    case Check::Range:
        // Integer ranges are closed at both ends.
        if (v < int64_t(l.lo) || v > int64_t(l.hi)) s.fail(key, l.allowed);
        return v;
    default: break;
    }
    throw std::logic_error("settings: '" + s.name(key) + "' is an integer with a check integers do not have");
}

const char* type_name(SettingType t) {
    switch (t) {
    case SettingType::Real: return "number";
    case SettingType::Integer: return "integer";
    case SettingType::Boolean: return "true/false";
    case SettingType::Choice: return "string";
    case SettingType::RealOrAuto: return "number or \"auto\"";
    case SettingType::String: return "string";
    case SettingType::Vec3: return "3 numbers";
    case SettingType::Rows: return "array of rows";
    }
    return "?";
}

std::string allowed_text(SettingType t, const Limits& l) {
    auto strip = [](std::string a) { return a.starts_with("must be ") ? a.substr(8) : a; };
    switch (l.check) {
    case Check::None:
        if (*l.allowed) return strip(l.allowed);
        if (t == SettingType::Boolean) return "true or false";
        if (t == SettingType::Vec3) return "3 finite numbers";
        return "any";
    case Check::Positive: return *l.allowed ? "> 0; " + strip(l.allowed) : "> 0";
    case Check::NonNegative: return *l.allowed ? ">= 0; " + strip(l.allowed) : ">= 0";
    default: return strip(l.allowed);
    }
}

std::string number_text(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string markdown_cell(const std::string& s) {
    std::string out;
    for (char ch : s) {
        if (ch == '|') out += '\\';
        out += ch;
    }
    return out;
}

}  // namespace cfg

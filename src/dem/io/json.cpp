#include "dem/io/json.h"

#include <cmath>
#include <cstdint>

#include <nlohmann/json.hpp>

namespace dem {

std::string json_string(const std::string& s) {
    // Invalid UTF-8 (a byte of a path in another encoding) is replaced, not thrown on: a record
    // must be written whatever a message holds.
    return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string json_double(double v) {
    if (!std::isfinite(v)) return "null";
    // Whole numbers (counts, a step) as integers, as the records always held them; 2^53 [-]
    // bounds the integers a double holds exactly. -0 stays a double ("-0.0").
    constexpr double kExact = 9007199254740992.0;
    if (v == std::trunc(v) && std::fabs(v) < kExact && !(v == 0 && std::signbit(v)))
        return nlohmann::json(static_cast<std::int64_t>(v)).dump();
    return nlohmann::json(v).dump();
}

std::string json_string_array(const std::vector<std::string>& v) {
    std::string out = "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + json_string(v[k]);
    return out + "]";
}

}  // namespace dem

// Test helper shared by the settings tests: a double as a TOML literal that reads back as the same
// float (a whole number keeps a ".0", so TOML does not take it for an integer).
#pragma once

#include <cstdio>
#include <string>

inline std::string toml_float_literal(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    std::string s = buf;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // stays a float
    return s;
}

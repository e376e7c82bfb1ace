// The one JSON writer of vppdem's records (summary.json, calibration.json, tension.json, ...):
// an object with keys in the order written, flat values or nested raw JSON. Strings and numbers
// are serialised by nlohmann-json (dem/io/json.cpp), the library that reads the records back
// (vpp/study/records.cpp, `vppdem analyze`, the tests), so every written double reads back bitwise: the
// shortest text that round-trips, integers (|v| < 2^53) without a decimal point.
#pragma once

#include <string>
#include <vector>

namespace dem {

// A JSON string literal: quoted, with '"', '\\' and every control character escaped.
std::string json_string(const std::string& s);
// A JSON number (the shortest round-trip form); null when v is not finite (JSON has no NaN).
std::string json_double(double v);
// A JSON array of strings on one line: ["a", "b"].
std::string json_string_array(const std::vector<std::string>& v);

class JsonObject {
public:
    JsonObject& num(const std::string& key, double v) { return raw(key, json_double(v)); }
    JsonObject& str(const std::string& key, const std::string& v) { return raw(key, json_string(v)); }
    JsonObject& boolean(const std::string& key, bool v) { return raw(key, v ? "true" : "false"); }
    // `json`: a value already in JSON (a nested object's value(), an array).
    JsonObject& raw(const std::string& key, const std::string& json) {
        body_ += body_.empty() ? "\n  " : ",\n  ";
        body_ += json_string(key) + ": " + json;
        return *this;
    }
    // The object as a value to nest in another one (no trailing newline).
    std::string value() const { return "{" + body_ + "\n}"; }
    // The object as a file's contents.
    std::string text() const { return value() + "\n"; }


private:
    std::string body_;
};

}  // namespace dem

// Minimal JSON object writer for summaries (flat keys, numbers, strings, nested raw JSON).
#pragma once

#include <cmath>
#include <string>

#include "dem/io/csv.h"

namespace dem {

class JsonObject {
public:
    JsonObject& num(const std::string& key, double v) {
        std::string s;
        if (std::isfinite(v)) append_number(s, v);
        else s = "null";
        return raw(key, s);
    }
    JsonObject& str(const std::string& key, const std::string& v) { return raw(key, quote(v)); }
    JsonObject& boolean(const std::string& key, bool v) { return raw(key, v ? "true" : "false"); }
    JsonObject& raw(const std::string& key, const std::string& json) {
        body_ += body_.empty() ? "\n  " : ",\n  ";
        body_ += quote(key) + ": " + json;
        return *this;
    }
    // The object as a value to nest in another one (no trailing newline).
    std::string value() const { return "{" + body_ + "\n}"; }
    // The object as a file's contents.
    std::string text() const { return value() + "\n"; }

    static std::string quote(const std::string& s) {
        std::string out = "\"";
        for (char c : s) {
            if (c == '"' || c == '\\') out += '\\';
            if (c == '\n') { out += "\\n"; continue; }
            // Other control characters (a tab in a message) must be escaped too, or a JSON
            // reader refuses the file.
            if (static_cast<unsigned char>(c) < 0x20) {
                static const char hex[] = "0123456789abcdef";
                out += "\\u00";
                out += hex[(c >> 4) & 0xf];
                out += hex[c & 0xf];
                continue;
            }
            out += c;
        }
        return out + "\"";
    }

private:
    std::string body_;
};

}  // namespace dem

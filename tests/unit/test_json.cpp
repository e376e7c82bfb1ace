// The JSON the runs write (dem/io/json.h) is read back by a strict JSON reader (nlohmann-json,
// as the study and the analyze command do): every string, control characters included, survives.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dem/io/json.h"

TEST(JsonObject, StringsWithControlCharactersReadBack) {
    const std::string odd = "tab\there, newline\nthere, quote \" backslash \\ bell \a end";
    dem::JsonObject j;
    j.str("warning", odd).num("x", 0.1).num("nan", std::nan("")).boolean("b", true);
    const nlohmann::json back = nlohmann::json::parse(j.text());
    EXPECT_EQ(back["warning"].get<std::string>(), odd);
    EXPECT_EQ(back["x"].get<double>(), 0.1);  // shortest round trip
    EXPECT_TRUE(back["nan"].is_null());
    EXPECT_TRUE(back["b"].get<bool>());
}

// Every double the writer prints reads back bitwise (the shortest round-trip text), whole
// numbers print without a decimal point (as the records always held counts), and awkward
// strings (quotes, backslashes, control characters, UTF-8, an empty key) survive as keys and
// values, nested objects included.
TEST(JsonObject, DoublesAndStringsRoundTripBitwise) {
    const std::vector<double> values = {0.1, 1e-300, 123456789.123456789, 1.0 / 3.0, -2.5e-7, 5e-324,
                                        1.7976931348623157e308, 56.0, -3.0, 9007199254740993.0, 1e20, -0.0, 0.0,
                                        6.02214076e23, 2.2250738585072014e-308};
    const std::vector<std::string> strings = {"", "plain", "quote \" and backslash \\", "tab\tcr\rnl\nff\fbs\b",
                                              std::string("nul\0inside", 10), "\x01\x1f\x7f", "Grad \xc2\xb0 \xe2\x82\xac",
                                              "slash / and {braces}: [1, 2]"};
    auto key = [](std::size_t k) {
        std::string s = "v";
        s += std::to_string(k);
        return s;
    };
    dem::JsonObject inner;
    for (std::size_t k = 0; k < values.size(); ++k) inner.num(key(k), values[k]);
    dem::JsonObject j;
    for (std::size_t k = 0; k < strings.size(); ++k) j.str(strings[k] + "#" + std::to_string(k), strings[k]);
    j.raw("inner", inner.value()).raw("list", dem::json_string_array(strings));
    const nlohmann::ordered_json back = nlohmann::ordered_json::parse(j.text());
    std::size_t k = 0;
    for (const auto& [key, v] : back.items()) {  // the keys in the order written
        if (k < strings.size()) {
            EXPECT_EQ(key, strings[k] + "#" + std::to_string(k));
            EXPECT_EQ(v.get<std::string>(), strings[k]);
        }
        ++k;
    }
    EXPECT_EQ(k, strings.size() + 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double got = back["inner"][key(i)].get<double>();
        EXPECT_EQ(std::memcmp(&got, &values[i], sizeof got), 0) << values[i] << " read back as " << got;
    }
    EXPECT_EQ(back["list"].get<std::vector<std::string>>(), strings);
    EXPECT_EQ(dem::json_double(56.0), "56");
    EXPECT_EQ(dem::json_double(0.1), "0.1");
    EXPECT_EQ(dem::json_double(-0.0), "-0.0");
    EXPECT_EQ(dem::json_double(std::numeric_limits<double>::infinity()), "null");
}

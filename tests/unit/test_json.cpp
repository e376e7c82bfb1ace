// The JSON the runs write (dem/io/json.h) is read back by a strict JSON reader (nlohmann-json,
// as the study and the analyze command do): every string, control characters included, survives.
#include <cmath>
#include <string>

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

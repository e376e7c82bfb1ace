// The cells of hand-built CSV tables (dem/io/csv.h), shared by summary.csv, summary_cases.csv,
// misfit.csv and misfit_runs.csv.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "dem/io/csv.h"

TEST(CsvCells, NumbersRoundTripAndMissingValuesAreEmpty) {
    EXPECT_EQ(dem::csv_number(0.1), "0.1");
    EXPECT_EQ(dem::csv_number(1275.0), "1275");
    EXPECT_EQ(dem::csv_number(std::nan("")), "");
    EXPECT_EQ(dem::csv_number(std::numeric_limits<double>::infinity()), "");
}

TEST(CsvCells, WordsAreQuotedOnlyWhenNeededAndStayOnOneLine) {
    EXPECT_EQ(dem::csv_text("grains.friction=0.3"), "grains.friction=0.3");
    EXPECT_EQ(dem::csv_text("a,b"), "\"a,b\"");
    EXPECT_EQ(dem::csv_text("say \"hi\""), "\"say \"\"hi\"\"\"");
    EXPECT_EQ(dem::csv_text("failed: line\nnext\rend"), "\"failed: line next end\"");
}

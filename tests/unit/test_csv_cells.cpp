// The cells of hand-built CSV tables (dem/io/csv.h), shared by summary.csv, summary_cases.csv,
// misfit.csv and misfit_runs.csv.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include <unistd.h>

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

// Issue 48, a full disk: CsvWriter ignored the results of fflush and fclose, so a file cut short
// was renamed into place as if complete (and a throw from the destructor aborted the process).
// The temporary file is a link to /dev/full, where every write fails with ENOSPC: close() throws
// naming the file, no file is left under the final name, and destroying the writer afterwards is
// quiet.
TEST(CsvWriterFullDisk, AWriteFailureIsAnErrorAndLeavesNoFileUnderTheFinalName) {
    namespace fs = std::filesystem;
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
    const fs::path d = fs::temp_directory_path() / ("vppdem_csv_full_" + std::to_string(::getpid()));
    fs::create_directories(d);
    const fs::path out = d / "forces.csv";
    fs::create_symlink("/dev/full", d / "forces.csv.part");
    std::string message;
    {
        dem::CsvWriter w(out.string(), "time,force");
        w.row({1.0, 2.0});
        try {
            w.close();
        } catch (const std::runtime_error& e) {
            message = e.what();
        }
    }
    EXPECT_NE(message.find("forces.csv"), std::string::npos) << message;
    EXPECT_NE(message.find("No space left"), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));
    // The atomic text writer alike: an existing file stays as it was.
    {
        std::ofstream(d / "summary.json") << "old\n";
    }
    fs::create_symlink("/dev/full", d / "summary.json.part");
    EXPECT_THROW(dem::write_text_atomic((d / "summary.json").string(), std::string(100000, 'x')), std::runtime_error);
    std::ifstream in(d / "summary.json");
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "old");
    fs::remove_all(d);
}

// The records' schema (vpp/analysis/records.h): cycles.csv written and read back from one table gives the
// same cycles bit for bit; summary.json's cycles and the CSV carry the same columns; a file
// missing a column the reader needs is refused naming it.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "vpp/analysis/records.h"

namespace fs = std::filesystem;
using namespace vpp;

namespace {

std::vector<CycleResult> sample_cycles(bool energy, bool settle) {
    std::vector<CycleResult> cs;
    for (int k = 1; k <= 3; ++k) {
        CycleResult c;
        c.cycle = k;
        c.dissipated_energy = 0.1 / k + 1e-17 * k;  // digits a short format would lose
        c.W = 1234.567890123 / k;
        c.peak_force = 812.0 + 1.0 / 3.0 * k;
        c.min_force = -3.25 * k;
        c.has_energy = energy;
        if (energy) {
            c.friction_dissipation = 0.07 / k;
            c.damping_dissipation = 0.02 / k;
            c.viscous_dissipation = 1e-5 * k;
            c.boundary_work = 0.1 / k + 0.003;
            c.energy_residual = -2.5e-9 * k;
        }
        c.has_settled = settle;
        c.settled = settle && k >= 2;
        cs.push_back(c);
    }
    return cs;
}

fs::path temp(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("vppdem_records_" + std::to_string(::getpid()) + "_" + name);
    return p;
}

std::string first_line(const fs::path& p) {
    std::ifstream f(p);
    std::string line;
    std::getline(f, line);
    return line;
}

bool same_bits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }

}  // namespace

TEST(Records, CyclesCsvReadsBackBitForBit) {
    for (const bool energy : {false, true})
        for (const bool settle : {false, true}) {
            const std::vector<CycleResult> cs = sample_cycles(energy, settle);
            const fs::path p = temp("cycles.csv");
            write_cycles_csv(p.string(), cs);
            const std::vector<CycleResult> back = read_cycles_csv(p.string());
            fs::remove(p);
            ASSERT_EQ(back.size(), cs.size());
            for (std::size_t k = 0; k < cs.size(); ++k) {
                EXPECT_EQ(back[k].has_energy, energy);
                EXPECT_EQ(back[k].has_settled, settle);
                for (const CycleColumn& col : cycle_columns()) {
                    if (!cycle_has(cs[k], col.group)) continue;
                    EXPECT_TRUE(same_bits(col.get(back[k]), col.get(cs[k]))) << col.name << " of cycle " << k + 1;
                }
            }
        }
}

TEST(Records, ColumnsOfBeforeKeepTheirPlaces) {
    const fs::path p = temp("cycles_header.csv");
    write_cycles_csv(p.string(), sample_cycles(true, true));
    EXPECT_EQ(first_line(p), "cycle,dissipated_energy,W,peak_force,min_force,friction_dissipation,damping_dissipation,"
                             "viscous_dissipation,settled,boundary_work,energy_residual");
    write_cycles_csv(p.string(), sample_cycles(false, false));  // a loop read by `vppdem analyze`
    EXPECT_EQ(first_line(p), "cycle,dissipated_energy,W,peak_force,min_force");
    fs::remove(p);
}

TEST(Records, SummaryCyclesAndTheCsvHoldTheSameColumns) {
    const std::vector<CycleResult> cs = sample_cycles(true, true);
    const nlohmann::json j = nlohmann::json::parse(cycles_json(cs));
    ASSERT_EQ(j.size(), cs.size());
    std::set<std::string> csv_names;
    for (const CycleColumn* c : cycle_columns_of(cs)) csv_names.insert(c->name);
    for (std::size_t k = 0; k < cs.size(); ++k) {
        std::set<std::string> json_names;
        for (const auto& [key, v] : j[k].items()) json_names.insert(key);
        EXPECT_EQ(json_names, csv_names) << "cycle " << k + 1;
        for (const CycleColumn* c : cycle_columns_of(cs)) {  // the columns these cycles have
            const CycleColumn& col = *c;
            if (col.flag) EXPECT_EQ(j[k][col.name].get<bool>(), col.get(cs[k]) != 0.0) << col.name;
            else EXPECT_TRUE(same_bits(j[k][col.name].get<double>(), col.get(cs[k]))) << col.name;
        }
    }
    // Without the ledger: neither has its columns.
    const nlohmann::json plain = nlohmann::json::parse(cycles_json(sample_cycles(false, true)));
    EXPECT_FALSE(plain[0].contains("friction_dissipation"));
    EXPECT_FALSE(plain[0].contains("boundary_work"));
    EXPECT_TRUE(plain[0].contains("settled"));
}

TEST(Records, AMissingColumnIsRefusedNamingIt) {
    const fs::path p = temp("cycles_bad.csv");
    {
        std::ofstream f(p);
        f << "cycle,dissipated_energy,peak_force,min_force\n1,0.1,800,-3\n";
    }
    try {
        read_cycles_csv(p.string());
        ADD_FAILURE() << "a cycles.csv without W was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no column W"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
    fs::remove(p);
}

TEST(Records, EveryColumnHasAUnitAndAMeaning) {
    std::set<std::string> names;
    for (const CycleColumn& c : cycle_columns()) {
        EXPECT_TRUE(names.insert(c.name).second) << c.name;
        EXPECT_NE(std::string(c.meaning), "") << c.name;
    }
    names.clear();
    for (const SampleColumn& c : sample_columns()) {
        EXPECT_TRUE(names.insert(c.name).second) << c.name;
        EXPECT_NE(std::string(c.meaning), "") << c.name;
    }
    EXPECT_EQ(sample_column_names(false).size(), 7u);
    EXPECT_EQ(sample_column_names(true).size(), 13u);
}

// A cycles.csv of an earlier vppdem (published study records) has the ledger's dissipations but
// not the columns added later: it still counts as having the ledger, the added ones read NaN.
TEST(Records, ACyclesCsvOfBeforeStillHasItsLedger) {
    const fs::path p = temp("cycles_before.csv");
    {
        std::ofstream f(p);
        f << "cycle,dissipated_energy,W,peak_force,min_force,friction_dissipation,damping_dissipation,"
             "viscous_dissipation,settled\n1,0.2,400,130,-20,0.1,0.07,0,1\n";
    }
    const std::vector<CycleResult> c = read_cycles_csv(p.string());
    fs::remove(p);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_TRUE(c[0].has_energy);
    EXPECT_TRUE(c[0].has_settled && c[0].settled);
    EXPECT_EQ(c[0].friction_dissipation, 0.1);
    EXPECT_TRUE(std::isnan(c[0].boundary_work));
    EXPECT_TRUE(std::isnan(c[0].energy_residual));
}

// Unit tests of the hysteresis-loop analysis (src/vpp/analysis/analysis.h): loop area and its sign against
// the closed form of an elliptic loop, W, zero-area loops, peak/min force, reading loops from CSV
// by column names (any order, missing column, automatic cycle split) and the cycles.csv header.
#include "vpp/analysis/analysis.h"
#include "vpp/analysis/records.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "dem/io/csv.h"

// The file's own names, apart from the other test files' in the unity build (CMakeLists.txt).
namespace test_analysis {

using namespace vpp;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kN = 500;  // samples per cycle

// Elliptic loop over `cycles` cycles: d = A/2 (1 - cos t), F = F0 + sign * B sin t, samples at
// t = 2 pi k / N, k = 0..N-1 of each cycle. sign = +1: the compression branch (t in (0, pi), d
// increasing) carries the larger force: dissipative, clockwise in the (d, F) plane.
LoopSeries ellipse(double A, double F0, double B, int cycles, double sign = 1.0) {
    LoopSeries s;
    for (int c = 0; c < cycles; ++c)
        for (int k = 0; k < kN; ++k) {
            const double t = 2 * kPi * k / kN;
            s.time.push_back(c + double(k) / kN);
            s.displacement.push_back(0.5 * A * (1 - std::cos(t)));
            s.force.push_back(F0 + sign * B * std::sin(t));
            s.cycle.push_back(c + 1);
        }
    return s;
}

// Triangular (sawtooth) displacement, amplitude A, starting at 0, samples k = 0..N-1 per cycle.
double triangle(double A, int k) {
    const int h = kN / 2;
    return k <= h ? A * k / h : A * (kN - k) / h;
}

// A fresh directory per test, removed at the end.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("vppdem_analysis_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    std::string operator/(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

TEST(Analysis, EllipseAreaIsDissipatedEnergy) {
    const double A = 0.010, F0 = 350.0, B = 120.0, r = 0.0255;
    const auto res = analyze_cycles(ellipse(A, F0, B, 3), r);
    ASSERT_EQ(res.size(), 3u);
    const double exact = kPi * (A / 2) * B;                                  // the ellipse
    const double polygon = 0.5 * kN * std::sin(2 * kPi / kN) * (A / 2) * B;  // its inscribed N-gon
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(res[c].cycle, c + 1);
        EXPECT_GT(res[c].dissipated_energy, 0.0);
        EXPECT_NEAR(res[c].dissipated_energy, exact, 1e-3 * exact);
        EXPECT_NEAR(res[c].dissipated_energy, polygon, 1e-12 * exact);
        EXPECT_NEAR(res[c].W, res[c].dissipated_energy / (kPi * r * r), 1e-12 * res[c].W);
        EXPECT_NEAR(res[c].peak_force, F0 + B, 1e-9);  // k = N/4: t = pi/2
        EXPECT_NEAR(res[c].min_force, F0 - B, 1e-9);   // k = 3N/4
    }
}

TEST(Analysis, ReversedLoopIsNegativeAndPapersSumHasOppositeSign) {
    const double A = 0.01, B = 50.0, r = 0.02;
    const LoopSeries s = ellipse(A, 10.0, B, 1, -1.0);  // release force above compression force
    const auto res = analyze_cycles(s, r);
    ASSERT_EQ(res.size(), 1u);
    EXPECT_LT(res[0].dissipated_energy, 0.0);
    EXPECT_NEAR(res[0].dissipated_energy, -kPi * (A / 2) * B, 1e-3 * kPi * (A / 2) * B);
    // The paper's W = 1/(2 s) sum (dz_i F_{i+1} - dz_{i+1} F_i) over the closed polygon is -W here.
    double paper = 0;
    for (int i = 0; i < kN; ++i) {
        const int j = (i + 1) % kN;
        paper += s.displacement[i] * s.force[j] - s.displacement[j] * s.force[i];
    }
    paper /= 2 * kPi * r * r;
    EXPECT_NEAR(res[0].W, -paper, 1e-9 * std::abs(paper));
}

TEST(Analysis, AreaIndependentOfStartSampleAndOffsets) {
    const double A = 0.01, B = 80.0;
    LoopSeries s = ellipse(A, 0.0, B, 1);
    const double e0 = analyze_cycles(s, 0.03)[0].dissipated_energy;
    // Rotate the samples (the cycle starts mid-loop) and shift force and displacement.
    LoopSeries t;
    for (int k = 0; k < kN; ++k) {
        const int i = (k + 137) % kN;
        t.time.push_back(k);
        t.displacement.push_back(s.displacement[i] + 0.4);
        t.force.push_back(s.force[i] - 1000.0);
        t.cycle.push_back(1);
    }
    EXPECT_NEAR(analyze_cycles(t, 0.03)[0].dissipated_energy, e0, 1e-9 * e0);
}

TEST(Analysis, ZeroAreaWhenForceIsAFunctionOfDisplacement) {
    const double A = 0.01;
    LoopSeries s = ellipse(A, 0.0, 0.0, 3);
    for (std::size_t i = 0; i < s.force.size(); ++i) {
        const double d = s.displacement[i];
        s.force[i] = 200.0 + 3e4 * d + 5e6 * d * d;  // same force on compression and release
    }
    const double scale = A * (3e4 * A + 5e6 * A * A);  // stroke x force range
    const auto res = analyze_cycles(s, 0.0255);
    ASSERT_EQ(res.size(), 3u);
    for (const auto& c : res) {
        EXPECT_LT(std::abs(c.dissipated_energy), 1e-9 * scale);
        EXPECT_NEAR(c.peak_force, 200.0 + 3e4 * A + 5e6 * A * A, 1e-9);
        EXPECT_NEAR(c.min_force, 200.0, 1e-9);
    }
}

TEST(Analysis, ShortCyclesAndUnassignedSamplesAreSkipped) {
    LoopSeries s = ellipse(0.01, 0.0, 10.0, 2);
    // Cycle 3 with two samples, and samples with cycle 0 (no cycle) in between.
    for (int k = 0; k < 2; ++k) {
        s.time.push_back(10 + k);
        s.displacement.push_back(0.001 * k);
        s.force.push_back(5.0);
        s.cycle.push_back(3);
    }
    for (int k = 0; k < 5; ++k) {
        s.time.push_back(20 + k);
        s.displacement.push_back(0.002 * k);
        s.force.push_back(1e6 * (k % 2));
        s.cycle.push_back(0);
    }
    const auto res = analyze_cycles(s, 0.02);
    ASSERT_EQ(res.size(), 2u);
    EXPECT_EQ(res[0].cycle, 1);
    EXPECT_EQ(res[1].cycle, 2);
    EXPECT_LT(res[1].peak_force, 11.0);
}

TEST(Analysis, BadInputThrows) {
    LoopSeries s = ellipse(0.01, 0.0, 10.0, 1);
    EXPECT_THROW(analyze_cycles(s, 0.0), std::invalid_argument);
    s.force.pop_back();
    EXPECT_THROW(analyze_cycles(s, 0.02), std::invalid_argument);
}

TEST(Analysis, ReadLoopCsvColumnsInAnyOrder) {
    const TempDir dir;
    const std::string path = dir / "order.csv";
    const LoopSeries s = ellipse(0.01, 300.0, 90.0, 3);
    std::string text = "# a comment line\nforce_total, extra ,cycle,time,displacement\n";
    for (std::size_t i = 0; i < s.time.size(); ++i) {
        for (double v : {s.force[i], 42.0, double(s.cycle[i]), s.time[i], s.displacement[i]}) {
            dem::append_number(text, v);
            text += ',';
        }
        text.back() = '\n';
    }
    write_file(path, text);
    const LoopSeries r = read_loop_csv(path, "time", "displacement", "force_total", "cycle");
    EXPECT_EQ(r.time, s.time);
    EXPECT_EQ(r.displacement, s.displacement);
    EXPECT_EQ(r.force, s.force);
    EXPECT_EQ(r.cycle, s.cycle);
    const auto a = analyze_cycles(r, 0.0255), b = analyze_cycles(s, 0.0255);
    ASSERT_EQ(a.size(), 3u);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c].dissipated_energy, b[c].dissipated_energy);
    // No time column: time is the sample index.
    const LoopSeries q = read_loop_csv(path, "", "displacement", "force_total", "cycle");
    ASSERT_EQ(q.time.size(), s.time.size());
    EXPECT_EQ(q.time[7], 7.0);
}

TEST(Analysis, ReadLoopCsvMissingColumnIsNamed) {
    const TempDir dir;
    const std::string path = dir / "missing.csv";
    write_file(path, "time,displacement,force_grains\n0,0,1\n1,1,2\n2,0,1\n");
    try {
        read_loop_csv(path, "time", "displacement", "force_total", "cycle");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("force_total"), std::string::npos) << msg;
        EXPECT_NE(msg.find("force_grains"), std::string::npos) << msg;  // lists available ones
        EXPECT_NE(msg.find("displacement"), std::string::npos) << msg;
    }
    // A missing cycle column is not an error: cycles are found automatically.
    EXPECT_NO_THROW(read_loop_csv(path, "time", "displacement", "force_grains", "cycle"));
    // A bad number names the line.
    write_file(path, "time,displacement,force\n0,0,1\n1,abc,2\n");
    try {
        read_loop_csv(path, "time", "displacement", "force", "");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
    }
}

TEST(Analysis, AutomaticCycleSplitEqualsExplicit) {
    // Sawtooth in mm, 3 cycles from 0 down to 10 mm and back, small noise on the displacement
    // (below half a sample step, so the minimum stays at the cycle start) and on the force.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double A = 10.0, step = A / (kN / 2);
    std::string with = "time,displacement,force,cycle\n", without = "displacement,time,force\n";
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < kN; ++k) {
            const double t = c * 60.0 + 60.0 * k / kN;
            const double d = triangle(A, k) + (k == 0 ? 0.0 : 0.2 * step * u(rng));
            const bool down = k < kN / 2;
            const double f = 100.0 * d + (down ? 150.0 : -150.0) + 5.0 * u(rng);
            std::string row;
            dem::append_number(row, t);
            row += ',';
            dem::append_number(row, d);
            row += ',';
            dem::append_number(row, f);
            with += row + ',' + std::to_string(c + 1) + '\n';
            std::string row2;
            dem::append_number(row2, d);
            row2 += ',';
            dem::append_number(row2, t);
            row2 += ',';
            dem::append_number(row2, f);
            without += row2 + '\n';
        }
    const TempDir dir;
    const std::string p1 = dir / "explicit.csv", p2 = dir / "auto.csv";
    write_file(p1, with);
    write_file(p2, without);
    const LoopSeries e = read_loop_csv(p1, "time", "displacement", "force", "cycle");
    const LoopSeries a1 = read_loop_csv(p2, "time", "displacement", "force", "");
    const LoopSeries a2 = read_loop_csv(p2, "time", "displacement", "force", "cycle");  // absent
    EXPECT_EQ(a1.cycle, e.cycle);
    EXPECT_EQ(a2.cycle, e.cycle);
    EXPECT_EQ(a1.displacement, e.displacement);
    const auto re = analyze_cycles(e, 0.0255), ra = analyze_cycles(a1, 0.0255);
    ASSERT_EQ(re.size(), 3u);
    ASSERT_EQ(ra.size(), 3u);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(ra[c].dissipated_energy, re[c].dissipated_energy);
        EXPECT_NEAR(re[c].dissipated_energy, 2 * 150.0 * A, 0.02 * 2 * 150.0 * A);  // parallelogram
    }
}

TEST(Analysis, SplitCyclesRobustToNoiseAndPartialEnds) {
    // Noisy sawtooth (3% of the stroke) that starts mid-stroke going up and ends mid-stroke:
    // the leading partial cycle and the unfinished last one get 0, the full ones 1..3.
    std::mt19937_64 rng(11);
    std::normal_distribution<double> g(0.0, 0.03);
    std::vector<double> d;
    std::vector<int> phase, kk;
    for (int c = 0; c < 5; ++c)
        for (int k = 0; k < kN; ++k) {
            if ((c == 0 && k < 100) || (c == 4 && k >= 200)) continue;
            d.push_back(triangle(1.0, k) + g(rng));
            phase.push_back(c);
            kk.push_back(k);
        }
    const std::vector<int> cyc = split_cycles(d);
    ASSERT_EQ(cyc.size(), d.size());
    int counts[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < cyc.size(); ++i) {
        ASSERT_GE(cyc[i], 0);
        ASSERT_LE(cyc[i], 3);
        ++counts[cyc[i]];
        // Away from the turning points at the bottom, the index is the true cycle.
        if (kk[i] > 50 && kk[i] < kN - 50) {
            EXPECT_EQ(cyc[i], phase[i] == 4 ? 0 : phase[i]) << i;
        }
    }
    for (int c = 1; c <= 3; ++c) EXPECT_NEAR(counts[c], kN, 50) << c;
    // A flat record has no cycles.
    EXPECT_EQ(split_cycles(std::vector<double>(10, 1.0)), std::vector<int>(10, 0));
}

TEST(Analysis, WriteCyclesCsvHeaderAndRows) {
    const TempDir dir;
    const std::string path = dir / "cycles.csv";
    std::vector<CycleResult> cs = {{1, 1.5, 734.2, 812.0, -3.25}, {2, 0.1, 49.0, 700.0, 0.0}};
    write_cycles_csv(path, cs);
    EXPECT_FALSE(std::filesystem::exists(path + ".part"));
    const std::string text = read_file(path);
    EXPECT_EQ(text.substr(0, text.find('\n')), "cycle,dissipated_energy,W,peak_force,min_force");
    EXPECT_EQ(text, "cycle,dissipated_energy,W,peak_force,min_force\n1,1.5,734.2,812,-3.25\n2,0.1,49,700,0\n");
    std::vector<std::string> header;
    const auto rows = dem::read_numeric_csv(path, 5, &header);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0][2], 734.2);
    write_cycles_csv(path, {});
    EXPECT_EQ(read_file(path), "cycle,dissipated_energy,W,peak_force,min_force\n");
}

TEST(Analysis, PartialCyclesAreFlagged) {
    // Three elliptic cycles of 500 samples, the last one cut off at a fraction f of its period.
    // Cut at 30-80% of the period: partial (the ellipse is back within 10% of its stroke, and so
    // counted complete, from about 90% of its period on).
    for (const double f : {0.3, 0.5, 0.8}) {
        LoopSeries s = ellipse(0.01, 100.0, 10.0, 3);
        const std::size_t keep = 2 * kN + std::size_t(f * kN);
        s.time.resize(keep);
        s.displacement.resize(keep);
        s.force.resize(keep);
        s.cycle.resize(keep);
        const auto r = analyze_cycles(s, 0.02);
        ASSERT_EQ(r.size(), 3u);
        EXPECT_TRUE(r[0].complete);
        EXPECT_TRUE(r[1].complete);
        EXPECT_FALSE(r[2].complete) << "cut at " << f;
        EXPECT_EQ(r[2].samples, int(f * kN));
    }
    // Whole cycles of any amplitude, and cycles with few samples (the last sample one step
    // before closing is a quarter of the stroke with 4 samples), are complete.
    LoopSeries s;
    const int n = 4;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < n; ++k) {
            const double A = 0.001 * (c + 1);
            s.time.push_back(c * n + k);
            s.displacement.push_back(k <= n / 2 ? A * k / (n / 2) : A * (n - k) / (n / 2));
            s.force.push_back(k < n / 2 ? 10.0 : -10.0);
            s.cycle.push_back(c + 1);
        }
    for (const CycleResult& c : analyze_cycles(s, 0.02)) EXPECT_TRUE(c.complete) << "cycle " << c.cycle;
    // A first cycle that starts at the far end (a record begun mid-cycle) is partial too.
    LoopSeries late = ellipse(0.01, 100.0, 10.0, 2);
    for (std::size_t i = 0; i < std::size_t(kN / 2); ++i) late.cycle[i] = 1;
    for (std::size_t i = std::size_t(kN / 2); i < late.cycle.size(); ++i) late.cycle[i] = i < std::size_t(kN) ? 2 : 3;
    const auto r = analyze_cycles(late, 0.02);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_FALSE(r[0].complete);  // the first half of a cycle
    EXPECT_FALSE(r[1].complete);  // the second half
    EXPECT_TRUE(r[2].complete);
}

TEST(Analysis, CsvWithAHeaderOnlyIsAnError) {
    const TempDir dir;
    const std::string path = dir / "empty.csv";
    write_file(path, "# no data\ntime,displacement,force_total,cycle\n\n");
    try {
        read_loop_csv(path, "time", "displacement", "force_total", "cycle");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no data rows"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

// Issue 48: a UTF-8 byte order mark before the header (a spreadsheet's export) made the first
// column "\xEF\xBB\xBFtime", and the refusal "no time column 'time'" showed no difference. It is
// skipped.
TEST(Analysis, AByteOrderMarkBeforeTheHeaderIsNoPartOfTheFirstColumn) {
    TempDir dir;
    write_file(dir / "bom.csv", "\xEF\xBB\xBFtime,displacement,force\n0,0,0\n1,1,1\n2,0,0\n");
    const LoopSeries s = read_loop_csv(dir / "bom.csv", "time", "displacement", "force", "");
    EXPECT_EQ(s.time, (std::vector<double>{0, 1, 2}));
}

// Issue 48: rows whose time runs backwards (a merged or re-sorted file) were taken in their
// order, loops and all. Refused, naming the line and both times.
TEST(Analysis, ATimeColumnRunningBackwardsIsRefused) {
    TempDir dir;
    write_file(dir / "unsorted.csv", "time,displacement,force\n0,0,0\n2,1,1\n1,0,0\n");
    try {
        read_loop_csv(dir / "unsorted.csv", "time", "displacement", "force", "");
        FAIL() << "accepted";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("line 4: column 'time' = 1 is earlier than the row before (2)"), std::string::npos) << m;
    }
}

}  // namespace test_analysis

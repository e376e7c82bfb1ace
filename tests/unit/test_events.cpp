// vpp::split_events (src/vpp/analysis/events.h): the dissipation of a cycle split into bursts of
// kinetic energy and the creep between them, on series whose split is known by construction.
#include <gtest/gtest.h>

#include <stdexcept>

#include "vpp/analysis/events.h"

namespace {

// 101 records: a kinetic energy of 1e-6 J (+-1% alternating) but for two bursts (records 20-22 at
// 1e-3 J, record 60 at 5e-4 J). Each interval dissipates by friction 1e-4 J and by damping 1e-5 J
// in the creep, 1e-2 J and 2e-3 J where a record at either end is in a burst, and 1e-7 J through the
// dashpots everywhere.
vpp::EventSeries two_bursts() {
    vpp::EventSeries s;
    double f = 0, d = 0, v = 0;
    for (int k = 0; k <= 100; ++k) {
        const bool burst = (k >= 20 && k <= 22) || k == 60;
        s.kinetic.push_back(burst ? (k == 60 ? 5e-4 : 1e-3) : 1e-6 * (k % 2 ? 1.01 : 0.99));
        if (k > 0) {
            const bool hot = s.kinetic[k] > 1e-5 || s.kinetic[k - 1] > 1e-5;
            f += hot ? 1e-2 : 1e-4;
            d += hot ? 2e-3 : 1e-5;
            v += 1e-7;
        }
        s.friction.push_back(f);
        s.damping.push_back(d);
        s.viscous.push_back(v);
    }
    return s;
}

}  // namespace

TEST(Events, TwoBurstsTakeTheirIntervalsDissipation) {
    // Burst 20-22: intervals 19-20 .. 22-23 (4); burst 60: 59-60, 60-61 (2): 6 of 100 intervals.
    const vpp::EventSplit e = vpp::split_events(two_bursts(), 3.0);
    EXPECT_EQ(e.events, 2);
    EXPECT_NEAR(e.event_fraction, 0.06, 1e-15);
    EXPECT_NEAR(e.baseline, 1e-6, 0.011e-6);  // the median of the quiet records, not the bursts
    EXPECT_NEAR(e.friction, 6 * 1e-2, 1e-12);
    EXPECT_NEAR(e.friction_total, 6 * 1e-2 + 94 * 1e-4, 1e-12);
    EXPECT_NEAR(e.damping, 6 * 2e-3, 1e-12);
    EXPECT_NEAR(e.damping_total, 6 * 2e-3 + 94 * 1e-5, 1e-12);
    EXPECT_NEAR(e.viscous, 6 * 1e-7, 1e-16);
    EXPECT_NEAR(e.viscous_total, 100 * 1e-7, 1e-16);
}

TEST(Events, TheThresholdDecidesWhatIsABurst) {
    // Above the smaller burst's 500x: only the larger counts; above both: none, nothing in events.
    const vpp::EventSplit one = vpp::split_events(two_bursts(), 600.0);
    EXPECT_EQ(one.events, 1);
    EXPECT_NEAR(one.event_fraction, 0.04, 1e-15);
    const vpp::EventSplit none = vpp::split_events(two_bursts(), 2000.0);
    EXPECT_EQ(none.events, 0);
    EXPECT_EQ(none.friction, 0.0);
    EXPECT_NEAR(none.friction_total, 6 * 1e-2 + 94 * 1e-4, 1e-12);
}

TEST(Events, BadInputIsRefused) {
    EXPECT_THROW(vpp::split_events(two_bursts(), 1.0), std::invalid_argument);
    vpp::EventSeries s = two_bursts();
    s.damping.pop_back();
    EXPECT_THROW(vpp::split_events(s, 3.0), std::invalid_argument);
    EXPECT_EQ(vpp::split_events(vpp::EventSeries{}, 3.0).events, 0);
}

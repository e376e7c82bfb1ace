// The cell grid of the broad phase (dem/detect/cell_grid.h): every particle in the cell of its
// position; a diverged step (a position that is not finite, or one thrown astronomically far) is
// a SimulationUnstable naming the particle, not an allocation failure.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "dem/detect/cell_grid.h"

using dem::CellGrid;
using dem::Vec3;

TEST(CellGrid, EveryParticleIsListedInTheCellOfItsPosition) {
    std::vector<Vec3> pos;
    for (int i = 0; i < 200; ++i) pos.push_back({0.001 * (i % 7), 0.0013 * (i % 11), 0.0007 * (i % 13)});
    CellGrid g;
    g.build(pos, 0.002, 4096);
    ASSERT_EQ(g.items.size(), pos.size());
    ASSERT_EQ(g.start.size(), std::size_t(g.ncells() + 1));
    for (int64_t c = 0; c < g.ncells(); ++c)
        for (uint32_t k = g.start[c]; k < g.start[c + 1]; ++k) EXPECT_EQ(g.index(g.coords(pos[g.items[k]])), c);
    EXPECT_GE(g.cell, 0.002);
}

TEST(CellGrid, ADivergedPositionIsAnInstabilityNamingTheParticle) {
    std::vector<Vec3> pos(50);
    for (int i = 0; i < 50; ++i) pos[i] = {0.001 * i, 0.0, 0.0};
    CellGrid g;
    pos[17].y = std::numeric_limits<double>::quiet_NaN();
    try {
        g.build(pos, 0.002, 4096);
        FAIL() << "a NaN position was accepted";
    } catch (const dem::SimulationUnstable& e) {
        EXPECT_NE(std::string(e.what()).find("particle 17"), std::string::npos) << e.what();
    }
    // Finite but thrown 1e16 m away (a damper branch without local damping, issue 47's review):
    // the cell count overflowed into "cannot create std::vector larger than max_size()".
    pos[17].y = 0.0;
    pos[33].z = 1e16;
    try {
        g.build(pos, 0.002, 4096);
        FAIL() << "a position 1e16 m away was accepted";
    } catch (const dem::SimulationUnstable& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("particle 33"), std::string::npos) << what;
        EXPECT_NE(what.find("axis z"), std::string::npos) << what;
    }
    // Far but not astronomically: a valid grid, cells coarsened to the cap.
    pos[33].z = 1e3;
    g.build(pos, 0.002, 4096);
    EXPECT_LE(g.ncells(), 4096);
    EXPECT_EQ(g.items.size(), pos.size());
}

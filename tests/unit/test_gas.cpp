// The air inside the damper, its law alone (vpp/membrane/gas.h): pump-down, leak and bleed against their
// closed forms, the regulator's set point, the operator split against the ODE's fixed point,
// the isothermal work.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "vpp/membrane/gas.h"

using vpp::advance_gas;
using vpp::PumpLine;

namespace {

constexpr double kAtm = 101325.0;  // [Pa]
constexpr double kV = 8e-5;        // [m^3] the paper's damper holds about 0.08 L of gas
constexpr double kS = 2.0 / 3600;  // [m^3/s] 2 m^3/h
constexpr double kDt = 1e-5;       // [s]

}  // namespace

// From the atmosphere, a pump alone (no set point reached) at fixed volume: p = p_atm
// exp(-S t / V). Each step is integrated exactly, so only rounding separates them (1e-12).
TEST(Gas, PumpDownFollowsTheExponentialWithTimeConstantVOverS) {
    PumpLine line{.speed = kS, .bleed = 0, .leak = 0, .p_set = 0, .p_atm = kAtm};
    double amount = kAtm * kV;
    const int n = 20000;  // 0.2 s, 1.4 time constants
    for (int k = 0; k < n; ++k) amount = advance_gas(amount, kV, kDt, line);
    const double tau = kV / kS;
    EXPECT_NEAR(amount / kV / (kAtm * std::exp(-n * kDt / tau)), 1.0, 1e-12);
}

// With a set point the pump stops there, exactly (the regulator closes), after the time the
// exponential takes to reach it, to within one step.
TEST(Gas, TheRegulatorStopsThePumpAtTheSetPoint) {
    const double p_set = kAtm - 0.06e6;
    PumpLine line{.speed = kS, .bleed = 0, .leak = 0, .p_set = p_set, .p_atm = kAtm};
    double amount = kAtm * kV;
    int steps = 0;
    while (amount != p_set * kV && steps < 1000000) {
        amount = advance_gas(amount, kV, kDt, line);
        ++steps;
    }
    const double t_expected = kV / kS * std::log(kAtm / p_set);
    EXPECT_NEAR(steps * kDt, t_expected, kDt);
    for (int k = 0; k < 100; ++k) amount = advance_gas(amount, kV, kDt, line);
    EXPECT_EQ(amount, p_set * kV);  // held, not drawn below
}

// A leak alone from a perfect vacuum: p = p_atm (1 - exp(-C t / V)).
TEST(Gas, ALeakRelaxesTowardsTheAtmosphere) {
    const double C = 1e-5;
    PumpLine line{.speed = 0, .bleed = 0, .leak = C, .p_set = 0, .p_atm = kAtm};
    double amount = 0.0;
    const int n = 5000;
    for (int k = 0; k < n; ++k) amount = advance_gas(amount, kV, kDt, line);
    EXPECT_NEAR(amount / kV / (kAtm * (1.0 - std::exp(-C * n * kDt / kV))), 1.0, 1e-10);
}

// Below the set point the bleed lets air in up to it, no further; a one-way regulator (bleed 0)
// and a sealed line (all 0) leave the gas alone.
TEST(Gas, TheBleedRaisesThePressureToTheSetPointOnly) {
    const double p_set = kAtm - 0.06e6;
    const double low = 0.8 * p_set * kV;
    PumpLine line{.speed = kS, .bleed = 1e-4, .leak = 0, .p_set = p_set, .p_atm = kAtm};
    // First step: the relaxation towards p_atm at rate B / V, closed form.
    const double eq = kAtm * kV;
    EXPECT_NEAR(advance_gas(low, kV, kDt, line), eq + (low - eq) * std::exp(-1e-4 * kDt / kV), 1e-12 * eq);
    double amount = low;
    for (int k = 0; k < 100000; ++k) amount = advance_gas(amount, kV, kDt, line);
    EXPECT_EQ(amount, p_set * kV);
    line.bleed = 0.0;
    EXPECT_EQ(advance_gas(low, kV, kDt, line), low);
    const PumpLine sealed{.speed = 0, .bleed = 0, .leak = 0, .p_set = p_set, .p_atm = kAtm};
    EXPECT_EQ(advance_gas(1.5 * p_set * kV, kV, kDt, sealed), 1.5 * p_set * kV);
    EXPECT_EQ(advance_gas(low, kV, kDt, sealed), low);
}

// A pump against a leak, set point out of reach: the ODE d(pV)/dt = -S p + C (p_atm - p) settles
// at p = C p_atm / (S + C). The split step's fixed point is off by O(dt / tau): about half of
// dt / tau = 7e-5 here, and ten times less at a ten times smaller step (first order).
TEST(Gas, PumpAgainstALeakSettlesWhereTheFlowsBalance) {
    const double C = 0.25 * kS, p_eq = C * kAtm / (kS + C);
    auto settled = [&](double dt) {
        PumpLine line{.speed = kS, .bleed = 0, .leak = C, .p_set = 0, .p_atm = kAtm};
        double amount = kAtm * kV;
        for (int k = 0; k < int(2.0 / dt); ++k) amount = advance_gas(amount, kV, dt, line);
        return std::abs(amount / kV / p_eq - 1.0);
    };
    const double e1 = settled(kDt), e2 = settled(0.1 * kDt);
    std::printf("split error at the fixed point: %.3g (dt = %g s), %.3g (dt / 10)\n", e1, kDt, e2);
    EXPECT_LT(e1, 0.6 * kDt * kS / kV);
    EXPECT_NEAR(e1 / e2, 10.0, 0.5);
}

// Isothermal work: amount ln(V1 / V0) against the trapezoid sum of p dV, p = amount / V, over
// 1e5 steps (error of order 1e-10 relative).
TEST(Gas, IsothermalWorkIsTheIntegralOfPdV) {
    const double amount = 41325.0 * kV, v0 = kV, v1 = 0.75 * kV;
    const int n = 100000;
    double w = 0.0;
    for (int k = 0; k < n; ++k) {
        const double a = v0 + (v1 - v0) * k / n, b = v0 + (v1 - v0) * (k + 1) / n;
        w += 0.5 * (amount / a + amount / b) * (b - a);
    }
    EXPECT_NEAR(vpp::isothermal_work(amount, v0, v1) / w, 1.0, 1e-9);
    EXPECT_LT(vpp::isothermal_work(amount, v0, v1), 0.0);  // compressed: work done on the gas
}

// The quasi-static mark of the damper (vpp::kQuasiStaticInertialNumber) against the inertial
// number's closed form and against the velocity-convergence runs it was calibrated on
// (docs/studies.md, "Velocity convergence: results"; docs/data/velocity_*.csv).
#include <cmath>
#include <gtest/gtest.h>

#include "vpp/settings/config.h"
#include "vpp/damper/damper.h"

namespace {

vpp::Config paper_damper(double velocity, double underpressure) {
    vpp::Config c;  // the paper's parameters are the defaults (the settings table)
    c.process.velocity = velocity;
    c.process.underpressure = underpressure;
    return c;
}

}  // namespace

TEST(QuasiStatic, InertialNumberIsItsClosedForm) {
    // I = (v / H) 2 r_k sqrt(rho_k / dp), worked by hand for the paper's grains (r_k 2.965 mm,
    // rho 2689.639 kg/m^3) at 0.05 m/s and 0.06 MPa, H = 98.8333 mm:
    // sqrt(2689.639 / 60000) = 0.2117246, 0.05 / 0.0988333 = 0.5059024, 2 r_k = 5.93e-3 m:
    // I = 0.5059024 * 5.93e-3 * 0.2117246 = 6.351741e-4.
    const double H = 0.0988333;
    const double I = vpp::inertial_number(paper_damper(0.05, 0.06e6), H);
    EXPECT_NEAR(I, 6.351741e-4, 1e-6 * 6.351741e-4);
    // Its scaling: linear in the speed, 1/sqrt in the confining pressure, 1/H in the height.
    EXPECT_NEAR(vpp::inertial_number(paper_damper(0.10, 0.06e6), H), 2.0 * I, 1e-12 * I);
    EXPECT_NEAR(vpp::inertial_number(paper_damper(0.05, 0.015e6), H), 2.0 * I, 1e-12 * I);
    EXPECT_NEAR(vpp::inertial_number(paper_damper(0.05, 0.06e6), 2.0 * H), 0.5 * I, 1e-12 * I);
}

TEST(QuasiStatic, MarkSeparatesTheMeasuredBiases) {
    // Paired runs (same prepared samples): W at a velocity against W at the slowest velocity
    // run, relative, with the inertial number of the faster run. Measured 2026-11-23
    // (scripts/velocity_convergence.sh; docs/data/velocity_quick.csv, velocity_small.csv): the
    // paper's damper (H 98.8 mm, against 0.005 m/s, 2 seeds) and the small damper (H 31.6 mm,
    // against 3.33e-4 m/s, 3 seeds), cycle 1.
    struct Case {
        double inertial_number, bias;
    };
    const Case measured[] = {
        {2.20e-4, 0.008}, {4.40e-4, 0.042}, {1.10e-3, 0.170}, {2.20e-3, 0.357},  // paper's, 0.02 MPa
        {1.27e-4, 0.020}, {2.54e-4, 0.041}, {6.35e-4, 0.166}, {1.27e-3, 0.261},  // paper's, 0.06 MPa
        {7.94e-5, -0.051}, {1.98e-4, 0.010}, {3.97e-4, 0.041}, {7.94e-4, 0.076},  // small, 0.06 MPa
        {1.98e-3, 0.137}, {3.97e-3, 0.207},
        {1.375e-4, 0.019}, {3.44e-4, 0.053}, {6.87e-4, 0.121}, {1.375e-3, 0.155},  // small, 0.02 MPa
        {3.44e-3, 0.254}, {6.87e-3, 0.472},
    };
    for (const Case& m : measured) {
        if (m.inertial_number < vpp::kQuasiStaticInertialNumber) {
            EXPECT_LE(std::abs(m.bias), 0.08) << "I = " << m.inertial_number;
        }
        if (std::abs(m.bias) > 0.10) {
            EXPECT_GE(m.inertial_number, vpp::kQuasiStaticInertialNumber) << "I = " << m.inertial_number;
        }
    }
    // The main job's velocity (scripts/main.sh, 0.02 m/s) is quasi-static by this mark; the
    // former 0.05 m/s is not.
    const double H = 0.0988333;
    EXPECT_LT(vpp::inertial_number(paper_damper(0.02, 0.06e6), H), vpp::kQuasiStaticInertialNumber);
    EXPECT_GT(vpp::inertial_number(paper_damper(0.05, 0.06e6), H), vpp::kQuasiStaticInertialNumber);
}

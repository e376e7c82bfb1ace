// Inputs and outputs of the laws written once (dem/core/hd.h), shared by the GCC-compiled
// reference (laws_reference.cpp) and the nvcc-compiled test (test_laws.cu): the same function
// bodies must give the same bits whichever compiler built them and wherever they run.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/clumps/quaternion.h"
#include "dem/core/vec3.h"

namespace cuda_test {

struct LawCase {
    // a contact (and a bond: the same numbers)
    double kn, ks, mu, cn, overlap, spin, dt, rest;
    dem::Vec3 n, vrel, fs, prev;
    // integration
    dem::Vec3 f, v, t, w;
    double inv_mass, inv_inertia, lambda;
    // pressure ring
    dem::Vec3 p1, p2, p3, p4;
    // a rigid body
    dem::Quat q;
    dem::Vec3 L, I;
};

struct LawResult {
    dem::Vec3 f_fric, fs_fric, prev_fric;
    double elastic, slip, viscous;
    dem::Vec3 f_smooth, f_bond, fs_bond;
    double bond_elastic;
    dem::Vec3 acc, ang_acc, area;
    dem::Quat q1;
    dem::Vec3 w1;
    dem::Vec3 adv_x, adv_v, adv_w;  // the batch engine's particle step
    dem::Vec3 bs_force, bs_t1, bs_t2, bs_fs, bs_prev, p_force;  // its bond step and pressure
    dem::Vec3 fp_force, fp_t1, fp_t2, fp_fs, fp_prev, sp_force;  // its particle pairs
    dem::Vec3 wp_force, wp_t2, wp_point, wp_fs, wf_force, wf_t2, wf_point, wf_fs;  // its wall pairs (plane, facet)
    double fp_energy[4], wp_energy[4], adv_energy[11];  // their energy terms (elastic, slip, release, viscous)
    // The serial parts of a step that the device runs in chunks (issue 58): a motion's
    // displacement and mean velocity (sampled, constant), a prescribed particle's placement, the
    // rebuild rules (as doubles: no padding in the comparison), the clock, the ledger's booking.
    dem::Vec3 mot_d, mot_v, mot_dc, mot_vc, place_pos, place_vel;
    double reach_pair, reach_wall, max_disp, rules, clock_time, clock_steps, bw_back, bw_fwd;
    double ledger_first[21], ledger_next[21];
};

// Built by the host compiler into a shared library of its own whose inline functions stay
// hidden (laws_reference.cpp): otherwise the linker would fold its instances of the laws and the
// test's into one copy, and the comparison could not fail.
#define VPPDEM_REF_API __attribute__((visibility("default")))
// n cases from a fixed seed (deterministic on every machine: integer arithmetic only).
VPPDEM_REF_API std::vector<LawCase> make_cases(std::size_t n);
// The laws on one case as the CPU build compiles them.
VPPDEM_REF_API LawResult reference(const LawCase& c);

}  // namespace cuda_test

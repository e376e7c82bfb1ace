// Energy ledger: every term of the energy balance, accumulated with the leapfrog integrator
// (World::params.track_energy). Formulas, sign conventions and what the residual measures:
// docs/energy.md.
//
// The ledger describes the state at the time t_n of the last compute_forces() (after
// integrate() moved the clock on to t_n + dt): stored energies are those at t_n, works and
// dissipations are summed over [t0, t_n], t0 being the first step after reset_energy().
// Every force's work over a step interval [t_n, t_n+1] is the trapezoid rule
// (F_n + F_n+1)/2 . (x_n+1 - x_n), which is what the leapfrog integrator does exactly with the
// kinetic energy K_n = 1/2 m v(t_n - dt/2) . v(t_n + dt/2); so the balance closes up to the
// contact law's own non-smoothness (onset and opening of contacts, torque arms).
#pragma once

#include <cstdint>

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem {

// The forward half of a live contact's dashpot work over [t_n, t_n + dt/2] [J]: its dashpot force
// fv on body 2 [N] against the relative velocity v2 - v1 at t_n + dt/2 [m/s], h = dt/2 [s]; zero
// for a hole or a contact without dashpot force. The ledger adds these per block of a store
// (lane_block_sum) and books minus their sum as pending viscous dissipation: World's ledger and
// the batch engine's device form the same sums.
VPPDEM_HD inline double dashpot_forward_work(bool live, const Vec3& fv, const Vec3& v1, const Vec3& v2, double h) {
    return live && !(fv == Vec3{}) ? dot(fv, v2 - v1) * h : 0.0;
}

struct EnergyLedger {
    // Work done on the particles since t0 [J].
    double boundary_work = 0;    // by moving walls and prescribed particles
    double pressure_work = 0;    // by the membrane pressure on free particles
    double gravity_work = 0;     // by gravity on free particles (= minus the change of m g z)
    double external_work = 0;    // by Particles::ext_force on free particles
    // Dissipated since t0 [J].
    double friction_slip = 0;       // Coulomb slip of the contact shear springs
    double shear_release = 0;       // shear springs still loaded when their contact opened
    double damping_dissipation = 0; // local (non-viscous) damping, forces and torques
    double viscous_dissipation = 0; // normal dashpots (restitution < 1)
    // Stored at `time` [J].
    double kinetic = 0;           // 1/2 m v- . v+ + 1/2 I w- . w+ of free particles
    double elastic_contacts = 0;  // 1/2 kn overlap^2 + |Fs|^2 / (2 ks) over touching contacts
    double elastic_bonds = 0;     // 1/2 kn (L - L0)^2 + |Fs|^2 / (2 ks) over bonds
    double stored0 = 0;           // kinetic + elastic at t0
    double time = 0;              // [s] t_n: the time these values describe
    double t0 = 0;                // [s] start of the ledger
    // Second halves (trapezoid) of the last step's forces: work over [time, time + dt], added
    // at the next step. Part of the state (a checkpoint keeps them).
    double pending_boundary = 0, pending_pressure = 0, pending_gravity = 0, pending_external = 0;
    double pending_damping = 0, pending_viscous = 0;
    uint64_t steps = 0;  // steps accounted since t0; 0: not started (the next step sets t0)

    VPPDEM_HD double friction_dissipation() const { return friction_slip + shear_release; }
    VPPDEM_HD double input_work() const { return boundary_work + pressure_work + gravity_work + external_work; }
    VPPDEM_HD double stored() const { return kinetic + elastic_contacts + elastic_bonds; }
    VPPDEM_HD double dissipation() const { return friction_dissipation() + damping_dissipation + viscous_dissipation; }
    // input - (stored - stored0) - dissipated: zero for an exact balance.
    VPPDEM_HD double residual() const { return input_work() - (stored() - stored0) - dissipation(); }
};

// Per-contact energy terms of one compute_forces(), written by the contact kernel into the
// contact's own slot and summed in contact order by integrate() (deterministic).
struct ContactEnergyStep {
    double elastic = 0;   // [J] stored after this step: 1/2 kn overlap^2 + |Fs|^2 / (2 ks)
    double slip = 0;      // [J] Coulomb slip over [t_n-1, t_n]
    double release = 0;   // [J] shear spring lost by a contact that opened this step
    double viscous = 0;   // [J] dashpot work over the first half, cn vn^2 dt / 2
    Vec3 fv;              // [N] dashpot force on body 2 (its second half is added after integration)
};

}  // namespace dem

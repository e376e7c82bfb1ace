// One step's entries into the energy ledger (docs/energy.md), written once for World
// (EnergyBook::account, World::follow_motions) and the batch engine's device, which keeps the
// ledger itself between its layouts: the terms' indices, the boundaries' work, and the booking
// of a step's sums (back halves and the contacts' terms on [t_n - dt, t_n], forward halves
// pending until the next step). The caller forms the sums in its fixed order; these add them.
#pragma once

#include "dem/core/energy.h"
#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem::ledger {

// The particles' terms, each summed over the back and the forward half step, then the kinetic
// energy: kParticleSums per block of particles (the integrator's).
enum ParticleTerm { kBoundary, kPressure, kGravity, kExternal, kDamping, kTerms };
inline constexpr int kParticleSums = 2 * kTerms + 1;  // back[kTerms], fwd[kTerms], kinetic
// The contacts' terms per block of a store (the pair kernels').
enum PairSum { kElastic, kSlip, kRelease, kViscous, kPairSums };

// A boundary's work on the particles over the step's halves [J], added to back and fwd: f is the
// force the particles exert on it [N] (a wall's reaction, or the contacts' and bonds' force on a
// prescribed particle), v_back and v_fwd its velocity over the back and the forward half [m/s],
// h = dt/2 [s].
VPPDEM_HD inline void add_boundary_work(double& back, double& fwd, const Vec3& f, const Vec3& v_back, const Vec3& v_fwd,
                                        double h) {
    back -= dot(f, v_back) * h;
    fwd -= dot(f, v_fwd) * h;
}

// Books step n (forces at t_n [s]) into L: back and fwd, the particles' and boundaries' half-step
// works [J]; cs, the contacts' sums (kPairSums) [J]; elastic_bonds, the bonds' stored energy [J];
// visc_fwd, the dashpots' pending forward halves [J]; release, the shear energy lost by opened
// contacts (and dropped by the stores) [J]; kinetic, the kinetic energy at t_n [J].
VPPDEM_HD inline void book_step(EnergyLedger& L, const double* back, const double* fwd, const double* cs,
                                double elastic_bonds, double visc_fwd, double release, double kinetic, double t_n) {
    const bool first = L.steps == 0;
    if (!first) {  // the back halves and the kernels' terms belong to [t_n - dt, t_n]
        L.boundary_work += L.pending_boundary + back[kBoundary];
        L.pressure_work += L.pending_pressure + back[kPressure];
        L.gravity_work += L.pending_gravity + back[kGravity];
        L.external_work += L.pending_external + back[kExternal];
        L.damping_dissipation += L.pending_damping + back[kDamping];
        L.viscous_dissipation += L.pending_viscous + cs[kViscous];
        L.friction_slip += cs[kSlip];
        L.shear_release += release;
    }
    L.pending_boundary = fwd[kBoundary];
    L.pending_pressure = fwd[kPressure];
    L.pending_gravity = fwd[kGravity];
    L.pending_external = fwd[kExternal];
    L.pending_damping = fwd[kDamping];
    L.pending_viscous = visc_fwd;
    L.kinetic = kinetic;
    L.elastic_contacts = cs[kElastic];
    L.elastic_bonds = elastic_bonds;
    L.time = t_n;
    if (first) {
        L.t0 = t_n;
        L.stored0 = L.stored();
    }
    ++L.steps;
}

}  // namespace dem::ledger

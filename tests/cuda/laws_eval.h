// The laws applied to one case (laws_cases.h), as one VPPDEM_HD function: the GCC reference
// and the nvcc test (host and device) compile this same body.
#pragma once

#include "dem/batch/bond_step.h"
#include "dem/batch/pair_step.h"
#include "dem/batch/particle_step.h"
#include "dem/bonds/bond_law.h"
#include "dem/clumps/rigid_rotation.h"
#include "dem/contact/linear_law.h"
#include "dem/core/hd.h"
#include "dem/core/ledger_step.h"
#include "dem/core/pressure.h"
#include "dem/detect/rebuild_rule.h"
#include "dem/integrate/step_clock.h"
#include "dem/walls/motion.h"
#include "dem/integrate/leapfrog.h"
#include "laws_cases.h"

namespace cuda_test {

VPPDEM_HD inline LawResult evaluate(const LawCase& c) {
    using dem::V3;
    LawResult r{};
    V3<double> fs = dem::lanes(c.fs), prev = dem::lanes(c.prev);
    dem::ContactEnergyLanes<double> e{};
    const V3<double> f = dem::linear_contact_force_lanes<true, double>(c.kn, c.ks, c.mu, c.cn, dem::lanes(c.n), c.overlap,
                                                                        dem::lanes(c.vrel), c.spin, c.dt, fs, prev, &e);
    r.f_fric = dem::vec3(f);
    r.fs_fric = dem::vec3(fs);
    r.prev_fric = dem::vec3(prev);
    r.elastic = e.elastic;
    r.slip = e.slip;
    r.viscous = e.viscous;
    r.f_smooth = dem::vec3(dem::normal_contact_force_lanes<false, double>(c.kn, c.cn, dem::lanes(c.n), c.overlap,
                                                                          dem::lanes(c.vrel), c.dt));
    V3<double> bfs = dem::lanes(c.fs), bprev = dem::lanes(c.prev);
    double be = 0;
    r.f_bond = dem::vec3(dem::bond_force_lanes<true, double>(c.kn, c.ks, c.rest, dem::lanes(c.n), c.rest + c.overlap,
                                                             dem::lanes(c.vrel), c.spin, c.dt, bfs, bprev, &be));
    r.fs_bond = dem::vec3(bfs);
    r.bond_elastic = be;
    r.acc = dem::damped_acceleration(c.f, c.inv_mass, c.v, c.dt, c.lambda);
    r.ang_acc = dem::damped_angular_acceleration(c.t, c.inv_inertia, c.w, c.lambda);
    r.area = dem::tributary_area(c.p1, c.p2, c.p3, c.p4);
    r.q1 = dem::rigid::drift(c.q, c.L, c.I, c.dt * 1e3);
    r.w1 = dem::rigid::angular_velocity(r.q1, c.L, c.I);
    dem::batch::ParticleState st{c.p1, c.v, c.w};
    dem::batch::advance_particle(st, c.f, c.vrel, c.t, 1.0 / c.inv_mass, c.inv_mass, c.inv_inertia, c.p2, c.dt, c.lambda);
    r.adv_x = st.x;
    r.adv_v = st.v;
    r.adv_w = st.w;
    dem::batch::ParticleState st2{c.p1, c.v, c.w};
    dem::batch::ParticleEnergy ae;
    dem::batch::advance_particle<true>(st2, c.f, c.vrel, c.t, 1.0 / c.inv_mass, c.inv_mass, c.inv_inertia, c.p2, c.dt,
                                       c.lambda, &ae, c.p3, c.rest);
    for (int k = 0; k < 5; ++k) {
        r.adv_energy[k] = ae.back[k];
        r.adv_energy[5 + k] = ae.fwd[k];
    }
    r.adv_energy[10] = ae.kinetic;
    dem::Vec3 bfs2 = c.fs, bprev2 = c.prev;
    const dem::batch::BondOut bo = dem::batch::bond_step({c.p1, c.v, c.w, c.rest}, {c.p1 + c.n * (2.0 * c.rest), c.vrel, c.t, c.rest},
                                                         c.kn, c.ks, 2.0 * c.rest, c.dt, bfs2, bprev2);
    r.bs_force = bo.force;
    r.bs_t1 = bo.torque1;
    r.bs_t2 = bo.torque2;
    r.bs_fs = bfs2;
    r.bs_prev = bprev2;
    r.p_force = dem::batch::pressure_force(c.p1, c.p2, c.p3, c.p4, c.kn);
    // The batch engine's contacts: two spheres of radius `rest` closer than touching by
    // `overlap` (apart when it is negative), a sphere against a plane and against a facet.
    const dem::ContactPhys ph{c.kn, c.ks, c.mu, c.cn};
    const double ov = c.cn == 0.0 ? -c.overlap : c.overlap;  // a third of the cases apart
    const dem::batch::PairEnd a{c.p1, c.v, c.w, c.rest};
    const dem::batch::PairEnd b{c.p1 + c.n * (2.0 * c.rest - ov), c.vrel, c.t, c.rest};
    dem::Vec3 pfs = c.fs, pprev = c.prev;
    const dem::batch::PairOut fo = dem::batch::frictional_pair(a, b, ph, c.dt, pfs, pprev);
    r.fp_force = fo.force;
    r.fp_t1 = fo.torque1;
    r.fp_t2 = fo.torque2;
    r.fp_fs = pfs;
    r.fp_prev = pprev;
    dem::Vec3 efs = c.fs, eprev = c.prev;
    dem::batch::PairEnergy pe;
    dem::batch::frictional_pair<true>(a, b, ph, c.dt, efs, eprev, &pe);
    r.fp_energy[0] = pe.elastic;
    r.fp_energy[1] = pe.slip;
    r.fp_energy[2] = pe.release;
    r.fp_energy[3] = pe.viscous;
    r.sp_force = dem::batch::smooth_pair(a, b, ph, c.dt).force;
    dem::batch::WallNow plane;
    plane.point = c.p2;
    plane.normal = c.n;
    plane.velocity = c.vrel;
    const dem::batch::PairEnd s{c.p2 + c.n * (c.rest - ov), c.v, c.w, c.rest};
    dem::Vec3 wfs = c.fs, wprev = c.prev;
    const dem::batch::PairOut po = dem::batch::wall_pair(s, plane, ph, c.dt, wfs, wprev);
    r.wp_force = po.force;
    r.wp_t2 = po.torque2;
    r.wp_point = po.point;
    r.wp_fs = wfs;
    dem::Vec3 gfs = c.fs, gprev = c.prev;
    dem::batch::PairEnergy we;
    dem::batch::wall_pair<true>(s, plane, ph, c.dt, gfs, gprev, &we);
    r.wp_energy[0] = we.elastic;
    r.wp_energy[1] = we.slip;
    r.wp_energy[2] = we.release;
    r.wp_energy[3] = we.viscous;
    dem::batch::WallNow facet;
    facet.plane = false;
    facet.v0 = c.p2;
    facet.v1 = c.p3;
    facet.v2 = c.p4;
    facet.velocity = c.vrel;
    const dem::batch::PairEnd sf{(c.p2 + c.p3 + c.p4) * (1.0 / 3.0) + c.n * (c.rest - ov), c.v, c.w, c.rest};
    dem::Vec3 ffs = c.fs, fprev = c.prev;
    const dem::batch::PairOut qo = dem::batch::wall_pair(sf, facet, ph, c.dt, ffs, fprev);
    r.wf_force = qo.force;
    r.wf_t2 = qo.torque2;
    r.wf_point = qo.point;
    r.wf_fs = ffs;
    // A motion of five samples 2 dt apart, read between them, and a constant one.
    dem::DisplacementSample h[5];
    for (int k = 0; k < 5; ++k) h[k] = {c.dt * (2.0 * k + 1.0), c.p1 * double(k) + c.fs * double(k * k)};
    const dem::MotionView m{c.v, h, 5}, mc{c.v, nullptr, 0};
    r.mot_d = dem::motion_displacement(m, c.dt * 4.3);
    r.mot_v = dem::motion_mean_velocity(m, c.dt * 2.7, c.dt * 6.9);
    r.mot_dc = dem::motion_displacement(mc, c.dt * 4.3);
    r.mot_vc = dem::motion_mean_velocity(mc, c.dt * 2.7, c.dt * 6.9);
    const dem::Placement pl = dem::placement_after_step(m, c.p2, c.dt * 3.1, c.dt);
    r.place_pos = pl.pos;
    r.place_vel = pl.vel;
    const double moved = c.overlap * 10.0, wall_move = c.rest * 0.05, skin = c.rest * 0.5;
    const dem::Reaches reach = dem::touch_reaches(moved, wall_move, skin);
    r.reach_pair = reach.pair;
    r.reach_wall = reach.wall;
    r.max_disp = dem::max_disp_after(c.overlap * c.overlap, 1e-9 * c.rest);
    r.rules = double(dem::particles_past_skin(moved, skin)) + 2.0 * double(dem::walls_past_skin(moved, wall_move, skin)) +
              4.0 * double(dem::stores_need_compaction(uint64_t(c.kn) % 4096, uint64_t(c.kn) % 10000));
    dem::StepClock clock{c.dt * 7.0, c.dt * 1.0000001, 3};
    double t = c.dt * 7.0 + 2.0 * c.dt * 1.0000001;
    uint64_t steps = 5;
    clock.advance(t, steps, c.dt);
    clock.advance(t, steps, c.dt);
    r.clock_time = t;
    r.clock_steps = double(steps);
    double back = c.overlap * c.kn, fwd = -back;
    dem::ledger::add_boundary_work(back, fwd, c.f, c.v, c.vrel, 0.5 * c.dt);
    r.bw_back = back;
    r.bw_fwd = fwd;
    const double bk[5] = {c.f.x, c.f.y, c.f.z, c.t.x, c.t.y}, fw[5] = {c.v.x, c.v.y, c.v.z, c.w.x, c.w.y};
    const double cs[4] = {c.L.x, c.L.y, c.L.z, c.kn * 1e-9};
    dem::EnergyLedger L;
    for (double* out : {r.ledger_first, r.ledger_next}) {
        dem::ledger::book_step(L, bk, fw, cs, c.mu, c.cn, c.spin, c.inv_mass * 1e-4, c.dt * 9.0);
        const double v[21] = {L.boundary_work, L.pressure_work, L.gravity_work, L.external_work, L.friction_slip,
                              L.shear_release, L.damping_dissipation, L.viscous_dissipation, L.kinetic,
                              L.elastic_contacts, L.elastic_bonds, L.stored0, L.time, L.t0, L.pending_boundary,
                              L.pending_pressure, L.pending_gravity, L.pending_external, L.pending_damping,
                              L.pending_viscous, double(L.steps)};
        for (int k = 0; k < 21; ++k) out[k] = v[k];
    }
    return r;
}

}  // namespace cuda_test

// The protocol stages of the damper run: fill, compress (the preparation), vacuum, cycle; and
// vpp::Damper, which runs them one call at a time.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

#include "dem/batch/batch_stepper.h"
#include "vpp/damper_run.h"

namespace vpp {

namespace damper_detail {

namespace {

// The grains' kinetic energy [J]: the spheres g0 .. g1, or every clump (the damper's clumps are
// its grains; their members' inverse mass is 0).
double grains_kinetic_energy(const dem::World& w, uint32_t g0, uint32_t g1) {
    double e = 0;
    if (!w.clumps().empty()) {
        for (std::size_t k = 0; k < w.clumps().size(); ++k) e += w.clump_kinetic_energy(k);
        return e;
    }
    for (uint32_t i = g0; i < g1; ++i) e += 0.5 * w.particles.mass[i] * norm2(w.particles.vel[i]);
    return e;
}

// Yade's unbalanced force: mean net force on free particles over mean contact force.
double unbalanced_force(const dem::World& w) {
    const auto& p = w.particles;
    double net = 0;
    std::size_t nfree = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.inv_mass[i] == 0.0) continue;
        const dem::Vec3 fx = p.ext_force.empty() ? dem::Vec3{} : p.ext_force[i];
        net += norm(p.force[i] + fx + w.params.gravity * p.mass[i]);
        ++nfree;
    }
    // Clumps: the net force on the body (its members' sum).
    const dem::Clumps& cl = w.clumps();
    for (std::size_t k = 0; k < cl.size(); ++k) {
        dem::Vec3 f = w.params.gravity * cl.mass[k];
        for (uint32_t e = cl.start[k]; e < cl.start[k + 1]; ++e) {
            const uint32_t i = cl.member[e];
            f += p.force[i] + (p.ext_force.empty() ? dem::Vec3{} : p.ext_force[i]);
        }
        net += norm(f);
        ++nfree;
    }
    double fc = 0;
    std::size_t nc = 0;
    w.for_each_touching([&](const dem::TouchingContact& c) {
        if (c.wall) return;
        fc += norm(c.force);
        ++nc;
    });
    if (nc == 0 || nfree == 0) return 1.0;
    return (net / double(nfree)) / (fc / double(nc));
}


}  // namespace

void DamperRun::next_stage(Stage s) {
    state_.stage = s;
    state_.stage_t0 = world_.time;
    state_.cap_d0 = world_.planes[kTopCap].motion.displacement(world_.time).z;
    checkpoint(true);
    vtk_frame(stage_name(s));
}

double DamperRun::top_ring_force_z() const {
    double f = 0;
    for (uint32_t i : top_ring_) f += world_.particles.force[i].z;
    return f;
}

void DamperRun::stage_fill() {
    const double max_time = 1.5;  // [s] of falling; a column of 20 cm settles in well under 1 s
    const double check = 2e-3;    // [s] between settling checks
    StageProgress prog("prepare: fill", uint64_t(max_time / world_.params.dt), options_);
    double next_check = next_check_after(world_.time, check);
    for (;;) {
        world_.step();
        prog.update(uint64_t((world_.time - state_.stage_t0) / world_.params.dt), world_.time);
        checkpoint(false);
        if (world_.time < next_check) continue;
        next_check = next_check_after(world_.time, check);
        const double t = world_.time - state_.stage_t0;
        const double ke = grains_kinetic_energy(world_, first_grain_, end_grain_);
        // The grains start at rest: a minimum time lets them fall first (a re-fill's grains
        // start just above the others and fall less far).
        const bool refilled = state_.report.count("prepare.refills") > 0;
        bool settled = false;
        if (t > (refilled ? 0.1 : 0.15) && ke < 1e-4 * settle_energy_scale()) {
            log("[prepare] grains settled after %.3f s (kinetic energy %.3g J)\n", t, ke);
            settled = true;
        } else if (t > max_time) {
            warn("prepare: grains not fully settled after 1.5 s of filling");
            settled = true;
        }
        if (!settled) continue;
        if (!refill()) break;
        // A re-fill starts the stage again: a checkpoint with the new grains, the settling clock.
        next_stage(Stage::Fill);
        next_check = next_check_after(world_.time, check);
    }
}

void DamperRun::stage_compress() {
    // Bring the cap just above the highest grain (nothing touches it on the way), then move it
    // down to the top ring at 0.1 m/s and let the grains rearrange; the re-filled grains stand
    // above the top ring, so the cap meets them and pushes them down to the damper height.
    const double top = highest_grain_top(), level = fill_level();
    const double z_cap0 = world_.planes[kTopCap].point.z;
    const double z_start = std::max(z_top_, top + 1e-4);
    const double speed = 0.1, hold = 0.02, window = 0.005;  // [m/s], [s], [s] (cap force averaged over the window)
    const double t0 = world_.time, t1 = t0 + (z_start - z_top_) / speed;
    dem::Motion m;
    m.history = {{t0 - 1e-12, {0, 0, z_start - z_cap0}}, {t1 + 1e-12, {0, 0, z_top_ - z_cap0}}};
    world_.planes[kTopCap].motion = m;
    world_.invalidate_candidates();
    log("[prepare] cap from %.4f m down to %.4f m (grains top %.4f m, level of the top layer %.4f m)\n", z_start,
        z_top_, top, level);
    const uint64_t n = uint64_t((t1 + hold - world_.time) / world_.params.dt) + 1;
    StageProgress prog("prepare: compress", n, options_);
    double f_max = 0, f_sum = 0;
    long f_n = 0;
    for (uint64_t s = 0; s < n; ++s) {
        world_.step();
        prog.update(s + 1, world_.time);
        const double f = world_.wall_force(kTopCap).z;  // [N] grains on the cap, pushing it up
        f_max = std::max(f_max, f);
        if (world_.time > t1 + hold - window) {
            f_sum += f;
            ++f_n;
        }
    }
    world_.clear_facets();  // the funnel goes
    const double r_in = lattice_.radius - config_.foil.particle_radius;
    const double cap_force = f_n ? f_sum / double(f_n) : 0.0;
    auto& r = state_.report;
    r["prepare.grains"] = double(grain_count_now());
    r["prepare.grain_top"] = top;
    r["prepare.fill_level"] = level;
    r["prepare.cap_travel"] = std::max(0.0, top - z_top_);
    r["prepare.cap_force"] = cap_force;
    r["prepare.cap_force_max"] = f_max;
    r["prepare.packing_fraction"] = packing_fraction(r_in, z_top_);
    r["prepare.packing_fraction_nominal"] =
        packing_fraction(config_.damper.radius, config_.damper.height);
    report_grain_sizes();
    log("[prepare] cap travel %.3g mm on the grains, cap force %.4g N at the end (%.4g N at most), packing "
        "fraction %.4f of the foil's interior\n", 1e3 * r["prepare.cap_travel"], cap_force, f_max,
        r["prepare.packing_fraction"]);
    if (!(cap_force > 0)) {
        char msg[320];
        std::snprintf(msg, sizeof msg,
                      "prepare: the cap ends above the grains (no force on it at the damper height %.4g m; their "
                      "top layer is at %.4g m): the first part of every compression meets no grains%s",
                      z_top_, level, config_.damper.refill ? "" : "; damper.refill = true fills the foil up to the cap");
        warn(msg);
    }
}

void DamperRun::stage_vacuum() {
    const double ramp = config_.process.ramp_time, min_hold = 0.02, check = 2e-3;
    set_foil_pressure();
    const double dp = config_.process.underpressure;
    const bool pump = config_.process.pressure_model != 0;
    // The pump model follows the constant model's ramp (a sample evacuated long before its
    // test) unless process.pump_down asks the pump to draw the gas down from the atmosphere:
    // time constant V / S (at 2 m^3/h on the paper's damper, 0.08 L of gas: 0.14 s), and the
    // hold may then last five of those.
    const bool pump_down = pump && config_.process.pump_down;
    double max_hold = 0.5;
    if (pump_down && config_.process.pump_speed > 0.0) max_hold += 5.0 * (foil_volume() - grain_volume()) / config_.process.pump_speed;
    StageProgress prog("vacuum", uint64_t((ramp + max_hold) / world_.params.dt), options_);
    double next_check = next_check_after(world_.time, check);
    const double ke_ref = settle_energy_scale();
    for (;;) {
        const double t = world_.time - state_.stage_t0;
        const double dp_set = dp * std::min(1.0, t / ramp);
        if (!pump) world_.pressure.dp = dp_set;
        if (air_recorded()) air_step(pump_down ? dp : dp_set);
        if (pump_down && !state_.report.count("cycle.pump_down_time") && world_.pressure.dp == dp)
            state_.report["cycle.pump_down_time"] = t;
        world_.step();
        prog.update(uint64_t(t / world_.params.dt), world_.time);
        checkpoint(false);
        if (world_.time < next_check) continue;
        next_check = next_check_after(world_.time, check);
        if (t < ramp + min_hold) continue;
        // Forces of the step just taken (computing them again would advance the shear springs).
        const double ke = grains_kinetic_energy(world_, first_grain_, end_grain_);
        const double ub = unbalanced_force(world_);
        // A pump-down also waits for the set underpressure.
        const bool drawn = !pump_down || world_.pressure.dp == dp;
        if (ke < 1e-4 * ke_ref && ub < 0.05 && drawn) {
            log("[vacuum] at rest %.3f s after the ramp: kinetic energy %.3g J, unbalanced force %.3g\n",
                t - ramp, ke, ub);
            break;
        }
        if (t > ramp + max_hold) {
            char msg[320];
            if (!drawn)
                std::snprintf(msg, sizeof msg, "vacuum: the pump has not drawn the set underpressure %.4g Pa %.2f s after "
                              "the ramp (dp = %.4g Pa; process.pump_speed %.3g m^3/s against process.leak_rate %.3g "
                              "m^3/s): cycling starts at this dp", dp, t - ramp, world_.pressure.dp, config_.process.pump_speed,
                              config_.process.leak_rate);
            else
                std::snprintf(msg, sizeof msg, "vacuum: sample not at rest %.2f s after the ramp (kinetic energy %.3g J, "
                              "unbalanced force %.3g)", t - ramp, ke, ub);
            warn(msg);
            break;
        }
    }
}

void DamperRun::set_foil_pressure() {
    // The lattice: the paper's intersection nodes off the end rows. The mesh: a fan on every
    // particle off the end rings. Either way the end rings carry no pressure: the caps close the
    // foil there (rigid walls, which the grains, not the air, load in the model).
    if (mesh_foil()) world_.pressure.fans = membrane_pressure_fans(membrane_);
    else world_.pressure.nodes = cylinder_pressure_nodes(lattice_);
}

double DamperRun::foil_volume() const {
    return mesh_foil() ? enclosed_volume(membrane_, world_.particles.pos) : enclosed_volume(lattice_, world_.particles.pos);
}

double DamperRun::grain_volume() const {
    // Summed once: the grains are fixed after the preparation, and air_step asks every step.
    if (grain_volume_ == 0.0) grain_volume_ = grains_volume_now();
    return grain_volume_;
}

double DamperRun::lid_area() const {
    // The polygon of the top ring's particle centres (shoelace, projected on the cap's plane).
    const std::vector<uint32_t>& ring = top_ring_;
    double a2 = 0.0;
    for (std::size_t k = 0; k < ring.size(); ++k) {
        const Vec3& p = world_.particles.pos[ring[k]];
        const Vec3& q = world_.particles.pos[ring[(k + 1) % ring.size()]];
        a2 += p.x * q.y - q.x * p.y;
    }
    return 0.5 * std::abs(a2);
}

void DamperRun::air_step(double dp_set) {
    const double v = foil_volume() - grain_volume();
    if (!(v > 0.0))
        throw std::runtime_error("air: the gas volume inside the foil is " + std::to_string(v) +
                                 " m^3 (the foil's enclosure minus the grains); the foil has collapsed onto them");
    const bool pump = config_.process.pressure_model != 0;
    if (pump && state_.gas_amount == 0.0) state_.gas_amount = kAtmosphericPressure * v;  // sealed at the atmosphere's
    // The gas's work over the step just taken, at the amount it held (isothermal: exact for a
    // fixed amount; the constant model's gas is at p_atm - dp).
    if (state_.gas_volume > 0.0) {
        state_.gas_work += pump ? isothermal_work(state_.gas_amount, state_.gas_volume, v)
                             : (kAtmosphericPressure - world_.pressure.dp) * (v - state_.gas_volume);
    }
    state_.gas_volume = v;
    if (!pump) return;
    const double p_set = kAtmosphericPressure - dp_set;
    if (state_.stage == Stage::Vacuum && !config_.process.pump_down) {
        // Evacuated along the constant model's ramp: the gas is held at the set point.
        state_.gas_amount = p_set * v;
    } else {
        PumpLine line;
        line.speed = config_.process.pump_speed;
        line.bleed = config_.process.bleed_rate;
        line.leak = config_.process.leak_rate;
        line.p_set = p_set;
        line.p_atm = kAtmosphericPressure;
        state_.gas_amount = advance_gas(state_.gas_amount, v, world_.params.dt, line);
    }
    // At the set point (the regulator closed there: advance_gas returns p_set v itself) dp is
    // the set dp, bit for bit: a pump that keeps up runs the constant model's steps exactly.
    world_.pressure.dp = state_.gas_amount == p_set * v ? dp_set : kAtmosphericPressure - state_.gas_amount / v;
}

AirSample DamperRun::air_sample() const {
    AirSample a;
    a.gas = state_.gas_volume;
    a.enclosed = state_.gas_volume + grain_volume();
    a.dp = world_.pressure.dp;
    a.p_inside = kAtmosphericPressure - world_.pressure.dp;
    a.lid_area = lid_area();
    a.gas_work = state_.gas_work;
    return a;
}

// The sample as cycling starts (after the vacuum and the start offset): the cap's height and
// force, the packing fraction in the foil as the vacuum has drawn it in (its mean radius over the
// free rows; the end rings stay at the build radius), and the cap's travel on the grains since it
// first met them in the preparation.
void DamperRun::record_start_of_cycling(const Sample& first) {
    double sum = 0;
    std::size_t cnt = 0;
    for (uint32_t i : free_foil_) {
        sum += std::hypot(world_.particles.pos[i].x, world_.particles.pos[i].y);
        ++cnt;
    }
    const double r_foil = cnt ? sum / double(cnt) : lattice_.radius;
    const double cap_z = world_.plane_point(kTopCap).z;
    auto& r = state_.report;
    r["cycle.foil_mean_radius"] = r_foil;
    r["cycle.cap_height"] = cap_z;
    r["cycle.cap_force"] = first.grains;
    r["cycle.packing_fraction"] = packing_fraction(r_foil - config_.foil.particle_radius, cap_z);
    if (r.count("prepare.grain_top")) r["cycle.cap_travel"] = std::max(0.0, r.at("prepare.grain_top") - cap_z);
}

void DamperRun::lay_out_cycles(dem::Motion& cap, dem::Motion& ring, double cap0, double ring0, int k0, int k1,
                               bool first_knot) const {
    const double A = config_.process.amplitude, T = cycle_period(config_.process);
    const bool sine = config_.process.waveform == 1;
    const double sign = config_.process.compression_first ? -1.0 : 1.0;  // z direction of the first leg
    // The sine as kSineKnots straight segments per cycle: within A (pi / kSineKnots)^2 / 4 =
    // 2.5e-6 A of the curve, the speed within 1.6e-6 of its own.
    constexpr int kSineKnots = 1000;
    for (int k = k0; sine && k <= k1; ++k)
        for (int j = 0; j < (k < k1 ? kSineKnots : 1); ++j) {
            if (k == k0 && j == 0 && !first_knot) continue;  // the first knot is there
            const double d = sign * A * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * j / kSineKnots));
            const double t = state_.cycle_t0 + (k + double(j) / kSineKnots) * T;
            cap.history.push_back({t, {0, 0, cap0 + d}});
            ring.history.push_back({t, {0, 0, ring0 + d}});
        }
    for (int k = k0; !sine && k <= k1; ++k) {
        if (k > k0 || first_knot) {
            cap.history.push_back({state_.cycle_t0 + k * T, {0, 0, cap0}});
            ring.history.push_back({state_.cycle_t0 + k * T, {0, 0, ring0}});
        }
        if (k < k1) {
            cap.history.push_back({state_.cycle_t0 + (k + 0.5) * T, {0, 0, cap0 + sign * A}});
            ring.history.push_back({state_.cycle_t0 + (k + 0.5) * T, {0, 0, ring0 + sign * A}});
        }
    }
}

void DamperRun::extend_cycling(int from) {
    const int ncyc = int(config_.process.cycles);
    if (ncyc <= from || (state_.samples.empty() && state_.window_n == 0 && state_.cycle_t0 == 0.0)) return;
    // The motion ends on a knot at the cycling's start position: the end of cycle K, K = from + 1
    // (stage_cycle lays out a cycle more than it runs; K = from in a checkpoint of a vppdem that
    // did not). The knots of cycles K .. ncyc follow, those a run of ncyc cycles lays out.
    dem::Motion& cap = world_.planes[kTopCap].motion;
    dem::Motion& ring = world_.motions.at(std::size_t(world_.particles.motion.at(top_ring_.front())));
    const double T = cycle_period(config_.process);
    const int K = int(std::llround((cap.history.back().time - state_.cycle_t0) / T));
    const double cap0 = cap.history.back().displacement.z, ring0 = ring.history.back().displacement.z;
    lay_out_cycles(cap, ring, cap0, ring0, K, ncyc + 1, false);
    if (K <= from)
        warn("process.cycles raised on a checkpoint of an older vppdem: its last step held the cap where a run of " +
             std::to_string(ncyc) + " cycles moves it on, so the record is a continuation, not bitwise that run's");
    // Such a checkpoint kept no window for the next cycle's first sample either (see stage_cycle).
    else if (state_.stage == Stage::Done && state_.window_n == 0 && config_.process.sample_window > world_.params.dt)
        warn("process.cycles raised: the first sample of cycle " + std::to_string(from + 1) +
             " averages a shorter window than process.sample_window");
    if (state_.stage == Stage::Done) {
        // Cycling again: the end of the run (next_stage(Done)) moved the displacements' origin to
        // where the cap stood then; the cycling's is the start position, the motion's last knot.
        state_.stage = Stage::Cycling;
        state_.cap_d0 = cap0;
    }
    log("damper: process.cycles %d -> %d: the run continues with cycles %d-%d\n", from, ncyc, from + 1, ncyc);
}

void DamperRun::stage_cycle(int upto) {
    const double A = config_.process.amplitude, T = cycle_period(config_.process);
    const double v = config_.process.frequency > 0.0 ? 2.0 * A / T : config_.process.velocity;  // the offset move's speed
    const int S = int(config_.process.samples_per_cycle), ncyc = int(config_.process.cycles);
    const double win = config_.process.sample_window;
    if (state_.samples.empty() && state_.window_n == 0 && state_.cycle_t0 == 0.0) {
        // Start of cycling: cap and top ring follow one history: an optional offset move, then
        // `cycles` triangles of the amplitude (down first for compression, up for extension).
        const double d0 = world_.planes[kTopCap].motion.displacement(world_.time).z;
        const double off = config_.process.start_offset;
        const double t_off = std::abs(off) / v;
        dem::Motion cap, ring;
        cap.history.push_back({world_.time, {0, 0, d0}});
        ring.history.push_back({world_.time, {0, 0, 0}});
        state_.cycle_t0 = world_.time + t_off;
        // One cycle more than the run cycles: the last step, which may end a fraction of a step
        // past the last cycle's end, moves as a longer run's does; so a run given more cycles
        // when it is resumed (extend_cycling) is that longer run, bit for bit. The run's records
        // end with the sample before (the extra knots move nothing it records).
        lay_out_cycles(cap, ring, d0 - off, -off, 0, ncyc + 1, t_off > 0);
        world_.planes[kTopCap].motion = cap;
        const uint32_t m = world_.add_motion(ring);
        for (uint32_t i : top_ring_) world_.set_prescribed(i, m);
        state_.cap_d0 = d0 - off;  // displacements are recorded from the cycling start position
        // Energy ledger (energy.csv); restarted at the first sample, the start of cycling.
        world_.params.track_energy = config_.output.energy;
        if (config_.output.energy) world_.reset_energy();
    } else if (!world_.params.track_energy && config_.output.energy) {
        warn("energy: resumed from a checkpoint without an energy ledger (an older vppdem's); no energy.csv");
    }
    const bool energy = world_.params.track_energy;
    const double t_end = state_.cycle_t0 + upto * T;  // the end of cycle `upto`
    const uint64_t total = uint64_t(std::ceil((t_end - world_.time) / world_.params.dt));
    StageProgress prog("cycle", total, options_);
    uint64_t done = 0;
    auto sample_time = [&](std::size_t s) { return state_.cycle_t0 + double(s) * T / S; };
    world_.profile().enable(options_.profile);
    world_.profile().reset();
    const bool air = air_recorded();
    // In a batch the World's particles are the batch's between the half steps: they are handed
    // back (sync) before anything here reads them (the air's volume, a checkpoint, a VTK frame),
    // and for good when the stage ends or throws.
    dem::batch::BatchStepper* const batch = options_.batch;
    struct LeaveBatch {
        dem::batch::BatchStepper* b;
        dem::World& w;
        ~LeaveBatch() {
            if (b) b->leave(w);
        }
    } leave_batch{batch, world_};
    while (world_.time < t_end - 0.5 * world_.params.dt) {
        if (air) {
            if (batch) batch->sync(world_);
            air_step(config_.process.underpressure);
        }
        if (batch) batch->compute_forces(world_);
        else world_.compute_forces();
        const std::size_t s = state_.samples.size();
        bool sampled = false;
        // The window of the sample that would open the cycle after the last is kept too (it lies
        // before the run's end; the sample is never taken): a run given more cycles when it is
        // resumed (extend_cycling) takes that sample as a run of that many cycles does.
        if (s <= std::size_t(ncyc) * S) {
            const double ts = sample_time(s);
            if (world_.time > ts - win - 0.5 * world_.params.dt) {
                state_.window_grains += world_.wall_force(kTopCap).z;
                state_.window_foil += top_ring_force_z();
                ++state_.window_n;
            }
            if (s < std::size_t(ncyc) * S && world_.time >= ts - 0.5 * world_.params.dt) {
                Sample smp;
                smp.time = world_.time;
                smp.displacement = state_.cap_d0 - world_.planes[kTopCap].motion.displacement(world_.time).z;
                smp.grains = state_.window_grains / double(state_.window_n);
                smp.foil = state_.window_foil / double(state_.window_n);
                state_.samples.push_back(smp);
                state_.window_grains = state_.window_foil = 0;
                state_.window_n = 0;
                sampled = true;
                // The ledger counts from the first sample: works and dissipations are 0 there.
                if (energy && s == 0) world_.reset_energy();
                if (air) {
                    if (s == 0) state_.gas_work = 0.0;
                    state_.air.push_back(air_sample());
                }
                if (s == 0) {
                    if (batch) batch->sync(world_);  // it reads the sample's geometry
                    record_start_of_cycling(smp);
                }
            }
        }
        world_.profile().lap(dem::Phase::kOutput);
        if (batch) batch->integrate(world_);
        else world_.integrate();
        // The ledger at this sample's time is complete once the step is integrated.
        if (energy && sampled) state_.energy.push_back(energy_row(world_.energy(), world_.energy().time - state_.cycle_t0));
        prog.update(++done, world_.time);
        checkpoint(false);
        if (config_.output.vtk_interval > 0 && recorder_.cycle_frame_due(world_.time)) {
            vtk_frame("cycle");
            recorder_.cycle_frame_written(world_.time, config_.output.vtk_interval);
        }
        world_.profile().lap(dem::Phase::kOutput);
    }
    if (batch) batch->leave(world_);
    if (options_.profile && done > 0) {
        const dem::PhaseProfile& pr = world_.profile();
        std::fprintf(stderr, "[cycle] time per phase over %llu steps (%d threads):\n", (unsigned long long)done, world_.params.threads);
        for (int k = 0; k < int(dem::Phase::kCount); ++k) {
            const auto ph = dem::Phase(k);
            std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step %6.1f%%\n", dem::phase_name(ph), pr.seconds(ph),
                1e6 * pr.seconds(ph) / double(done), 100.0 * pr.seconds(ph) / std::max(pr.total(), 1e-300));
        }
        std::fprintf(stderr, "  %-18s %10.3f s %9.2f us/step\n", "total", pr.total(), 1e6 * pr.total() / double(done));
    }
    world_.profile().enable(false);
}


void DamperRun::prepare() {
    if (state_.stage == Stage::Fill) {
        stage_fill();
        next_stage(Stage::Compress);
    }
    if (state_.stage == Stage::Compress) {
        stage_compress();
        next_stage(Stage::Prepared);
        save_prepared();
        apply_config_to_prepared();
    }
}

void DamperRun::vacuum() {
    prepare();
    warn_once(process_warnings_);  // after prepared.ckpt (see process_warnings_); once on a resume
    if (state_.stage == Stage::Prepared) next_stage(Stage::Vacuum);
    if (state_.stage == Stage::Vacuum) {
        stage_vacuum();
        next_stage(Stage::Cycling);
    }
}

int DamperRun::cycles_done() const {
    const int ncyc = int(config_.process.cycles);
    if (state_.stage == Stage::Done) return ncyc;
    if (state_.stage < Stage::Cycling || (state_.samples.empty() && state_.window_n == 0 && state_.cycle_t0 == 0.0)) return 0;
    // The test that ends stage_cycle(k), so a run stopped there counts k (and one stopped within
    // a cycle, in a checkpoint, the cycles before it).
    const double T = cycle_period(config_.process);
    for (int k = ncyc; k > 0; --k)
        if (!(world_.time < state_.cycle_t0 + k * T - 0.5 * world_.params.dt)) return k;
    return 0;
}

int DamperRun::cycle(int n) {
    vacuum();
    const int ncyc = int(config_.process.cycles);
    const int done = cycles_done();
    if (n == 0) return done;
    const int upto = n < 0 ? ncyc : done + n;
    if (upto > ncyc)
        throw std::runtime_error("cycle(" + std::to_string(n) + "): " + std::to_string(ncyc - done) + " of process.cycles = " +
                                 std::to_string(ncyc) + " cycle(s) remain; the cycling's motion is laid out for "
                                 "process.cycles when it starts: set process.cycles to the cycles wanted");
    if (state_.stage == Stage::Done) return done;
    stage_cycle(upto);
    if (upto == ncyc) next_stage(Stage::Done);
    return upto;
}

}  // namespace damper_detail

Damper::Damper(const Config& c, const DamperOptions& opt) : run_(std::make_unique<damper_detail::DamperRun>(c, opt)) {}
Damper::~Damper() = default;
Damper::Damper(Damper&&) noexcept = default;
Damper& Damper::operator=(Damper&&) noexcept = default;

void Damper::prepare() { run_->prepare(); }
void Damper::vacuum() { run_->vacuum(); }
int Damper::cycle(int n) { return run_->cycle(n); }
void Damper::save(const std::string& path) const { run_->save(path); }
void Damper::set_progress(std::function<void(const char*, uint64_t, uint64_t, double)> hook) {
    run_->set_progress(std::move(hook));
}
std::string Damper::stage() const { return damper_detail::stage_name(run_->state().stage); }
int Damper::cycles_done() const { return run_->cycles_done(); }
int Damper::cycles_total() const { return int(run_->config().process.cycles); }
const std::vector<DamperSample>& Damper::samples() const { return run_->state().samples; }
const std::vector<DamperAirSample>& Damper::air() const { return run_->state().air; }
ForcesTable Damper::forces() const { return run_->forces(); }
std::vector<std::vector<double>> Damper::energy() const {
    std::vector<std::vector<double>> rows;
    for (const damper_detail::EnergyRow& e : run_->state().energy)
        rows.emplace_back(e.v, e.v + damper_detail::kEnergyRowSize);
    return rows;
}
std::vector<std::string> Damper::energy_columns() { return dem::energy_column_names(); }
void Damper::write_records(const std::string& dir) const { run_->write_records(dir); }
const dem::World& Damper::world() const { return run_->world(); }
const Config& Damper::config() const { return run_->config(); }

}  // namespace vpp

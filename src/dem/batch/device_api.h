// The batch engine's device (docs/gpu.md): what the host side of the device backend
// (device_batch.cpp, GCC) and the kernels (device_kernels.inl: nvcc in device_cuda.cu, or the
// host compiler in device_emul.cpp, the "emulated device" whose memory is host memory and whose
// launches are loops) share. Plain data only: no World, no CUDA type.
//
// Memory: the particles, bonds and pressure nodes of all systems concatenated (Globals, laid
// out as BatchSystems); per system its contact stores, candidate lists, interaction lists,
// walls, rebuild positions, lifecycle and scratch (SysView, device pointers); one outbox for all
// systems (what comes back per half step, downloaded in one copy).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "dem/batch/force_probe.h"
#include "dem/batch/pair_step.h"
#include "dem/contact/linear_law.h"
#include "dem/core/energy.h"
#include "dem/core/vec3.h"
#include "dem/integrate/step_clock.h"
#include "dem/walls/motion.h"

namespace dem::batch::dev {

inline constexpr int64_t kBlock = 64;        // the ledger's block of entries (kernels::kBlock)
inline constexpr int kPairSums = 4;          // kernels::kPairSums (elastic, slip, release, viscous)
inline constexpr int kParticleSums = 11;     // kernels::kParticleSums
inline constexpr uint32_t kNone = 0xffffffffu;  // kNoSlot
inline constexpr uint32_t kSmooth = 1u << 31;    // kSmoothBit
VPPDEM_HD inline int64_t blocks(int64_t n) { return (n + kBlock - 1) / kBlock; }

// One ActiveContacts store on the device. Its size (slots in use, holes included) is the
// system's Life::size; cap is its room, which no size reaches between two layouts (a store holds
// at most one slot per candidate: see DeviceBatch::ensure_stores).
struct Store {
    uint32_t *i = nullptr, *j = nullptr, *cand = nullptr;
    ContactPhys* phys = nullptr;
    Vec3 *shear = nullptr, *prev = nullptr, *force = nullptr, *torque1 = nullptr, *torque2 = nullptr, *point = nullptr,
         *fv = nullptr;
    double* terms = nullptr;  // scratch: kPairSums per slot (the ledger)
    double* dterms = nullptr;  // scratch: per slot its dashpot's forward half (the ledger) [J]
    // Bit q of word q / 64: slot q is a hole (cand == kNone, q < size); placement finds the lowest
    // hole 64 slots at a time. Kept with cand by the kernels, made from it at each layout.
    uint64_t* hole_bits = nullptr;
    uint32_t cap = 0;
};

struct Cands {
    uint32_t *start = nullptr, *other = nullptr, *slot = nullptr;  // start: n + 1 entries
    float* gap = nullptr;
    uint32_t size = 0;
};

// A system's contact lifecycle as the device keeps it (ContactSet's counts): written by the forces
// kernel, mirrored by the host after each forces half, set by the host at each layout.
struct Life {
    uint64_t found[2] = {0, 0};      // this step's (particle, candidate) records touching without a contact: pp, pw
    uint64_t opened[3] = {0, 0, 0};  // this step's slots found apart, per store
    uint64_t holes = 0;              // ContactSet::holes (World's count, which decides its compactions)
    uint32_t size[3] = {0, 0, 0};    // slots per store, holes included (ActiveContacts::size)
    uint32_t free[3] = {0, 0, 0};    // holes per store (a placement with none appends at once)
    uint32_t overflow = 0;           // nonzero: a list or a store had no room (DeviceBatch throws)
    uint32_t pad = 0;
};

// A material's coefficients as the contact lifecycle reads them (dem::Material without its name).
struct MatCoef {
    double young = 0, ratio = 0, friction = 0;  // [Pa], [-] ks/kn, [-]
};

// What changes every step and goes up before the forces half (one copy for all systems, with
// the walls now and their next velocities).
struct StepIn {
    double dp = 0;                          // [Pa] the foil's underpressure
    float pair_reach = 0, wall_reach = 0;  // [m] World::engine_reach()
};

// What comes back per half step (device pointers into the outbox sections, this system's part).
struct Outbox {
    Life* life = nullptr;        // this system's lifecycle (mirrored by the host)
    uint64_t* max_d2 = nullptr;  // this system's largest squared move (a double's bits)
    Vec3* reactions = nullptr;   // the walls' forces, then their torques (WallState::sum_reactions)
    Vec3* presc = nullptr;       // per prescribed particle: force, pressure force
    double *sum_fric = nullptr, *sum_smooth = nullptr, *sum_walls = nullptr, *sum_bonds = nullptr,
           *sum_particles = nullptr;  // the ledger's block sums
    // The dashpots' forward halves (EnergyBook::dashpot_blocks) per block of the frictional,
    // frictionless and wall stores, at blocks(cap) apart.
    double* sum_dashpots = nullptr;
    // With a batch of kTotalsFrom systems or more, EnergyBook::account's sums of those blocks, so
    // that the blocks need not come down (null: they come down): the forces' [4 pair terms
    // (frictional, frictionless, wall blocks in order) | the bonds'], the motion's [11 particle
    // terms | the dashpots' forward halves negated]. Formed in account()'s order from +0, so the
    // host puts them where account() adds them from +0 and gets its bits.
    double* ftotals = nullptr;
    double* mtotals = nullptr;
    Vec3* pstate = nullptr;  // chunks: per prescribed particle its position and velocity after the step
};
inline constexpr int kForceTotals = kPairSums + 1;

// ---- Chunks (DeviceBatch::run): the device steps a system on by itself, up to its next event,
// running what World's serial parts of a step do (dem/detect/rebuild_rule.h, the motions, the
// clock, the ledger's booking: the same functions). The host lays the system out again when it
// stops for a rebuild or a compaction, and hands it back to its caller at its event.
enum Stop : uint32_t {
    kRunning = 0,
    kEvent = 1,       // its steps reached stop_at
    kRebuild = 2,     // the candidates must be found again (World's broad phase, on the host)
    kCompaction = 3,  // the stores' holes are to be dropped (World's layout, on the host)
};

// A wall as its motion moves it (WallState::move): planes first, then facets (the walls' order).
struct WallRef {
    uint32_t plane = 1, one_sided = 0;
    Vec3 point, normal;  // [m], [-] a plane at t = 0
    Vec3 v0, v1, v2;     // [m] a facet at t = 0
    MotionView motion;   // its samples in device memory
};
// A prescribed particle: its reference position [m] and its motion (World::prescribed_next).
struct PrescRef {
    Vec3 ref;
    MotionView motion;
};

// What World's serial parts keep between two steps (World::EngineSteps, the ledger), up with a
// chunk and down after it. In the outbox: one copy each way for all systems.
struct Chunk {
    double time = 0;       // [s] World::time
    uint64_t steps = 0;    // World::steps
    StepClock clock;       // World's clock
    uint64_t stop_at = 0;  // the system stops when its steps reach this (its caller's next event)
    double max_disp = 0, wall_move = 0, skin = 0, ref_round = 0;  // [m] BroadPhase's
    double dropped = 0;    // [J] shear energy the last layout dropped (ContactSet), booked at the next step
    EnergyLedger ledger;
    ForceProbe probe;       // the caller's window (SysView::probe_particles)
    uint32_t stop = kRunning;
    uint32_t dashpots = 0;  // a material with restitution below 1 (the ledger's dashpot halves)
};
inline constexpr int kMotionTotals = kParticleSums + 1;
inline constexpr std::size_t kTotalsFrom = 8;  // systems in the batch

struct SysView {
    int active = 0;          // 0: skipped (a member that left)
    int track = 0;           // the energy ledger
    int with_pressure = 0;
    int bond_point = 0;      // the bonds' shear springs driven at the bond point (dem::BondArm)
    int64_t base = 0, n = 0;  // particles base .. base + n of Globals
    int64_t bond0 = 0, bond1 = 0, node0 = 0, node1 = 0, presc0 = 0, presc1 = 0;
    double dt = 0, lambda = 0;
    Vec3 gravity;
    const StepIn* in = nullptr;  // dp and the reaches of this step
    const Vec3* presc_in = nullptr;  // per prescribed particle: its position and velocity at t + dt (World's motions)
    uint32_t walls_n = 0;        // walls (planes, then facets)
    Cands pp, pw;
    Store fric, smooth, walls;
    // Each particle's interaction list: ref[start[i] .. start[i] + count[i]), room for cap[i]
    // (its bonds and one entry per candidate it is in: a list never outgrows it between layouts).
    uint32_t *link_start = nullptr, *link_count = nullptr, *link_cap = nullptr, *link_ref = nullptr;
    // The lifecycle's scratch: the records found this step (2 words each, room for every candidate)
    // and the slots found apart (room for every slot of the store).
    uint32_t *found_pp = nullptr, *found_pw = nullptr;
    uint32_t* opened[3] = {nullptr, nullptr, nullptr};
    // The new contacts' coefficients: the materials, the damping ratio of each pair of them
    // (zeta[a * materials + b], from the host: see contact_phys_of), each wall's material.
    const MatCoef* mats = nullptr;
    const double* zeta = nullptr;
    uint32_t materials = 0;
    const uint32_t* wall_mat = nullptr;
    const WallNow* wall_now = nullptr;
    const Vec3* wall_vnext = nullptr;  // [m/s] each wall's velocity over the next step (the ledger)
    const FloatVec3* ref_pos = nullptr;
    double* pterms = nullptr;   // scratch: kParticleSums per particle
    double* bterms = nullptr;   // scratch: one per bond
    Outbox out;
    // Chunks (null ck: the host runs the serial parts of each step). The device writes this
    // step's reaches, walls now, their next velocities and the prescribed particles' next
    // positions where the pointers above read them (in_w, wall_now_w, wall_vnext_w, presc_in_w).
    Chunk* ck = nullptr;
    const WallRef* wall_ref = nullptr;
    const Vec3* wall_ref_disp = nullptr;  // [m] each wall's displacement at the last rebuild
    const PrescRef* presc_ref = nullptr;
    Vec3* presc_v0 = nullptr;             // scratch: each prescribed particle's velocity before the step
    const uint32_t* probe_particles = nullptr;  // the probe's particles (the system's indices)
    uint32_t probe_n = 0;
    StepIn* in_w = nullptr;
    WallNow* wall_now_w = nullptr;
    Vec3* wall_vnext_w = nullptr;
    Vec3* presc_in_w = nullptr;
};

// Whether a system's kernels skip this launch: it left the batch, its chunk stopped, or a store
// or a list had no room (the host throws).
VPPDEM_HD inline bool idle(const SysView& s) {
    return !s.active || (s.ck && s.ck->stop != kRunning) || s.out.life->overflow;
}

// The concatenated arrays of all systems (BatchSystems' layout, global indices).
struct Globals {
    Vec3 *x = nullptr, *v = nullptr, *w = nullptr, *f = nullptr, *fx = nullptr, *t = nullptr;
    double *m = nullptr, *inv_m = nullptr, *inv_i = nullptr, *r = nullptr;
    uint32_t* mat = nullptr;  // each particle's material (index into its system's SysView::mats)
    Vec3* pressure_slot = nullptr;
    int64_t *bi = nullptr, *bj = nullptr;
    double *kn = nullptr, *ks = nullptr, *rest = nullptr;
    Vec3 *bshear = nullptr, *bprev = nullptr, *bforce = nullptr, *btorque1 = nullptr, *btorque2 = nullptr;
    int64_t* node = nullptr;
    int64_t* ring = nullptr;  // 4 per node
    uint32_t* prescribed = nullptr;
};

// A device: memory and the launches over B systems (views: B SysViews in device memory).
class Device {
public:
    virtual ~Device() = default;
    virtual const char* name() const = 0;
    virtual void* alloc(std::size_t bytes) = 0;  // zeroed
    virtual void release(void* p) = 0;
    virtual void put(void* dst, const void* src, std::size_t bytes) = 0;   // host -> device
    virtual void get(void* dst, const void* src, std::size_t bytes) = 0;   // device -> host
    // Copies from the device that are waited for together (a relayout's contacts: one wait for
    // the bus rather than one per array): get_async into host memory from host_alloc (CUDA:
    // page-locked, which a copy needs to run without the host; the emulated device: plain), then
    // wait(), which returns when every copy and launch asked for so far is done.
    virtual void* host_alloc(std::size_t bytes) = 0;
    virtual void host_release(void* p) = 0;
    virtual void get_async(void* dst, const void* src, std::size_t bytes) = 0;
    virtual void wait() = 0;
    virtual void forces(const Globals& g, const SysView* views, int B) = 0;
    virtual void motion(const Globals& g, const SysView* views, int B) = 0;
    // Up to K whole steps of each system with a chunk (SysView::ck), each system stopping at its
    // own event, rebuild or compaction (Chunk::stop); no copy and no wait between the steps.
    virtual void chunk(const Globals& g, const SysView* views, int B, int K) = 0;
    // The kernels' own time since the device was made [s] (CUDA: events around each launch, read
    // at the copy that follows it; emulated: the launches' wall time): the rest of a half's time
    // is the bus, the launches' latency and the waits.
    virtual double kernel_seconds() = 0;
};

// The host compiler's device (device_emul.cpp): every build has it (the tests run it). Each
// system's block is `threads_per_block` host threads meeting at the kernels' barriers.
std::unique_ptr<Device> emulated_device(int threads_per_block = 1);
// The CUDA device (device_cuda.cu with VPPDEM_CUDA; otherwise a stub that throws, naming the
// option). cuda_built(): this vppdem was built with it. cuda_devices(): how many GPUs, 0 when
// none or when the driver answers with an error (*why, when given, says which).
std::unique_ptr<Device> cuda_device();
bool cuda_built();
int cuda_devices(const char** why = nullptr);

}  // namespace dem::batch::dev

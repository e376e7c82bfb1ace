// A rigid tool: a group of facets (a mesh), and optionally particles clamped to it, that
// translate together along z by a motion program (issue 47: press, hold, lift; displacement- or
// force-controlled, monotone or cyclic). The program is a list of segments; each belongs to one
// stage of the application's run (an integer the application numbers), so that a run's stages
// can move its tools in turn and a tool without a segment in a stage holds still.
//
// How a tool moves: through the World's own prescribed motions (dem/walls/motion.h). Each
// segment lays out the knots of a piecewise-linear displacement when it starts (move, hold,
// cycle), or the next step's knot every step (force control): the walls' and the clamped
// particles' positions and velocities, the broad phase's rebuild test and the energy ledger's
// boundary work all follow from the Motion as for any prescribed wall, and the knots are part of
// the checkpoint (the facets' and the particles' motions), so a resumed run moves as an
// uninterrupted one does. The tool itself has no mass: particles never move it, they load it.
//
// Its reaction (tool_force) is the sum of the contact forces of the particles on its facets
// (World::wall_force) plus the forces on its clamped particles from their contacts, bonds and
// pressure (what holds them in place): the force the tool must exert on its surroundings'
// opposite, as a load cell between the tool and its drive measures it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/walls/motion.h"
#include "dem/world/world.h"

namespace dem {

enum class SegmentKind : int32_t {
    Move = 0,   // displacement control: to the z displacement `to` at `speed`
    Hold = 1,   // stand still for `duration`
    Force = 2,  // force control: move at `speed` against `force` until the reaction F_z reaches it
                // (or the travel reaches `max_travel`), then stand still; monotone
    Cycle = 3,  // displacement control: `cycles` triangles of `amplitude` (signed: the first leg's
                // direction) about the start position at `speed`
    ForceHold = 4,  // force control for `duration`: a proportional servo toward the reaction `force`,
                    // v = -sign(force) speed clamp((force - F_z) / |force|, -1, 1) (keeps a load on a
                    // sample that shrinks or creeps)
};

struct ToolSegment {
    SegmentKind kind = SegmentKind::Hold;
    int32_t stage = 0;      // the application's stage this segment runs in
    double to = 0.0;        // [m] Move: z displacement from the tool's build position
    double speed = 0.0;     // [m/s] Move, Force, Cycle: > 0; ForceHold: the largest speed
    double duration = 0.0;  // [s] Hold, ForceHold
    double force = 0.0;     // [N] Force, ForceHold: target reaction F_z (> 0: the particles push the tool up, so it moves down)
    double max_travel = 0.0;  // [m] Force: the segment ends after this travel whatever the force (> 0)
    double amplitude = 0.0; // [m] Cycle
    int32_t cycles = 0;     // Cycle: >= 1
};

struct Tool {
    std::string name;
    uint32_t facet0 = 0, facet1 = 0;  // its facets: World::facets[facet0 .. facet1)
    std::vector<uint32_t> clamped;    // particles that follow it (made prescribed by clamp_to_tool)
    int32_t motion = -1;              // World::motions index of the clamped particles (-1: none)
    std::vector<ToolSegment> program; // in stage order
};

// Where a tool's program stands; part of the application's saved run state.
struct ToolState {
    int32_t segment = 0;  // the running segment (program.size(): done)
    int32_t started = 0;  // 1: the running segment has laid out its motion
    double t0 = 0.0;      // [s] the running segment's start
    double d0 = 0.0;      // [m] z displacement at its start
};

// Appends `facets` (motion, mask, material as the caller set them) to the World as the tool's.
void add_tool_facets(World& w, Tool& t, const std::vector<Facet>& facets);
// Makes `particles` follow the tool from now on (prescribed; a Motion of their own that mirrors
// the facets'). Call before the tool first moves (its displacement is 0).
void clamp_to_tool(World& w, Tool& t, const std::vector<uint32_t>& particles);

// The tool's z displacement from its build position at time `time` [m].
double tool_displacement(const World& w, const Tool& t, double time);
// The particles' force on the tool from the last compute_forces() [N]: the contact forces on its
// facets plus the forces on its clamped particles.
Vec3 tool_force(const World& w, const Tool& t);

// Before each step of stage `stage`: ends the segments that are done (a force segment reads the
// reaction of the step before), starts the next one of this stage and lays out the tool's motion
// for the coming step. Returns true when the tool has no segment of this stage left (it then
// holds where it stands). Segments of an earlier stage left unfinished are skipped.
bool drive_tool(World& w, const Tool& t, ToolState& s, int32_t stage);

// Seconds the segments of `stage` take at most (force segments: max_travel / speed), from the
// tool at displacement `d` [m]; for progress estimates.
double program_duration(const Tool& t, int32_t stage, double d);

}  // namespace dem

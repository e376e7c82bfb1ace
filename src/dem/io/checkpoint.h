// Binary checkpoints of the whole World, so a run can be stopped and resumed with results
// bitwise identical to an uninterrupted run.
//
// File layout (version 2; all integers and doubles in the host's byte order, which must be
// little-endian -- checked at compile time; the files are not meant to move between
// architectures):
//   char[8]  magic "VPPDEMCK"
//   uint32   format version
//   uint64   payload size in bytes
//   payload: sections, each  char[4] tag, uint64 length, `length` bytes
//            MATL materials, PART particles, WALL planes and facets, MOTN particle motions,
//            PRES membrane pressure, PARM parameters, CLCK time/steps/time base,
//            CONT contact lists, BOND bonds, VRLT rebuild state and flags,
//            LAST wall geometry and reactions of the last compute_forces(), ENRG energy ledger
//            (optional: only when energy is tracked), CLMP clumps (optional: only when there
//            are clumps), APPS app blob
//   uint64   FNV-1a 64 checksum of everything before it (magic to end of payload)
// Vectors are stored as uint64 count + raw elements, strings as uint64 length + bytes.
#pragma once

#include <string>

#include "dem/world/world.h"

namespace dem {

// Version 2: light candidate lists and stores of live contacts (CONT), bond history as two
// arrays (BOND), block sums of the energy terms (ENRG). Version 1 files still load: their
// contact lists are converted (a run resumed from one continues, not bitwise as before).
inline constexpr uint32_t kCheckpointVersion = 2;

// Saves the complete World state plus an application blob (opaque bytes, e.g. the damper's
// stage and config) atomically: writes PATH.part, flushes and fsyncs it, renames it to PATH.
// Throws std::runtime_error naming the path if writing fails (PATH is then left untouched).
void save_checkpoint(const std::string& path, const World& w, const std::string& app_state);

// Restores into `w` (overwritten entirely) and returns the app blob. Throws
// std::runtime_error naming the path when the file is missing, is not a vppdem checkpoint,
// has an unsupported version, or is truncated or corrupt. `w` is only modified on success.
std::string load_checkpoint(const std::string& path, World& w);

// Rewrites the header's payload size and the trailing checksum of a checkpoint's bytes so that
// they pass load_checkpoint's integrity checks (the fuzzer's mutated inputs reach the decoder
// this way; one home for the layout). Leaves a buffer shorter than header + checksum as it is.
void reseal_checkpoint_bytes(std::string& bytes);

}  // namespace dem

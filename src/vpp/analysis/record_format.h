// How a force-displacement record is laid out and which way it counts: its columns, units and
// sign convention. One description for `vppdem analyze` and for calibrate's measured loops, so
// that a rig's file is read alike by both (the same flags, the same warnings).
#pragma once

#include <string>

#include "vpp/analysis/analysis.h"

namespace vpp {

struct RecordFormat {
    std::string time_col = "time", disp_col = "displacement", force_col = "force";
    std::string cycle_col;              // cycle index column; empty or not in the file: split_cycles
    double disp_scale = 1.0;            // [m per file unit] 1e-3 for mm
    double force_scale = 1.0;           // [N per file unit] 1e3 for kN
    bool compression_negative = false;  // the file counts compression negative: flip both
};

// The record in SI units, compression positive. Cycles come from cycle_col when the file has
// it, else from the displacement after the sign flip (a cycle starts at the start position,
// which is the maximum of a compression-negative stroke). Throws as read_loop_csv does.
LoopSeries read_record(const std::string& path, const RecordFormat& f);

// Why the record's signs look the other way round, or "" when they do not. Two signs:
//  - its loops enclose a negative total area: a damper dissipates, so with displacement and
//    force both counting compression positive its loop runs the positive way round; one of the
//    two columns counts the other way (no flag mends that: both flip together);
//  - when the protocol loads in compression first, a force negative on average over the cycles
//    and largest in magnitude where negative: a compressed damper pushes back, so the whole
//    record counts compression negative (pass --compression-negative), or, with the flag
//    given, positive (drop it).
std::string orientation_doubt(const LoopSeries& s, bool compression_negative, bool compression_first);

}  // namespace vpp

// Lane arithmetic: the contact and bond laws are written once, as templates over a "lane" type
// R, and run both on plain doubles (R = double: tests, tails of loops, rare paths) and on SIMD
// vectors of doubles (R = a Highway vector, dem/kernels/kernels.cpp: the hot kernels).
//
// Why one source: the scalar and the vector path must give the same bits (results may not
// depend on the machine's vector width). Every operation used here is exactly rounded in IEEE
// 754 (+, -, *, /, sqrt, comparisons, selection), and the vector path applies the same
// operations in the same order to each lane, so both agree bit for bit. What would break it,
// and is therefore not used: fused multiply-add (the build passes -ffp-contract=off so the
// compiler cannot fuse either), reassociated sums, approximate reciprocals.
//
// The R = double functions are here; each SIMD target gets the same names for its vectors
// (dem/kernels/kernels.cpp), and both include the generic templates of dem/core/lanes-inl.h.
#pragma once

#include <cmath>

#include "dem/core/hd.h"
#include "dem/core/vec3.h"

namespace dem {

// ---- R = double
VPPDEM_HD inline double lit(double, double v) { return v; }  // a constant in every lane; first argument: type tag
VPPDEM_HD inline double neg(double a) { return -a; }
VPPDEM_HD inline double lane_sqrt(double a) { return std::sqrt(a); }
VPPDEM_HD inline double select(bool m, double a, double b) { return m ? a : b; }
VPPDEM_HD inline bool both(bool a, bool b) { return a && b; }

#include "dem/core/lanes-inl.h"  // IWYU pragma: export

VPPDEM_HD inline V3<double> lanes(const Vec3& v) { return {v.x, v.y, v.z}; }
VPPDEM_HD inline Vec3 vec3(const V3<double>& v) { return {v.x, v.y, v.z}; }

}  // namespace dem

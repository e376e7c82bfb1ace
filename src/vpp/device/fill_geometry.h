// The geometry the device's fill is placed by (device/fill_sites.h, device/pour.h): whether a
// point lies inside a closed surface, its distance to one, and the fill's jitter, drawn the same
// on every platform. Internal to vpp/device/*.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/core/vec3.h"
#include "dem/mesh/surface_mesh.h"
#include "vpp/membrane/membrane.h"

namespace vpp::device_detail {

// [m] Distance from p [m] to triangle (a, b, c) [m] (the closest point by region, Ericson's
// "Real-Time Collision Detection" 5.1.5).
double point_triangle_distance(const dem::Vec3& p, const dem::Vec3& a, const dem::Vec3& b, const dem::Vec3& c);

// Whether p [m] lies inside the closed, outward surface m: its winding number, the triangles'
// solid angles summed (van Oosterom and Strackee), is 1 inside and 0 outside; robust for any
// shape.
bool inside(const dem::SurfaceMesh& m, const dem::Vec3& p);

// Whether p [m] lies inside the membrane's closed triangulation of its particles at `pos` [m]
// (the winding number, as inside()): the surface the seal closes.
bool inside_membrane(const Membrane& m, const std::vector<dem::Vec3>& pos, const dem::Vec3& p);

// [m] The distance from p [m] to the nearest of m's triangles.
double distance_to_surface(const dem::SurfaceMesh& m, const dem::Vec3& p);

// A uniform double in [0, 1) from 53 bits of the generator state `s` (splitmix64, advanced):
// the same draw on every platform (std::uniform_real_distribution is left to the library).
double uniform(uint64_t& s);

}  // namespace vpp::device_detail

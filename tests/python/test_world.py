# vppdem.World: the generic DEM core built from Python, checked against closed forms.
import math

import numpy as np
import pytest

import vppdem


def test_free_fall_matches_the_leapfrog_closed_form():
    # A lone sphere under gravity. The leapfrog (v at half steps, starting from v(-dt/2) = 0)
    # gives z_n = z0 - g dt^2 n (n + 1) / 2 exactly: the parabola z0 - g t^2 / 2 plus the known
    # first-order offset g t dt / 2 of starting the half-step velocity at t = 0.
    w = vppdem.World()
    w.add_material("steel", density=7800.0, young=2e11)
    w.add_sphere([0.0, 0.0, 1.0], 0.01)
    w.dt = 1e-4          # [s]
    w.local_damping = 0  # free flight: no damping force
    g, n, z0 = 9.81, 2000, 1.0
    w.step(n)
    t = n * w.dt
    assert w.time == pytest.approx(t, rel=1e-12)
    z = w.positions[0, 2]
    assert z == pytest.approx(z0 - g * w.dt**2 * n * (n + 1) / 2, rel=1e-12, abs=1e-12)
    assert abs(z - (z0 - g * t**2 / 2)) <= g * t * w.dt / 2 * (1 + 1e-9)
    assert w.half_step_velocities[0, 2] == pytest.approx(-g * t, rel=1e-12)
    assert w.positions.shape == (1, 3) and w.velocities.shape == (1, 3) and w.forces.shape == (1, 3)


def test_head_on_impact_restitution():
    # Two equal spheres approach at +-v with the normal dashpot of restitution e: they leave at
    # +-e v (tests/physics/test_impacts.cpp checks the same in C++ to 1%).
    e, v, r = 0.5, 0.1, 0.005
    w = vppdem.World()
    w.gravity = [0.0, 0.0, 0.0]
    w.add_material("glass", density=2500.0, young=1e8, restitution=e, friction=0.0)
    w.add_sphere([-r * 1.01, 0, 0], r, velocity=[v, 0, 0])
    w.add_sphere([r * 1.01, 0, 0], r, velocity=[-v, 0, 0])
    w.dt = 0.02 * w.critical_dt()
    w.step(1)
    while w.contact_count() > 0 or w.half_step_velocities[0, 0] > 0:
        w.step(50)
        assert w.time < 1.0
    vout = w.half_step_velocities
    assert -vout[0, 0] / v == pytest.approx(e, rel=0.01)
    assert vout[1, 0] / v == pytest.approx(e, rel=0.01)
    # Momentum is conserved by the pair forces.
    assert vout[0, 0] + vout[1, 0] == pytest.approx(0.0, abs=1e-12)


def test_sphere_comes_to_rest_on_a_plane():
    # At rest on the floor the plane carries the sphere's weight.
    w = vppdem.World()
    w.add_material("m", density=2000.0, young=1e7, restitution=0.3)
    w.add_plane([0, 0, 0], [0, 0, 1])
    i = w.add_sphere([0, 0, 0.011], 0.01)
    w.local_damping = 0.2
    w.dt = 0.1 * w.critical_dt()
    w.step(20000)
    m = w.masses[i]
    assert w.wall_force(0)[2] == pytest.approx(-m * 9.81, rel=1e-3)
    assert 0.0099 < w.positions[i, 2] < 0.01


def test_facets_from_vertices_and_moving_walls(tmp_path):
    # A floor of two triangles, raised at constant velocity: the sphere resting on it rises.
    w = vppdem.World()
    w.add_material("m", density=2000.0, young=1e7, restitution=0.3)
    tri = np.array([[[-1, -1, 0], [1, -1, 0], [1, 1, 0]], [[-1, -1, 0], [1, 1, 0], [-1, 1, 0]]], float)
    first = w.add_facets(tri)
    assert (first, w.facet_count) == (0, 2)
    w.add_sphere([0, 0, 0.0105], 0.01)
    w.local_damping = 0.2
    w.dt = 0.1 * w.critical_dt()
    w.step(5000)
    z0 = w.positions[0, 2]
    w.set_facet_motion(0, 2, velocity=[0, 0, 0.01])
    t0 = w.time
    w.step(5000)
    assert w.positions[0, 2] - z0 == pytest.approx(0.01 * (w.time - t0), rel=0.05)
    # The same floor through an STL file.
    stl = tmp_path / "floor.stl"
    with open(stl, "w") as f:
        f.write("solid floor\n")
        for t in tri * 1000:  # in millimetres
            f.write(" facet normal 0 0 1\n  outer loop\n")
            for p in t:
                f.write(f"   vertex {p[0]} {p[1]} {p[2]}\n")
            f.write("  endloop\n endfacet\n")
        f.write("endsolid floor\n")
    w2 = vppdem.World()
    w2.add_material("m")
    assert w2.add_stl(stl, scale=1e-3) == (0, 2)


def test_bonds_hold_two_spheres_together():
    w = vppdem.World()
    w.gravity = [0, 0, 0]
    w.add_material("m", density=1000.0, young=1e6)
    a = w.add_sphere([0, 0, 0], 0.01, velocity=[-0.01, 0, 0])
    b = w.add_sphere([0.02, 0, 0], 0.01, velocity=[0.01, 0, 0])
    w.add_bond(a, b, kn=100.0, ks=50.0)
    assert w.bond_count == 1
    w.dt = 1e-4
    w.step(20000)
    d = np.linalg.norm(w.positions[1] - w.positions[0])
    # An undamped spring of kn between two masses m: the gap oscillates by at most v_rel / omega.
    m = w.masses[0]
    omega = math.sqrt(2 * 100.0 / m)
    assert abs(d - 0.02) <= 0.02 / omega * 1.01


def test_errors_are_python_exceptions():
    w = vppdem.World()
    with pytest.raises(ValueError, match="no particles"):
        w.step(1)
    with pytest.raises(ValueError, match="add_material first"):
        w.add_sphere([0, 0, 0], 0.01)
    w.add_material("m")
    with pytest.raises(ValueError, match="3 components"):
        w.add_sphere([0, 0], 0.01)
    with pytest.raises(IndexError):
        w.wall_force(3)
    with pytest.raises(RuntimeError, match="missing.stl"):
        w.add_stl("missing.stl")
    # A particle that does not exist is named, nothing written past the arrays' end.
    w.add_sphere([0, 0, 0], 0.01)
    with pytest.raises(ValueError, match="particle 1 does not exist"):
        w.set_fixed(1)
    with pytest.raises(ValueError, match="particle 1 does not exist"):
        w.set_particle_motion(1, velocity=[0, 0, 1])
    assert len(w) == 1


def test_a_new_skin_resumes_the_same_from_a_checkpoint(tmp_path):
    # The candidate lists were built for the old skin: a new one must take effect with a rebuild at
    # the next step, in the world that goes on and in one loaded from a checkpoint taken just then
    # (the loaded world knows only the new skin).
    w = _pile(1)
    w.skin = 2.5e-3  # [m] (the default: half the smallest radius, 1 mm)
    w.save(tmp_path / "s.ckpt")
    r = vppdem.World.load(tmp_path / "s.ckpt")
    w.step(3000)
    r.step(3000)
    assert np.array_equal(w.positions, r.positions)
    assert np.array_equal(w.velocities, r.velocities)


def _pile(threads):
    # 216 grains dropped into a box of planes; the same scene on any thread count.
    w = vppdem.World()
    w.threads = threads
    w.add_material("m", density=2500.0, young=1e7, friction=0.5, restitution=0.4)
    for p, n in [([0, 0, 0], [0, 0, 1]), ([-0.02, 0, 0], [1, 0, 0]), ([0.02, 0, 0], [-1, 0, 0]),
                 ([0, -0.02, 0], [0, 1, 0]), ([0, 0.02, 0], [0, -1, 0])]:
        w.add_plane(p, n)
    rng = np.random.default_rng(3)
    for k in range(216):
        i, j, l = k % 6, (k // 6) % 6, k // 36
        w.add_sphere([-0.0125 + 0.005 * i, -0.0125 + 0.005 * j, 0.003 + 0.005 * l] + rng.uniform(-2e-4, 2e-4, 3), 0.002)
    w.local_damping = 0.2
    w.dt = 0.2 * w.critical_dt()
    w.step(5000)  # 0.065 s: the lower layers have landed
    return w


def test_results_do_not_depend_on_the_thread_count():
    a, b = _pile(1), _pile(2)
    assert a.contact_count() > 50  # a state with contacts, not free flight
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.velocities, b.velocities)
    np.testing.assert_array_equal(a.forces, b.forces)


def test_clumps_fall_like_points_and_rest_with_their_weight():
    # A dimer and a template clump (three spheres) from Python: in free flight the centre follows
    # the leapfrog parabola of a point mass and a free spin keeps its energy; on the floor they
    # rest with their weight (tests/physics/test_clumps.cpp has the closed forms in C++).
    w = vppdem.World()
    w.add_material("m", density=2000.0, young=1e7, restitution=0.3)
    k, first, n = w.add_clump([0, 0, 0.05], "dimer", radius=0.005, angular_velocity=[0.0, 3.0, 10.0])
    assert (k, first, n) == (0, 0, 2)
    k2, first2, n2 = w.add_clump([0.05, 0, 0.05], [[0, 0, 0, 0.004], [0.004, 0, 0, 0.004], [0, 0.004, 0, 0.004]], radius=0.005)
    assert (k2, first2, n2) == (1, 2, 3) and w.clump_count() == 2 and len(w) == 5
    s = w.clump_state(0)
    assert s["mass"] == pytest.approx(2000.0 * 4 / 3 * math.pi * 0.005**3, rel=1e-12)
    e0 = s["kinetic_energy"]
    w.dt = 1e-5
    w.local_damping = 0
    g, steps = 9.81, 1000
    w.step(steps)
    s = w.clump_state(0)
    assert s["position"][2] == pytest.approx(0.05 - g * w.dt**2 * steps * (steps + 1) / 2, rel=1e-12)
    rot = s["kinetic_energy"] - 0.5 * s["mass"] * sum(v * v for v in s["velocity"])
    assert rot == pytest.approx(e0, rel=1e-6)
    # The members stay on the body: the dimer's two centres one member radius apart.
    p = w.positions
    r_member = (0.005**3 / (2 - 5 / 16)) ** (1 / 3)  # the union of two unit balls 1 apart: (2 - 5/16) 4/3 pi
    assert np.linalg.norm(p[1] - p[0]) == pytest.approx(r_member, rel=1e-9)
    w.add_plane([0, 0, 0], [0, 0, 1])
    w.local_damping = 0.4
    w.dt = 0.1 * w.critical_dt()
    w.step(30000)
    weight = (w.clump_state(0)["mass"] + w.clump_state(1)["mass"]) * g
    assert -w.wall_force(0)[2] == pytest.approx(weight, rel=1e-5)
    with pytest.raises(ValueError, match="not built in"):
        w.add_clump([0, 0, 0.1], "cube", radius=0.005)

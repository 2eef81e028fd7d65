"""Analytic physics scenes with known outcomes. Each test states its tolerance."""

from __future__ import annotations

import math

import numpy as np

from engine import Scene
from helpers.sim import WORLD, simulate

G = 9.81
DT = 1.0 / 60.0
FLOOR = 0.4


def slot(scene: Scene, ref) -> int:
    return scene.slot(ref, WORLD)


def test_free_fall_matches_closed_form():
    """A body in the air follows symplectic Euler exactly (1e-4 m) and the continuous parabola within
    the integrator's known offset g t dt / 2 (+1e-4 m)."""
    scene = Scene()
    ball = scene.add_circle((2.5, 4.5), radius=0.1)
    _, traj = simulate(WORLD, scene.build(WORLD), 1.0)
    y = traj.position[:40, slot(scene, ball), 1]  # 0.67 s, before it reaches the floor
    n = np.arange(1, len(y) + 1)
    discrete = 4.5 - G * DT**2 * n * (n + 1) / 2
    np.testing.assert_allclose(y, discrete, atol=1e-4)
    t = n * DT
    continuous = 4.5 - 0.5 * G * t**2
    assert np.all(np.abs(y - continuous) <= G * t * DT / 2 + 1e-4)
    np.testing.assert_allclose(traj.velocity[:40, slot(scene, ball), 1], -G * t, rtol=1e-4, atol=1e-5)  # [m/s]


def test_box_resting_on_floor_stays_put():
    """A box placed on the floor drifts < 2 mm and ends with speed < 1e-3 m/s and spin < 1e-3 rad/s over 10 s."""
    scene = Scene()
    box = scene.add_box((2.0, FLOOR + 0.25), size=(0.6, 0.5))
    _, traj = simulate(WORLD, scene.build(WORLD), 10.0)
    i = slot(scene, box)
    drift = np.linalg.norm(traj.position[:, i] - np.array([2.0, FLOOR + 0.25]), axis=-1)
    assert drift.max() < 2e-3, drift.max()
    assert np.linalg.norm(traj.velocity[-1, i]) < 1e-3
    assert abs(traj.angular_velocity[-1, i]) < 1e-3


def test_stack_of_four_boxes_stands():
    """Four stacked boxes stand for 10 s: every box within 1 cm of its start, tilt < 0.02 rad, final speed
    < 1e-2 m/s."""
    scene = Scene()
    start = [(2.5 + 0.02 * (k % 2), FLOOR + 0.2 + 0.4 * k) for k in range(4)]
    boxes = [scene.add_box(p, size=(0.4, 0.4)) for p in start]
    _, traj = simulate(WORLD, scene.build(WORLD), 10.0)
    for box, p in zip(boxes, start, strict=True):
        i = slot(scene, box)
        assert np.abs(traj.position[:, i] - np.array(p)).max() < 0.01, (i, traj.position[-1, i], p)
        assert np.abs(traj.angle[:, i]).max() < 0.02
        assert np.linalg.norm(traj.velocity[-1, i]) < 1e-2


def _pendulum(length: float, amplitude: float):
    scene = Scene()
    pivot = (2.5, 4.2)
    hub = scene.add_box(pivot, size=(0.1, 0.1), fixed=True)
    bob_at = (pivot[0] + length * math.sin(amplitude), pivot[1] - length * math.cos(amplitude))
    bob = scene.add_circle(bob_at, radius=0.05)
    scene.add_revolute_joint(hub, bob, anchor=pivot)
    return scene, bob, pivot


def test_pendulum_period_matches_theory():
    """A compound pendulum (circle on a 1 m rod, 0.1 rad) swings with period 2 pi sqrt(I_pivot / (m g L))
    within 3%, and the joint drifts < 5 mm."""
    length, amplitude, radius = 1.0, 0.1, 0.05
    scene, bob, pivot = _pendulum(length, amplitude)
    _, traj = simulate(WORLD, scene.build(WORLD), 10.0)
    i = slot(scene, bob)
    x = traj.position[:, i, 0] - pivot[0]
    crossings = np.nonzero(np.diff(np.sign(x)) != 0)[0]
    times = (crossings + 1 - x[crossings + 1] / (x[crossings + 1] - x[crossings])) * DT
    measured = 2 * np.mean(np.diff(times))
    theory = 2 * math.pi * math.sqrt((0.5 * radius**2 + length**2) / (G * length))
    assert abs(measured - theory) / theory < 0.03, (measured, theory)
    rod = np.linalg.norm(traj.position[:, i] - np.array(pivot), axis=-1)
    assert np.abs(rod - length).max() < 5e-3


def test_fixed_joint_holds_relative_angle_under_load():
    """A heavy beam welded to a fixed post holds its angle within 0.02 rad and its anchor within 1 cm for 3 s."""
    scene = Scene()
    post = scene.add_box((1.5, 3.0), size=(0.2, 0.2), fixed=True)
    beam = scene.add_box((2.1, 3.0), size=(1.0, 0.1), density=5.0)
    scene.add_fixed_joint(post, beam, anchor=(1.6, 3.0))
    _, traj = simulate(WORLD, scene.build(WORLD), 3.0)
    i = slot(scene, beam)
    assert np.abs(traj.angle[:, i]).max() < 0.02
    assert np.abs(traj.position[:, i] - np.array([2.1, 3.0])).max() < 0.01


def test_fixed_joint_between_falling_bodies_keeps_reference_angle():
    """Two bodies welded at 0.5 rad apart keep that relative angle (within 0.02 rad) through a fall onto the floor."""
    scene = Scene()
    a = scene.add_box((2.0, 2.0), size=(0.6, 0.2))
    b = scene.add_box((2.35, 2.15), size=(0.4, 0.15), angle=0.5)
    scene.add_fixed_joint(a, b, anchor=(2.3, 2.05))
    _, traj = simulate(WORLD, scene.build(WORLD), 3.0)
    relative = traj.angle[:, slot(scene, b)] - traj.angle[:, slot(scene, a)]
    assert np.abs(relative - 0.5).max() < 0.02


def test_motor_drives_wheel_to_target_speed():
    """A motor (speed 1, power 1, action 0.5) spins a free wheel to 0.5 * 1 * 6 = 3 rad/s within 0.05 rad/s
    in 2 s, and a negative action reverses it."""
    for action, target in ((0.5, 3.0), (-1.0, -6.0)):
        scene = Scene()
        hub = scene.add_box((2.5, 3.0), size=(0.1, 0.1), fixed=True)
        wheel = scene.add_circle((2.5, 3.0), radius=0.3)
        scene.add_revolute_joint(hub, wheel, anchor=(2.5, 3.0), motor_speed=1.0, motor_power=1.0)
        actions = np.zeros(WORLD.num_actions)
        actions[0] = action
        _, traj = simulate(WORLD, scene.build(WORLD), 2.0, actions=actions)
        spin = traj.angular_velocity[:, slot(scene, wheel)]
        assert abs(spin[-1] - target) < 0.05
        assert np.abs(spin).max() <= abs(target) + 1e-4  # never overshoots (the reference rings)


def test_revolute_limits_hold_against_a_motor():
    """A motor pushing an arm into its limits (+-0.5 rad) stops there within 0.03 rad, on either side."""
    for action in (1.0, -1.0):
        scene = Scene(gravity=(0.0, 0.0))
        hub = scene.add_box((2.5, 2.5), size=(0.1, 0.1), fixed=True)
        arm = scene.add_box((2.9, 2.5), size=(0.8, 0.1))
        scene.add_revolute_joint(hub, arm, anchor=(2.5, 2.5), motor_speed=1.0, motor_power=1.0, limits=(-0.5, 0.5))
        actions = np.zeros(WORLD.num_actions)
        actions[0] = action
        _, traj = simulate(WORLD, scene.build(WORLD), 2.0, actions=actions)
        angle = traj.angle[:, slot(scene, arm)]
        assert np.abs(angle).max() < 0.5 + 0.03
        assert abs(angle[-1] - 0.5 * action) < 0.03


def test_thruster_gives_force_over_mass():
    """Without gravity a centred thruster accelerates its body at F / m = 10 * power / (rho * area), within 0.1%,
    along its world direction."""
    scene = Scene(gravity=(0.0, 0.0))
    box = scene.add_box((2.5, 2.5), size=(0.5, 0.4), density=2.0, angle=0.3)
    angle = 0.3 + math.pi / 2
    scene.add_thruster(box, anchor=(2.5, 2.5), angle=angle, power=1.5)
    actions = np.zeros(WORLD.num_actions)
    actions[WORLD.num_joints] = 1.0
    _, traj = simulate(WORLD, scene.build(WORLD), 1.0, actions=actions)
    accel = 10.0 * 1.5 / (2.0 * 0.5 * 0.4)
    velocity = traj.velocity[:12, slot(scene, box)]  # 0.2 s, before it reaches a wall
    t = np.arange(1, len(velocity) + 1) * DT
    expected = accel * t[:, None] * np.array([math.cos(angle), math.sin(angle)])
    np.testing.assert_allclose(velocity, expected, rtol=1e-3, atol=1e-5)
    assert np.abs(traj.angular_velocity[:12, slot(scene, box)]).max() < 1e-4


def test_off_centre_thruster_also_spins_its_body():
    """A thruster 0.2 m right of the centre pushing up spins a box counter-clockwise: after one step
    omega = (r x F) dt / I, within 1e-3 relative."""
    scene = Scene(gravity=(0.0, 0.0))
    box = scene.add_box((2.5, 2.5), size=(0.6, 0.2), density=1.0)
    scene.add_thruster(box, anchor=(2.7, 2.5), angle=math.pi / 2, power=1.0)
    actions = np.zeros(WORLD.num_actions)
    actions[WORLD.num_joints] = 1.0
    _, traj = simulate(WORLD, scene.build(WORLD), 1.0, actions=actions)
    mass = 0.6 * 0.2
    inertia = mass * (0.6**2 + 0.2**2) / 12
    expected = 0.2 * 10.0 * DT / inertia
    assert abs(traj.angular_velocity[0, slot(scene, box)] - expected) / expected < 1e-3


def test_sliding_box_stops_at_friction_distance():
    """A box sliding at 3 m/s stops after v^2 / (2 mu g), mu = 0.4 sqrt(f_box^2 + f_floor^2), within 5%."""
    v0, friction = 3.0, 0.5
    scene = Scene()
    box = scene.add_box((0.5, FLOOR + 0.1), size=(0.3, 0.2), friction=friction, velocity=(v0, 0.0))
    _, traj = simulate(WORLD, scene.build(WORLD), 2.0)
    i = slot(scene, box)
    mu = 0.4 * math.sqrt(friction**2 + 1.0**2)
    expected = v0**2 / (2 * mu * G)
    travelled = traj.position[-1, i, 0] - 0.5
    assert abs(travelled - expected) / expected < 0.05, (travelled, expected)
    assert abs(traj.velocity[-1, i, 0]) < 1e-3


def test_momentum_conserved_in_gravity_free_collision():
    """Without gravity, a box and a circle of different masses collide (off-centre): total linear momentum
    is conserved to 1e-4 relative, and they do exchange momentum."""
    scene = Scene(gravity=(0.0, 0.0))
    box = scene.add_box((1.5, 2.5), size=(0.4, 0.4), density=2.0, velocity=(2.0, 0.0))
    ball = scene.add_circle((3.5, 2.65), radius=0.2, density=0.7, velocity=(-1.0, 0.0), restitution=0.5)
    state = scene.build(WORLD)
    _, traj = simulate(WORLD, state, 1.0)  # they meet after ~0.5 s and reach no wall within 1 s
    masses = np.array([2.0 * 0.16, 0.7 * math.pi * 0.04])
    idx = [slot(scene, box), slot(scene, ball)]
    momentum = (masses[:, None] * traj.velocity[:, idx]).sum(axis=1)
    initial = masses[0] * np.array([2.0, 0.0]) + masses[1] * np.array([-1.0, 0.0])
    np.testing.assert_allclose(momentum, np.broadcast_to(initial, momentum.shape), atol=1e-4 * np.linalg.norm(initial))
    assert traj.velocity[-1, idx[0], 0] < 1.5  # the box was slowed by the hit


def test_restitution_bounce_height():
    """A ball with restitution 1 dropped on a restitution-1 floor rebounds to > 90% of its drop height."""
    scene = Scene()
    scene.arena[0].restitution = 1.0
    ball = scene.add_circle((2.5, 2.4), radius=0.1, restitution=1.0)
    _, traj = simulate(WORLD, scene.build(WORLD), 2.0)
    y = traj.position[:, slot(scene, ball), 1]
    bottom = int(np.argmin(y[:60]))
    assert y[bottom:].max() - 0.5 > 0.9 * (2.4 - 0.5)


def test_jointed_bodies_do_not_collide_even_through_a_chain():
    """Overlapping bodies linked directly or through a chain of joints never touch or push apart (1e-4 m)."""
    scene = Scene(gravity=(0.0, 0.0))
    a = scene.add_box((2.0, 2.0), size=(0.6, 0.6))
    b = scene.add_box((2.3, 2.0), size=(0.6, 0.6))
    c = scene.add_circle((1.9, 2.1), radius=0.3)  # overlaps a, linked to it only through b
    scene.add_revolute_joint(a, b, anchor=(2.15, 2.0))
    scene.add_revolute_joint(b, c, anchor=(2.1, 2.05))
    state = scene.build(WORLD)
    _, traj = simulate(WORLD, state, 1.0)
    np.testing.assert_allclose(traj.position[-1], np.asarray(state.bodies.position), atol=1e-4)
    assert not traj.touching.any()


def test_collision_mode_rule():
    """Mode 0 passes through mode 1 but not through mode 2 (the reference's rule)."""
    for other_mode, passes in ((1, True), (2, False)):
        scene = Scene()
        ghost = scene.add_circle((2.5, 2.0), radius=0.2, collision_mode=0)
        scene.add_box((2.5, 0.6), size=(1.0, 0.4), fixed=True, collision_mode=other_mode)
        _, traj = simulate(WORLD, scene.build(WORLD), 1.0)
        y = traj.position[-1, slot(scene, ghost), 1]
        assert (y < 0.7) == passes, (other_mode, y)


def test_arena_holds_mode_zero_bodies():
    """The arena is mode 2, as in the reference: a body that collides with nothing else still lands on the floor."""
    scene = Scene()
    ghost = scene.add_circle((2.5, 2.0), radius=0.2, collision_mode=0)
    _, traj = simulate(WORLD, scene.build(WORLD), 1.5)
    np.testing.assert_allclose(traj.position[-1, slot(scene, ghost), 1], 0.6, atol=0.02)


def test_inactive_body_neither_moves_nor_collides():
    """An inactive body keeps its pose exactly and a body falling through its place is not stopped by it."""
    scene = Scene()
    ghost = scene.add_box((2.5, 1.0), size=(1.0, 0.2), active=False)
    ball = scene.add_circle((2.5, 2.0), radius=0.1)
    state = scene.build(WORLD)
    _, traj = simulate(WORLD, state, 1.0)
    assert np.array_equal(traj.position[-1, slot(scene, ghost)], np.asarray(state.bodies.position[slot(scene, ghost)]))
    assert traj.position[-1, slot(scene, ball), 1] < 0.6


def test_fast_thin_body_does_not_tunnel():
    """A ball at 40 m/s toward a 5 cm wall stops at the wall (speculative contacts), not behind it."""
    scene = Scene(gravity=(0.0, 0.0))
    scene.add_box((3.0, 2.5), size=(0.05, 2.0), fixed=True)
    ball = scene.add_circle((1.0, 2.5), radius=0.05, velocity=(40.0, 0.0))
    _, traj = simulate(WORLD, scene.build(WORLD), 1.0)
    assert traj.position[:, slot(scene, ball), 0].max() < 3.0 - 0.025 - 0.05 + 0.01


def test_touching_flags_per_pair():
    """A ball resting on a box touches the box (and the box the floor); the ball never touches the far circle."""
    from engine import touching_matrix
    from engine.pairs import pair_table

    scene = Scene()
    box = scene.add_box((2.0, FLOOR + 0.2), size=(0.6, 0.4))
    ball = scene.add_circle((2.0, FLOOR + 0.4 + 0.15), radius=0.15)
    far = scene.add_circle((4.0, 3.0), radius=0.1, fixed=True)
    _, traj = simulate(WORLD, scene.build(WORLD), 1.0)
    matrix = np.asarray(touching_matrix(WORLD, traj.touching[-1]))
    i, j, k = slot(scene, box), slot(scene, ball), slot(scene, far)
    assert matrix[i, j] and matrix[j, i] and matrix[0, i]
    assert not matrix[j, k] and not matrix[0, j]
    assert traj.touching.shape[1] == pair_table(WORLD).num_pairs

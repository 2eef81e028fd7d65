"""Observations: symbolic-flat sizes, the symbolic-entity layout, masks and attention channels, and pixels."""

from __future__ import annotations

import functools

import jax
import numpy as np
import pytest

from engine import SIZES, BodyRef, Scene
from kinetix_cli.config import ModelSettings
from kinetix_cli.constants import MODEL_NAMES
from kinetix_cli.env import pixels
from kinetix_cli.env.level import Bindings, Level, make_level, stack_levels
from kinetix_cli.env.observations import (
    JOINT_BINDING,
    SHAPE_COS,
    SHAPE_POSITION,
    SHAPE_ROLE,
    SHAPE_SIN,
    THRUSTER_ANCHOR,
    THRUSTER_BINDING,
    THRUSTER_DIRECTION,
    symbolic_entity,
    symbolic_flat,
    used_bindings,
)
from kinetix_cli.env.pixels import pixel_observation

FLOOR = BodyRef("arena", 0)


def bindings_for(static, motor=(), auto=(), thruster=()) -> Bindings:
    """Bindings padded to the size (unlisted slots: binding 0, not auto)."""

    def pad(values, n, dtype):
        out = np.zeros(n, dtype)
        out[: len(values)] = values
        return out

    return Bindings(
        motor=pad(motor, static.num_joints, np.int32),
        motor_auto=pad(auto, static.num_joints, bool),
        thruster=pad(thruster, static.num_thrusters, np.int32),
    )


def small_scene() -> Scene:
    """A box with a jointed wheel and a thruster: fits every size."""
    scene = Scene()
    box = scene.add_box((1.0, 1.0), (0.4, 0.2))
    wheel = scene.add_circle((1.0, 0.8), 0.1)
    scene.add_revolute_joint(box, wheel, anchor=(1.0, 0.8), motor_speed=1.0)
    scene.add_thruster(box, anchor=(0.8, 1.0), angle=0.0)
    return scene


@pytest.mark.parametrize(("name", "expected"), [("s", 140), ("m", 247), ("l", 679)])
def test_symbolic_flat_sizes(name, expected):
    static = SIZES[name]
    out = jax.eval_shape(functools.partial(symbolic_flat, static), small_scene().build(static), bindings_for(static))
    assert out.shape == (expected,)


def test_entity_widths_do_not_depend_on_the_size():
    """Only the entity counts change with the size; every feature width is the same."""
    for name, static in SIZES.items():
        p, c, j, t = static.num_polygons, static.num_circles, static.num_joints, static.num_thrusters
        n = p + c
        out = jax.eval_shape(
            functools.partial(symbolic_entity, static), small_scene().build(static), bindings_for(static)
        )
        shapes = {k: (v.shape, v.dtype) for k, v in vars(out).items()}
        f32, i32, b = np.dtype("float32"), np.dtype("int32"), np.dtype("bool")
        assert shapes == {
            "polygons": ((p, 27), f32),
            "circles": ((c, 19), f32),
            "joints": ((2 * j, 22), f32),
            "joint_src": ((2 * j,), i32),
            "joint_dst": ((2 * j,), i32),
            "thrusters": ((t, 8), f32),
            "thruster_body": ((t,), i32),
            "polygon_mask": ((p,), b),
            "circle_mask": ((c,), b),
            "joint_mask": ((2 * j,), b),
            "thruster_mask": ((t,), b),
            "attention_mask": ((4, n, n), b),
            "gravity": ((2,), f32),
        }, name


@pytest.fixture(scope="module")
def chain():
    """Size m: a box resting on the floor, wheel A pinned to it (limits, motor), B welded to A, C free.

    Slots: floor 0, walls 1..3, box 4, empty polygon 5, circles A 6, B 7, C 8.
    """
    static = SIZES["m"]
    obs = jax.jit(symbolic_entity, static_argnums=0)(static, *chain_scene(static))
    return static, jax.tree.map(np.asarray, obs)


def chain_scene(static):
    """The physics and bindings of `chain`'s scene."""
    scene = Scene()
    box = scene.add_box((1.0, 0.5), (0.6, 0.2))  # bottom edge on the floor top (y = 0.4)
    a = scene.add_circle((1.2, 0.9), 0.15)
    bb = scene.add_circle((1.5, 0.9), 0.15)
    scene.add_circle((4.0, 3.0), 0.2)
    scene.add_revolute_joint(box, a, anchor=(1.2, 0.7), motor_speed=2.0, limits=(-0.5, 1.0))
    scene.add_fixed_joint(a, bb, anchor=(1.35, 0.9))
    scene.add_thruster(bb, anchor=(1.5, 1.0), angle=0.0)
    return scene.build(static), bindings_for(static, motor=(3, 0), thruster=(1,))


def test_entity_masks(chain):
    static, obs = chain
    assert obs.polygon_mask.tolist() == [True, False, False, False, True, False]
    assert obs.circle_mask.tolist() == [True, True, True]
    assert obs.joint_mask.tolist() == [True, True, True, True]
    assert obs.thruster_mask.tolist() == [True, False]
    assert obs.thruster_body[0] == 7
    assert not obs.polygons[1:4].any() and not obs.polygons[5].any()  # walls, ceiling, empty slot are zero
    np.testing.assert_allclose(obs.polygons[[0, 4], 26], [1.0, 0.5], atol=1e-7)  # collision mode / 2: floor 2, box 1
    np.testing.assert_allclose(obs.circles[:, 18], 0.5, atol=1e-7)
    np.testing.assert_allclose(obs.gravity, (0.0, -0.981), atol=1e-6)


def test_used_bindings(chain):
    """The chain's one motor is on binding 3 and its one thruster on thruster binding 1; the fixed joint drives
    nothing. Batched observations answer per scene."""
    _, obs = chain
    assert used_bindings(obs).tolist() == [False, False, False, True, False, True]
    two = jax.tree.map(lambda x: np.stack([x, x]), obs)
    two.thruster_mask[1] = False
    assert used_bindings(two).tolist() == [[False, False, False, True, False, True], [False] * 3 + [True, False, False]]


def test_the_columns_models_read_by_name_hold_what_they_say(chain):
    """The column constants that `rl.networks.RelationalMLP` reads: positions, roles and angles of shapes, motor
    bindings of joint rows, bindings, anchors and body-frame directions of thruster rows."""
    static, obs = chain
    p = static.num_polygons
    np.testing.assert_allclose(obs.polygons[4, SHAPE_POSITION], (1.0, 0.5), atol=1e-6)  # the box
    np.testing.assert_allclose(obs.circles[1, SHAPE_POSITION], (1.5, 0.9), atol=1e-6)  # wheel B
    np.testing.assert_array_equal(obs.circles[1, SHAPE_ROLE], (1, 0, 0, 0))  # neutral
    np.testing.assert_allclose(obs.circles[1, [SHAPE_SIN, SHAPE_COS]], (0.0, 1.0), atol=1e-6)
    np.testing.assert_array_equal(obs.joints[0, JOINT_BINDING], (0, 0, 0, 1))  # the motor on binding 3
    np.testing.assert_array_equal(obs.joints[1, JOINT_BINDING], (0, 0, 0, 0))  # the fixed joint has no motor
    thruster = obs.thrusters[0]
    assert obs.thruster_body[0] == p + 1
    np.testing.assert_array_equal(thruster[THRUSTER_BINDING], (0, 1))
    np.testing.assert_allclose(thruster[THRUSTER_ANCHOR], (0.0, 0.1), atol=1e-6)  # (1.5, 1.0) from B's centre
    np.testing.assert_allclose(thruster[THRUSTER_DIRECTION], (1.0, 0.0), atol=1e-6)  # angle 0: (cos, sin)


def test_attention_channels(chain):
    static, obs = chain
    att = obs.attention_mask
    shapes = [0, 4, 6, 7, 8]
    masked = [1, 2, 3, 5]
    for ch in range(4):
        assert att[ch][masked].sum() == 0 and att[ch][:, masked].sum() == 0, ch
        assert all(att[ch][i, i] for i in shapes), ch
        np.testing.assert_array_equal(att[ch], att[ch].T)
    assert att[0][np.ix_(shapes, shapes)].all()

    def pairs(ch):
        return {(i, j) for i, j in zip(*np.nonzero(att[ch]), strict=True) if i < j}

    assert pairs(1) == {(4, 6), (4, 7), (6, 7)}  # the chain box - A - B
    assert pairs(2) == {(4, 6), (6, 7)}  # direct joints only
    assert pairs(3) == {(0, 4)}  # the box rests on the floor; joined pairs never count as contacts


def test_without_attention_the_mask_is_all_false_and_the_rest_the_same(chain):
    """What the models other than the transformer get (`ModelSettings.reads_attention`)."""
    static, obs = chain
    scene_physics, bindings = chain_scene(static)
    plain = jax.jit(symbolic_entity, static_argnums=(0, 3))(static, scene_physics, bindings, False)
    assert plain.attention_mask.shape == obs.attention_mask.shape and not plain.attention_mask.any()
    jax.tree.map(np.testing.assert_array_equal, plain.replace(attention_mask=obs.attention_mask), obs)
    assert [ModelSettings(name=m).reads_attention for m in MODEL_NAMES] == [m == "transformer" for m in MODEL_NAMES]


def test_reversed_joint_rows_mirror(chain):
    static, obs = chain
    j = static.num_joints
    fwd, rev = obs.joints[:j], obs.joints[j:]
    np.testing.assert_array_equal(obs.joint_src, [4, 6, 6, 7])
    np.testing.assert_array_equal(obs.joint_dst, [6, 7, 4, 6])
    # limits (columns 11, 12) on angle_dst - angle_src: [-0.5, 1.0] forwards, [-1.0, 0.5] reversed
    np.testing.assert_allclose(fwd[0, 11:13], (-0.5, 1.0), atol=1e-6)
    np.testing.assert_allclose(rev[0, 11:13], (-1.0, 0.5), atol=1e-6)
    np.testing.assert_allclose(rev[:, 13:15], fwd[:, 15:17], atol=1e-6)  # [m]; anchors swap
    np.testing.assert_allclose(rev[:, 15:17], fwd[:, 13:15], atol=1e-6)  # [m]
    np.testing.assert_allclose(rev[:, 19], -fwd[:, 19], atol=1e-6)  # relative angle
    assert fwd[:, 21].tolist() == [0, 0] and rev[:, 21].tolist() == [1, 1]
    np.testing.assert_array_equal(rev[:, :11], fwd[:, :11])  # flags, binding, speed, power, has_limits
    assert fwd[0, 4:8].tolist() == [0, 0, 0, 1]  # motor binding 3


# --- pixels ---------------------------------------------------------------------------------------
def px(x: float, y: float) -> tuple[int, int]:
    """(row, col) of the pixel containing world point (x, y) [m]."""
    return int((5.0 - y) * 25), int(x * 25)


def pixel_level(floor_role: int) -> Level:
    """Size s: a green and a red ball joined by a motor (binding 2), a thruster (binding 1) on red's centre,
    and a fixed neutral box."""
    static = SIZES["s"]
    scene = Scene()
    scene.arena[0].role = floor_role
    scene.add_box((1.0, 3.0), (0.6, 0.6), fixed=True)
    green = scene.add_circle((2.5, 2.5), 0.3, role=1)
    red = scene.add_circle((3.5, 2.5), 0.3, role=3)
    scene.add_revolute_joint(green, red, anchor=(3.0, 2.5), motor_speed=1.0)
    scene.add_thruster(red, anchor=(3.5, 2.5), angle=0.0)
    return make_level(scene.build_numpy(static), bindings_for(static, motor=(2,), thruster=(1,)))


@pytest.fixture(scope="module")
def batch():
    """Two scenes (neutral floor, blue floor) observed with one jit + vmap call of each observation."""
    static = SIZES["s"]
    levels = stack_levels([pixel_level(0), pixel_level(2)])

    @jax.jit
    @jax.vmap
    def observe(level):
        return (
            pixel_observation(static, level.physics, level.bindings),
            symbolic_entity(static, level.physics, level.bindings),
        )

    images, entities = observe(levels)
    return np.asarray(images), entities, levels


PIXEL = 1e-6
"""Absolute tolerance of a pixel value [0-1]: a few float32 ulps at 1, far below one colour level (1/255)."""


def rgb(colour) -> np.ndarray:
    return np.asarray(colour, np.float32) / 255.0


def test_pixels_shape_range_and_background(batch):
    images, _, _ = batch
    assert images.shape == (2, 125, 125, 3) and images.dtype == np.float32
    assert images.min() >= 0.0 and images.max() <= 1.0
    np.testing.assert_allclose(images[0][px(4.5, 4.5)], rgb(pixels.BACKGROUND), atol=PIXEL)
    np.testing.assert_allclose(images[0][px(0.5, 0.6)], rgb(pixels.BACKGROUND), atol=PIXEL)  # just above the floor


def test_pixels_shapes_and_markers(batch):
    image = batch[0][0]
    np.testing.assert_allclose(image[px(2.5, 2.5)], rgb((0, 204, 0)), atol=PIXEL)  # green ball's centre
    np.testing.assert_allclose(image[px(2.5, 2.75)], rgb((0, 204, 0)), atol=PIXEL)
    np.testing.assert_allclose(image[px(2.5, 2.85)], rgb(pixels.BACKGROUND), atol=PIXEL)  # just outside it
    np.testing.assert_allclose(image[px(3.5, 2.7)], rgb((255, 102, 102)), atol=PIXEL)  # red ball
    np.testing.assert_allclose(image[px(1.0, 3.0)], rgb((80, 80, 80)), atol=PIXEL)  # fixed neutral box
    np.testing.assert_allclose(image[px(1.25, 3.25)], rgb((80, 80, 80)), atol=PIXEL)
    np.testing.assert_allclose(image[px(1.35, 3.0)], rgb(pixels.BACKGROUND), atol=PIXEL)
    np.testing.assert_allclose(image[px(3.0, 2.5)], rgb(pixels.MOTOR_COLOURS[2]), atol=PIXEL)  # joint dot
    np.testing.assert_allclose(image[px(3.5, 2.5)], rgb(pixels.THRUSTER_COLOURS[1]), atol=PIXEL)  # thruster dot on top


def test_pixels_floor(batch):
    images = batch[0]
    row = px(0.0, 0.39)[0]
    floor = np.broadcast_to(rgb((80, 80, 80)), images[0][row:].shape)
    np.testing.assert_allclose(images[0][row:], floor, atol=PIXEL)
    np.testing.assert_allclose(images[1][px(2.0, 0.2)], rgb((0, 102, 204)) * 0.5, atol=PIXEL)  # fixed blue floor
    np.testing.assert_allclose(images[0][px(2.0, 0.42)], rgb(pixels.BACKGROUND), atol=PIXEL)


def test_batched_entity_matches_single_scene(batch):
    _, entities, levels = batch
    static = SIZES["s"]
    one = jax.tree.map(lambda x: x[1], jax.device_get(levels))  # on the host: op by op it is ~40 small compiles
    single = jax.jit(symbolic_entity, static_argnums=0)(static, one.physics, one.bindings)
    for got, want in zip(jax.tree.leaves(jax.device_get(entities)), jax.tree.leaves(single), strict=True):
        np.testing.assert_allclose(got[1], np.asarray(want), atol=1e-6)

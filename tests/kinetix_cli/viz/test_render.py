"""Host-side renderer: frame size, colours where the shapes are, actuator markers, atomic PNG/GIF files."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from PIL import Image

from engine import SIZES, Scene
from kinetix_cli.env.level import Bindings
from kinetix_cli.viz.render import frame_size, header_height, render_frame, save_gif, save_png

SCALE = 60


def make_scene():
    """A green box with a motorised wheel and a thruster pushing +x, and a fixed blue circle (size m)."""
    scene = Scene()
    box = scene.add_box((1.5, 2.0), size=(0.8, 0.5), role=1)
    wheel = scene.add_circle((1.5, 1.4), radius=0.25)
    scene.add_circle((4.0, 1.5), radius=0.4, role=2, fixed=True)
    scene.add_revolute_joint(box, wheel, anchor=(1.5, 1.4), motor_speed=1.0)
    scene.add_thruster(box, anchor=(1.1, 2.0), angle=0.0)
    static = SIZES["m"]
    physics = scene.build_numpy(static)
    bindings = Bindings(
        motor=np.array([2, 0], np.int32), motor_auto=np.zeros(static.num_joints, bool), thruster=np.zeros(2, np.int32)
    )
    return physics, bindings


def pixel(image: Image.Image, x: float, y: float, scale: float = SCALE) -> np.ndarray:
    """RGB of the pixel showing world point (x, y) [m]."""
    px = int((x + 0.1) * scale)
    py = header_height(scale) + int((5.1 - y) * scale)
    return np.asarray(image.getpixel((px, py)), dtype=int)


def near(rgb: np.ndarray, expected, tol: int = 12) -> bool:
    return bool(np.all(np.abs(rgb - np.asarray(expected)) <= tol))


@pytest.fixture(scope="module")
def scene():
    return make_scene()


@pytest.fixture(scope="module")
def frame(scene):
    physics, bindings = scene
    return render_frame(physics, bindings, scale=SCALE, title="test level", caption="t = 0.0 s")


@pytest.mark.parametrize("scale", [25, SCALE, 100])
def test_size_follows_scale(scene, scale):
    image = render_frame(*scene, scale=scale)
    assert image.mode == "RGB"
    assert image.size == frame_size(scale)
    assert image.size == (round(5.2 * scale), header_height(scale) + round(5.1 * scale))


def test_colours_where_the_shapes_are(frame):
    assert near(pixel(frame, 1.7, 2.1), (0, 204, 0))  # the green box
    assert near(pixel(frame, 4.0, 1.7), (0, 51, 102))  # the fixed blue circle: blue x 0.5
    assert near(pixel(frame, 1.5, 1.25), (160, 160, 160))  # the neutral wheel below its joint
    assert near(pixel(frame, 2.8, 4.0), (255, 255, 255), tol=3)  # background, far from everything
    assert near(pixel(frame, 2.5, 0.2), (80, 80, 80))  # the neutral floor
    assert pixel(frame, -0.05, 3.0).sum() < 3 * 250  # the left wall strip is drawn


def test_floor_role_and_inactive_walls(scene):
    physics, bindings = scene
    bodies = physics.bodies.replace(role=physics.bodies.role.copy(), active=physics.bodies.active.copy())
    bodies.role[0] = 3
    bodies.active[1] = False
    image = render_frame(physics.replace(bodies=bodies), bindings, scale=SCALE)
    assert near(pixel(image, 2.5, 0.2), (255, 102, 102))  # a red floor in its role colour
    assert near(pixel(image, -0.05, 3.0), (255, 255, 255), tol=3)  # no left wall


def test_actions_light_the_thruster_and_motor(scene, frame):
    physics, bindings = scene
    acting = render_frame(physics, bindings, scale=SCALE, actions=[0, 0, 1, 0, 1, 0])
    assert near(pixel(frame, 0.8, 2.0), (255, 255, 255), tol=3)  # behind the idle nozzle: nothing
    flame = pixel(acting, 0.8, 2.0)
    assert flame[0] > 200 and flame[2] < 150  # a flame points away from the push (+x)
    halo = pixel(acting, 1.5 + 0.1, 1.4)  # the running motor gets a halo over the wheel
    assert not near(halo, pixel(frame, 1.5 + 0.1, 1.4), tol=20)
    with pytest.raises(ValueError, match="actions"):
        render_frame(physics, bindings, actions=[0, 1])


def test_jax_leaves_render_the_same(scene, frame):
    physics, bindings = scene
    on_device = jax.tree.map(jnp.asarray, physics), jax.tree.map(jnp.asarray, bindings)
    device = render_frame(*on_device, scale=SCALE, title="test level", caption="t = 0.0 s")
    assert np.array_equal(np.asarray(device), np.asarray(frame))


def test_batch_is_rejected(scene):
    physics, bindings = scene
    batch = jax.tree.map(lambda x: np.stack([x, x]), physics)
    with pytest.raises(ValueError, match="one scene"):
        render_frame(batch, bindings)


def test_save_png_round_trip(tmp_path, frame):
    path = tmp_path / "out" / "frame.png"
    save_png(frame, path)
    with Image.open(path) as loaded:
        assert loaded.format == "PNG"
        assert np.array_equal(np.asarray(loaded.convert("RGB")), np.asarray(frame))
    save_png(frame, path)  # overwriting is fine too
    assert sorted(p.name for p in path.parent.iterdir()) == ["frame.png"]


def test_save_gif_round_trip(tmp_path, scene):
    physics, bindings = scene
    frames = [render_frame(physics, bindings, scale=25, actions=[0, 0, 1, 0, k / 3, 0]) for k in range(4)]
    path = tmp_path / "clip" / "replay.gif"
    save_gif(frames, path, fps=20)
    with Image.open(path) as loaded:
        assert loaded.format == "GIF"
        assert loaded.n_frames == 4
        assert loaded.size == frames[0].size
        assert loaded.info["loop"] == 0
        assert loaded.info["duration"] == 50
        loaded.seek(3)
        last = np.asarray(loaded.convert("RGB"), dtype=int)
    assert np.abs(last - np.asarray(frames[3], dtype=int)).mean() < 3  # adaptive palette stays close
    assert sorted(p.name for p in path.parent.iterdir()) == ["replay.gif"]
    with pytest.raises(ValueError, match="frame"):
        save_gif([], tmp_path / "empty.gif")
    assert not (tmp_path / "empty.gif").exists()

"""Recorded episodes (`record_episodes`): several levels in one batched rollout, each episode its own level's,
cut at its own end, with the start state first. Episodes in a grid (`tile_clips`, `rollout_frames`): the grid's
size, a clip that ends early holding its last frame, a caption under each tile."""

from __future__ import annotations

import jax
import numpy as np
import pytest
from PIL import Image

from helpers.paths import LEVELS
from kinetix_cli.env.actions import sample_action
from kinetix_cli.env.factory import make_env
from kinetix_cli.errors import UserError
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS
from kinetix_cli.viz.render import frame_size
from kinetix_cli.viz.rollout import (
    GAP_COLOUR,
    Episode,
    ending_caption,
    episode_frames,
    record_episodes,
    rollout_frames,
    tile_clips,
)


def test_a_batch_of_levels_gives_each_level_its_own_episode():
    # [A, B, B, A] with keys [a, b, b, a] in one call (one compile): episodes 0 and 3, and 1 and 2, must be equal,
    # so the batch's episodes are split by level index, not mixed up
    specs = [load_level(LEVELS / "s" / name) for name in ("rocket-car-jump.json", "pad-to-pad.json")]
    env, params = make_env(SOLUTION_SETTINGS, specs[0].default_static())
    levels = [spec.build(env.static) for spec in specs]
    a, b = jax.random.split(jax.random.key(3))
    policy = lambda key, obs, t: sample_action(env.action, key)  # noqa: E731
    episodes = record_episodes(
        env, params, [levels[0], levels[1], levels[1], levels[0]], policy, jax.numpy.stack([a, b, b, a]), 64
    )
    for i, j in ((0, 3), (1, 2)):
        assert episodes[i].length == episodes[j].length and episodes[i].solved == episodes[j].solved
        np.testing.assert_array_equal(episodes[i].rewards, episodes[j].rewards)
        jax.tree.map(np.testing.assert_array_equal, episodes[i].physics, episodes[j].physics)
    for episode, level in zip(episodes, [levels[0], levels[1], levels[1], levels[0]], strict=True):
        start = jax.tree.map(lambda x: x[0], episode.physics)
        jax.tree.map(np.testing.assert_array_equal, start, jax.tree.map(np.asarray, level.physics))
        assert len(episode.rewards) == len(episode.actions) == episode.length
        assert jax.tree.leaves(episode.physics)[0].shape[0] == episode.length + 1
    assert not np.array_equal(episodes[0].physics.bodies.position[1], episodes[1].physics.bodies.position[1])


W, H, GAP = 40, 30, 4


def _clip(*shades: int) -> list[Image.Image]:
    """Plain frames of W x H px, one grey shade each."""
    return [Image.new("RGB", (W, H), (shade, shade, shade)) for shade in shades]


def _tile(image: Image.Image, row: int, col: int, strip: int = 0) -> np.ndarray:
    top, left = GAP + row * (H + strip + GAP), GAP + col * (W + GAP)
    return np.asarray(image)[top : top + H, left : left + W]


def test_tiles_hold_their_last_frame_until_the_longest_clip_ends():
    # three clips of 3, 1 and 2 frames in two columns: two rows, the fourth place empty; every grid frame shows
    # clip k's frame min(t, len - 1), and the 2 held frames at the end show every clip's last
    clips = [_clip(10, 20, 30), _clip(40), _clip(50, 60)]
    grid = tile_clips(clips, columns=2, gap=GAP, hold=2)
    assert len(grid) == 3 + 2
    assert {image.size for image in grid} == {(2 * W + 3 * GAP, 2 * H + 3 * GAP)}
    for t, image in enumerate(grid):
        assert _tile(image, 0, 0)[0, 0, 0] == [10, 20, 30][min(t, 2)]
        assert _tile(image, 0, 1)[0, 0, 0] == 40
        assert _tile(image, 1, 0)[0, 0, 0] == [50, 60][min(t, 1)]
        np.testing.assert_array_equal(_tile(image, 1, 1), np.full((H, W, 3), GAP_COLOUR, np.uint8))
    np.testing.assert_array_equal(np.asarray(grid[-1]), np.asarray(grid[2]))


def test_captions_are_written_under_their_tiles_in_their_colours():
    red, green = (200, 30, 30), (0, 130, 0)
    plain = tile_clips([_clip(90), _clip(90)], columns=2, gap=GAP)
    grid = tile_clips([_clip(90), _clip(90)], columns=2, captions=[("failed", red), ("solved", green)], gap=GAP)
    (image,) = grid
    strip = image.height - plain[0].height
    assert strip > 0 and image.width == plain[0].width
    pixels = np.asarray(image)
    for col, colour in ((0, red), (1, green)):
        left = GAP + col * (W + GAP)
        under = pixels[GAP + H : GAP + H + strip, left : left + W].reshape(-1, 3).astype(int)
        redness = under[:, 0] - under[:, 1]  # text is anti-aliased: its pixels lie between its colour and white
        assert (redness > 100).any() == (colour == red) and (redness < -60).any() == (colour == green)
        assert _tile(image, 0, col, strip)[0, 0, 0] == 90


def test_fewer_clips_than_columns_make_one_row():
    grid = tile_clips([_clip(1, 2), _clip(3)], columns=5, gap=0)
    assert [image.size for image in grid] == [(2 * W, H)] * 2


def test_tile_clips_refuses_bad_input():
    with pytest.raises(ValueError, match="at least one clip"):
        tile_clips([], columns=2)
    with pytest.raises(ValueError, match="at least one frame"):
        tile_clips([_clip(1), []], columns=2)
    with pytest.raises(ValueError, match="columns"):
        tile_clips([_clip(1)], columns=0)
    with pytest.raises(ValueError, match="differ in size"):
        tile_clips([_clip(1), [Image.new("RGB", (W + 1, H))]], columns=2)
    with pytest.raises(ValueError, match="1 captions for 2 clips"):
        tile_clips([_clip(1), _clip(2)], columns=2, captions=[("a", (0, 0, 0))])


def _still_episode(name: str, length: int, *, solved: bool, step_seconds: float = 0.1) -> Episode:
    """An episode of `length` steps that stands still at the level's start (no engine run)."""
    level = load_level(LEVELS / "s" / name).build()
    return Episode(
        physics=jax.tree.map(lambda x: np.repeat(np.asarray(x)[None], length + 1, axis=0), level.physics),
        bindings=jax.tree.map(np.asarray, level.bindings),
        action_type="multi-discrete",
        actions=np.zeros((length, 6), np.int32),
        rewards=np.zeros(length),
        solved=solved,
        failed=not solved,
        length=length,
        step_seconds=step_seconds,
    )


def test_one_episode_is_its_own_frames_and_several_a_captioned_grid():
    scale = 20
    a, b = _still_episode("pad-to-pad.json", 4, solved=True), _still_episode("aim-then-fire.json", 2, solved=False)
    frames, fps = rollout_frames([("a", "s", a)], scale=scale)
    assert fps == pytest.approx(10.0, abs=1e-6)
    expected = episode_frames("a", a, scale=scale)
    assert len(frames) == len(expected) == 5
    for got, want in zip(frames, expected, strict=True):
        np.testing.assert_array_equal(np.asarray(got), np.asarray(want))
    frames, fps = rollout_frames([("a", "s", a), ("b", "s", b)], scale=scale, every=2)
    assert fps == pytest.approx(5.0, abs=1e-6)
    assert len(frames) == 3 + 5  # steps 0, 2, 4 of the longer episode, then a second (5 frames at 5/s) held
    w, h = frame_size(scale)
    assert frames[0].width == 2 * w + 3 * 6 and frames[0].height > h + 2 * 6  # one row, a caption strip under it
    assert ending_caption(a, "s") == ("size s: solved in 4 steps (0.40 s)", (0, 130, 0))
    assert ending_caption(b, "m") == ("size m: failed after 2 steps (0.20 s)", (200, 30, 30))


def test_episodes_of_unlike_step_lengths_are_refused():
    a = _still_episode("pad-to-pad.json", 2, solved=True)
    b = _still_episode("pad-to-pad.json", 2, solved=True, step_seconds=0.2)
    with pytest.raises(UserError, match="one GIF needs them all alike"):
        rollout_frames([("a", "s", a), ("b", "s", b)])

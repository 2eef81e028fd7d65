"""The Gymnasium environments: Gymnasium's checker on the single environment, and the vector environment's numpy
batches, spaces, same-step auto-reset with the final observation kept, seeding, batches of fresh levels drawn as
episodes start, rgb_array rendering (through Gymnasium's RecordVideo) and bad arguments."""

from __future__ import annotations

import sys
import types
import warnings
from pathlib import Path

import gymnasium
import jax
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.wrappers import RecordVideo

import kinetix_cli.gym  # noqa: F401  registers the id
from helpers.traces import traces
from kinetix_cli.errors import UserError
from kinetix_cli.gym import ENV_ID, KinetixGymnasiumEnv, KinetixVectorEnv

INFINITE_BOUNDS = ("minimum value is -infinity", "maximum value is infinity")
"""The checker's only remarks: observation features (positions, velocities) have no bounds."""


def test_the_single_environment_passes_gymnasiums_checker():
    env = gymnasium.make(ENV_ID, levels="s", max_steps=8, observation="symbolic-entity")  # a Dict space
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    remarks = [str(w.message) for w in caught]
    assert all(any(bound in remark for bound in INFINITE_BOUNDS) for remark in remarks), remarks
    obs, _ = env.reset(seed=3)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert isinstance(reward, float) and isinstance(terminated, bool) and set(info) == {"solved", "failed"}
    assert obs["polygons"].dtype == np.float32 and env.observation_space.contains(obs)


def test_the_vector_environment_keeps_terminated_truncated_and_the_final_observation():
    envs = gymnasium.make_vec(ENV_ID, num_envs=4, levels="s", max_steps=5)  # the random example's compile
    assert isinstance(envs.unwrapped, KinetixVectorEnv)
    assert envs.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.SAME_STEP
    obs, _ = envs.reset(seed=7)
    again, _ = envs.reset(seed=7)
    np.testing.assert_array_equal(obs, again)  # a seed gives the same start
    assert envs.observation_space.contains(obs) and obs.shape == (4, 140) and obs.dtype == np.float32
    envs.action_space.seed(0)
    seen_end = False
    for _ in range(6):  # the 5-step cap ends every episode by the 5th step
        obs, reward, terminated, truncated, infos = envs.step(envs.action_space.sample())
        assert reward.dtype == np.float32 and reward.shape == (4,)
        assert terminated.dtype == truncated.dtype == np.bool_ and not (terminated & truncated).any()
        done = terminated | truncated
        np.testing.assert_array_equal(infos["_final_obs"], done)
        if done.any():
            seen_end = True
            assert not np.array_equal(infos["final_obs"][done], obs[done])  # obs is the new episode's start
            assert (infos["solved"][done] | infos["failed"][done] | truncated[done]).all()
        assert envs.observation_space.contains(obs)
    assert seen_end
    envs.close()


def test_bad_arguments_are_clear_errors():
    with pytest.raises(gymnasium.error.Error, match="num_envs"):
        KinetixVectorEnv(0, levels="s")
    with pytest.raises(UserError, match="observation: expected one of .*got 'rgb'"):
        gymnasium.make_vec(ENV_ID, num_envs=2, observation="rgb")
    envs = KinetixVectorEnv(2, levels="s")
    with pytest.raises(gymnasium.error.ResetNeeded):
        envs.step(np.zeros((2, 6), np.int32))


def test_fresh_levels_are_drawn_again_once_a_batch_of_episodes_has_started():
    envs = KinetixVectorEnv(2, levels="fresh", size="s", fresh_levels=4, max_steps=2)  # test_environment's sampler
    first, _ = envs.reset(seed=1)
    pool, started, draws = envs.params.pool, 2, 0
    actions = np.zeros((2, 6), np.int32)

    def step(t: int) -> None:
        nonlocal pool, started, draws
        _, _, terminated, truncated, _ = envs.step(actions)
        started += int((terminated | truncated).sum())
        drawn = not _same(envs.params.pool, pool)
        assert drawn == (started >= 4), (t, started)
        if drawn:
            draws, started, pool = draws + 1, 0, envs.params.pool

    step(0)  # the 2-step cap ends both episodes every second step at the latest
    with traces() as traced:  # the reset drew a batch: neither the step nor a new batch compiles again
        for t in range(1, 6):
            step(t)
    assert draws >= 1 and traced[0] == 0
    again, _ = envs.reset(seed=1)  # a seed gives the same batch and the same starts
    np.testing.assert_array_equal(first, again)


def test_rgb_array_renders_the_scene_and_record_video_captures_every_frame(tmp_path, monkeypatch):
    clips = []

    class ImageSequenceClip:  # moviepy's clip, as RecordVideo calls it; moviepy is not a dependency
        def __init__(self, frames, fps):
            clips.append((list(frames), fps))

        def write_videofile(self, path, logger=None):
            Path(path).touch()

    for name in ("moviepy", "moviepy.video", "moviepy.video.io", "moviepy.video.io.ImageSequenceClip"):
        monkeypatch.setitem(sys.modules, name, types.ModuleType(name))
    sys.modules["moviepy.video.io.ImageSequenceClip"].ImageSequenceClip = ImageSequenceClip

    env = gymnasium.make(ENV_ID, levels="s", max_steps=5, render_mode="rgb_array")
    fps = pytest.approx(30.0, abs=1e-3)  # frames/s: 1 / (frame skip 2 x dt 1/60 s in float32)
    assert env.metadata["render_modes"] == ["rgb_array"] and env.metadata["render_fps"] == fps
    recorder = RecordVideo(env, str(tmp_path / "videos"), episode_trigger=lambda episode: True)
    recorder.reset(seed=0)
    steps, done = 0, False
    while not done:
        _, _, terminated, truncated, _ = recorder.step(recorder.action_space.sample())
        steps, done = steps + 1, terminated or truncated
    last = env.render()  # the episode's last state: a single environment waits for its caller's reset
    recorder.close()
    ((frames, clip_fps),) = clips
    assert len(frames) == steps + 1 and clip_fps == fps
    assert (tmp_path / "videos" / "rl-video-episode-0.mp4").exists()
    assert all(f.shape == (282, 260, 3) and f.dtype == np.uint8 for f in frames)
    np.testing.assert_array_equal(frames[-1], last)
    assert not np.array_equal(frames[0], frames[-1])
    collected = gymnasium.make(ENV_ID, levels="s", max_steps=5, render_mode="rgb_array_list")  # RenderCollection
    collected.reset(seed=0)
    collected.step(collected.action_space.sample())
    assert [f.shape for f in collected.render()] == [(282, 260, 3)] * 2


def test_the_vector_environment_renders_its_first_environment():
    envs = gymnasium.make_vec(ENV_ID, num_envs=4, levels="s", max_steps=5, render_mode="rgb_array")  # shared compile
    assert envs.render_mode == "rgb_array" and envs.metadata["render_modes"] == ["rgb_array"]
    envs.reset(seed=0)
    frame = envs.render()
    assert frame.shape == (282, 260, 3) and frame.dtype == np.uint8


def test_an_unknown_render_mode_is_a_clear_error():
    with pytest.raises(gymnasium.error.Error, match="render_mode: 'human' is not one of rgb_array"):
        KinetixGymnasiumEnv(levels="s", render_mode="human")
    with pytest.raises(gymnasium.error.Error, match="render_mode: 'ansi'"):
        KinetixVectorEnv(2, levels="s", render_mode="ansi")


def _same(a, b) -> bool:
    return jax.tree.all(jax.tree.map(np.array_equal, a, b))

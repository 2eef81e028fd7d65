"""Record one episode of a level and turn it into GIF frames (`kinetix rollout`).

`record_episode` plays the episode with the episode runner (`kinetix_cli.env.episode.run_episode`, `record=True`)
under any policy: an open-loop one (no-op, random, the level's solution) or a trained network sampling its
actions, in the environment the caller built (a run's own settings for a trained policy). `episode_frames` draws
it; `tile_clips` puts the clips of several episodes side by side in one grid, each under a caption, every clip
holding its last frame until the longest ends.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Sequence

import jax
import numpy as np
from PIL import Image, ImageDraw, ImageFont

from kinetix_cli.env.actions import binding_values
from kinetix_cli.env.colours import Colour
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import Policy, run_episode
from kinetix_cli.env.level import Level, share_engine_params, stack_levels, to_host
from kinetix_cli.errors import UserError
from kinetix_cli.viz.render import render_frame

GAP_COLOUR: Colour = (255, 255, 255)
"""Colour of the gaps between and around the tiles of a grid, and of their caption strips."""

ENDING_COLOURS: dict[str, Colour] = {"solved": (0, 130, 0), "failed": (200, 30, 30), "timed out": (90, 90, 90)}
"""Caption colour of a tile by how its episode ended (`Episode.ending`)."""


@dataclasses.dataclass
class Episode:
    """A recorded episode (host numpy).

    Attributes:
        physics: engine `State` with a leading time axis: the start, then the state after each step
            (length + 1 entries).
        bindings: the level's bindings.
        action_type: the environment's action type (how `actions` read).
        actions: (length, ...) actions taken.
        rewards: (length,) rewards.
        solved, failed: how it ended (neither: it ran out of time).
        length: environment steps played.
        step_seconds: simulated time per environment step [s].
    """

    physics: object
    bindings: object
    action_type: str
    actions: np.ndarray
    rewards: np.ndarray
    solved: bool
    failed: bool
    length: int
    step_seconds: float

    @property
    def total_return(self) -> float:
        return float(self.rewards.sum())

    @property
    def ending(self) -> str:
        """How the episode ended: "solved", "failed" or "timed out"."""
        return "solved" if self.solved else "failed" if self.failed else "timed out"


def record_episode(
    env: KinetixEnv, params: EnvParams, level: Level, policy: Policy, key: jax.Array, horizon: int
) -> Episode:
    """Play one episode of `level` under `policy` and keep every state until it ends."""
    return record_episodes(env, params, [level], policy, key[None], horizon)[0]


def record_episodes(
    env: KinetixEnv, params: EnvParams, levels: list[Level], policy: Policy, keys: jax.Array, horizon: int
) -> list[Episode]:
    """Play one episode of each level (same size) under `policy`, level i with `keys[i]`, all in one batched
    rollout (one compile for the batch), and keep every state of each until it ends."""

    @functools.partial(jax.jit, static_argnums=2)
    def play(levels, keys, level_axes):
        episode = functools.partial(run_episode, env, params, policy=policy, horizon=horizon, record=True)
        return jax.vmap(lambda level, key: episode(level, key=key), in_axes=(level_axes, 0))(levels, keys)

    batch, level_axes = share_engine_params(stack_levels(levels))
    outcomes, traces = to_host(play(batch, keys, level_axes))
    episodes = []
    for i, level in enumerate(levels):
        length = int(outcomes.length[i])
        start = jax.tree.map(lambda x: np.asarray(x)[None], level.physics)
        frames = jax.tree.map(lambda a, b, i=i, n=length: np.concatenate([a, b[i, :n]]), start, traces.physics)
        episodes.append(
            Episode(
                physics=frames,
                bindings=to_host(level.bindings),
                action_type=env.action,
                actions=traces.action[i, :length],
                rewards=traces.reward[i, :length],
                solved=bool(outcomes.solved[i]),
                failed=bool(outcomes.failed[i]),
                length=length,
                step_seconds=env.frame_skip * float(level.engine_params.dt),
            )
        )
    return episodes


def episode_frames(title: str, episode: Episode, scale: float = 80, every: int = 1) -> list:
    """PIL frames of an episode (every `every`-th step, plus the last) with time and return captions."""
    returns = np.concatenate([[0.0], np.cumsum(episode.rewards)])
    picks = list(range(0, episode.length + 1, every))
    if picks[-1] != episode.length:
        picks.append(episode.length)
    frames = []
    for i in picks:
        physics = jax.tree.map(lambda x, i=i: x[i], episode.physics)
        action = None if i == 0 else np.asarray(binding_values(episode.action_type, episode.actions[i - 1]))
        status = ""
        if i == episode.length:
            status = "  solved" if episode.solved else "  failed" if episode.failed else ""
        caption = f"t = {i * episode.step_seconds:4.2f} s   step {i:3d}   return {returns[i]:+.2f}{status}"
        frames.append(
            render_frame(physics, episode.bindings, scale=scale, title=title, caption=caption, actions=action)
        )
    return frames


def rollout_frames(
    episodes: Sequence[tuple[str, str, Episode]], *, scale: float = 80, every: int = 1, columns: int | None = None
) -> tuple[list[Image.Image], float]:
    """The GIF of `kinetix rollout`: its frames and frames per second [1/s].

    One episode is `episode_frames` of it. Several are tiled (`tile_clips`) in `columns` per row (None: a square-ish
    grid), each tile captioned with its level's size and how it ended, with a second's pause at the end.

    Args:
        episodes: (title, level size, episode) per tile; every episode's steps must last equally long.
        scale: pixels per metre of each tile [px/m].
        every: draw every `every`-th step (and the last); the GIF plays at the same speed.
    """
    steps = {episode.step_seconds for _, _, episode in episodes}
    if len(steps) != 1:
        raise UserError(f"rollout: the levels' steps last {sorted(steps)} s; one GIF needs them all alike")
    fps = 1.0 / (steps.pop() * every)
    clips = [episode_frames(title, episode, scale=scale, every=every) for title, _, episode in episodes]
    if len(clips) == 1:
        return clips[0], fps
    captions = [ending_caption(episode, size) for _, size, episode in episodes]
    columns = columns or math.ceil(math.sqrt(len(clips)))
    return tile_clips(clips, columns, captions, hold=round(fps)), fps


def ending_caption(episode: Episode, size: str) -> tuple[str, Colour]:
    """A tile's caption and its colour: the level size and how the episode ended, e.g. 'size m: solved in 41 steps
    (0.68 s)'."""
    how, seconds = "in" if episode.solved else "after", episode.length * episode.step_seconds
    text = f"size {size}: {episode.ending} {how} {episode.length} steps ({seconds:.2f} s)"
    return text, ENDING_COLOURS[episode.ending]


def tile_clips(
    clips: Sequence[Sequence[Image.Image]],
    columns: int,
    captions: Sequence[tuple[str, Colour]] | None = None,
    *,
    gap: int = 6,
    hold: int = 0,
) -> list[Image.Image]:
    """Several clips played side by side: one grid image per time step, the clips tiled row by row.

    Args:
        clips: one list of frames per clip (each non-empty), every frame the same size (w, h) [px].
        columns: tiles per row (>= 1); fewer clips than `columns` make one row of them.
        captions: one (text, colour) per clip, written in a strip under its tile; None: no strips.
        gap: white space between the tiles and around the grid [px].
        hold: extra grid frames at the end, every clip on its last frame (a pause before a GIF loops).

    Returns:
        `max(len(clip)) + hold` RGB images of `cols * w + (cols + 1) * gap` by `rows * (h + strip) + (rows + 1) *
        gap` pixels, where cols = min(columns, len(clips)), rows = ceil(len(clips) / cols) and strip is the caption
        strip's height (0 without captions). Grid frame t shows clip k's frame min(t, len(clip k) - 1): a clip
        that ends early holds its last frame.

    Examples:
        A clip of 3 frames beside one of 1, which holds its frame while the other plays:

        >>> white, black = Image.new("RGB", (40, 30), "white"), Image.new("RGB", (40, 30), "black")
        >>> grid = tile_clips([[white, white, white], [black]], columns=2, gap=4)
        >>> len(grid), grid[0].size, grid[2].getpixel((4 + 40 + 4, 4))
        (3, (92, 38), (0, 0, 0))
    """
    if not clips or not all(clips):
        raise ValueError("tile_clips: need at least one clip, and at least one frame in each")
    if columns < 1:
        raise ValueError(f"tile_clips: columns must be >= 1, got {columns}")
    if gap < 0 or hold < 0:
        raise ValueError(f"tile_clips: gap and hold must be >= 0, got {gap} and {hold}")
    if captions is not None and len(captions) != len(clips):
        raise ValueError(f"tile_clips: {len(captions)} captions for {len(clips)} clips")
    sizes = {frame.size for clip in clips for frame in clip}
    if len(sizes) != 1:
        raise ValueError(f"tile_clips: frames differ in size: {sorted(sizes)}")
    (width, height), cols = sizes.pop(), min(columns, len(clips))
    rows = math.ceil(len(clips) / cols)
    font_size = int(np.clip(round(height / 24), 9, 28))
    strip = 0 if captions is None else font_size + 2 * max(2, font_size // 3)
    base = Image.new("RGB", (cols * width + (cols + 1) * gap, rows * (height + strip) + (rows + 1) * gap), GAP_COLOUR)
    places = [divmod(k, cols) for k in range(len(clips))]
    corners = [(gap + c * (width + gap), gap + r * (height + strip + gap)) for r, c in places]
    if captions is not None:
        draw, font = ImageDraw.Draw(base), _font(font_size)
        for (text, colour), (left, top) in zip(captions, corners, strict=True):
            x = left + max(0.0, (width - draw.textlength(text, font=font)) / 2)
            draw.text((x, top + height + (strip - font_size) / 2), text, fill=colour, font=font)
    grid = []
    for t in range(max(map(len, clips)) + hold):
        image = base.copy()
        for clip, corner in zip(clips, corners, strict=True):
            image.paste(clip[min(t, len(clip) - 1)], corner)
        grid.append(image)
    return grid


def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """Pillow's built-in font at `size` px (the fixed bitmap font where FreeType is missing), as the frames use."""
    try:
        return ImageFont.load_default(size=size)
    except (TypeError, ImportError, OSError):
        return ImageFont.load_default()

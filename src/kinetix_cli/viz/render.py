"""Host-side pictures of one scene (numpy + Pillow): PNG stills and GIF replays for people.

The picture shows the world x in [-0.1, 5.1] m, y in [0, 5.1] m at `scale` pixels per metre (y up) under
a header strip with the title, the caption and a legend of the action bindings the scene uses. Shapes are
filled by role (fixed shapes darker), revolute joints are rings coloured by their motor binding, fixed
joints small crossed squares, thrusters nozzles coloured by binding whose flame grows with the action.
World geometry is drawn `SUPERSAMPLE` times larger and downscaled with LANCZOS for smooth edges; text is
drawn at the final resolution so it stays crisp.

Examples:
    A shipped level at 50 px/m; `save_png(image, "rocket-car-jump.png")` writes it:

    >>> from kinetix_cli.levels.files import load_level
    >>> from kinetix_cli.levels.suites import suite_folder
    >>> level = load_level(suite_folder("s") / "rocket-car-jump.json").build()
    >>> image = render_frame(level.physics, level.bindings, scale=50, title="rocket car jump", caption="t = 0.0 s")
    >>> image.size, image.size == frame_size(50)
    ((260, 282), True)
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from kinetix_cli.env.colours import BACKGROUND, Colour
from kinetix_cli.io import atomic_write
from kinetix_cli.viz.scene import (
    VIEW_X,
    VIEW_Y,
    Joint,
    Scene,
    Shape,
    Thruster,
    describe_scene,
    mix,
    rotate,
    scaled,
)

SUPERSAMPLE = 3
"""World geometry is drawn this many times larger, then downscaled."""

FLAME_CORE: Colour = (255, 245, 170)
HEADER_FILL: Colour = (244, 244, 244)
TEXT: Colour = (20, 20, 20)


# Sizes of the markers, in metres.
_OUTLINE_M = 0.018
_JOINT_RING_M = 0.065
_FIXED_JOINT_M = 0.05
_NOZZLE_LENGTH_M = 0.11
_NOZZLE_WIDTH_M = 0.12
_FLAME_LENGTH_M = 0.35
_ARROW_RADIUS_M = 0.13
_ACTIVE_THRESHOLD = 0.05


# --- geometry ------------------------------------------------------------------------------------
def frame_size(scale: float = 100) -> tuple[int, int]:
    """(width, height) [px] of a frame at `scale` px/m, header strip included."""
    return _world_size(scale)[0], header_height(scale) + _world_size(scale)[1]


def header_height(scale: float = 100) -> int:
    """Height [px] of the header strip (two text lines) at `scale` px/m."""
    size = _font_size(scale)
    return 2 * size + 3 * _pad(size)


def _world_size(scale: float) -> tuple[int, int]:
    return round((VIEW_X[1] - VIEW_X[0]) * scale), round((VIEW_Y[1] - VIEW_Y[0]) * scale)


def _font_size(scale: float) -> int:
    return int(np.clip(round(0.14 * scale), 9, 28))


def _pad(font_size: int) -> int:
    return max(2, font_size // 3)


class _Canvas:
    """A drawing surface mapping world metres (y up) to pixels (y down) at `px_per_m` px/m."""

    def __init__(self, image: Image.Image, px_per_m: float, y_offset: float = 0.0) -> None:
        self.image = image
        self.draw = ImageDraw.Draw(image)
        self.px_per_m = px_per_m
        self.y_offset = y_offset

    def px(self, point) -> tuple[float, float]:
        """Pixel coordinates of a world point (x, y) [m]."""
        x, y = float(point[0]), float(point[1])
        return (x - VIEW_X[0]) * self.px_per_m, self.y_offset + (VIEW_Y[1] - y) * self.px_per_m

    def len(self, metres: float) -> float:
        """A world length [m] in pixels."""
        return metres * self.px_per_m

    def width(self, metres: float) -> int:
        """A line width [px] for a world thickness [m], at least 1 px."""
        return max(1, round(metres * self.px_per_m))

    def polygon(self, points: np.ndarray, fill: Colour | None, outline: Colour | None, thickness_m: float) -> None:
        """Fill a world polygon (n, 2) [m] and stroke its edges `thickness_m` [m] wide."""
        xy = [self.px(p) for p in points]
        if fill is not None:
            self.draw.polygon(xy, fill=fill)
        if outline is not None:
            self.draw.line([*xy, xy[0], xy[1]], fill=outline, width=self.width(thickness_m), joint="curve")

    def circle(self, centre, radius_m: float, fill: Colour | None, outline: Colour | None, thickness_m: float) -> None:
        """A disc of `radius_m` [m] at world `centre`, with an outline `thickness_m` [m] wide inside the edge."""
        cx, cy = self.px(centre)
        r = self.len(radius_m)
        width = self.width(thickness_m) if outline is not None else 0
        self.draw.ellipse((cx - r, cy - r, cx + r, cy + r), fill=fill, outline=outline, width=width)

    def segment(self, a, b, colour: Colour, thickness_m: float) -> None:
        """A straight world segment from `a` to `b` [m]."""
        self.draw.line([self.px(a), self.px(b)], fill=colour, width=self.width(thickness_m))


# --- the scene -----------------------------------------------------------------------------------
def _draw_shape(canvas: _Canvas, shape: Shape) -> None:
    """A polygon, or a disc with a radius line from the centre along the body's x axis, so its rotation shows."""
    if shape.points is not None:
        canvas.polygon(shape.points, shape.fill, shape.line, _OUTLINE_M)
        return
    canvas.circle(shape.centre, shape.radius, shape.fill, shape.line, _OUTLINE_M)
    tip = shape.centre + rotate(np.array([shape.radius - _OUTLINE_M / 2, 0.0]), shape.angle)
    canvas.segment(shape.centre, tip, shape.line, _OUTLINE_M)


def _draw_curved_arrow(canvas: _Canvas, centre: np.ndarray, action: float, colour: Colour) -> None:
    """An arc around `centre` whose sweep grows with |action|, with a head showing the turn direction
    (counter-clockwise for a positive action)."""
    sweep = math.radians(60 + 200 * min(1.0, abs(action)))
    start = math.radians(100)
    sign = 1.0 if action > 0 else -1.0
    angles = start + sign * np.linspace(0.0, sweep, 24)
    r = _ARROW_RADIUS_M
    points = [centre + r * np.array([math.cos(a), math.sin(a)]) for a in angles]
    canvas.draw.line([canvas.px(p) for p in points], fill=colour, width=canvas.width(0.022), joint="curve")
    end, tangent = angles[-1], sign * np.array([-math.sin(angles[-1]), math.cos(angles[-1])])
    tip = centre + r * np.array([math.cos(end), math.sin(end)]) + 0.05 * tangent
    normal = np.array([math.cos(end), math.sin(end)])
    base = tip - 0.075 * tangent
    head = [tip, base + 0.045 * normal, base - 0.045 * normal]
    canvas.polygon(np.asarray(head), colour, None, 0)


def _draw_joint(canvas: _Canvas, joint: Joint) -> None:
    """Fixed: a small white square with a dark cross. Revolute: a ring filled with the motor colour (white
    without a motor), with a halo and a curved arrow when its motor is running."""
    anchor = joint.anchor
    if joint.fixed:
        h = _FIXED_JOINT_M
        square = anchor + np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
        canvas.polygon(square, (255, 255, 255), (20, 20, 20), 0.012)
        canvas.segment(square[0], square[2], (20, 20, 20), 0.012)
        canvas.segment(square[1], square[3], (20, 20, 20), 0.012)
        return
    colour, action = joint.colour, joint.action
    if colour is not None and action is not None and abs(action) > _ACTIVE_THRESHOLD:
        canvas.circle(anchor, _JOINT_RING_M * 1.9, mix(colour, BACKGROUND, 0.55), None, 0)
        _draw_curved_arrow(canvas, anchor, action, scaled(colour, 0.8))
    ring = (255, 255, 255) if colour is None else colour
    canvas.circle(anchor, _JOINT_RING_M, ring, (20, 20, 20), 0.014)
    canvas.circle(anchor, _JOINT_RING_M * 0.35, (255, 255, 255), (20, 20, 20), 0.01)


def _draw_thruster(canvas: _Canvas, thruster: Thruster) -> None:
    """A nozzle at the anchor opening away from the push direction; a flame whose length grows with the
    action comes out of it when the thruster fires."""
    anchor, colour, action = thruster.anchor, thruster.colour, thruster.action
    forward = np.array([math.cos(thruster.push), math.sin(thruster.push)])
    side = np.array([-forward[1], forward[0]])
    if action is not None and action > _ACTIVE_THRESHOLD:
        length = _NOZZLE_LENGTH_M + _FLAME_LENGTH_M * action
        outer = [
            anchor + 0.8 * _NOZZLE_WIDTH_M * side,
            anchor - length * forward,
            anchor - 0.8 * _NOZZLE_WIDTH_M * side,
        ]
        core = [
            anchor + 0.4 * _NOZZLE_WIDTH_M * side,
            anchor - 0.6 * length * forward,
            anchor - 0.4 * _NOZZLE_WIDTH_M * side,
        ]
        canvas.polygon(np.asarray(outer), mix(colour, (255, 60, 0), 0.3), None, 0)
        canvas.polygon(np.asarray(core), FLAME_CORE, None, 0)
    half = _NOZZLE_WIDTH_M / 2
    nozzle = [anchor + 0.35 * half * side, anchor - _NOZZLE_LENGTH_M * forward + half * side]
    nozzle += [anchor - _NOZZLE_LENGTH_M * forward - half * side, anchor - 0.35 * half * side]
    canvas.polygon(np.asarray(nozzle), colour, (20, 20, 20), 0.012)


def _draw_scene(canvas: _Canvas, scene: Scene) -> list[tuple[np.ndarray, str, Colour]]:
    """Paint the scene back to front; return the actuator labels (world point, text, colour)."""
    for wall in scene.walls:
        canvas.polygon(wall.strip, wall.fill, None, 0)
        canvas.segment(wall.face[0], wall.face[1], wall.line, 0.02)
    for shape in scene.shapes:
        _draw_shape(canvas, shape)
    labels = []
    for joint in scene.joints:
        _draw_joint(canvas, joint)
        if joint.label is not None:
            labels.append((joint.anchor, joint.label, joint.colour))
    for thruster in scene.thrusters:
        _draw_thruster(canvas, thruster)
        forward = np.array([math.cos(thruster.push), math.sin(thruster.push)])
        labels.append((thruster.anchor - (_NOZZLE_LENGTH_M + 0.04) * forward, thruster.label, thruster.colour))
    return labels


# --- text ----------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=16)
def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """Pillow's built-in font at `size` px (the fixed bitmap font where FreeType is missing)."""
    try:
        return ImageFont.load_default(size=size)
    except (TypeError, ImportError, OSError):
        return ImageFont.load_default()


def _draw_labels(canvas: _Canvas, labels: list[tuple[np.ndarray, str, Colour]], font_size: int) -> None:
    """Actuator labels up and right of their world points, dark text with a white halo."""
    font = _font(max(8, round(font_size * 0.85)))
    offset = canvas.len(_JOINT_RING_M) + 1
    for point, text, colour in labels:
        x, y = canvas.px(point)
        canvas.draw.text(
            (x + offset, y - offset),
            text,
            fill=scaled(colour, 0.6),
            font=font,
            anchor="ld",
            stroke_width=2,
            stroke_fill=(255, 255, 255),
        )


def _legend_width(draw: ImageDraw.ImageDraw, entries: list[tuple[str, Colour]], font, size: int, pad: int) -> float:
    """Width [px] of the legend: per entry a swatch, its text and a gap."""
    return sum(size * 0.7 + pad + draw.textlength(text, font=font) + 2 * pad for text, _ in entries)


def _draw_legend(
    draw, entries: list[tuple[str, Colour]], font, right: float, y_mid: float, size: int, pad: int
) -> None:
    """The legend right-aligned at x = `right` [px], centred on the line at `y_mid` [px]."""
    x = right
    box = size * 0.7
    for text, colour in reversed(entries):
        x -= draw.textlength(text, font=font)
        draw.text((x, y_mid), text, fill=TEXT, font=font, anchor="lm")
        x -= box + pad
        draw.rectangle((x, y_mid - box / 2, x + box, y_mid + box / 2), fill=colour, outline=scaled(colour, 0.5))
        x -= 2 * pad


def _fit(draw: ImageDraw.ImageDraw, text, font, width: float) -> str:
    """`text` (None -> ""), cut short with "..." where it is wider than `width` [px]."""
    text = str(text or "")
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "...", font=font) > width:
        text = text[:-1]
    return text.rstrip() + "..."


def _draw_header(image: Image.Image, scale: float, title, caption, entries: list[tuple[str, Colour]]) -> None:
    """The header strip: title (line 1) and caption (line 2) on the left; the binding legend on the right of
    the first line it fits beside (left out when it fits neither: the scene labels still name the bindings)."""
    size = _font_size(scale)
    pad = _pad(size)
    height = header_height(scale)
    draw = ImageDraw.Draw(image)
    draw.rectangle((0, 0, image.width, height - 1), fill=HEADER_FILL)
    draw.line((0, height - 1, image.width, height - 1), fill=(190, 190, 190))
    room = image.width - 4 * pad
    lines = ((_fit(draw, title, _font(size), room), TEXT), (_fit(draw, caption, _font(size), room), (70, 70, 70)))
    tops = [pad + k * (size + pad) for k in range(len(lines))]
    for (text, colour), top in zip(lines, tops, strict=True):
        if text:
            draw.text((2 * pad, top), text, fill=colour, font=_font(size))
    legend_font = _font(max(8, size - 2))
    legend = _legend_width(draw, entries, legend_font, size, pad)
    for (text, _), top in zip(lines, tops, strict=True):
        used = draw.textlength(text, font=_font(size)) + 2 * pad if text else 0
        if entries and 2 * pad + used + legend <= image.width:
            _draw_legend(draw, entries, legend_font, image.width - 2 * pad, top + size / 2, size, pad)
            return


# --- public API ----------------------------------------------------------------------------------
def render_frame(
    physics,
    bindings,
    *,
    scale: float = 100,
    title: str | None = None,
    caption: str | None = None,
    actions: Sequence[float] | np.ndarray | None = None,
) -> Image.Image:
    """Draw one scene as an RGB image of `frame_size(scale)` pixels.

    Args:
        physics: engine `State` of one scene (numpy or jax leaves, no batch axis).
        bindings: `kinetix_cli.level.Bindings` of the same scene.
        scale: pixels per metre of the world view x in [-0.1, 5.1], y in [0, 5.1] [px/m].
        title: first header line (e.g. the level name).
        caption: second header line (e.g. 't = 1.2 s  return 0.43').
        actions: the 6 binding actions (4 motor in [-1, 1], 2 thruster in [0, 1]); when given, firing
            thrusters show a flame and running motors a halo and a curved arrow (counter-clockwise > 0).
    """
    if not scale > 0:
        raise ValueError(f"scale must be > 0 px/m, got {scale}")
    scene = describe_scene(physics, bindings, actions)
    world_w, world_h = _world_size(scale)
    big = Image.new("RGB", (world_w * SUPERSAMPLE, world_h * SUPERSAMPLE), BACKGROUND)
    canvas = _Canvas(big, scale * SUPERSAMPLE)
    labels = _draw_scene(canvas, scene)

    image = Image.new("RGB", frame_size(scale), BACKGROUND)
    top = header_height(scale)
    image.paste(big.resize((world_w, world_h), Image.Resampling.LANCZOS), (0, top))
    _draw_labels(_Canvas(image, scale, y_offset=top), labels, _font_size(scale))
    _draw_header(image, scale, title, caption, scene.legend)
    return image


def render_level(level, **kwargs) -> Image.Image:
    """`render_frame(level.physics, level.bindings, **kwargs)` for a `kinetix_cli.level.Level`."""
    return render_frame(level.physics, level.bindings, **kwargs)


def save_png(image: Image.Image, path: str | os.PathLike) -> None:
    """Write `image` as a PNG at `path`, atomically (parent folders are created)."""
    atomic_write(path, lambda f: image.save(f, format="PNG", optimize=True))


def _shared_palette(frames: list[Image.Image], colours: int = 128) -> Image.Image:
    """An adaptive palette fitted to up to 8 frames spread over the clip (one palette: no flicker)."""
    picks = [frames[i] for i in np.unique(np.linspace(0, len(frames) - 1, min(8, len(frames))).astype(int))]
    strip = Image.new("RGB", (picks[0].width, picks[0].height * len(picks)))
    for k, frame in enumerate(picks):
        strip.paste(frame.convert("RGB"), (0, k * picks[0].height))
    return strip.quantize(colors=colours, method=Image.Quantize.MEDIANCUT)


def save_gif(frames: list[Image.Image], path: str | os.PathLike, fps: float = 30) -> None:
    """Write `frames` (same size) as a GIF looping forever at `fps` frames per second [1/s], atomically.

    The frames share one adaptive palette of 128 colours, without dithering, to keep the file small.
    """
    if not frames:
        raise ValueError("save_gif: need at least one frame")
    if not fps > 0:
        raise ValueError(f"save_gif: fps must be > 0, got {fps}")
    sizes = {frame.size for frame in frames}
    if len(sizes) != 1:
        raise ValueError(f"save_gif: frames differ in size: {sorted(sizes)}")
    palette = _shared_palette(frames)
    quantised = [f.convert("RGB").quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    duration = max(10, round(1000 / fps))

    def save(f) -> None:
        quantised[0].save(
            f, format="GIF", save_all=True, append_images=quantised[1:], loop=0, duration=duration, disposal=1
        )

    atomic_write(path, save)

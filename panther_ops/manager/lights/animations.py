"""Animation frames: ImageAnimation and ChargingAnimation, and their playback.

A frame is one RGBA tuple per LED of a segment. An ImageAnimation turns its image into
``round(duration x frequency)`` frames: the image is resized to (LEDs x frames), row i is
frame i; with a ``color`` the image is made grayscale, normalised so its brightest pixel is
full, and multiplied by the colour. A ChargingAnimation shows a solid colour, red (empty) to
green (full), for a share of the cycle proportional to the battery percentage, with sine
fades at both ends. Playback repeats the frames ``repeat`` times.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.lights.config import AnimationPart, parse_color

RGBA = tuple[int, int, int, int]
Frame = tuple[RGBA, ...]
CHARGING_FADE_FACTOR = 0.15
HUE_EMPTY, HUE_FULL = 0.0, 120.0


@dataclass(frozen=True)
class Frames:
    """An animation's frames for one segment size (one cycle) and how it plays."""

    frames: tuple[Frame, ...]
    repeat: int
    brightness: float
    _shaded: dict[int, tuple[tuple[int, int, int], ...]] = field(
        default_factory=dict, compare=False, repr=False)

    @property
    def length(self) -> int:
        return len(self.frames)

    def shaded(self, index: int) -> tuple[tuple[int, int, int], ...]:
        """What the LEDs show for frame `index` (computed once per frame)."""
        colours = self._shaded.get(index)
        if colours is None:
            colours = tuple(shade(p, self.brightness) for p in self.frames[index])
            self._shaded[index] = colours
        return colours


def anim_length(params: Mapping[str, Any], frequency: float) -> int:
    """Frames per cycle: round(duration x frequency)."""
    length = round(float(params["duration"]) * frequency)
    if length < 1:
        raise LightsConfigError("animation duration is too short for the controller frequency")
    return length


@lru_cache(maxsize=128)
def _image_frames(path: Path, mtime: float, color: int | None, num_led: int,
                  length: int) -> tuple[Frame, ...]:
    from PIL import Image

    with Image.open(path) as raw:
        image = raw.convert("RGBA").resize((num_led, length), Image.Resampling.BILINEAR)
    pixels = list(image.get_flattened_data() if hasattr(image, "get_flattened_data")
                  else image.getdata())
    if color is not None:
        grays = [(299 * r + 587 * g + 114 * b + 500) // 1000 for r, g, b, _ in pixels]
        top = max(grays) or 1
        red, green, blue = (color >> 16) & 0xFF, (color >> 8) & 0xFF, color & 0xFF
        source, pixels = pixels, []
        for gray, (_, _, _, alpha) in zip(grays, source, strict=True):
            level = gray * 255 // top
            pixels.append((level * red // 255, level * green // 255, level * blue // 255, alpha))
    return tuple(tuple(pixels[row * num_led:(row + 1) * num_led]) for row in range(length))


def image_frames(part: AnimationPart, num_led: int, frequency: float) -> Frames:
    """Frames of an ImageAnimation part for a segment of `num_led` LEDs."""
    if part.image is None:
        raise LightsConfigError(f"image {part.image_ref or '(none)'} is in the robot's image, not on this computer: "
                                "it cannot be drawn here")
    try:
        mtime = part.image.stat().st_mtime
        frames = _image_frames(part.image, mtime, parse_color(part.params.get("color")),
                               num_led, anim_length(part.params, frequency))
    except OSError as exc:
        raise LightsConfigError(f"cannot read image {part.image}: {exc}") from exc
    return Frames(frames, int(part.params.get("repeat", 1)),
                  float(part.params.get("brightness", 1.0)))


def hsv_to_rgb(hue: float) -> tuple[int, int, int]:
    """Full saturation and value; hue in degrees."""
    h = hue / 360.0 * 6.0
    i = math.floor(h)
    f = h - i
    q, t = int((1.0 - f) * 255), int(f * 255)
    return [(255, t, 0), (q, 255, 0), (0, 255, t), (0, q, 255), (t, 0, 255), (255, 0, q)][i % 6]


def charging_frames(part: AnimationPart, num_led: int, frequency: float, param: str) -> Frames:
    """Frames of a ChargingAnimation for battery percentage `param` (a string, 0..1)."""
    try:
        value = float(param)
    except ValueError as exc:
        raise LightsConfigError(f"ChargingAnimation needs a battery percentage, got {param!r}") from exc
    if not math.isfinite(value):
        raise LightsConfigError(f"ChargingAnimation needs a finite battery percentage, got {param!r}")
    percent = min(max(value, 0.0), 1.0)
    length = anim_length(part.params, frequency)
    fade = round(length * CHARGING_FADE_FACTOR)
    on = max(round(length * percent), 2 * fade)
    if on >= length:
        fade = 0
    start, end = (length - on) // 2, (length + on) // 2
    red, green, blue = hsv_to_rgb((HUE_FULL - HUE_EMPTY) * percent + HUE_EMPTY)

    def solid(level: float) -> Frame:
        return ((int(red * level), int(green * level), int(blue * level), 255),) * num_led

    frames: list[Frame] = []
    for i in range(length):
        if i < start or i >= end:
            frames.append(solid(0.0))
        elif i < start + fade:
            frames.append(solid(math.sin(math.pi / 2 * (i - start) / fade)))
        elif i <= end - fade:
            frames.append(solid(1.0))
        else:
            frames.append(solid(math.sin(math.pi / (2 * fade) * ((i - end) + 2 * fade))))
    return Frames(tuple(frames), int(part.params.get("repeat", 1)),
                  float(part.params.get("brightness", 1.0)))


def part_frames(part: AnimationPart, num_led: int, frequency: float, param: str = "") -> Frames:
    """Frames of any animation part for one segment."""
    if part.is_charging:
        return charging_frames(part, num_led, frequency, param)
    if part.is_moving:
        raise LightsConfigError(f"{part.type} is played by the robot's lights controller; panther-ops does not "
                                "draw it")
    return image_frames(part, num_led, frequency)


class Playback:
    """One segment playing `Frames` (the C++ Animation::Update counters)."""

    def __init__(self, frames: Frames) -> None:
        self.frames = frames
        self.reset()

    def reset(self) -> None:
        self.iteration = 0
        self.cycle = 0
        self.finished = False
        self.progress = 0.0
        self.index: int | None = None

    def update(self) -> None:
        """Advance one controller step."""
        length = self.frames.length
        if self.cycle >= self.frames.repeat:
            self.index = None
            return
        self.index = self.iteration
        self.iteration += 1
        self.progress = (self.iteration + length * self.cycle) / (length * self.frames.repeat)
        if self.iteration >= length:
            self.iteration = 0
            self.cycle += 1
        if self.cycle >= self.frames.repeat:
            self.finished = True


    @property
    def current(self) -> Frame | None:
        """The frame shown now (None before the first update and after the last cycle)."""
        return None if self.index is None else self.frames.frames[self.index]

    def colours(self) -> tuple[tuple[int, int, int], ...] | None:
        """What the LEDs show now."""
        return None if self.index is None else self.frames.shaded(self.index)


def shade(pixel: RGBA, brightness: float) -> tuple[int, int, int]:
    """What an LED shows: colour x alpha x animation brightness."""
    r, g, b, a = pixel
    scale = a / 255.0 * brightness
    return (round(r * scale), round(g * scale), round(b * scale))

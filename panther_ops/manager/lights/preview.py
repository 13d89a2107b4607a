"""Render an animation ID as an animated GIF of both bumpers.

One GIF frame per controller frame (50 Hz, 20 ms each): ``duration x 50 x repeat`` frames.
Each LED is a square; the front bumper is on top, the rear one below, and a thin progress
bar under them (it also keeps consecutive frames distinct, which GIF writers would merge).
Colours are exact: every frame gets its own palette of the colours it shows.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.lights.animations import Playback, part_frames
from panther_ops.manager.lights.config import CONTROLLER_FREQUENCY, LedConfig, Segment
from panther_ops.manager.lights.validate import animations_with_layout

if TYPE_CHECKING:
    from PIL import Image

LED_PX = 11
GAP_PX = 3
BAR_PX = 2
RGB = tuple[int, int, int]


@dataclass(frozen=True)
class Preview:
    """What `render_preview` wrote."""

    path: Path
    frames: int
    frame_ms: int
    name: str
    colours: tuple[Mapping[int, tuple[RGB, ...]], ...]
    """Per frame: channel -> LED colours (what the GIF shows)."""


def _panel_frames(config: LedConfig, anim_id: int, param: str) -> tuple[str, list[dict[int, tuple[RGB, ...]]]]:
    desc = config.animations.get(anim_id)
    if desc is None:
        raise LightsConfigError(f"no animation with ID {anim_id} "
                                f"(known: {', '.join(map(str, sorted(config.animations)))})")
    players: list[tuple[Segment, Playback]] = []
    for part in desc.parts:
        for name in part.segments:
            segment = config.segments[name]
            players.append((segment, Playback(part_frames(part, segment.num_leds,
                                                          CONTROLLER_FREQUENCY, param))))
    total = max(p.frames.length * p.frames.repeat for _, p in players)
    frames: list[dict[int, tuple[RGB, ...]]] = []
    for _ in range(total):
        panels = {c: [(0, 0, 0)] * p.number_of_leds for c, p in config.panels.items()}
        for segment, player in players:
            player.update()
            shown = player.colours()
            if shown is None:
                continue
            colours = list(shown[::-1] if segment.inverted else shown)
            panels[segment.channel][segment.offset:segment.offset + segment.num_leds] = colours
        frames.append({c: tuple(v) for c, v in panels.items()})
    return desc.name, frames


def _draw(panels: Mapping[int, tuple[RGB, ...]], index: int, total: int,
          width_leds: int) -> Image.Image:
    from PIL import Image, ImageDraw

    bar_colour: RGB = (90, 90, 90)
    colours = sorted({(0, 0, 0), bar_colour, *(c for leds in panels.values() for c in leds)})
    lookup = {c: i for i, c in enumerate(colours)}
    channels = sorted(panels)
    width = width_leds * LED_PX
    height = len(channels) * (LED_PX + GAP_PX) + BAR_PX
    image = Image.new("P", (width, height), lookup[(0, 0, 0)])
    image.putpalette([v for c in colours for v in c])
    draw = ImageDraw.Draw(image)
    for row, channel in enumerate(channels):
        top = row * (LED_PX + GAP_PX)
        for led, colour in enumerate(panels[channel]):
            draw.rectangle((led * LED_PX, top, led * LED_PX + LED_PX - 1, top + LED_PX - 1),
                           fill=lookup[colour])
    bar = max(1, (width * (index + 1)) // total)
    draw.rectangle((0, height - BAR_PX, bar - 1, height - 1), fill=lookup[bar_colour])
    return image


def render_preview(path: str | Path, anim_id: int, out_gif: str | Path,
                   led_config: str | Path | None = None, param: str | None = None) -> Preview:
    """Write an animated GIF of animation `anim_id` on both bumpers.

    Args:
        path: a led_config YAML or a user animations YAML (``user_animations:``).
        anim_id: the animation to draw.
        out_gif: where to write the GIF.
        led_config: panels and segments for a user file (default: the shipped led_config).
        param: the animation parameter (battery percentage for ChargingAnimation; 0.5 if None).

    Returns:
        The file, its frame count (duration x 50 x repeat) and the colours of every frame.

    Raises:
        LightsConfigError: unknown ID, invalid animation or unreadable image.
    """
    config = animations_with_layout(path, led_config)
    name, frames = _panel_frames(config, anim_id, "0.5" if param is None else param)
    width_leds = max(*(p.number_of_leds for p in config.panels.values()), -(-len(frames) // LED_PX))
    images = [_draw(panels, i, len(frames), width_leds) for i, panels in enumerate(frames)]
    out = Path(out_gif)
    frame_ms = round(1000 / CONTROLLER_FREQUENCY)
    images[0].save(out, save_all=True, append_images=images[1:], duration=frame_ms, loop=0,
                   optimize=False, disposal=1)
    return Preview(out, len(images), frame_ms, name, tuple(frames))

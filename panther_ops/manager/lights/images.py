"""The default animation images (templates/lights/animations/*.png), drawn with Pillow.

Like the panther_lights images: columns are LEDs (46, one bumper), rows are time (resized
to the animation's frame count). `draw_default_images` regenerates the shipped files:
``python -m panther_ops.manager.lights.images templates/lights/animations``.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from PIL import Image

WIDTH, HEIGHT = 46, 100
COLOURS: dict[str, tuple[int, int, int]] = {
    "red": (255, 0, 0),
    "green": (0, 255, 0),
    "blue": (0, 0, 255),
    "orange": (255, 100, 0),
    "yellow": (255, 200, 0),
    "cyan": (0, 200, 255),
    "purple": (160, 0, 255),
}
Shape = Callable[[int, int], float]


def triangle(x: int, y: int) -> float:
    """A band growing from the centre to the ends and back (rows = time)."""
    reach = (1.0 - abs(2.0 * y / (HEIGHT - 1) - 1.0)) * (WIDTH / 2 + 2)
    distance = abs(x - (WIDTH - 1) / 2)
    return max(0.0, min(1.0, reach - distance))


def strip(x: int, y: int) -> float:
    """A short strip running from one end to the other."""
    centre = -4 + (WIDTH + 8) * y / (HEIGHT - 1)
    return max(0.0, 1.0 - abs(x - centre) / 4.0)


def blink(times: int) -> Shape:
    """The whole bumper blinking `times` times, smoothly."""

    def shape(_x: int, y: int) -> float:
        return max(0.0, math.sin(math.pi * times * y / HEIGHT)) ** 2

    return shape


def draw(shape: Shape, colour: tuple[int, int, int]) -> Image.Image:
    """An RGBA image of `shape` in `colour`."""
    from PIL import Image

    image = Image.new("RGBA", (WIDTH, HEIGHT))
    for y in range(HEIGHT):
        for x in range(WIDTH):
            level = shape(x, y)
            image.putpixel((x, y), (*(int(c * level) for c in colour), 255))
    return image


def default_images() -> dict[str, tuple[Shape, tuple[int, int, int]]]:
    """File name -> (shape, colour) of every shipped image."""
    images: dict[str, tuple[Shape, tuple[int, int, int]]] = {
        f"triangle01_{name}.png": (triangle, rgb) for name, rgb in COLOURS.items()
    }
    images["strip01_red.png"] = (strip, COLOURS["red"])
    images["strip01_purple.png"] = (strip, COLOURS["purple"])
    images["battery_low.png"] = (blink(2), COLOURS["orange"])
    images["battery_critical.png"] = (blink(4), COLOURS["red"])
    return images


def draw_default_images(out_dir: str | Path) -> list[Path]:
    """Write every default image into `out_dir`; return the paths."""
    target = Path(out_dir)
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for name, (shape, colour) in default_images().items():
        path = target / name
        draw(shape, colour).save(path)
        written.append(path)
    return written


if __name__ == "__main__":  # pragma: no cover - a maintenance command
    for written_path in draw_default_images(sys.argv[1] if len(sys.argv) > 1 else "."):
        print(written_path)

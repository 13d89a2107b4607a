"""LED animations: one finding per rule, the GIF preview, ChargingAnimation, the queue."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml
from PIL import Image

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.lights.animations import Frames, Playback, charging_frames
from panther_ops.manager.lights.config import AnimationPart, load_led_config
from panther_ops.manager.lights.controller import LightsController
from panther_ops.manager.lights.images import default_images, draw
from panther_ops.manager.lights.preview import render_preview
from panther_ops.manager.lights.releases import release_for
from panther_ops.manager.lights.validate import validate_animations
from panther_ops.manager.paths import LIGHTS, default_led_config

IMAGE = "$(find panther_lights)/animations/strip01_red.png"


def user_file(tmp_path: Path, animations: list[dict[str, Any]]) -> Path:
    path = tmp_path / "user_animations.yaml"
    path.write_text(yaml.safe_dump({"user_animations": animations}))
    return path


def animation(**changes: Any) -> dict[str, Any]:
    base: dict[str, Any] = {"id": 21, "name": "MINE", "priority": 2, "animations": [
        {"type": "panther_lights::ImageAnimation", "segments": "all",
         "animation": {"image": IMAGE, "duration": 2, "repeat": 2, "color": 0xFFFF00}}]}
    inner = base["animations"][0]["animation"]
    for key, value in changes.items():
        if key in {"type", "segments"}:
            base["animations"][0][key] = value
        elif key in {"id", "priority", "name"}:
            base[key] = value
        elif value is None:
            inner.pop(key)
        else:
            inner[key] = value
    return base


def led_config(tmp_path: Path, mutate: Any) -> Path:
    doc = yaml.safe_load(default_led_config().read_text())
    mutate(doc)
    path = tmp_path / "led_config.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_shipped_configuration_and_the_manual_example_are_valid() -> None:
    assert validate_animations(default_led_config()) == []
    assert validate_animations(LIGHTS / "user_animations.example.yaml") == []
    config = load_led_config()
    assert sorted(config.animations) == [0, 1, 2, 3, 4, 5, 6, 7, 9]
    assert config.animations[2].priority == 1 and config.animations[9].parts[0].is_charging
    assert config.segments["rear"].inverted and config.segments["front"].num_leds == 46


USER_RULES: list[tuple[str, list[dict[str, Any]]]] = [
    ("anim-id-reserved", [animation(id=19)]),
    ("anim-id-duplicate", [animation(), animation(name="AGAIN")]),
    ("anim-priority-reserved", [animation(priority=1)]),
    ("anim-priority-invalid", [animation(priority=4)]),
    ("anim-too-long", [animation(duration=3, repeat=4)]),
    ("anim-duration-invalid", [animation(duration=0)]),
    ("anim-repeat-invalid", [animation(repeat=0)]),
    ("anim-brightness-range", [animation(brightness=1.5)]),
    ("anim-image-path", [animation(image="animations/relative.png")]),
    ("anim-image-not-found", [animation(image="$(find panther_lights)/animations/no_such_image.png")]),
    ("anim-color-invalid", [animation(color="red")]),
    ("anim-type-unknown", [animation(type="panther_lights::FireworksAnimation")]),
    ("anim-segments-unknown", [animation(segments="roof")]),
]


@pytest.mark.parametrize(("code", "animations"), USER_RULES, ids=[c for c, _ in USER_RULES])
def test_each_user_rule_has_its_own_finding(tmp_path: Path, code: str,
                                            animations: list[dict[str, Any]]) -> None:
    findings = validate_animations(user_file(tmp_path, animations))
    assert [f.code for f in findings] == [code]
    assert findings[0].severity.value == "error"


MANUAL_EXAMPLE = """\
user_animations:
  # animation with default image and custom color
  - id: 21
    name: ANIMATION_1
    priority: 2
    animations:
      - type: panther_lights::ImageAnimation
        segments: all
        animation:
          image: $(find panther_lights)/animations/strip01_red.png
          duration: 2
          repeat: 2
          color: 0xffff00
  # animation with custom image
  - id: 22
    name: ANIMATION_2
    priority: 3
    animations:
      - type: panther_lights::ImageAnimation
        segments: all
        animation:
          image: /animations/custom_image.png
          duration: 3
          repeat: 1
  # animation with a custom image from custom ROS package
  - id: 23
    name: ANIMATION_3
    priority: 3
    animations:
      - type: panther_lights::ImageAnimation
        segments: all
        animation:
          image: $(find my_custom_animation_package)/animations/custom_image.png
          duration: 3
          repeat: 1
  # different animations for Front and Rear Bumper Light
  - id: 24
    name: ANIMATION_4
    priority: 3
    animations:
      - type: panther_lights::ImageAnimation
        segments: front
        animation:
          image: $(find panther_lights)/animations/triangle01_blue.png
          duration: 2
          repeat: 2
      - type: panther_lights::ImageAnimation
        segments: rear
        animation:
          image: $(find panther_lights)/animations/triangle01_red.png
          duration: 3
          repeat: 1
"""


def test_the_manuals_own_example_is_accepted_with_the_robots_images_unchecked(tmp_path: Path) -> None:
    """Issue 11 finding 12: an absolute robot path and a package of the robot are not errors
    here; they are reported as not checked, with the reason."""
    path = tmp_path / "my_awesome_user_animations.yaml"
    path.write_text(MANUAL_EXAMPLE)
    findings = validate_animations(path)
    assert [f.severity.value for f in findings] == ["warning", "warning"]
    assert [f.code for f in findings] == ["anim-image-unchecked", "anim-image-unchecked"]
    assert "/animations/custom_image.png" in findings[0].message and "on the robot" in findings[0].message
    assert "my_custom_animation_package" in findings[1].message and "robot" in findings[1].message


def test_a_plugin_animation_type_is_a_warning_not_a_refusal(tmp_path: Path) -> None:
    findings = validate_animations(user_file(tmp_path, [animation(type="my_lights::FireworksAnimation")]))
    assert [(f.severity.value, f.code) for f in findings] == [("warning", "anim-type-custom")]
    assert "my_lights::FireworksAnimation" in findings[0].message


def test_an_id_of_the_led_config_is_taken(tmp_path: Path) -> None:
    findings = validate_animations(user_file(tmp_path, [animation(id=21), animation(id=9)]))
    assert {f.code for f in findings} == {"anim-id-reserved", "anim-id-duplicate"}
    assert any("CHARGING_BATTERY" in f.message for f in findings)


LAYOUT_RULES: list[tuple[str, Any]] = [
    ("segments-map-unknown-segment", lambda d: d["segments_map"].update(top=["roof"])),
    ("segment-channel-unknown", lambda d: d["segments"][0].update(channel=3)),
    ("segment-range-outside", lambda d: d["segments"][1].update(led_range="46-0")),
    ("segment-range-invalid", lambda d: d["segments"][1].update(led_range="0..45")),
]


@pytest.mark.parametrize(("code", "mutate"), LAYOUT_RULES, ids=[c for c, _ in LAYOUT_RULES])
def test_each_layout_rule_has_its_own_finding(tmp_path: Path, code: str, mutate: Any) -> None:
    findings = validate_animations(led_config(tmp_path, mutate))
    assert code in [f.code for f in findings]
    assert [f.code for f in findings if f.code.startswith("seg")] == [code]


def test_every_rule_message_is_distinct(tmp_path: Path) -> None:
    messages = set()
    for i, (code, animations) in enumerate(USER_RULES):
        folder = tmp_path / f"u{i}"
        folder.mkdir()
        found = validate_animations(user_file(folder, copy.deepcopy(animations)))
        messages |= {f.message for f in found if f.code == code}
    for i, (code, mutate) in enumerate(LAYOUT_RULES):
        folder = tmp_path / f"l{i}"
        folder.mkdir()
        messages |= {f.message for f in validate_animations(led_config(folder, mutate))
                     if f.code == code}
    assert len(messages) == len(USER_RULES) + len(LAYOUT_RULES)


GRAYS = [255, 200, 128, 64, 0]


def tiny_png(path: Path) -> Path:
    """4 LEDs wide, 5 rows (frames) tall, each row one gray level."""
    image = Image.new("RGB", (4, len(GRAYS)))
    for y, gray in enumerate(GRAYS):
        for x in range(4):
            image.putpixel((x, y), (gray, gray, gray))
    image.save(path)
    return path


@pytest.mark.parametrize(("duration", "repeat"), [(0.1, 1), (0.1, 3)])
def test_render_preview_frames_are_image_rows_times_the_colour(tmp_path: Path, duration: float,
                                                              repeat: int) -> None:
    png = tiny_png(tmp_path / "rows.png")
    colour = (0xFF, 0x80, 0x20)
    path = user_file(tmp_path, [animation(image=str(png), duration=duration, repeat=repeat,
                                          color=0xFF8020)])
    out = tmp_path / "preview.gif"
    preview = render_preview(path, 21, out)
    expected_frames = round(duration * 50 * repeat)
    assert preview.frames == expected_frames == len(GRAYS) * repeat
    with Image.open(out) as gif:
        assert gif.n_frames == expected_frames
        for index in range(expected_frames):
            gif.seek(index)
            assert gif.info["duration"] == 20
            rgb = gif.convert("RGB")
            gray = GRAYS[index % len(GRAYS)]
            want = tuple(gray * c // 255 for c in colour)
            for led in (0, 17, 45):
                assert rgb.getpixel((led * 11 + 5, 5)) == want       # front bumper
                assert rgb.getpixel((led * 11 + 5, 14 + 5)) == want  # rear bumper
            assert preview.colours[index][1][0] == want


def test_render_preview_rejects_unknown_ids(tmp_path: Path) -> None:
    with pytest.raises(LightsConfigError, match="no animation with ID 42"):
        render_preview(default_led_config(), 42, tmp_path / "x.gif")


def part(duration: float = 1.0) -> AnimationPart:
    return AnimationPart("panther_lights::ChargingAnimation", ("front",),
                         {"duration": duration, "repeat": 1})


def lit(frames: Frames) -> list[tuple[int, int, int, int]]:
    return [f[0] for f in frames.frames if f[0][:3] != (0, 0, 0)]


def test_charging_animation_duty_cycle_and_colour_follow_the_battery() -> None:
    empty, half, full = (charging_frames(part(), 46, 50.0, p) for p in ("0.0", "0.5", "1.0"))
    assert len(half.frames) == 50
    assert len(lit(full)) == 50 and {c[:3] for c in lit(full)} == {(0, 255, 0)}
    assert 20 <= len(lit(half)) <= 25 and (255, 255, 0, 255) in lit(half)
    assert max(c[0] for c in lit(empty)) > 0 and all(c[1] == 0 for c in lit(empty))
    assert len(lit(empty)) < len(lit(half)) < len(lit(full))
    with pytest.raises(LightsConfigError):
        charging_frames(part(), 46, 50.0, "lots")


def test_playback_repeats_then_goes_dark() -> None:
    playback = Playback(Frames((((1, 1, 1, 255),), ((2, 2, 2, 255),)), repeat=2, brightness=1.0))
    seen = []
    for _ in range(5):
        playback.update()
        seen.append(playback.current[0][0] if playback.current else None)
    assert seen == [1, 2, 1, 2, None] and playback.finished


def showing(controller: LightsController) -> str | None:
    return controller.showing()["front"]


def test_queue_priorities_and_background_animation() -> None:
    controller = LightsController(load_led_config())
    controller.set_animation(1, "", True, 0.0)           # READY, repeating: the background
    controller.advance(1.0)
    assert showing(controller) == "READY"
    controller.set_animation(3, "", False, 1.0)          # MANUAL_ACTION, priority 3: queued
    controller.advance(2.0)
    assert showing(controller) == "MANUAL_ACTION"
    controller.set_animation(6, "", False, 2.0)          # LOW_BATTERY, priority 2: interrupts 3
    controller.advance(2.1)
    assert showing(controller) == "LOW_BATTERY"
    controller.advance(6.2)                              # 2 s x 2 later: the interrupted one resumes
    assert showing(controller) == "MANUAL_ACTION"
    controller.advance(9.5)
    assert showing(controller) == "READY"                # back to the background


def test_priority_1_removes_waiting_animations_of_priority_2_and_3() -> None:
    controller = LightsController(load_led_config())
    controller.set_animation(1, "", True, 0.0)
    controller.advance(0.5)
    controller.set_animation(5, "", False, 0.5)
    controller.set_animation(3, "", False, 0.5)
    assert len(controller.queue.items) == 2
    controller.set_animation(2, "", False, 0.5)          # ERROR, priority 1
    assert [i.desc.name for i in controller.queue.items] == ["ERROR"]
    controller.advance(0.6)
    assert showing(controller) == "ERROR"


def test_waiting_animations_time_out_and_the_queue_has_a_limit() -> None:
    controller = LightsController(load_led_config())
    controller.set_animation(5, "", False, 0.0)          # GOAL_ACHIEVED plays 6 s
    controller.advance(0.1)
    controller.set_animation(3, "", False, 0.2)          # waits behind it
    controller.queue.items[0].desc = controller.queue.items[0].desc.__class__(
        3, "SHORT_LIVED", 3, 1.0, controller.queue.items[0].desc.parts)
    controller.advance(6.5)
    assert showing(controller) != "SHORT_LIVED"
    for _ in range(10):
        assert controller.set_animation(3, "", False, 7.0)[0]
    assert controller.set_animation(3, "", False, 7.0) == (False, "Animation queue overloaded")
    assert controller.set_animation(99, "", False, 7.0) == (False, "No animation with ID: 99")


def test_per_segment_animations_within_one_id(tmp_path: Path) -> None:
    config = load_led_config(None, LIGHTS / "user_animations.example.yaml")
    controller = LightsController(config)
    controller.set_animation(24, "", True, 0.0)
    controller.advance(1.0)
    panels = controller.panel_colours()
    front = {c for c in panels[1] if c != (0, 0, 0)}
    rear = {c for c in panels[2] if c != (0, 0, 0)}
    assert front and rear and all(b > r for r, _, b in front) and all(r > b for r, _, b in rear)


def pixels(image: Image.Image) -> list[Any]:
    flat = getattr(image, "get_flattened_data", None)
    return list(flat() if flat is not None else image.getdata())


def test_shipped_images_are_the_drawn_ones() -> None:
    for name, (shape, colour) in default_images().items():
        with Image.open(LIGHTS / "animations" / name) as shipped:
            assert pixels(shipped.convert("RGBA")) == pixels(draw(shape, colour))


REPO = Path(__file__).resolve().parents[2]


def test_the_projects_shipped_lights_files_of_every_stack_validate() -> None:
    """templates/config holds each stack's own lights files (2.2 uses animations/panther/)."""
    files = sorted((REPO / "templates" / "config").glob("*/*lights/config/*.yaml"))
    files = [f for f in files if "driver" not in f.name]
    if not files:
        pytest.skip("templates/config is not in this checkout")
    for path in files:  # a file without a robot: its types' release; 2.3.2's uses images new in 2.3.2
        release = release_for((2, 3, 2)) if "husarion-ugv-2.3.2" in path.parts else None
        assert validate_animations(path, release=release) == [], path

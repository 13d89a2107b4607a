"""`panther-ops lights validate|preview|deploy|test`: LED animations of the bumpers."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Optional

import typer

from panther_ops.cli.context import Fleet
from panther_ops.cli.options import TARGETS, WRITE, Json, OptStr, shared, whole_number

app = typer.Typer(help="LED animations: check, preview as a GIF, deploy, test on a robot.", no_args_is_help=True)

LedConfig = Annotated[
    Optional[Path],  # noqa: UP045
    typer.Option("--led-config", help="Panels and segments the file builds on (default: the stock led_config)."),
]


@app.command("validate")
def validate(
    file: Annotated[Path, typer.Argument(help="A user animations file (user_animations:) or a led_config.")],
    led_config: LedConfig = None,
    stack: Annotated[OptStr, typer.Option(
        "--stack", help="Check with the lights rules of this release (e.g. 2.1.1, 2.2.2); default: the release "
        "whose lights package the file's animation types name.")] = None,
    json_out: Json = False,
) -> int:
    """Check animations with the rules of the robot's release: IDs 0-19 reserved and unique, the
    release's priorities (1-3 on panther_ros, user animations 2-3; 0-3 on husarion_ugv 2.2, user
    animations 1-3), duration x repeat <= 10 s, brightness 0-1 (panther_ros), the release's
    animation types, stock images the release ships ($(find <lights package>)/...) or absolute
    paths, hex colours, segments and segments_map names defined, channels present in panels,
    led_range inside its panel. Every rule has its own message; exit 2 when the file would be refused.

    \b
    Example:
      panther-ops lights validate my_awesome_user_animations.yaml --stack 2.1.1
    """
    from panther_ops.cli.views.findings import report_findings
    from panther_ops.core.stack import stack_option
    from panther_ops.manager import validate_animations
    from panther_ops.manager.lights.releases import release_for

    release = release_for(stack_option(stack).version) if stack is not None else None
    return report_findings(str(file), validate_animations(file, led_config, release), json_out=json_out,
                           what="animations")


@app.command("preview")
def preview(
    file: Annotated[Path, typer.Argument(help="Animations file (user animations or led_config).")],
    anim_id: Annotated[int, typer.Option("--id", parser=whole_number(0, 65535),
                                                help="Animation id to draw (0-65535).")],
    out: Annotated[Path, typer.Option("--out", help="GIF to write.")] = Path("animation.gif"),
    led_config: LedConfig = None,
    param: Annotated[OptStr, typer.Option(
        "--param", help="Animation parameter (battery level 0-1 for ChargingAnimation).")] = None,
    json_out: Json = False,
) -> int:
    """Draw both bumpers of animation --id as an animated GIF, frame by frame at the lights
    controller's 50 Hz (duration x 50 x repeat frames). --json: the GIF written, its animation,
    frames and frame time.

    \b
    Example:
      panther-ops lights preview my_animations.yaml --id 21 --out anim.gif
    """
    from panther_ops.core.parse.numbers import NumberError, decimal
    from panther_ops.errors import UsageError
    from panther_ops.manager import render_preview

    if param is not None:
        try:
            decimal(param, 0, 1)
        except NumberError:
            raise UsageError(f"--param {param!r} is not allowed",
                             hint="a battery level from 0 to 1, e.g. 0.3") from None
    if out.suffix.lower() != ".gif" or out.is_dir() or not out.parent.is_dir():
        raise UsageError(f"--out {out}: not a GIF file path in an existing directory",
                         hint="e.g. --out anim.gif")
    p = render_preview(file, anim_id, out, led_config, param)
    if json_out:
        from panther_ops.cli.render import emit_json

        emit_json({"schema": 1, "command": "lights preview", "file": str(file), "id": anim_id, "out": str(p.path),
                   "animation": p.name, "frames": p.frames, "frame_ms": p.frame_ms})
    else:
        typer.echo(f"{p.path}: {p.name}, {p.frames} frames of {p.frame_ms} ms")
    return 0


@app.command("deploy")
@shared(*WRITE)
def deploy(
    fleet: Fleet,
    file: Annotated[Path, typer.Argument(help="User animations file; the images it references come along.")],
) -> int:
    """Validate, then push a user animations file with its images to the robots and point the
    driver at it (user_led_animations_file, 2.2: user_led_animations_path) through the pipeline.

    \b
    Example:
      panther-ops lights deploy my_animations.yaml -g warehouse --yes
    """
    from panther_ops.core.config.read import read_and_plan_push
    from panther_ops.core.kinds import FileKind
    from panther_ops.core.robot.push import read_bundle

    bundle = read_bundle(FileKind.USER_ANIMATIONS, file)  # the user animations validator, as config push
    return fleet.change(f"lights deploy {file.name}", lambda c: read_and_plan_push(c, FileKind.USER_ANIMATIONS, bundle))


@app.command("test")
@shared(*TARGETS, "json_out")
def test(
    fleet: Fleet,
    anim_id: Annotated[int, typer.Argument(parser=whole_number(0, 65535),
                                                   help="Animation id to show (0-65535, the message's uint16).")],
    param: Annotated[str, typer.Option("--param", help="Animation parameter.")] = "",
    repeating: Annotated[bool, typer.Option("--repeating", help="Keep repeating it.")] = False,
) -> int:
    """Show an animation on the robot now: the lights/set_animation service call, made inside
    the driver container (as the manual's `ros2 service call` example).

    \b
    Example:
      panther-ops lights test 21 --repeating -r panther-01
    """
    from panther_ops.core.manager_ops.lights import set_animation
    from panther_ops.errors import UsageError

    if any(ord(c) < 32 or ord(c) == 127 for c in param):
        raise UsageError(f"--param {param!r} holds a control character", hint="one line of printable text")

    def task(c: Any) -> Any:
        return set_animation(c, anim_id, param, repeating)

    return fleet.run("lights test", task)

"""`manager run --sim` on a terminal (issue 26, findings 2 and 8): what the panel says about
each tree, the service calls (live and at the end), bumper rows that say what they show
without colour, and a Ctrl-C typed into the terminal that leaves one panel, not a broken one.

The process runs on a pseudo-terminal that is its controlling terminal; Ctrl-C is typed
into it (the terminal echoes ``^C`` and signals the process), and what the terminal shows
afterwards is rebuilt by a small screen model (``screen.py``).
"""

from __future__ import annotations

import re

from tests.ux.screen import Screen
from tests.ux.termrun import ctrl_c_typed, on_pty, plain

COLS = 100


def _sim_until(seconds: float, **env: str) -> tuple[list[str], int, float]:
    """``manager run --sim`` (charging, 10 x speed) interrupted once the panel shows ``seconds``
    or more: the screen's lines, the exit code, the seconds from the Ctrl-C to the end."""
    def ready(out: str) -> bool:
        return any(float(t) >= seconds for t in re.findall(r"time\s+(\d+\.\d) s", out))

    got = ctrl_c_typed(["manager", "run", "--sim", "--speed", "10"], ready, cols=COLS, env=env)
    screen = Screen(COLS)
    screen.feed(got.run.out)
    return screen.text(), got.run.code, got.after_s


def test_ctrl_c_leaves_one_panel_then_the_calls_and_exits_130() -> None:
    lines, code, after = _sim_until(3.0)
    assert code == 130 and after < 0.5, (code, after)
    shown = "\n".join(lines)
    assert "Traceback" not in shown
    assert sum(line.startswith("╭") for line in lines) == 1, shown  # one top border: no stale copy
    assert sum(line.startswith("╰") for line in lines) == 1, shown
    after_panel = lines[next(i for i, line in enumerate(lines) if line.startswith("╰")) + 1:]
    assert re.match(r"service calls \(\d+\):", after_panel[0]), after_panel
    assert any("lights/set_animation(id=1" in line for line in after_panel), after_panel
    assert re.search(r"interrupted \(Ctrl-C\) at t=\d+\.\d s", "\n".join(after_panel))


def test_trees_say_idle_and_what_they_last_did_never_a_bare_skipped() -> None:
    lines, _code, _after = _sim_until(2.0)
    rows = {line.split()[1]: line for line in lines if line.startswith("│ ") and len(line.split()) > 2}
    assert "SKIPPED" not in "\n".join(lines)
    for tree in ("lights", "safety"):
        assert re.search(rf"│ {tree}\s+(idle\s+(last: \S.* at \d+\.\d s|nothing to do yet)|running|success|failure)",
                         rows[tree]), rows[tree]
    assert re.search(r"│ calls\s+\d+ so far, the latest:", rows["calls"]), rows["calls"]


def test_without_colour_the_bumper_rows_name_their_colours() -> None:
    lines, _code, _after = _sim_until(2.0, NO_COLOR="1")
    for bumper in ("front", "rear"):
        row = next(line for line in lines if line.startswith(f"│ {bumper} "))
        assert re.search(r"\d+ (off|(dim )?(red|orange|yellow|green|cyan|blue|magenta|white))", row), row


def test_a_run_to_its_end_lists_every_service_call() -> None:
    got = on_pty(["manager", "run", "--sim", "--scenario", "battery_overheat", "--duration", "46", "--speed", "200"],
                 cols=COLS)
    assert got.code == 0, got.out
    text = plain(got.out)
    listed = text[text.index("service calls ("):].splitlines()
    assert int(re.findall(r"service calls \((\d+)\)", listed[0])[0]) == len(listed) - 1
    assert any("hardware/e_stop_trigger()" in line for line in listed), listed  # docs/manager.md's run


def test_colour_names_and_runs() -> None:
    from panther_ops.cli.views.sim import bumper_words, colour_name

    assert colour_name((0, 0, 0)) == "off" and colour_name((0, 255, 0)) == "green"
    assert colour_name((255, 120, 0)) == "orange" and colour_name((60, 0, 0)) == "dim red"
    leds = ((0, 0, 0),) * 18 + ((0, 255, 0),) * 10 + ((0, 0, 0),) * 18
    assert bumper_words(leds) == "18 off, 10 green, 18 off"

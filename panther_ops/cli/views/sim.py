"""Live terminal view of a simulated manager run (rich).

On a terminal: a panel redrawn every tick (narrower than the terminal, so the ``^C`` a
terminal echoes on Ctrl-C never wraps a line under the live view and leaves a stale copy
of it), with each tree's state (``idle`` while none of its branches applies, with the last
branch that acted), the service calls made so far (the latest in the panel, all of them
listed when the run ends or is interrupted), and the bumpers as coloured cells with the
colours named, so the rows say what they show without colour (``NO_COLOR``) too.
Piped: a line per simulated second (and per tick that made a call).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from panther_ops.cli.output import is_terminal, use_color
from panther_ops.cli.render import _console, esc

BUMPER_CELLS = 46
SHOWN_CALLS = 4
"""The latest service calls the panel lists (all of them are listed at the end)."""
PANEL_WIDTH = 100

_NAMED = {"red": (255, 0, 0), "orange": (255, 128, 0), "yellow": (255, 255, 0), "green": (0, 255, 0),
          "cyan": (0, 255, 255), "blue": (0, 0, 255), "magenta": (255, 0, 255), "white": (255, 255, 255)}


def colour_name(rgb: tuple[Any, ...]) -> str:
    """The nearest plain name of an LED colour: ``off``, ``green``, ``dim red``..."""
    r, g, b = (int(x) for x in rgb[:3])
    peak = max(r, g, b)
    if peak < 16:
        return "off"
    scaled = [c * 255 / peak for c in (r, g, b)]
    name = min(_NAMED, key=lambda n: sum((a - c) ** 2 for a, c in zip(scaled, _NAMED[n], strict=True)))
    return name if peak >= 128 else f"dim {name}"


def bumper_words(leds: tuple[Any, ...], most: int = 5) -> str:
    """A bumper's LEDs in words, run by run: ``18 off, 10 green, 18 off``."""
    runs: list[list[Any]] = []
    for rgb in leds:
        name = colour_name(rgb)
        if runs and runs[-1][1] == name:
            runs[-1][0] += 1
        else:
            runs.append([1, name])
    words = ", ".join(f"{n} {name}" for n, name in runs[:most])
    return words + (f", ... ({len(runs) - most} more runs)" if len(runs) > most else "")


def _bumper(leds: tuple[Any, ...], colour: bool, width: int = BUMPER_CELLS) -> str:
    if not leds:
        return "(off)"
    if not colour:
        return esc(bumper_words(leds))
    step = max(1, len(leds) // width)
    cells = []
    for rgb in leds[::step][:width]:
        r, g, b = (int(x) for x in rgb[:3])
        cells.append(f"[on #{r:02x}{g:02x}{b:02x}] [/]")
    lit = sorted({colour_name(rgb) for rgb in leds} - {"off"})
    return "".join(cells) + "  " + esc(", ".join(lit) or "off")


class SimView:
    """The terminal view's memory across ticks: the last branch each tree acted in, every
    service call made."""

    def __init__(self, title: str, colour: bool) -> None:
        self.title = title
        self.colour = colour
        self.acted: dict[str, tuple[str, float]] = {}
        self.calls: list[tuple[float, str]] = []
        self.last: Any = None

    def update(self, s: Any) -> None:
        self.last = s
        self.calls.extend((s.time, c) for c in s.calls)
        for name in ("lights", "safety", "shutdown"):
            tick = getattr(s, name)
            if tick is not None and tick.status not in ("SKIPPED", "WAITING") and tick.branch:
                self.acted[name] = (tick.branch, s.time)

    def tree(self, name: str, tick: Any) -> str:
        """A tree's state in words: ``idle`` while none of its branches applies."""
        if tick.status == "WAITING":
            return "waiting for its inputs"
        if tick.status == "SKIPPED":
            before = self.acted.get(name)
            return "idle    " + (f"last: {esc(before[0])} at {before[1]:.1f} s" if before else "nothing to do yet")
        return f"{tick.status.lower():8}{esc(tick.branch)}"

    def panel(self, width: int) -> Any:
        from rich.panel import Panel
        from rich.table import Table

        s = self.last
        t = Table.grid(padding=(0, 2))
        t.add_column(style="bold", no_wrap=True)
        t.add_column()
        power = "   [red]powered off[/]" if s.powered_off else ""
        t.add_row("time", f"{s.time:7.1f} s   mode {esc(s.mode)}{power}")
        t.add_row("front", _bumper(s.front, self.colour))
        t.add_row("rear", _bumper(s.rear, self.colour))
        t.add_row("animation", esc(", ".join(f"{k}: {v}" for k, v in s.animations.items() if v) or "-"))
        charger = "charger on" if s.charger else "charger off"
        t.add_row("battery", f"{s.battery_percent:5.1%}  {s.battery_status}/{s.battery_health}  {charger}")
        t.add_row("temps", f"battery {s.bat_temp:5.1f} °C   cpu {s.cpu_temp:5.1f} °C   driver {s.driver_temp:5.1f} °C")
        flag = {True: "[green]on[/]", False: "[dim]off[/]"}
        estop = "[red]TRIGGERED[/]" if s.e_stop else "[green]released[/]"
        t.add_row("io", f"fan {flag[s.fan]}   aux {flag[s.aux]}   e-stop {estop}")
        for name in ("lights", "safety", "shutdown"):
            tick = getattr(s, name)
            if tick is not None:
                t.add_row(name, self.tree(name, tick))
        latest = "\n".join(f"{at:6.1f} s  {esc(call)}" for at, call in self.calls[-SHOWN_CALLS:])
        t.add_row("calls", f"{len(self.calls)} so far" + (f", the latest:\n{latest}" if latest else ""))
        if s.shutdown_reason:
            t.add_row("shutdown", f"[red]{esc(s.shutdown_reason)}[/]")
        return Panel(t, title=esc(self.title), width=width)

    def calls_list(self) -> list[str]:
        """Every service call of the run, with its simulated time."""
        return [f"service calls ({len(self.calls)}):"] + [f"  t={at:6.1f}s {call}" for at, call in self.calls]


def _events(last: Any, s: Any) -> list[str]:
    """What changed between two snapshots that a reader of the lines must not miss: the
    mode, the shutdown starting (and why), the robot powering off."""
    events = []
    if last is not None and s.mode != last.mode:
        events.append(f"mode {last.mode} -> {s.mode}")
    if s.shutdown_reason and (last is None or not last.shutdown_reason):
        events.append(f"shutting down: {s.shutdown_reason}")
    if s.powered_off and (last is None or not last.powered_off):
        events.append("powered off")
    return events


def live(snapshots: Iterator[Any], title: str) -> int:
    """Show each snapshot as it comes; on a non-terminal print a line per simulated second."""
    out = _console()
    if not is_terminal():
        last = None
        for s in snapshots:
            for event in _events(last, s):
                out.print(f"t={s.time:6.1f}s {esc(event)}", soft_wrap=True)
            if last is None or int(s.time) != int(last.time) or s.calls:
                anims = ",".join(str(v) for v in s.animations.values() if v)
                out.print(f"t={s.time:6.1f}s mode={esc(s.mode)} bat={s.battery_percent:5.1%} {s.battery_status:12} "
                          f"T={s.bat_temp:4.1f}/{s.cpu_temp:4.1f}/{s.driver_temp:4.1f} fan={int(s.fan)} "
                          f"aux={int(s.aux)} estop={int(s.e_stop)} anim={esc(anims)}"
                          + (f" calls={esc('; '.join(s.calls))}" if s.calls else ""), soft_wrap=True)
            last = s
        return 0
    from rich.live import Live

    view = SimView(title, use_color())
    width = min(PANEL_WIDTH, out.width - 3)  # room for the ^C a terminal echoes: it must not wrap
    code = 0
    try:
        with Live(console=out, refresh_per_second=10) as live_view:
            for s in snapshots:
                view.update(s)
                live_view.update(view.panel(width))
    except KeyboardInterrupt:
        code = 130
    for line in view.calls_list():
        out.print(esc(line), soft_wrap=True)
    if code:
        at = f" at t={view.last.time:.1f} s" if view.last is not None else ""
        out.print(f"interrupted (Ctrl-C){at}", soft_wrap=True)
    return code

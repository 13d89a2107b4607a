"""Live terminal view of a simulated manager run (rich)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from panther_ops.cli.output import is_terminal
from panther_ops.cli.render import _console, esc


def _bumper(leds: tuple[Any, ...], width: int = 46) -> str:
    if not leds:
        return "[dim](off)[/]"
    step = max(1, len(leds) // width)
    cells = []
    for rgb in leds[::step][:width]:
        r, g, b = (int(x) for x in rgb[:3])
        cells.append(f"[on #{r:02x}{g:02x}{b:02x}] [/]")
    return "".join(cells)


def _panel(s: Any, title: str) -> Any:
    from rich.panel import Panel
    from rich.table import Table

    t = Table.grid(padding=(0, 2))
    t.add_column(style="bold")
    t.add_column()
    power = "   [red]powered off[/]" if s.powered_off else ""
    t.add_row("time", f"{s.time:7.1f} s   mode {esc(s.mode)}{power}")
    t.add_row("front", _bumper(s.front))
    t.add_row("rear", _bumper(s.rear))
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
            t.add_row(name, f"{tick.status:9} {esc(tick.branch)}")
    if s.calls:
        t.add_row("calls", esc("; ".join(s.calls)))
    if s.shutdown_reason:
        t.add_row("shutdown", f"[red]{esc(s.shutdown_reason)}[/]")
    return Panel(t, title=esc(title))


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

    try:
        with Live(console=out, refresh_per_second=10) as view:
            for s in snapshots:
                view.update(_panel(s, title))
    except KeyboardInterrupt:
        return 130
    return 0

"""The simulation runner: both trees on a simulated Panther at 10 Hz, one snapshot per tick.

Terminal-independent: a `Snapshot` holds plain values (bumper colours, battery,
temperatures, fan / AUX / E-stop, what each tree did); the CLI renders them. With a
`ManualClock` (the default) time jumps from tick to tick, so a 10-minute scenario runs in a
second; with a `MonotonicClock` it runs in real time.
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import yaml

from panther_ops.manager.clock import Clock, ManualClock
from panther_ops.manager.config import ManagerConfig, config_with_params
from panther_ops.manager.lights.config import load_led_config
from panther_ops.manager.lights.controller import LightsController
from panther_ops.manager.runtime import ManagerRuntime, TickReport, TreeSource, TreeTick
from panther_ops.manager.sim.adapter import CallRecord, SimRobotIO, sim_backends
from panther_ops.manager.sim.scenario import Scenario, ScenarioPlayer, load_scenario

RGB = tuple[int, int, int]
TICK_RATE = 10.0


@dataclass(frozen=True)
class Snapshot:
    """The simulated robot and the manager after one tick."""

    tick: int
    time: float
    mode: str
    battery_percent: float
    battery_status: str
    battery_health: str
    charger: bool
    bat_temp: float
    cpu_temp: float
    driver_temp: float
    fan: bool
    aux: bool
    e_stop: bool
    powered_off: bool
    depleted: bool
    animations: Mapping[str, str | None]
    """Segment name -> animation it shows."""
    front: tuple[RGB, ...]
    rear: tuple[RGB, ...]
    lights: TreeTick | None
    safety: TreeTick | None
    shutdown: TreeTick | None
    calls: tuple[str, ...]
    """Service calls made in this tick."""
    shutdown_reason: str | None
    hosts: Mapping[str, bool]
    """Simulated shutdown hosts: ip -> still up."""


class Simulation:
    """A scenario, the simulated robot and the manager, advanced tick by tick."""

    def __init__(self, scenario: Scenario, *, trees: TreeSource | None = None,
                 config: ManagerConfig | None = None, led_config: str | Path | None = None,
                 clock: Clock | None = None, rate: float = TICK_RATE) -> None:
        self.scenario = scenario
        self.clock = clock or ManualClock()
        self.period = 1.0 / rate
        self._tmp = tempfile.TemporaryDirectory(prefix="panther-sim-")
        params = dict(scenario.params)
        if scenario.hosts:
            hosts_file = Path(self._tmp.name) / "shutdown_hosts.yaml"
            entries = [{k: v for k, v in h.items() if k not in {"reachable", "shutdown_delay"}}
                       for h in scenario.hosts]
            hosts_file.write_text(yaml.safe_dump({"hosts": entries}), encoding="utf-8")
            params["shutdown_hosts_path"] = str(hosts_file)
        self.config = config_with_params(params, config, scenario.source or scenario.name)
        self.model = scenario.build_model()
        self.lights = LightsController(load_led_config(led_config), start=self.clock.now())
        self.io = SimRobotIO(self.model, self.clock, self.lights, ScenarioPlayer(scenario))
        self.runtime = ManagerRuntime(self.config, self.io, self.clock, trees=trees,
                                      backends=sim_backends(self.io))
        self.start = self.clock.now()
        self.ticks = 0

    def step(self) -> Snapshot:
        """Tick the manager once at the current time and describe the result."""
        calls_before = len(self.io.calls)
        report = self.runtime.tick()
        self.io.update()
        snapshot = self._snapshot(report, self.io.calls[calls_before:])
        self.ticks += 1
        return snapshot

    def _snapshot(self, report: TickReport, calls: Sequence[CallRecord]) -> Snapshot:
        model, panels = self.model, self.lights.panel_colours()
        channels = sorted(panels)
        dark: tuple[RGB, ...] = ()
        if model.powered_off:
            panels = {c: [(0, 0, 0)] * len(v) for c, v in panels.items()}
        return Snapshot(
            tick=self.ticks, time=round(report.time - self.start, 6), mode=report.mode.value,
            battery_percent=model.charge, battery_status=model.status().name,
            battery_health=model.health().name, charger=model.charger, bat_temp=model.bat_temp,
            cpu_temp=model.cpu_temp, driver_temp=model.driver_temp, fan=model.fan, aux=model.aux,
            e_stop=model.e_stop, powered_off=model.powered_off, depleted=model.depleted,
            animations=self.lights.showing(),
            front=tuple(panels[channels[0]]) if channels else dark,
            rear=tuple(panels[channels[1]]) if len(channels) > 1 else dark,
            lights=report.lights, safety=report.safety, shutdown=report.shutdown,
            calls=tuple(str(c.request) for c in calls),
            shutdown_reason=report.shutdown_reason,
            hosts={ip: h.up(self.clock.now()) for ip, h in model.hosts.items()},
        )

    def run(self, duration: float | None = None) -> Iterator[Snapshot]:
        """Snapshots at 10 Hz for `duration` seconds (default: the scenario's)."""
        end = self.start + (self.scenario.duration if duration is None else duration)
        while self.clock.now() < end - 1e-9:
            yield self.step()
            due = self.start + self.ticks * self.period  # no drift from adding 0.1 repeatedly
            self.clock.sleep(max(0.0, due - self.clock.now()))

    def close(self) -> None:
        """Drop the trees' blackboards and the temporary hosts file."""
        self.runtime.close()
        self._tmp.cleanup()


def run_simulation(scenario: Scenario | str | Path, *, trees: TreeSource | None = None,
                   config: ManagerConfig | None = None, led_config: str | Path | None = None,
                   clock: Clock | None = None, duration: float | None = None,
                   ) -> Iterator[Snapshot]:
    """Run a scenario with the manager's trees; yield one `Snapshot` per 10 Hz tick.

    Args:
        scenario: a `Scenario` or a scenario YAML path.
        trees: `TreeSource.python()` (default) or `TreeSource.projects(lights, safety)`.
        config: manager parameters (the scenario's ``params`` are applied on top).
        led_config: LED configuration (default: templates/lights/led_config.yaml).
        clock: `ManualClock` (default, runs as fast as possible) or `MonotonicClock`.
        duration: simulated seconds (default: the scenario's ``duration``).
    """
    loaded = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    simulation = Simulation(loaded, trees=trees, config=config, led_config=led_config,
                            clock=clock)
    try:
        yield from simulation.run(duration)
    finally:
        simulation.close()

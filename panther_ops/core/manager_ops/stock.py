"""What the stock lights/safety managers of each release run with, and how the deployed one differs.

The stock nodes read their parameters from the files their launch passes, always in the image
(``<share>/<package>/config/...``; no launch argument points elsewhere), over the node's own
defaults. `manager deploy` carries those values over into ``config/manager.yaml`` — read from
the robot's image (the driver container, so a file mounted over the package's is the one read),
else this table's values of the robot's release — and the inventory's ``desired.manager.params``
go over them. Facts (husarion/husarion_ugv_ros = the history of husarion/panther_ros):

* 2.0.2–2.1.0: ``panther_manager/config/{lights,safety}_manager_config.yaml``; 2.1.1–2.1.x:
  ``panther_manager/config/{lights,safety}_manager.yaml``
  (husarion/husarion_ugv_ros@2.0.4:panther_manager/launch/manager_bt.launch.py,
  @2.1.1:panther_manager/launch/manager.launch.py). Node defaults
  (@2.0.4:panther_manager/src/{lights,safety}_manager_node.cpp ``DeclareParameters``): fan on/off
  CPU 70/60 °C, driver 45/35 °C; the shipped files set CPU 75/70 and driver 50/45, the other
  values as the defaults (windows 6, thresholds 0.4/0.1, animation periods 30/15 s, charging
  step 0.1, fan-off timeout 60 s, 10 Hz).
* 2.2.x: ``husarion_ugv_manager/config/{lights,safety}_manager.yaml``
  (@2.2.2:husarion_ugv_manager/launch/manager.launch.py); node parameters of
  generate_parameter_library (@2.2.2:husarion_ugv_manager/src/{lights,safety}_manager_parameters.yaml):
  the same defaults, the low/critical animation periods named ``battery.anim_period.*`` — the
  shipped file's ``battery.animation_period.low`` is not read by the node —; the shipped files
  set CPU 75/70, driver 50/45 and a charging step of 0.05.
* 2.0.1: one ``manager_bt_node`` with ``panther_manager/config/manager_bt_config.yaml``
  (Panther >= 1.2; @2.0.1:panther_manager/launch/manager_bt.launch.py): CPU 75/70, driver 50/45,
  ``lights.``/``safety.`` prefixed 2.0 names, charging step 0.1.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from panther_ops.manager.versions import by_release

_NODE_DEFAULTS: dict[str, float | int] = {
    "lights.timer_frequency": 10.0, "battery.percent.window_len": 6, "battery.percent.threshold.low": 0.4,
    "battery.percent.threshold.critical": 0.1, "battery.animation_period.low": 30.0,
    "battery.animation_period.critical": 15.0, "battery.charging_anim_step": 0.1, "safety.timer_frequency": 10.0,
    "fan_turn_off_timeout": 60.0, "battery.temp.window_len": 6, "cpu.temp.window_len": 6, "cpu.temp.fan_on": 70.0,
    "cpu.temp.fan_off": 60.0, "driver.temp.window_len": 6, "driver.temp.fan_on": 45.0, "driver.temp.fan_off": 35.0,
}
"""The stock parameters the deployed manager takes over (its trees use them alike), by manager.yaml
key (2.1.1+ names, as docs/manager.md lists them; `manager.config.param_targets` says what each sets),
at the node defaults."""

_SHIPPED_FANS: dict[str, float | int] = {"cpu.temp.fan_on": 75.0, "cpu.temp.fan_off": 70.0,
                                         "driver.temp.fan_on": 50.0, "driver.temp.fan_off": 45.0}


@dataclass(frozen=True)
class StockManager:
    """One release family's stock manager: its parameter files and what it runs with."""

    releases: str
    package: str
    files: tuple[str, ...]
    """Under the package's share directory (``config/...``), lights first."""
    values: Mapping[str, float | int]
    """The values it runs with (its files over its node defaults), by manager.yaml key."""
    source: str
    renamed: Mapping[str, str]
    """Node parameter -> manager.yaml key, where the node's name differs (2.2's anim_period)."""
    ignored: tuple[str, ...] = ()
    """Keys in its files that its nodes do not read."""

    def carried(self, notes: list[str] | tuple[str, ...] = ()) -> CarriedParams:
        """This release's stock values, as what a robot carries over (its own could not be read)."""
        return CarriedParams(dict(self.values), f"the stock values of {self.releases} ({self.source})", tuple(notes))

    def paths(self) -> list[str]:
        """The files as ``$(find <package>)/...`` (resolved in the image)."""
        return [f"$(find {self.package})/{f}" for f in self.files]


_R = "husarion/husarion_ugv_ros"
STOCK_2_0_1 = StockManager(
    "panther_ros 2.0.1", "panther_manager", ("config/manager_bt_config.yaml",),
    {**_NODE_DEFAULTS, **_SHIPPED_FANS},
    f"{_R}@2.0.1:panther_manager/config/manager_bt_config.yaml, src/manager_bt_node.cpp", {})
STOCK_2_0 = StockManager(
    "panther_ros 2.0.2-2.1.0", "panther_manager",
    ("config/lights_manager_config.yaml", "config/safety_manager_config.yaml"),
    {**_NODE_DEFAULTS, **_SHIPPED_FANS},
    f"{_R}@2.0.4:panther_manager/config/{{lights,safety}}_manager_config.yaml, src/*_manager_node.cpp", {})
STOCK_2_1 = StockManager(
    "panther_ros 2.1.1-2.1.x", "panther_manager", ("config/lights_manager.yaml", "config/safety_manager.yaml"),
    {**_NODE_DEFAULTS, **_SHIPPED_FANS},
    f"{_R}@2.1.1:panther_manager/config/{{lights,safety}}_manager.yaml, src/*_manager_node.cpp", {})
STOCK_2_2 = StockManager(
    "husarion_ugv 2.2.x", "husarion_ugv_manager", ("config/lights_manager.yaml", "config/safety_manager.yaml"),
    {**_NODE_DEFAULTS, **_SHIPPED_FANS, "battery.charging_anim_step": 0.05},
    f"{_R}@2.2.2:husarion_ugv_manager/config/{{lights,safety}}_manager.yaml, src/*_manager_parameters.yaml",
    {"battery.anim_period.low": "battery.animation_period.low",
     "battery.anim_period.critical": "battery.animation_period.critical"},
    ("battery.animation_period.low", "battery.animation_period.critical"))


def stock_manager(version: tuple[int, int, int]) -> StockManager:
    """The stock manager of a release (2.0.1 and later; deploy refuses 2.0.0)."""
    return by_release(version, (((2, 2, 0), STOCK_2_2), ((2, 1, 1), STOCK_2_1), ((2, 0, 2), STOCK_2_0)), STOCK_2_0_1)


INTENDED_DIFFERENCES = (
    "SSH shutdowns check host keys (known_hosts mounted from the robot); the stock node (libssh) does not",
    "the trees are the release's stock BT projects (templates/config/<generation>/<pkg>/behavior_trees, equal to "
    "upstream's), not the robot's own: a project the robot was given in place of the stock one (a "
    "lights_bt_project_path / safety_bt_project_path, 2.2's ~/config LightsBT.btproj) is not carried over",
)
"""Where the deployed manager departs from the stock one on purpose, on every release
(docs/manager.md, "Intended differences from the stock manager"); every deploy plan says them."""
_DIFFERENCES_BY_FAMILY = {
    "panther_ros 2.0.1": ("battery temperature: E-stop and AUX off above 55 °C, shutdown above 62 °C (2.0.2+'s "
                          "kCriticalBatteryTemp and kFatalBatteryTemp); 2.0.1's manager_bt_config.yaml has "
                          "high_bat_temp 55 and critical_bat_temp 59",
                          "the trees are 2.0.2-2.0.4's stock projects: panther-ops has no template of 2.0.1's "
                          "(husarion/panther_ros@2.0.1:panther_manager/behavior_trees, another Safety tree layout)"),
    "husarion_ugv 2.2.x": ("no Groot2 monitoring server (the stock nodes' bt_server_port 5555 / 6666)",),
}
OWN_SHUTDOWN = ("the robot powers itself off by ExecuteCommand {SHUTDOWN_LOCALHOST_COMMAND} (panther-ops' "
                "templates/behavior_trees/shutdown.xml, as husarion_ugv 2.2.1+'s stock tree), not the stock "
                "ShutdownSingleHost(localhost, husarion, 'sudo shutdown now'): host keys are checked here and "
                "the robot's own is normally not in its known_hosts; the command is the same user's "
                "'sudo shutdown now' over ssh (or D-Bus PowerOff on a 2.2 robot with the socket mounted)")
"""Releases before husarion_ugv 2.2.1 (core/manager_ops/projects.py)."""


def intended_differences(stock: StockManager, version: tuple[int, int, int]) -> tuple[str, ...]:
    """The intended differences from ``stock``'s manager on a robot of ``version``."""
    from panther_ops.core.manager_ops.projects import OWN_SHUTDOWN_BEFORE

    own = (OWN_SHUTDOWN,) if version < OWN_SHUTDOWN_BEFORE else ()
    return INTENDED_DIFFERENCES + own + _DIFFERENCES_BY_FAMILY.get(stock.releases, ())


@dataclass(frozen=True)
class CarriedParams:
    """The stock values manager.yaml starts from, where they came from, and what went wrong reading."""

    values: dict[str, float | int]
    origin: str
    notes: tuple[str, ...] = ()


def robot_params(stock: StockManager, texts: Mapping[str, str | None] | None, image: str) -> CarriedParams:
    """The robot's own stock values: its files as the image has them (``texts``: path as in
    :meth:`StockManager.paths` -> text, None: not there) over the node defaults; None (``texts``):
    not read, so this release's stock values."""
    from panther_ops.manager.config import param_targets

    if texts is None:
        return stock.carried()
    values = dict(_NODE_DEFAULTS)
    notes: list[str] = []
    read: list[str] = []
    for path in stock.paths():
        text = texts.get(path)
        if text is None:
            notes.append(f"{path} is not in {image}: the stock value of {stock.releases} is used for what it sets")
            continue
        try:
            found = _node_params(text)
        except ValueError as exc:
            notes.append(f"{path} in {image}: {exc}; the stock values of {stock.releases} are used")
            return stock.carried(notes)
        read.append(path)
        for name, value in found.items():
            key = stock.renamed.get(name, name)
            if name not in stock.ignored and key in values:
                values[key] = value
    if not read:
        return stock.carried(notes)
    for path in stock.paths():  # a file the image lacks: that file's stock values
        if path not in read:
            section = "lights" if "light" in path else "safety"
            for key, target in param_targets(dict.fromkeys(_NODE_DEFAULTS)).items():
                if str(target).startswith(f"{section}."):
                    values[key] = stock.values[key]
    return CarriedParams(values, f"the robot's own, read in {image}: {', '.join(read)}", tuple(notes))


def _node_params(text: str) -> dict[str, Any]:
    """Every node's ``ros__parameters`` of a parameter file, flattened to manager.yaml keys
    (``timer_frequency`` per node: ``lights.`` / ``safety.``; 2.0.1's prefixed names mapped)."""
    import yaml

    from panther_ops.manager.config import flatten

    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ValueError(f"not YAML ({str(exc).splitlines()[0]})") from None
    out: dict[str, Any] = {}
    for node, params in _sections(doc):
        for key, value in flatten(params).items():
            if isinstance(value, (bool, list, dict)) or not isinstance(value, (int, float)):
                continue
            name = _V2_0_1.get(key, key)
            if name == "timer_frequency":
                name = f"{'lights' if 'light' in node else 'safety'}.timer_frequency"
            out[name] = value
    return out


def _sections(doc: Any) -> list[tuple[str, Mapping[str, Any]]]:
    found: list[tuple[str, Mapping[str, Any]]] = []
    if isinstance(doc, Mapping):
        for node, body in doc.items():
            if isinstance(body, Mapping) and isinstance(body.get("ros__parameters"), Mapping):
                found.append((str(node), body["ros__parameters"]))
            elif isinstance(body, Mapping):
                found.extend(_sections(body))
    return found


_V2_0_1 = {
    "lights.timer_frequency": "lights.timer_frequency", "safety.timer_frequency": "safety.timer_frequency",
    "battery_percent_window_len": "battery.percent.window_len",
    "lights.low_battery_threshold_percent": "battery.percent.threshold.low",
    "lights.critical_battery_threshold_percent": "battery.percent.threshold.critical",
    "lights.low_battery_anim_period": "battery.animation_period.low",
    "lights.critical_battery_anim_period": "battery.animation_period.critical",
    "lights.update_charging_anim_step": "battery.charging_anim_step",
    "battery_temp_window_len": "battery.temp.window_len", "cpu_temp_window_len": "cpu.temp.window_len",
    "driver_temp_window_len": "driver.temp.window_len",
    "safety.cpu_fan_on_temp": "cpu.temp.fan_on", "safety.cpu_fan_off_temp": "cpu.temp.fan_off",
    "safety.driver_fan_on_temp": "driver.temp.fan_on", "safety.driver_fan_off_temp": "driver.temp.fan_off",
}
"""2.0.1's manager_bt_node names -> manager.yaml keys."""


def overrides(carried: CarriedParams, params: Mapping[str, Any]) -> list[str]:
    """``desired.manager.params`` that change a carried stock value, as plan lines."""
    from panther_ops.manager.config import flatten

    out = []
    for key, value in flatten(params).items():
        if key in carried.values and value != carried.values[key]:
            out.append(f"{key}: {value} (desired.manager.params; the robot's stock manager: {carried.values[key]})")
    return out

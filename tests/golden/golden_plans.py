"""Run a planner golden case (tests/golden/plans/<feature>/*.yaml): pure inputs -> the plan, no robot.

A case names the planner, what the reader read and what the user asked:

    description: set wheel_type on a 2.1.1 robot
    planner: config.set            # a key of PLANNERS below
    compose: templates/compose/panther-2.1.1.yaml   # compose.yaml as read (repository file; optional)
    home: /home/husarion            # optional; compose.yaml is <home>/compose.yaml
    stack: auto                     # the inventory's stack: setting (optional)
    namespace: null                 # the inventory's namespace: (optional)
    files:                          # every other file the planner reads: robot path ->
      /home/husarion/x.yaml: templates/...   # a repository file,
      /home/husarion/y.yaml: {text: "..."}   # literal content,
      /home/husarion/z.yaml: null            # or absent on the robot
    facts: {engine: null}           # facts by kind (``kind`` or ``kind key``), optional; {text: ...}: bytes;
                                    # webui: {state: <the snap's answers>, host: ...} or {warning: ...}
    args: {...}                     # what the user asked (per planner)
    expect: {...}                   # the plan, as :func:`render` shows it

The case's reads must be exactly what the planner asks for: a read it asks for and the
case lacks fails (NotRead), and so does a read the case lists that it never asks for.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from panther_ops.core.apply.plan import plan_desired
from panther_ops.core.config import plan as config_planners
from panther_ops.core.config.plan import plan_push
from panther_ops.core.driver import plan as driver_planners
from panther_ops.core.driver.images import parse_target
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.plan_rollback import plan_rollback
from panther_ops.core.fleet.reads import Need, Reads
from panther_ops.core.gps.plan import GpsOptions, plan_disable, plan_enable
from panther_ops.core.gps.router.plan import RouterRequest, router_plan
from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S
from panther_ops.core.manager_ops.bundle import ManagerBundle
from panther_ops.core.manager_ops.plan import plan_deploy, plan_remove
from panther_ops.core.robot.push import Bundle
from panther_ops.core.robot.robot_config import ComposeRead
from panther_ops.core.shutdown import plan as plan_hosts

ROOT = Path(__file__).resolve().parents[2]
PLANS = ROOT / "tests" / "golden" / "plans"


class TrackedReads(Reads):
    """A :class:`Reads` that remembers which files and facts the planner asked for."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.asked: set[Any] = set()

    def file(self, path: str) -> bytes | None:
        self.asked.add(Need("file", path))
        return super().file(path)

    def fact(self, kind: str, key: str = "") -> Any:
        self.asked.add(Need(kind, key))
        return super().fact(kind, key)


def _content(value: Any) -> bytes | None:
    if value is None:
        return None
    if isinstance(value, dict):
        return str(value["text"]).encode()
    return (ROOT / str(value)).read_bytes()


def _webui(value: dict[str, Any]) -> Any:
    from panther_ops.core.remote.webui.plan import WebuiRead
    from panther_ops.core.remote.webui.state import parse_state

    if "state" not in value:
        return WebuiRead(None, warning=value["warning"])
    return WebuiRead(parse_state(value["state"]), value.get("host", "10.15.20.3"))


def _hosts_add(raw: ComposeRead, reads: Reads, a: dict[str, Any]) -> RobotPlan:
    from panther_ops.core.kinds.hostsfile import add_host, new_entry
    from panther_ops.core.robot.robot_config import parse_config

    rf = plan_hosts.hosts_in_use(parse_config(raw, reads.stack), reads)
    assert rf is not None, "the case's robot uses its image's default hosts file: that plan is config push's"
    edit, warnings = plan_hosts.hosts_edit(rf, lambda text, _mode: add_host(text, new_entry(**a["entry"])))
    plan = plan_hosts.plan_in_place(reads.robot, rf, edit, warnings)
    assert plan is not None
    return plan


def _shutdown_robot(raw: ComposeRead, reads: Reads, a: dict[str, Any]) -> RobotPlan:
    """`shutdown robot`'s plan (hosts to shut down) shown as a RobotPlan: summary = the hosts."""
    from panther_ops.core.robot.robot_config import parse_config

    rf = plan_hosts.hosts_in_use(parse_config(raw, reads.stack), reads)
    assert rf is not None
    sp = plan_hosts.shutdown_plan(reads.robot, rf, a.get("power_budget", POWER_BUDGET_S))
    plan = RobotPlan(sp.robot, "; ".join(f"{h.ip}:{h.port} {h.method.value}" for h in sp.hosts))
    plan.data["source"] = sp.hosts_file.source
    return plan


def _push(raw: ComposeRead, reads: Reads, a: dict[str, Any]) -> RobotPlan:
    data = str(a["text"]).encode() if "text" in a else (ROOT / a["file"]).read_bytes()
    bundle = Bundle(Path(a.get("name") or Path(a["file"]).name), data)
    return plan_push(raw, reads, FileKind(a["kind"]), bundle, force=a.get("force", False))


def _deploy(raw: ComposeRead, reads: Reads, a: dict[str, Any]) -> RobotPlan:
    b = a["bundle"]  # a stand-in archive: the real one changes with every change of the manager's code
    bundle = ManagerBundle(str(b["text"]).encode(), b["version"], b["build"], dependencies=b.get("dependencies", {}))
    return plan_deploy(raw, reads, a.get("desired", {}), sim=a.get("sim"), scenario=a.get("scenario"), bundle=bundle)


def _router(raw: ComposeRead, reads: Reads, a: dict[str, Any]) -> RobotPlan:
    req = RouterRequest(**{k: tuple(v) if k == "sentences" else v for k, v in a["request"].items()})
    return router_plan(reads.robot, a["address"], a["state"], req, a.get("fingerprint"), a.get("pinned_now", False))


PLANNERS: dict[str, Callable[[ComposeRead, Reads, dict[str, Any]], RobotPlan]] = {
    "config.set": lambda raw, reads, a: config_planners.plan_args(
        raw, reads, a.get("sets", {}), a.get("unsets", []), force=a.get("force", False),
        everywhere=a.get("everywhere", False)),
    "config.controller": lambda raw, reads, a: config_planners.plan_controller(
        raw, reads, a["limits"], force=a.get("force", False)),
    "config.push": _push,
    "gps.enable": lambda raw, reads, a: plan_enable(raw, reads, GpsOptions(**a)),
    "gps.disable": lambda raw, reads, a: plan_disable(raw, reads),
    "driver.restart": lambda raw, reads, a: driver_planners.plan_restart(raw, reads),
    "driver.update": lambda raw, reads, a: driver_planners.plan_update(
        raw, reads, parse_target(a["tag"], force=a.get("force", False)) if a.get("tag") else None,
        desired_image=a.get("desired_image"), force=a.get("force", False), pull=a.get("pull", False)),
    "driver.restore": lambda raw, reads, a: driver_planners.plan_restore_defaults(raw, reads, hard=a.get("hard", False)),
    "shutdown.hosts_add": _hosts_add,
    "shutdown.robot": _shutdown_robot,
    "manager.deploy": _deploy,
    "manager.remove": lambda raw, reads, a: plan_remove(raw, reads),
    "config.rollback": lambda raw, reads, a: plan_rollback(reads, a.get("to"), only=a.get("only")),
    "config.rollback_local": lambda raw, reads, a: plan_hosts.plan_local_restore(reads, Path(a["file"]), a.get("to")),
    "gps.router": _router,
    "apply.desired": lambda raw, reads, a: plan_desired(raw, reads, a.get("desired", {}), force=a.get("force", False)),
}


def run_case(case: dict[str, Any]) -> tuple[RobotPlan, TrackedReads]:
    home = case.get("home", "/home/husarion")
    compose = (ROOT / case["compose"]).read_bytes() if case.get("compose") else b""  # not every planner reads it
    raw = ComposeRead(home, f"{home}/compose.yaml", compose, case.get("mode"))
    facts: dict[Need, Any] = {}
    for name, value in (case.get("facts") or {}).items():
        kind, _, key = str(name).partition(" ")
        facts[Need(kind, key)] = _content(value) if isinstance(value, dict) and set(value) == {"text"} else value
        if kind == "webui":
            facts[Need(kind, key)] = _webui(value)
    reads = TrackedReads(case.get("robot", "panther-01"), str(case.get("stack", "auto")), case.get("namespace"),
                         {path: _content(v) for path, v in (case.get("files") or {}).items()}, facts)
    plan = PLANNERS[case["planner"]](raw, reads, case.get("args") or {})
    return plan, reads


def render(plan: RobotPlan) -> dict[str, Any]:
    """What a golden case checks of a plan: everything a user sees of it, diffs included."""
    out: dict[str, Any] = {
        "summary": plan.summary,
        "noop": plan.noop,
        "recreate": list(plan.recreate) if plan.edits else [],
        "verify": [" ".join([v.service, *(f"+{w}" for w in v.cmd_contains), *(f"-{w}" for w in v.cmd_lacks)])
                   for v in plan.verify],
        "warnings": list(plan.warnings),
        "diff": "".join(d.unified if d.unified.endswith("\n") else d.unified + "\n" for d in plan.diffs),
    }
    data = {k: v for k, v in sorted(plan.data.items()) if isinstance(v, (str, int, float, bool, list)) or v is None}
    if data:
        out["data"] = data
    return out

"""`python3 -m panther_ops.manager`: the runtime manager as a long-running process.

This is what the ``panther_ops_manager`` compose service runs on a robot (`panther-ops
manager deploy`, docs/manager-deploy.md), from the archive the deploy uploads::

    python3 /opt/panther-ops/manager/<version>/panther_ops_manager.pyz \\
        --config /opt/panther-ops/manager/config/manager.yaml \\
        --lights-bt .../PantherLightsBT.btproj --safety-bt .../PantherSafetyBT.btproj

Modes:

* ``ros2`` (default): ROS 2 topics and services of the robot (`adapters.ros2.run_on_ros2`),
  real shutdown backends, real clock, until the Shutdown tree is done.
* ``--sim``: the simulation adapter (a simulated Panther driven by a scenario, in real
  time, the scenario started over when it ends) — for a lab or a bench without ROS. No LED
  frames are rendered (on a robot the driver's lights controller does that), so Pillow is
  not needed.

It prints one line when it starts and, in simulation, each service call and a status line
every ``--status-every`` seconds (``docker logs`` shows them). SIGTERM and SIGINT end it
cleanly (exit 0), also as PID 1 of a container.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

_FIND = re.compile(r"^\$\(find ([A-Za-z0-9_]+)\)(.*)$")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python3 -m panther_ops.manager",
                                description="The runtime manager: Lights, Safety and Shutdown trees.")
    p.add_argument("--config", action="append", default=[], metavar="FILE",
                   help="manager parameter file (lights_manager/safety_manager shape); repeatable")
    p.add_argument("--lights-bt", metavar="BTPROJ", help="Lights BehaviorTree project (with --safety-bt)")
    p.add_argument("--safety-bt", metavar="BTPROJ", help="Safety+Shutdown BehaviorTree project")
    p.add_argument("--shutdown-hosts", metavar="FILE",
                   help="shutdown hosts file; $(find pkg)/... is looked up in AMENT_PREFIX_PATH")
    p.add_argument("--namespace", default=None, help="robot namespace (default: $ROBOT_NAMESPACE)")
    p.add_argument("--known-hosts", default=None, metavar="FILE", help="known_hosts for SSH shutdowns")
    p.add_argument("--stack", default=None, metavar="X.Y.Z",
                   help="the robot's stack version: message package, topic and service names "
                        "(default: husarion_ugv_msgs if importable, else panther_msgs 2.1)")
    p.add_argument("--sim", action="store_true", help="run on the simulated Panther instead of ROS 2")
    p.add_argument("--scenario", metavar="FILE", help="simulation scenario (default: the shipped charging one)")
    p.add_argument("--status-every", type=float, default=10.0, metavar="S",
                   help="simulation: a status line every S seconds (0: none)")
    p.add_argument("--cycles", type=int, default=0, help="simulation: stop after N scenario runs (0: never)")
    p.add_argument("--check", action="store_true",
                   help="load the parameters, trees (and scenario), tick once in simulation, say so, exit")
    return p


def resolve_find(path: str, ament_prefix_path: str | None = None) -> str:
    """``$(find pkg)/rest`` -> ``<prefix>/share/pkg/rest`` of the first prefix having the package."""
    m = _FIND.match(path.strip())
    if not m:
        return path
    pkg, rest = m.group(1), m.group(2)
    prefixes = (ament_prefix_path if ament_prefix_path is not None
                else os.environ.get("AMENT_PREFIX_PATH", "")).split(":")
    for prefix in filter(None, prefixes):
        share = Path(prefix) / "share" / pkg
        if share.is_dir():
            return str(share) + rest
    return path


def version_line() -> str:
    """`panther_ops.manager <version> (<where it was loaded from>)`."""
    import panther_ops

    version = getattr(panther_ops, "__version__", "?")
    build = getattr(panther_ops, "__build__", "")
    where = Path(__file__).resolve().parents[2]
    return f"panther_ops.manager {version}{'-' + build if build else ''} ({where}, Python {sys.version.split()[0]})"


def _say(message: str) -> None:
    sys.stdout.write(message + "\n")
    sys.stdout.flush()


def _stop_on_term() -> None:
    """SIGTERM -> KeyboardInterrupt (as PID 1 of a container a signal without handler is ignored)."""

    def handler(_signum: int, _frame: Any) -> None:
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, handler)
    signal.signal(signal.SIGINT, handler)


def _trees(args: argparse.Namespace) -> Any:
    from panther_ops.manager.runtime import TreeSource

    if bool(args.lights_bt) != bool(args.safety_bt):
        raise SystemExit("--lights-bt and --safety-bt go together")
    if args.lights_bt:
        return TreeSource.projects(args.lights_bt, args.safety_bt)
    return TreeSource.python()


def _config(args: argparse.Namespace) -> Any:
    from panther_ops.manager.config import config_with_params, load_manager_config

    config = load_manager_config(args.config)
    hosts = args.shutdown_hosts
    if hosts is None and config.safety.shutdown_hosts_path:
        hosts = config.safety.shutdown_hosts_path
    if hosts:
        resolved = resolve_find(hosts)
        if not Path(resolved).is_file():
            _say(f"warning: shutdown hosts file {hosts} not found: only the robot itself is shut down")
        config = config_with_params({"shutdown_hosts_path": resolved}, config, "--shutdown-hosts")
    for note in config.notes:
        _say(f"note: {note}")
    return config


def hosts_warnings(path: str, known_hosts: str | None = None) -> list[str]:
    """What keeps the hosts of a shutdown hosts file from being shut down from here."""
    from panther_ops.manager.errors import ManagerError
    from panther_ops.manager.shutdown_executor.backends import ssh_method
    from panther_ops.manager.shutdown_executor.hosts import load_shutdown_hosts

    if not path or not Path(path).is_file():
        return []
    try:
        loaded = load_shutdown_hosts(path)
    except ManagerError as exc:
        return [f"shutdown hosts file {path}: {exc}"]
    out = [f"shutdown hosts file {path}: {p}" for p in loaded.problems]
    ssh = [h.ip for h in loaded.hosts if h.secret is None]
    if ssh and ssh_method() is None:
        out.append(f"neither paramiko nor an ssh client in this image: SSH shutdown of {', '.join(ssh)} will fail "
                   "(HTTP hosts of husarion-shutdown need nothing more)")
    if ssh:
        from panther_ops.manager.shutdown_executor.knownhosts import is_known

        kh = Path(known_hosts) if known_hosts else Path.home() / ".ssh" / "known_hosts"
        text = kh.read_text(errors="replace") if kh.is_file() else ""
        unknown = [h.describe() for h in loaded.hosts if h.secret is None and not is_known(text, h.ip, h.port)]
        if unknown:
            out.append(f"no host key in {kh} for {', '.join(unknown)}: their SSH shutdown will fail "
                       "(unknown host keys are refused)")
    return out


def interfaces(args: argparse.Namespace) -> Any:
    """The robot's ROS 2 interfaces: from ``--stack``, else from the message package importable here."""
    from panther_ops.manager.adapters.interfaces import detect_interfaces, interfaces_for, parse_stack
    from panther_ops.manager.errors import ConfigError

    if args.stack is None:
        return detect_interfaces()
    try:
        return interfaces_for(parse_stack(args.stack))
    except ValueError as exc:
        raise ConfigError(str(exc)) from None


def check(args: argparse.Namespace) -> int:
    """Load everything the service would run and tick it once on the simulated robot."""
    from panther_ops.manager.clock import ManualClock
    from panther_ops.manager.runtime import ManagerRuntime
    from panther_ops.manager.sim.adapter import SimRobotIO, sim_backends
    from panther_ops.manager.sim.model import PantherModel
    from panther_ops.manager.sim.scenario import ScenarioPlayer, load_scenario

    config = _config(args)
    trees = _trees(args)
    ros = interfaces(args)
    if not args.sim:
        for warning in hosts_warnings(config.safety.shutdown_hosts_path, args.known_hosts):
            _say(f"warning: {warning}")
    scenario = load_scenario(args.scenario) if args.scenario else None
    clock = ManualClock()
    model = scenario.build_model() if scenario else PantherModel()
    io = SimRobotIO(model, clock, None, ScenarioPlayer(scenario) if scenario else None)
    runtime = ManagerRuntime(config, io, clock, trees=trees, backends=sim_backends(io), interfaces=ros)
    try:
        report = runtime.tick()
    finally:
        runtime.close()
    mode = "simulation" if args.sim else "ROS 2"
    _say(f"{version_line()}: check ok ({mode} mode; {ros.stack} interfaces, {ros.msg_package}; "
         f"hosts file {config.safety.shutdown_hosts_path or 'none'}; "
         f"first tick {report.mode.value}, {len(io.calls)} service calls)")
    return 0


def run_ros2(args: argparse.Namespace) -> int:  # pragma: no cover - needs ROS 2
    from panther_ops.manager.adapters.ros2 import run_on_ros2

    namespace = args.namespace if args.namespace is not None else os.environ.get("ROBOT_NAMESPACE", "")
    ros = interfaces(args)
    _say(f"{version_line()}: ROS 2 mode, namespace {namespace or '/'}, {ros.stack} interfaces ({ros.msg_package})")
    config = _config(args)
    for warning in hosts_warnings(config.safety.shutdown_hosts_path, args.known_hosts):
        _say(f"warning: {warning}")
    run_on_ros2(config, trees=_trees(args), namespace=namespace, known_hosts=args.known_hosts, interfaces=ros)
    _say("manager: the Shutdown tree is done")
    return 0


def _status(t: float, runtime: Any, io: Any) -> str:
    m = io.model
    return (f"t={t:7.1f} {runtime.mode.value}: battery {m.charge * 100:.0f}% {m.status().name} "
            f"{m.health().name}, bat {m.bat_temp:.1f} C, cpu {m.cpu_temp:.1f} C, driver {m.driver_temp:.1f} C, "
            f"fan {'on' if m.fan else 'off'}, aux {'on' if m.aux else 'off'}, "
            f"e-stop {'on' if m.e_stop else 'off'}{', POWERED OFF' if m.powered_off else ''}")


def run_sim(args: argparse.Namespace) -> int:
    """Scenario after scenario on a simulated Panther, in real time, until stopped."""
    import yaml

    from panther_ops.manager.clock import ScaledClock
    from panther_ops.manager.config import config_with_params
    from panther_ops.manager.paths import SCENARIOS
    from panther_ops.manager.runtime import ManagerRuntime
    from panther_ops.manager.sim.adapter import SimRobotIO, sim_backends
    from panther_ops.manager.sim.scenario import ScenarioPlayer, load_scenario

    path = args.scenario or str(SCENARIOS / "charging.yaml")
    scenario = load_scenario(path)
    base = _config(args)
    trees = _trees(args)
    ros = interfaces(args)
    _say(f"{version_line()}: simulation mode, scenario {scenario.name} ({scenario.duration:g} s, "
         f"started over when it ends), trees {'from ' + args.lights_bt if args.lights_bt else 'built in'}")
    cycle = 0
    with tempfile.TemporaryDirectory(prefix="panther-ops-manager-") as tmp:
        params = dict(scenario.params)
        if scenario.hosts:
            hosts_file = Path(tmp) / "shutdown_hosts.yaml"
            entries = [{k: v for k, v in h.items() if k not in {"reachable", "shutdown_delay"}}
                       for h in scenario.hosts]
            hosts_file.write_text(yaml.safe_dump({"hosts": entries}), encoding="utf-8")
            params["shutdown_hosts_path"] = str(hosts_file)
        config = config_with_params(params, base, scenario.source or scenario.name)
        while args.cycles <= 0 or cycle < args.cycles:
            cycle += 1
            clock = ScaledClock(1.0)  # events are relative to the start of the run
            io = SimRobotIO(scenario.build_model(), clock, None, ScenarioPlayer(scenario))
            runtime = ManagerRuntime(config, io, clock, trees=trees, backends=sim_backends(io), interfaces=ros)
            _say(f"run {cycle}: scenario {scenario.name}")
            seen = [0, 0.0]

            def stop(report: Any, io: Any = io, runtime: Any = runtime, seen: list[Any] = seen) -> bool:
                for call in io.calls[seen[0]:]:
                    _say(f"t={call.time:7.1f} call {call.request} -> {'ok' if call.result.success else 'failed'}"
                         f"{': ' + call.result.message if call.result.message else ''}")
                seen[0] = len(io.calls)
                if args.status_every > 0 and report.time >= seen[1]:
                    _say(_status(report.time, runtime, io))
                    seen[1] = (report.time // args.status_every + 1) * args.status_every  # on a 10 s grid
                return False

            try:
                runtime.run(duration=scenario.duration, stop=stop)
            finally:
                runtime.close()
            if runtime.shutdown_reason:
                _say(f"run {cycle}: shut down ({runtime.shutdown_reason}); the simulated robot starts again")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    _stop_on_term()
    try:
        if args.check:
            return check(args)
        return run_sim(args) if args.sim else run_ros2(args)
    except KeyboardInterrupt:
        _say("manager: stopped")
        return 0
    except Exception as exc:  # the container log must say why it ended
        from panther_ops.manager.errors import ManagerError

        if isinstance(exc, ManagerError):
            _say(f"error: {exc}")
            return 2
        raise


if __name__ == "__main__":
    sys.exit(main())

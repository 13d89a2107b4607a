"""`panther-ops manager deploy|remove`: the runtime manager as a compose service on the robot.

deploy, as ONE plan through the pipeline (diff, confirm, backup, atomic writes, recreate,
verify, roll back):

* upload ``~/panther-ops/manager/<version>/panther_ops_manager.pyz`` (`manager_bundle`),
  ``config/manager.yaml`` (the stock manager's parameter values of this robot — read in its
  image in ROS 2 mode, the release's stock values (`stock.py`) otherwise — with the inventory's
  ``desired.manager.params`` over them, the shutdown hosts file and the robot's own shutdown
  command; the intended differences from the stock manager in its head), the release's stock BT
  projects (`projects.py`), in simulation ``config/scenario.yaml``, and
  ``deployed.json`` (what is deployed, and what ``remove`` must restore);
* add the compose service ``panther_ops_manager``: the driver's image, the driver's
  ``x-common-config`` merge, the directory mounted read-only at ``/opt/panther-ops/manager``,
  command ``python3 .../panther_ops_manager.pyz --config ... --lights-bt ... --safety-bt ...``
  (``--sim --scenario ...`` in simulation);
* set ``disable_manager:=True`` on the driver (2.0.1+; 2.2 spells it ``true``) so the
  stock lights/safety managers stand down;
* recreate the services that changed and check both stay up.

remove reverts exactly: the service and ``disable_manager`` as they were before the first
deploy (compose.yaml byte-identical), the uploaded files deleted, empty directories too.

The planners here are pure functions of compose.yaml as read, the files and facts they ask
for (:class:`Reads`) and the inventory's ``desired:``; the reads are `read.py`'s, the
executor `apply.py`'s.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.manager_ops.bundle import ARCHIVE_NAME, ManagerBundle, build_bundle
from panther_ops.core.manager_ops.layout import Layout, _state_bytes, as_manager_plan, brief, parse_state, state_path
from panther_ops.core.manager_ops.projects import deployed_projects
from panther_ops.core.manager_ops.service import ServiceSpec, _check_params, _check_scenario, manager_yaml, service_spec
from panther_ops.core.manager_ops.settings import (
    DISABLE_ARG,
    DISABLE_SINCE,
    ROBOT_DIR,
    SERVICE,
    STATE_FILE,
    ManagerSettings,
    manager_settings,
    scenario_path,
)
from panther_ops.core.manager_ops.stock import (
    CarriedParams,
    StockManager,
    intended_differences,
    overrides,
    robot_params,
    stock_manager,
)
from panther_ops.core.robot.edits import compose_plan, edit_args
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.errors import UsageError

RUNNING = "manager-running"
"""Fact: warnings about the deployed manager's container (none when it runs)."""


# ---------------------------------------------------------------------------------------
# deploy
# ---------------------------------------------------------------------------------------
def _arg_name(cfg: RobotConfig) -> str:
    from panther_ops.core.robot.launch_args import spec

    return spec(DISABLE_ARG).name_for(cfg.stack)


def _refuse_old(cfg: RobotConfig, robot: str) -> None:
    if cfg.stack.version < DISABLE_SINCE:
        raise UsageError(
            f"{robot} runs {cfg.stack.label()}: disable_manager exists from panther_ros 2.0.1, so the stock "
            "manager could not be stood down and two managers would drive the lights and the E-stop",
            hint="update the driver first (panther-ops driver update), then deploy the manager",
        )


def plan_deploy(raw: ComposeRead, reads: Reads, desired: Mapping[str, Any], *, sim: bool | None = None,
                scenario: str | None = None, bundle: ManagerBundle | None = None) -> RobotPlan:
    """One plan: upload, service, disable_manager; nothing is written here."""
    cfg = parse_config(raw, reads.stack)
    _refuse_old(cfg, reads.robot)
    settings = manager_settings(desired, sim=sim, scenario=scenario)
    if not settings.enabled:
        plan = compose_plan(reads.robot, cfg, "no change", [], [], "desired.manager.enabled is false: not deployed "
                            "(panther-ops manager remove takes a deployed one away)")
        plan.recreate = ()
        return plan
    warnings = _check_params(settings.params)
    bundle = bundle or build_bundle()
    lay = Layout(cfg.home, bundle.version)
    state = parse_state(reads.file(state_path(cfg.home)))
    spec = service_spec(reads, cfg, lay, settings)
    ssh_via = None
    stock = stock_manager(cfg.stack.version)
    texts = None
    if settings.mode == "ros2":  # the stock manager stands down: ours must do what it did
        from panther_ops.core.manager_ops.checks import IMAGE_PROBE, check_safety

        command = str(settings.params.get("shutdown_localhost_command", spec.localhost_command))
        w, ssh_via = check_safety(reads, cfg, spec.hosts_file, spec.hosts_source, command)
        warnings += w
        facts = reads.fact(IMAGE_PROBE, spec.hosts_file)
        texts = None if facts is None else {p: facts.param_texts.get(p) for p in stock.paths()}
    carried = robot_params(stock, texts, cfg.compose.driver_image)
    warnings += list(carried.notes)
    intended = intended_differences(stock, cfg.stack.version)
    differences = [*intended, *overrides(carried, settings.params)]
    arg = _arg_name(cfg)
    files, what = _deploy_files(cfg, lay, settings, spec, bundle, state, arg, carried, stock, intended)
    edits = _file_edits(reads, lay, files, state)
    _put_service(cfg, spec)
    driver_before = cfg.compose.service(cfg.service)
    w, driver_verify = edit_args(cfg, {DISABLE_ARG: True}, [], False)
    warnings += w
    driver_changed = cfg.compose.service(cfg.service) != driver_before
    recreate = [SERVICE]
    verify = [Verify(SERVICE, (lay.container_archive,))]
    if driver_changed:
        recreate.insert(0, cfg.service)
        verify.insert(0, driver_verify)
    old_version = state.get("version") if state else None
    head = (f"manager {old_version} -> {bundle.version}" if old_version and old_version != bundle.version
            else f"manager {bundle.version}")
    parts = [f"deploy {head} ({settings.mode}) as service {SERVICE} on {cfg.compose.driver_image}",
             f"stock parameters: {carried.origin.split(' (', 1)[0]}; {len(differences)} differences from the "
             "stock manager (manager.yaml's head)"]
    if driver_changed:
        parts.append(f"{arg}:={cfg.compose.args[arg]} on {cfg.service} (stock manager stands down)")
    noop = (f"manager {bundle.version} ({settings.mode}) already deployed; "
            f"{arg}:={cfg.compose.args.get(arg)} on {cfg.service}")
    briefs = {e.path: brief(e, what.get(e.path, "")) for e in edits if e.path in what or e.after is None}
    plan = as_manager_plan(compose_plan(reads.robot, cfg, "; ".join(parts), warnings, verify, noop, extra=edits),
                           briefs)
    plan.recreate = tuple(recreate) if plan.edits else ()
    plan.warnings = [x for x in plan.warnings if not x.startswith(f"services.{SERVICE}.")]
    if not plan.edits:
        plan.warnings += reads.fact(RUNNING)
    plan.data.update({"action": "deploy", "version": bundle.version, "mode": settings.mode, "service": SERVICE,
                      "image": cfg.compose.driver_image, "shutdown_hosts": spec.hosts_source,
                      "stack": cfg.stack.version_str, "ssh_shutdowns": ssh_via,
                      "parameters": {"origin": carried.origin, "values": carried.values},
                      "differences": differences})
    return plan


def _deploy_files(cfg: RobotConfig, lay: Layout, settings: ManagerSettings, spec: ServiceSpec,
                  bundle: ManagerBundle, state: Mapping[str, Any] | None,
                  arg: str, carried: CarriedParams, stock: StockManager,
                  intended: tuple[str, ...]) -> tuple[dict[str, bytes], dict[str, str]]:
    """Every file of the deployment (robot path -> content) and one-line descriptions of the copies."""
    files: dict[str, bytes] = {lay.archive: bundle.data,
                               lay.config("manager.yaml"): manager_yaml(settings, spec, bundle.version, carried,
                                                                         stock, intended)}
    what = {lay.archive: f"{ARCHIVE_NAME} {bundle.version}: panther_ops.manager + "
                         + ", ".join(f"{k} {v}" for k, v in bundle.dependencies.items())}
    for name, (source, description) in deployed_projects(cfg.stack).files.items():
        files[lay.config("behavior_trees", name)] = source.read_bytes()
        what[lay.config("behavior_trees", name)] = description
    if settings.mode == "sim":
        source = scenario_path(settings.scenario)
        _check_scenario(source)
        files[lay.config("scenario.yaml")] = source.read_bytes()
        what[lay.config("scenario.yaml")] = f"scenario {settings.scenario} ({source.name})"
    doc = {
        "format": 1, "version": bundle.version, "build": bundle.build, "mode": settings.mode,
        "service": SERVICE, "driver_service": cfg.service, "compose_file": cfg.compose_path,
        "image": cfg.compose.driver_image, "archive_sha256": bundle.sha256, "dependencies": bundle.dependencies,
        # what remove restores: kept from the first deploy on
        "disable_manager_before": state.get("disable_manager_before") if state else cfg.compose.args.get(arg),
        "files": sorted(files),
        "scenario": settings.scenario if settings.mode == "sim" else None,
    }
    files[lay.state] = _state_bytes(doc)
    return files, what


def _file_edits(reads: Reads, lay: Layout, files: Mapping[str, bytes],
                state: Mapping[str, Any] | None) -> list[FileEdit]:
    """Files to write (content differs) and files of an earlier deployment to delete."""
    edits: list[FileEdit] = []
    for path, content in files.items():
        before = reads.file(path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    earlier = {str(p) for p in (state or {}).get("files", [])}
    for old_path in sorted(earlier - set(files)):
        if not old_path.startswith(lay.root + "/"):
            continue  # never delete outside our directory, whatever deployed.json says
        old = reads.file(old_path)
        if old is not None:
            edits.append(FileEdit(old_path, old, None))
    return edits


def _put_service(cfg: RobotConfig, spec: ServiceSpec) -> None:
    """The service in compose.yaml as planned (unchanged when it already is)."""
    compose = cfg.compose
    if SERVICE in compose.services():
        try:
            compose.add_service(SERVICE, spec.mapping, merge=spec.merge)  # False: already as planned
            return
        except UsageError:  # there, with other settings: rewrite it
            compose.remove_service(SERVICE)
    compose.add_service(SERVICE, spec.mapping, merge=spec.merge)


# ---------------------------------------------------------------------------------------
# remove
# ---------------------------------------------------------------------------------------
def plan_remove(raw: ComposeRead, reads: Reads) -> RobotPlan:
    """Take the service out, put disable_manager back as it was, delete the uploaded files."""
    cfg = parse_config(raw, reads.stack)
    state = parse_state(reads.file(state_path(cfg.home)))
    compose = cfg.compose
    root = f"{cfg.home}/{ROBOT_DIR}"
    warnings: list[str] = []
    present = SERVICE in compose.services()
    if not present and state is None:
        plan = compose_plan(reads.robot, cfg, "no change", [], [], "the manager is not deployed")
        plan.recreate = ()
        return plan
    arg = _arg_name(cfg)
    if present:
        compose.remove_service(SERVICE)
    driver_before = compose.service(cfg.service)
    verify = Verify(cfg.service)
    if state is not None:
        before = state.get("disable_manager_before")
        if before is None:
            if arg in compose.args:
                verify = Verify(cfg.service, cmd_lacks=(f"{arg}:={compose.args[arg]}",))
                compose.unset_arg(arg)
        elif compose.args.get(arg) != str(before):
            compose.set_arg(arg, str(before))
            verify = Verify(cfg.service, (f"{arg}:={before}",))
    elif arg in compose.args:
        verify = Verify(cfg.service, cmd_lacks=(f"{arg}:={compose.args[arg]}",))
        compose.unset_arg(arg)
        warnings.append(f"no {root}/{STATE_FILE}: {arg} is unset (assumed it was not set before the deploy)")
    driver_changed = compose.service(cfg.service) != driver_before
    edits: list[FileEdit] = []
    paths = [str(p) for p in (state or {}).get("files", []) if str(p).startswith(root + "/")]
    for path in [*sorted(set(paths)), f"{root}/{STATE_FILE}"]:
        old = reads.file(path)
        if old is not None:
            edits.append(FileEdit(path, old, None))
    version = (state or {}).get("version", "?")
    parts = [f"remove manager {version} (service {SERVICE})" if present else f"remove manager {version} files"]
    if driver_changed:
        parts.append(f"{arg} restored on {cfg.service} (stock manager back)")
    plan = as_manager_plan(compose_plan(reads.robot, cfg, "; ".join(parts), warnings,
                                        [verify] if driver_changed else [], "the manager is not deployed", extra=edits),
                           {e.path: brief(e, "") for e in edits if e.path != cfg.compose_path})
    plan.recreate = (cfg.service,) if driver_changed else ()
    plan.data.update({"action": "remove", "version": version, "service": SERVICE, "root": root,
                      "had_service": present})
    return plan

"""The plan of `driver update <2.3 tag>` on a husarion_ugv 2.2 robot, and of the way back.

Pure functions of compose.yaml as read and the files and facts asked for (:class:`Reads`):

- **2.2 -> 2.3** (:func:`plan_migration`): one plan with every file it changes, in exact diffs:
  the image in compose.yaml (launch arguments 2.3 no longer has removed, each named), and each
  file of the config tree the driver reads (``~/config`` at ``/config``, `RobotConfig.tree_read`)
  translated by its translator (`TRANSLATORS`); the joy2twist file moves to husarion_ugv_teleop
  on 2.3.2. Files whose schema did not change are named and left byte-identical. A value with
  no 2.3 form refuses the whole robot (`MigrationRefused`, exit 2) before anything is written.
  The pipeline then backs every file up, writes, recreates, verifies and rolls back on failure
  (`driver.apply.apply_update`).
- **2.3 -> 2.2** (:func:`plan_way_back`): the backup of the migration (the newest applied one)
  restored as `config rollback` restores a backup, with the image the user asked for.
"""

from __future__ import annotations

import functools
import posixpath
from collections.abc import Callable

from panther_ops.core.driver.migrate.components import translate_components
from panther_ops.core.driver.migrate.controller import translate_controller
from panther_ops.core.driver.migrate.joy2twist import joy2twist_path, translate_joy2twist
from panther_ops.core.driver.migrate.launch import migrate_launch
from panther_ops.core.driver.migrate.lights_tree import translate_lights_tree
from panther_ops.core.driver.migrate.localization import translate_localization
from panther_ops.core.driver.migrate.translated import MigrationRefused, Translated, version_label
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Stack
from panther_ops.core.yaml.paths import DocumentError
from panther_ops.errors import UsageError

Translator = Callable[[str, str, tuple[int, int, int]], Translated]

MIGRATION = "migrate"
"""How a migration's backup is recognised: its summary starts with this word."""
_WHEELS = ("WH01", "WH02", "WH04", "WH05")
_EKF = ("enu_localization", "enu_localization_with_gps", "relative_localization", "relative_localization_with_gps")
TRANSLATORS: dict[str, Translator] = {
    **{f"husarion_ugv_controller/config/{w}_controller.yaml": translate_controller for w in _WHEELS},
    **{f"husarion_ugv_localization/config/{e}.yaml": translate_localization for e in _EKF},
    "husarion_ugv_description/config/components.yaml": translate_components,
    "husarion_ugv_manager/behavior_trees/lights.xml": translate_lights_tree,
}
"""The files update_config_directory puts in the tree whose 2.3 form differs, under the tree
(husarion_ugv_ros@2.2.2:docker/utils/update_config_directory.sh), and their translators."""
UNCHANGED = ("husarion_ugv_lights/config/user_animations.yaml", "husarion_ugv_lights/config/{model}_animations.yaml",
             "husarion_ugv_manager/behavior_trees/LightsBT.btproj", "husarion_ugv_manager/config/shutdown_hosts.yaml")
"""Tree files whose schema 2.3 keeps: left byte-identical (``git diff 2.2.2 2.3.2`` is empty for
user_animations and shutdown_hosts; 2.3.2's LightsBT.btproj and animations only add models and
ids that a 2.2 file can go without)."""
_ARG_KINDS: dict[str, Translator] = {"controller_config_path": translate_controller,
                                     "components_config_path": translate_components,
                                     "localization_config_path": translate_localization}
"""Launch arguments naming a file of a kind that changed: a customised file they point to is translated too."""


def _check_target(cfg: RobotConfig, new: Stack) -> None:
    if new.version < (2, 3, 1):
        raise UsageError(
            f"husarion_ugv {new.version_str} runs the gamepad as a compose service of its own "
            "(gamepad_controller) and reads animations from the image: panther-ops migrates to 2.3.1 and 2.3.2",
            hint="give a 2.3.2 tag, e.g. jazzy-2.3.2-20260622")
    if cfg.stack.version < (2, 2, 0):
        raise UsageError(
            f"{cfg.stack.label()} -> {new.label()}: a migration to Jazzy starts from husarion_ugv 2.2",
            hint="update the robot to husarion_ugv 2.2.2 first (a reinstall from panther_ros, see `driver update "
                 "--help`), then migrate")


@functools.lru_cache(maxsize=256)
def translated(translator: Translator, text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """``translator(text, path, target)``, once per fleet: robots with the same file share it (pure).

    Raises:
        MigrationRefused: the translator's refusals, and a file the in-place editor cannot
            change without touching more than the keys (a flow mapping ``{...}`` where a key
            must be added), named with the fix.
    """
    try:
        return translator(text, path, target)
    except MigrationRefused:
        raise
    except DocumentError as exc:
        raise MigrationRefused(
            f"cannot be translated in place ({exc.message})", path=path,
            hint="write the mappings the migration adds keys to as block mappings (one key per line, as "
                 "husarion_ugv_ros writes them), then migrate") from exc


def _edit(edits: list[FileEdit], notes: list[str], path: str, before: bytes | None, out: Translated) -> None:
    after = out.text.encode()
    notes.extend(out.notes)
    if after != before:
        edits.append(FileEdit(path, before, after))


def _translate(reads: Reads, path: str, translator: Translator, target: tuple[int, int, int],
               edits: list[FileEdit], notes: list[str]) -> bool:
    before = reads.file(path)
    if before is None:
        return False
    _edit(edits, notes, path, before, translated(translator, before.decode(), path, target))
    return True


def _joy2twist(reads: Reads, tree: str, model: str, target: tuple[int, int, int], edits: list[FileEdit],
               notes: list[str]) -> None:
    """The gamepad file translated; on 2.3.2 moved into husarion_ugv_teleop (the old one removed).
    A tree without one gets 2.2.2's stock file translated (2.3.2's teleop reads it from the tree)."""
    old = joy2twist_path(tree, model, (2, 2, 2))
    new = joy2twist_path(tree, model, target)
    text = reads.file(old)
    if text is None and new == old:
        return
    if text is None:
        from panther_ops.core.kinds import FileKind
        from panther_ops.core.robot.files import config_file
        from panther_ops.core.stack import stack_from_version

        source = config_file(stack_from_version("2.2.2"), FileKind.JOY2TWIST, robot_model=model).template_text()
        notes.append(f"{new}: created from 2.2.2's stock gamepad file (the tree had none; 2.3.2's teleop reads it)")
    else:
        source = text.decode()
    out = translated(translate_joy2twist, source, new, target)
    if new != old:
        _edit(edits, notes, new, reads.file(new), out)
        if text is not None:
            edits.append(FileEdit(old, text, None))
            notes.append(f"{old} moved to {new} (2.3.2 reads the gamepad file from husarion_ugv_teleop)")
        return
    _edit(edits, notes, old, text, out)


def plan_migration(cfg: RobotConfig, reads: Reads, new_ref: str, new: Stack, warnings: list[str]) -> RobotPlan:
    """2.2 -> 2.3: compose.yaml's image and arguments, and every tree file translated (see the module)."""
    _check_target(cfg, new)
    from panther_ops.core.robot.robot_model import robot_model_of

    target = new.version
    service = cfg.service
    current = cfg.compose.driver_image
    old_args = dict(cfg.compose.args)
    launch = migrate_launch(old_args, target, cfg.compose_path)
    notes = list(launch.notes)
    for name in launch.dropped:
        cfg.compose.unset_arg(name, service)
    cfg.compose.set_image(new_ref, service)
    edits: list[FileEdit] = []
    kept: list[str] = []
    tree = cfg.host_path_of(CONTAINER_CONFIG_DIR)
    if cfg.tree_read and tree:
        model = robot_model_of(reads, cfg)
        for rel, translator in TRANSLATORS.items():
            _translate(reads, posixpath.join(tree, rel), translator, target, edits, notes)
        _joy2twist(reads, tree, model, target, edits, notes)
        for rel in UNCHANGED:
            path = posixpath.join(tree, rel.format(model=model))
            if reads.file(path) is not None:
                kept.append(path)
    else:
        notes.append("the config tree (~/config at /config with common_dir_path) is not read by this driver: only "
                     "compose.yaml changes")
    done = {e.path for e in edits}
    for arg, translator in _ARG_KINDS.items():
        value = cfg.compose.args.get(arg)
        host = cfg.host_path_of(value) if value else None
        if host and host not in done and not _translate(reads, host, translator, target, edits, notes):
            notes.append(f"{arg}:={value} names {host}, which is not on the robot: not translated")
    after = cfg.compose.text().encode()
    edits.insert(0, FileEdit(cfg.compose_path, cfg.before, after, cfg.mode))
    old_label, new_label = version_label(cfg.stack.version), version_label(target)
    written = [e.path for e in edits[1:] if e.after is not None]
    summary = (f"{MIGRATION} husarion_ugv {old_label} -> {new_label}: image {current} -> {new_ref}"
               + (f"; {len(written)} config file(s) translated" if written else ""))
    words = tuple(f"{k}:={v}" for k, v in cfg.compose.args.items())
    lacks = tuple(f"{k}:={old_args[k]}" for k in launch.dropped)
    plan = RobotPlan(reads.robot, summary, edits, (service,), cfg.compose_path, [Verify(service, words, lacks)],
                     None, [*warnings, *notes, *cfg.compose.notes], home=cfg.home)
    plan.data.update(stack=cfg.stack.label(), migration={
        "from": old_label, "to": new_label, "translated": written,
        "removed": [e.path for e in edits if e.after is None], "kept": kept,
        "launch_args_removed": list(launch.dropped)})
    return plan


def plan_way_back(cfg: RobotConfig, reads: Reads, new_ref: str, new: Stack, warnings: list[str]) -> RobotPlan:
    """2.3 -> 2.2: the newest applied migration's backup restored, the image set to ``new_ref``.

    Raises:
        UsageError: no migration backup on the robot (the 2.3 files are not translated back).
    """
    from panther_ops.core.fleet.plan_rollback import HISTORY, plan_rollback

    entries = [e for e in reads.fact(HISTORY) if str(e.get("summary", "")).startswith(MIGRATION + " ")
               and str(e.get("status", "")).startswith("applied")]
    if not entries:
        raise UsageError(
            f"{reads.robot} runs {cfg.stack.label()} and has no backup of a migration from 2.2: panther-ops does not "
            "translate 2.3 files back to 2.2",
            hint="`panther-ops config rollback --to ID` restores a backup you choose; or update with --force and "
                 "then `panther-ops config restore-defaults` for 2.2's stock files")
    entry = entries[-1]
    restore = plan_rollback(reads, str(entry["id"]))
    edits: list[FileEdit] = []
    notes = [f"restores backup {entry['id']} (taken before: {entry.get('command') or entry.get('summary')})"]
    changed = [f["path"] for f in entry.get("files", []) if f.get("sha256_after") is not None
               and f["path"] in {e.path for e in restore.edits} and _changed_since(reads, f)]
    if changed:
        notes.append("changed on 2.3 since the migration, and set back to their 2.2 form: " + ", ".join(changed))
    for e in restore.edits:
        after = e.after
        if e.path == cfg.compose_path and after is not None:
            from panther_ops.core.robot.compose import ComposeFile

            back = ComposeFile.parse(after.decode(), cfg.compose_path)
            saved = back.driver_image
            if saved != new_ref:
                back.set_image(new_ref, back.driver_service())
                notes.append(f"the backup's image {saved} replaced by {new_ref}")
            after = back.text().encode()
        edits.append(FileEdit(e.path, e.before, after, cfg.mode if e.path == cfg.compose_path else e.mode))
    if not any(e.path == cfg.compose_path for e in edits):
        cfg.compose.set_image(new_ref, cfg.service)
        edits.insert(0, FileEdit(cfg.compose_path, cfg.before, cfg.compose.text().encode(), cfg.mode))
    summary = (f"back to husarion_ugv {new.version_str} from backup {entry['id']}: image "
               f"{cfg.compose.driver_image} -> {new_ref}")
    plan = RobotPlan(reads.robot, summary, edits, (cfg.service,), cfg.compose_path, [Verify(cfg.service)], None,
                     [*warnings, *notes], home=cfg.home)
    plan.data.update(stack=cfg.stack.label(), backup_restored=entry["id"])
    return plan


def _changed_since(reads: Reads, f: dict[str, object]) -> bool:
    import hashlib

    now = reads.file(str(f["path"]))
    return (hashlib.sha256(now).hexdigest() if now is not None else None) != f.get("sha256_after")

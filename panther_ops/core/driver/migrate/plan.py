"""The plan of `driver update <2.3 tag>` on a husarion_ugv 2.2 robot, and of the way back.

Pure functions of compose.yaml as read and the files and facts asked for (:class:`Reads`):

- **2.2 -> 2.3, and 2.3.1 -> 2.3.2** (:func:`plan_migration`): one plan with every file it
  changes, in exact diffs: the image in compose.yaml (launch arguments 2.3 no longer has removed, each named), and each
  file of the config tree the driver reads (``~/config`` at ``/config``, `RobotConfig.tree_read`)
  translated by its translator (`TRANSLATORS`); the joy2twist file moves to husarion_ugv_teleop
  on 2.3.2. Files whose schema did not change are named and left byte-identical. A value with
  no 2.3 form refuses the whole robot (`MigrationRefused`, exit 2) before anything is written.
  The pipeline then backs every file up, writes, recreates, verifies and rolls back on failure
  (`driver.apply.apply_update`).
- **2.3 -> 2.2, and 2.3.2 -> 2.3.1** (:func:`plan_way_back`): the backup of the newest applied
  migration taken on that line (2.2.x; 2.3.1) restored as `config rollback` restores a backup,
  with the image the user asked for.
"""

from __future__ import annotations

import functools
import posixpath
import re
from collections.abc import Callable
from dataclasses import dataclass, field

from panther_ops.core.driver.migrate.checked import Checker
from panther_ops.core.driver.migrate.components import translate_components
from panther_ops.core.driver.migrate.controller import translate_controller
from panther_ops.core.driver.migrate.dirs import DIRS_KEY, dirs_of
from panther_ops.core.driver.migrate.joy2twist import joy2twist_path, translate_joy2twist
from panther_ops.core.driver.migrate.launch import migrate_launch
from panther_ops.core.driver.migrate.lights_tree import translate_lights_tree
from panther_ops.core.driver.migrate.localization import translate_localization
from panther_ops.core.driver.migrate.stock import stock_text
from panther_ops.core.driver.migrate.translated import MUX_SINCE, MigrationRefused, Translated, version_label
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind, Target
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
_KINDS: dict[Translator, FileKind] = {translate_controller: FileKind.CONTROLLER,
                                      translate_components: FileKind.COMPONENTS,
                                      translate_lights_tree: FileKind.BT_LIGHTS}
"""The file kind whose validator checks each translator's output (`checked.Checker`); the EKF files have none."""
LIGHTS_PROJECT = "husarion_ugv_manager/behavior_trees/LightsBT.btproj"


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


@dataclass
class _Planned:
    """One robot's edits and notes so far; each translation is checked (`checked.Checker`) before it is planned."""

    reads: Reads
    checker: Checker
    edits: list[FileEdit] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    review: list[str] = field(default_factory=list)

    def edit(self, path: str, before: bytes | None, out: Translated, kind: FileKind | None) -> None:
        after = out.text.encode()
        self.notes.extend(out.notes)
        self.notes.extend(self._checked(kind, path, after))
        if out.review:
            self.review.append(path)
        if after != before:
            self.edits.append(FileEdit(path, before, after))

    def _checked(self, kind: FileKind | None, path: str, after: bytes) -> list[str]:
        """``after`` through its kind's validator: its warnings (a lights tree inside the project next to it,
        or 2.2.2's stock project when the tree has none)."""
        if kind is None:
            return []
        project = None
        if kind is FileKind.BT_LIGHTS:
            btproj = posixpath.join(posixpath.dirname(path), posixpath.basename(LIGHTS_PROJECT))
            data = self.reads.file(btproj)
            project = (posixpath.basename(btproj), data if data is not None else stock_text(LIGHTS_PROJECT).encode())
        return self.checker.check(kind, path, after, project=project)

    def translate(self, path: str, translator: Translator, target: tuple[int, int, int]) -> bool:
        before = self.reads.file(path)
        if before is None:
            return False
        self.edit(path, before, translated(translator, before.decode(), path, target), _KINDS.get(translator))
        return True

    def joy2twist(self, tree: str, model: str, target: tuple[int, int, int]) -> None:
        """The gamepad file translated; on 2.3.2 moved into husarion_ugv_teleop (the old one removed).
        A tree without one gets 2.2.2's stock file translated (2.3.2's teleop reads it from the tree)."""
        old = joy2twist_path(tree, model, (2, 2, 2))
        new = joy2twist_path(tree, model, target)
        text = self.reads.file(old)
        if text is None and new == old:
            return
        if text is None:
            from panther_ops.core.robot.files import config_file
            from panther_ops.core.stack import stack_from_version

            source = config_file(stack_from_version("2.2.2"), FileKind.JOY2TWIST, robot_model=model).template_text()
            self.notes.append(f"{new}: created from 2.2.2's stock gamepad file (the tree had none; 2.3.2's teleop "
                              "reads it)")
        else:
            source = text.decode()
        out = translated(translate_joy2twist, source, new, target)
        if new != old:
            self.edit(new, self.reads.file(new), out, FileKind.JOY2TWIST)
            if text is not None:
                self.edits.append(FileEdit(old, text, None))
                self.notes.append(f"{old} moved to {new} (2.3.2 reads the gamepad file from husarion_ugv_teleop)")
            return
        self.edit(old, text, out, FileKind.JOY2TWIST)


def plan_migration(cfg: RobotConfig, reads: Reads, new_ref: str, new: Stack, warnings: list[str]) -> RobotPlan:
    """2.2 -> 2.3 and 2.3.1 -> 2.3.2 (2.3.1's files are 2.2's translated, which the same translators carry
    on: 2.3.1's stock files become 2.3.2's byte for byte): compose.yaml's image and arguments, and every
    tree file translated (see the module)."""
    _check_target(cfg, new)
    from panther_ops.core.robot.robot_model import robot_model_of

    target = new.version
    service = cfg.service
    current = cfg.compose.driver_image
    old_args = dict(cfg.compose.args)
    launch = migrate_launch(old_args, target, cfg.compose_path)
    from panther_ops.core.robot.namespace import driver_namespace
    from panther_ops.core.robot.robot_model import wheel_type_of

    out = _Planned(reads, Checker(Target(new, wheel_type_of(reads, cfg), driver_namespace(reads, cfg)[0])))
    notes = out.notes
    notes.extend(launch.notes)
    for name in launch.dropped:
        cfg.compose.unset_arg(name, service)
    cfg.compose.set_image(new_ref, service)
    edits = out.edits
    kept: list[str] = []
    tree = cfg.host_path_of(CONTAINER_CONFIG_DIR)
    if cfg.tree_read and tree:
        model = robot_model_of(reads, cfg)
        for rel, translator in TRANSLATORS.items():
            out.translate(posixpath.join(tree, rel), translator, target)
        out.joy2twist(tree, model, target)
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
        if host and host not in done and not out.translate(host, translator, target):
            notes.append(f"{arg}:={value} names {host}, which is not on the robot: not translated")
    after = cfg.compose.text().encode()
    notes.extend(out.checker.check(FileKind.COMPOSE, cfg.compose_path, after))
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
        "review": out.review,
        "launch_args_removed": list(launch.dropped)})
    created = [e.path for e in edits if e.before is None and e.after is not None]
    plan.data[DIRS_KEY] = dirs_of(created, [e.path for e in edits if e.before is not None], tree)
    return plan


def plan_way_back(cfg: RobotConfig, reads: Reads, new_ref: str, new: Stack, warnings: list[str]) -> RobotPlan:
    """2.3 -> 2.2 (or 2.3.2 -> 2.3.1): the newest applied migration's backup taken on that line restored,
    the image set to ``new_ref``.

    Raises:
        UsageError: no migration backup on the robot (the 2.3 files are not translated back).
    """
    from panther_ops.core.fleet.plan_rollback import HISTORY, plan_rollback

    entries = [e for e in reads.fact(HISTORY) if _line(migrated_from(str(e.get("summary", "")))) == _line(new.version)
               and str(e.get("status", "")).startswith("applied")]
    if not entries:
        line = "2.2" if new.version < (2, 3, 0) else new.version_str
        raise UsageError(
            f"{reads.robot} runs {cfg.stack.label()} and has no backup of a migration from {line}: panther-ops does "
            f"not translate {cfg.stack.version_str} files back to {line}",
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
    plan.data[DIRS_KEY] = dirs_of([e.path for e in edits if e.after is None], [e.path for e in edits if e.after],
                                  cfg.host_path_of(CONTAINER_CONFIG_DIR))
    return plan


_FROM = re.compile(rf"^{MIGRATION} husarion_ugv (\d+)\.(\d+)\.(\d+) -> ")


def migrated_from(summary: str) -> tuple[int, int, int] | None:
    """The release a migration's backup was taken on (its summary: ``migrate husarion_ugv 2.2.2 -> 2.3.2: ...``)."""
    m = _FROM.match(summary)
    return (int(m[1]), int(m[2]), int(m[3])) if m else None


def _line(version: tuple[int, int, int] | None) -> int | None:
    """Releases whose files a way back restores alike: 2.2.x (Humble), 2.3 before the mux, 2.3.2 on."""
    if version is None:
        return None
    return 0 if version < (2, 3, 0) else 1 if version < MUX_SINCE else 2


def _changed_since(reads: Reads, f: dict[str, object]) -> bool:
    import hashlib

    now = reads.file(str(f["path"]))
    return (hashlib.sha256(now).hexdigest() if now is not None else None) != f.get("sha256_after")

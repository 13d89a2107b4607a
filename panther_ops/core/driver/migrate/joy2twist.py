"""The gamepad's parameters (``joy2twist_<model>.yaml``), 2.2 -> 2.3.

Sources: husarion_ugv_ros@2.2.2:husarion_ugv_bringup/config/joy2twist_{panther,lynx}.yaml
(``cmd_vel_stamped: false``, no ``cmd_vel_topic``: joy2twist's default ``cmd_vel``);
@2.3.1: the same place, ``cmd_vel_stamped: true``; @2.3.2:husarion_ugv_teleop/config/
joy2twist_{panther,lynx}.yaml: ``cmd_vel_topic: manual/cmd_vel`` (the twist mux's manual
input, priority 100) before ``cmd_vel_stamped: true``; every other key unchanged. The file
moves with 2.3.2 (update_config_directory copies it from husarion_ugv_teleop), see
:func:`joy2twist_path`.
"""

from __future__ import annotations

from panther_ops.core.driver.migrate.textedit import Path, insert_after, insert_before, set_raw
from panther_ops.core.driver.migrate.translated import MUX_SINCE, MigrationRefused, Translated
from panther_ops.core.yaml.document import YamlDocument

MANUAL_TOPIC = "manual/cmd_vel"
DEFAULT_TOPIC = "cmd_vel"
"""joy2twist's own default topic (what a 2.2 file without ``cmd_vel_topic`` publishes on)."""


def joy2twist_path(package_dir: str, model: str, target: tuple[int, int, int]) -> str:
    """``<config tree>/<package>/config/joy2twist_<model>.yaml`` for husarion_ugv ``target``."""
    package = "husarion_ugv_teleop" if target >= MUX_SINCE else "husarion_ugv_bringup"
    return f"{package_dir}/{package}/config/joy2twist_{model}.yaml"


def _params(doc: YamlDocument, path: str) -> Path:
    """``/**: ros__parameters`` (upstream's form) or ``/**: <node>: ros__parameters``."""
    data = doc.to_plain()
    if isinstance(data, dict):
        for top, body in data.items():
            if not isinstance(body, dict):
                continue
            if isinstance(body.get("ros__parameters"), dict):
                return (str(top), "ros__parameters")
            for node, inner in body.items():
                if isinstance(inner, dict) and isinstance(inner.get("ros__parameters"), dict):
                    return (str(top), str(node), "ros__parameters")
    raise MigrationRefused("no <node>.ros__parameters mapping: not a joy2twist parameters file", path=path,
                           hint="the file's top is `/**: ros__parameters:` as in husarion_ugv_ros@2.2.2")


def translate_joy2twist(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """A 2.2 joy2twist file for husarion_ugv ``target``: stamped twists, on 2.3.2 to the mux's manual input."""
    doc = YamlDocument(text, path)
    params = _params(doc, path)
    name = path.rsplit("/", 1)[-1]
    notes: list[str] = []
    stamped = (*params, "cmd_vel_stamped")
    topic = (*params, "cmd_vel_topic")
    if doc.exists(stamped):
        set_raw(doc, stamped, "true")
    elif doc.keys(params):
        first = doc.keys(params)[0]
        if isinstance(doc.get((*params, first)), dict | list):
            doc.set(stamped, True)
        else:
            insert_after(doc, (*params, first), "cmd_vel_stamped", "true")
    else:
        doc.set(stamped, True)
    if target >= MUX_SINCE:
        current = doc.get(topic, None)
        if current is None:
            insert_before(doc, stamped, "cmd_vel_topic", MANUAL_TOPIC)
        elif current == DEFAULT_TOPIC:
            set_raw(doc, topic, MANUAL_TOPIC)
        elif current != MANUAL_TOPIC:
            notes.append(f"{name}: cmd_vel_topic {current} kept as customised; on 2.3.2 the gamepad drives through "
                         f"the twist mux only on {MANUAL_TOPIC} (priority 100); other topics are not mux inputs")
    return Translated(doc.text, tuple(notes))


"""The EKF files (``husarion_ugv_localization/config/*_localization*.yaml``), 2.2 -> 2.3.

Sources: husarion_ugv_ros@2.2.2, @2.3.1 and @2.3.2:husarion_ugv_localization/config/
{enu,relative}_localization{,_with_gps}.yaml: 2.3 adds ``stamped_control: true`` after
``use_control`` (the controller's twists are stamped on Jazzy); 2.3.2 lowers
``control_timeout`` from 0.5 to 0.2 (the twist mux's input timeout). A customised
``control_timeout`` is kept and named.
"""

from __future__ import annotations

from panther_ops.core.driver.migrate.textedit import Path, insert_after, set_raw
from panther_ops.core.driver.migrate.translated import MUX_SINCE, Translated
from panther_ops.core.yaml.document import YamlDocument

STOCK_TIMEOUT = 0.5
"""``control_timeout`` of every 2.2.2 EKF file."""


def _ekf(doc: YamlDocument) -> Path | None:
    data = doc.to_plain()
    if not isinstance(data, dict):
        return None
    for top, body in data.items():
        if isinstance(body, dict) and isinstance(body.get("ekf_filter"), dict):
            return (str(top), "ekf_filter", "ros__parameters")
    return None


def translate_localization(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """A 2.2 EKF file for husarion_ugv ``target``; a file with no ``ekf_filter`` is kept as it is."""
    doc = YamlDocument(text, path)
    params = _ekf(doc)
    if params is None or not doc.exists(params):
        return Translated(text)
    name = path.rsplit("/", 1)[-1]
    notes: list[str] = []
    if not doc.exists((*params, "stamped_control")):
        if doc.exists((*params, "use_control")):
            insert_after(doc, (*params, "use_control"), "stamped_control", "true")
        else:
            doc.set((*params, "stamped_control"), True)
    timeout = doc.get((*params, "control_timeout"), None)
    if target >= MUX_SINCE and timeout == STOCK_TIMEOUT:
        set_raw(doc, (*params, "control_timeout"), "0.2")
    elif target >= MUX_SINCE and timeout is not None:
        notes.append(f"{name}: control_timeout {timeout} kept as customised (2.3.2's default is 0.2, the twist "
                     "mux's input timeout)")
    return Translated(doc.text, tuple(notes))

"""``husarion_ugv_description/config/components.yaml``, 2.2 -> 2.3.

Sources: husarion_ugv_ros@2.2.2 and @2.3.2:husarion_ugv_description/config/components.yaml and
CONFIGURATION.md: a component's namespace is ``device_namespace`` on 2.2 and ``name`` on 2.3
(2.2.2's own example also carried a ``name: camera`` line that 2.2 ignored; 2.3.2's example
has only ``name``). Every other key (``type``, ``parent_link``, ``xyz``, ``rpy``) is kept.
"""

from __future__ import annotations

from panther_ops.core.driver.migrate.textedit import rename_key
from panther_ops.core.driver.migrate.translated import MigrationRefused, Translated
from panther_ops.core.yaml.document import YamlDocument


def translate_components(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """``device_namespace`` -> ``name`` in every component (the 2.2-ignored ``name`` dropped).

    Raises:
        MigrationRefused: a component with a ``name`` and a different ``device_namespace``
            (2.3 has one key for both).
    """
    doc = YamlDocument(text, path)
    components = doc.get("components", None)
    notes: list[str] = []
    if not isinstance(components, list):
        return Translated(text)
    for i, item in enumerate(components):
        if not isinstance(item, dict):
            continue
        label = f"components[{i}] ({item.get('type', '?')})"
        has_ns = "device_namespace" in item
        if "name" in item and has_ns and item["name"] != item["device_namespace"]:
            raise MigrationRefused(
                f"name {item['name']!r} and device_namespace {item['device_namespace']!r} differ: husarion_ugv 2.3 "
                "names a component by `name` alone", path=path, line=doc.line_of(("components", i, "name")),
                key=f"components[{i}].name",
                hint=f"delete `name: {item['name']}` (2.2 ignores it; device_namespace becomes 2.3's name) or set "
                     "device_namespace to the name you want, then migrate")
        if "name" in item:
            doc.delete(("components", i, "name"))
            if not has_ns:
                notes.append(f"components.yaml: {label} name: {item['name']} removed: 2.2 ignored it, and on 2.3 "
                             "it would become the component's namespace")
        if has_ns:
            rename_key(doc, ("components", i, "device_namespace"), "name")
            notes.append(f"components.yaml: {label} device_namespace: {item['device_namespace']} -> "
                         f"name: {item['device_namespace']}")
    return Translated(doc.text, tuple(notes))

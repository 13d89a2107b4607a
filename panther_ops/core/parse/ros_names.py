"""ROS 2 names: topics, services and namespaces, by the rules rcl and rmw enforce.

Sources (ros2/rcl@humble:rcl/src/rcl/validate_topic_name.c, ros2/rmw@humble:
rmw/src/validate_namespace.c and validate_full_topic_name.c, the design article "Topic and
Service name mapping to DDS"): a topic or service name is not empty; holds only ASCII letters,
digits, ``_`` and ``/``, plus balanced ``{substitutions}`` and a leading ``~`` that a ``/``
follows; no token starts with a digit; no ``//`` and no ``__``; it does not end with ``/``.
A namespace (a launch ``namespace:=`` argument or ``ROBOT_NAMESPACE``) holds no ``~`` and no
``{}``; the empty namespace is the global one. A fully qualified name is at most 247
characters once a namespace is added (rmw's limit less the DDS prefix).
"""

from __future__ import annotations

import re

MAX_LENGTH = 247
_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*", re.ASCII)
_SUBST = re.compile(r"\{[A-Za-z_][A-Za-z0-9_]*\}", re.ASCII)


class RosNameError(ValueError):
    """A text that is not a valid ROS name; ``str()`` says what is wrong."""


RULES = ("ASCII letters, digits, '_' and '/'; no token starting with a digit; no '//' or '__'; "
         "not ending with '/'")


def _tokens(text: str, kind: str, *, substitutions: bool) -> None:
    body = text[1:] if text.startswith("/") else text
    for token in body.split("/"):
        if token == "":
            raise RosNameError(f"not a valid ROS {kind}: an empty token ('//' or a trailing '/'); {RULES}")
        if substitutions and _SUBST.fullmatch(token):
            continue
        if not _TOKEN.fullmatch(token):
            bad = next((c for c in token if not (c.isascii() and (c.isalnum() or c == "_"))), None)
            why = (f"'{bad}' is not allowed" if bad is not None
                   else f"the token '{token}' starts with a digit")
            raise RosNameError(f"not a valid ROS {kind}: {why}; {RULES}")
    if "__" in text:
        raise RosNameError(f"not a valid ROS {kind}: '__' is reserved; {RULES}")


def topic_name(text: object, kind: str = "topic name") -> str:
    """A topic or service name (relative, absolute, or private ``~/x``). Raises RosNameError."""
    if not isinstance(text, str) or not text:
        raise RosNameError(f"a ROS {kind}: a non-empty text ({RULES})")
    if len(text) > MAX_LENGTH:
        raise RosNameError(f"not a valid ROS {kind}: longer than {MAX_LENGTH} characters")
    body = text
    if body.startswith("~"):
        if body != "~" and not body.startswith("~/"):
            raise RosNameError(f"not a valid ROS {kind}: '~' must be followed by '/' (e.g. ~/{body[1:]})")
        if body == "~":
            return text
        body = body[2:]
    if body.endswith("/") and body != "/":
        raise RosNameError(f"not a valid ROS {kind}: it ends with '/'; {RULES}")
    if body == "/":
        raise RosNameError(f"not a valid ROS {kind}: '/' alone names nothing")
    _tokens(body, kind, substitutions=True)
    return text


def service_name(text: object) -> str:
    """A service name (the same rules as a topic's). Raises RosNameError."""
    return topic_name(text, "service name")


def namespace(text: object) -> str:
    """A namespace as a launch argument takes it: empty (global), relative (``panther``) or
    absolute (``/fleet/panther``); no ``~`` or ``{}``. Raises RosNameError."""
    if not isinstance(text, str):
        raise RosNameError(f"a ROS namespace: a text ({RULES})")
    if text in ("", "/"):
        return text
    if len(text) > MAX_LENGTH:
        raise RosNameError(f"not a valid ROS namespace: longer than {MAX_LENGTH} characters")
    if text.endswith("/"):
        raise RosNameError(f"not a valid ROS namespace: it ends with '/'; {RULES}")
    _tokens(text, "namespace", substitutions=False)
    return text

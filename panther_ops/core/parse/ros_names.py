"""ROS 2 names: topics, services and namespaces, by the rules rcl and rmw enforce.

Sources (ros2/rcl@humble: rcl/src/rcl/validate_topic_name.c and expand_topic_name.c;
ros2/rmw@humble: rmw/src/validate_namespace.c and validate_full_topic_name.c; the design
article "Topic and Service name mapping to DDS"):

* a topic or service name is not empty and holds only ASCII letters, digits, ``_`` and
  ``/``, plus balanced ``{substitutions}`` (anywhere in a token, not nested, no ``/`` inside,
  not starting with a digit) and a ``~`` that is only ever the first character, alone or
  followed by ``/``;
* no token (the text between two ``/``) starts with a digit, none is empty (no ``//``: rmw
  refuses it once the name is expanded), and the name does not end with ``/``;
* the substitutions rcl expands are ``{node}``, ``{ns}`` and ``{namespace}``; any other is an
  error when the node starts (RCL_RET_UNKNOWN_SUBSTITUTION), so it is refused here;
* a namespace (a launch ``namespace:=`` argument, ``ROBOT_NAMESPACE``) has the rules of a
  fully qualified name: no ``~`` and no ``{}``; empty (or ``/``) is the global one; launch
  makes a relative one absolute by adding a ``/``;
* lengths: a fully qualified name is at most 247 characters (rmw's RMW_TOPIC_MAX_NAME_LENGTH,
  255 less the DDS prefix), a namespace at most 245 (RMW_NAMESPACE_MAX_LENGTH), both counted
  with the leading ``/``. A relative name is counted as given (its node's namespace is not
  known here).

The design article also speaks of "single underscores" in tokens; neither rcl nor rmw refuses
``__`` and a node with such a name runs, so it is accepted here.
"""

from __future__ import annotations

MAX_LENGTH = 247
NAMESPACE_MAX_LENGTH = MAX_LENGTH - 2
SUBSTITUTIONS = ("node", "ns", "namespace")


class RosNameError(ValueError):
    """A text that is not a valid ROS name; ``str()`` says what is wrong."""


RULES = ("ASCII letters, digits, '_' and '/'; no token starting with a digit; no '//'; not ending with '/'")
TOPIC_RULES = RULES + "; topics and services may also use {node}, {ns}, {namespace} and a leading '~/'"


def _is_word_char(c: str) -> bool:
    return c.isascii() and (c.isalnum() or c == "_")


def _characters(body: str, kind: str, rules: str, *, substitutions: bool) -> None:
    """rcl's character pass: allowed characters, balanced and well-formed ``{}``."""
    opened = -1
    for i, c in enumerate(body):
        if _is_word_char(c):
            if opened >= 0 and i == opened + 1 and c.isdigit():
                raise RosNameError(f"not a valid ROS {kind}: a substitution starts with a digit; {rules}")
        elif c == "/":
            if opened >= 0:
                raise RosNameError(f"not a valid ROS {kind}: '/' inside a {{substitution}}; {rules}")
        elif c == "{" and substitutions:
            if opened >= 0:
                raise RosNameError(f"not a valid ROS {kind}: a '{{' inside a {{substitution}}; {rules}")
            opened = i
        elif c == "}" and substitutions:
            if opened < 0:
                raise RosNameError(f"not a valid ROS {kind}: a '}}' without its '{{'; {rules}")
            name = body[opened + 1:i]
            if name not in SUBSTITUTIONS:
                raise RosNameError(f"not a valid ROS {kind}: unknown substitution {{{name}}} (rcl expands "
                                   f"{', '.join('{' + s + '}' for s in SUBSTITUTIONS)})")
            opened = -1
        elif c == "~":
            why = ("'~' is allowed only as the first character, alone or as '~/...'" if substitutions
                   else "'~' is not allowed in a namespace")
            raise RosNameError(f"not a valid ROS {kind}: {why}; {rules}")
        else:
            raise RosNameError(f"not a valid ROS {kind}: {c!r} is not allowed; {rules}")
    if opened >= 0:
        raise RosNameError(f"not a valid ROS {kind}: a '{{' without its '}}'; {rules}")


def _tokens(body: str, kind: str, rules: str) -> None:
    """No empty token (``//``) and no token starting with a digit."""
    for token in (body[1:] if body.startswith("/") else body).split("/"):
        if token == "":
            raise RosNameError(f"not a valid ROS {kind}: an empty token ('//'); {rules}")
        if token[0].isdigit():
            raise RosNameError(f"not a valid ROS {kind}: the token '{token}' starts with a digit; {rules}")


def topic_name(text: object, kind: str = "topic name") -> str:
    """A topic or service name (relative, absolute, or private ``~/x``). Raises RosNameError."""
    if not isinstance(text, str) or not text:
        raise RosNameError(f"a ROS {kind}: a non-empty text ({TOPIC_RULES})")
    if len(text) > MAX_LENGTH:
        raise RosNameError(f"not a valid ROS {kind}: longer than {MAX_LENGTH} characters")
    if text == "~":
        return text
    body = text
    if body.startswith("~"):
        if not body.startswith("~/"):
            raise RosNameError(f"not a valid ROS {kind}: '~' must be followed by '/' (e.g. ~/{body[1:]})")
        body = body[2:]
        if not body:
            raise RosNameError(f"not a valid ROS {kind}: it ends with '/'; {TOPIC_RULES}")
    if body.endswith("/"):
        why = "'/' alone names nothing" if body == "/" else f"it ends with '/'; {TOPIC_RULES}"
        raise RosNameError(f"not a valid ROS {kind}: {why}")
    _characters(body, kind, TOPIC_RULES, substitutions=True)
    _tokens(body, kind, TOPIC_RULES)
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
    if len(text.lstrip("/")) + 1 > NAMESPACE_MAX_LENGTH:
        raise RosNameError(f"not a valid ROS namespace: longer than {NAMESPACE_MAX_LENGTH} characters")
    if text.endswith("/"):
        raise RosNameError(f"not a valid ROS namespace: it ends with '/'; {RULES}")
    _characters(text, "namespace", RULES, substitutions=False)
    _tokens(text, "namespace", RULES)
    return text

"""The robot's ``/home/husarion/compose.yaml``: driver service, launch command, volumes, env.

`ComposeFile` wraps a `YamlDocument`, so every edit rewrites only the lines it must and the
rest of the file stays byte-identical (comments, ``x-common-config: &common-config`` and its
``<<: *common-config`` merges, quoting, blank lines). ``text()`` is the new file.

Inherited values: when a service gets ``environment`` (or ``volumes``, ``restart``...) only
through ``<<: *common-config``, editing it for that service writes an explicit override key
in the service (a copy of the inherited value with the change) and leaves the anchor as it
was -- other services keep what they had. `notes` says so. Pass ``shared=True`` to the
environment methods to edit the anchor itself (every service merging it changes).

The driver's ``command`` may be a one-line string, a folded ``>`` / literal ``|`` block or
a list (flow ``[...]`` or block); `set_arg` / `unset_arg` keep that form: a one-line string
stays one line (quoting kept), a block gets a new line at the indentation of the argument
lines, a list is edited item by item (a new argument is appended at the end). A command
``bash -c "ros2 launch ..."`` (husarion/panther-docker@2.0.4 and @2.1.1:demo/
compose.minimal-setup.yaml's gamepad) is edited inside its script (`launchcmd`).

Size (~790 lines): one class over one document, the compose model every feature edits
(services, image, command and its launch arguments, volumes, environment); each part goes
through the same document and merge-key rules, which is why they are kept in one place.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from panther_ops.core.robot.launchcmd import (
    CommandForm,
    LaunchCommand,
    Token,
    arg_word,
    check_script_word,
    last_arg,
    launch_words,
    parse_launch_argv,
    put_arg,
    remove_args,
    remove_word,
    script_span,
    shell_tokens,
    split_arg,
)
from panther_ops.core.stack import Stack, parse_image
from panther_ops.core.yaml.document import (
    Alias,
    DocumentError,
    PathPart,
    Quoted,
    YamlDocument,
    format_path,
)
from panther_ops.errors import InputError, RemoteStateError, UsageError

DRIVER_SERVICE_NAMES = ("husarion_ugv_ros", "panther_ros")
DRIVER_IMAGE_REPOS = ("husarion/panther", "husarion/husarion-ugv")
_SERVICE_NAME = re.compile(r"^[a-zA-Z0-9][a-zA-Z0-9_.-]*$")
_ENV_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


_MERGE = re.compile(r"<<:\s*\*([^\s,\]]+)")
"""A merge key in a service's text: ``<<: *common-config``."""


class ComposeError(InputError):
    """The compose file lacks what is needed (e.g. no driver service), or an edit is refused."""


@dataclass(frozen=True)
class Volume:
    """One ``volumes:`` entry of a service.

    Attributes:
        source: host path or named volume (None for an anonymous volume).
        target: path inside the container.
        read_only: mounted ``:ro`` / ``read_only: true``.
        options: the short-syntax option string (``ro``, ``ro,z``, ``""``).
        long_syntax: written as a mapping (``type``/``source``/``target``).
        index: position in the service's list.
    """

    source: str | None
    target: str
    read_only: bool
    options: str
    long_syntax: bool
    index: int

    def spec(self) -> str:
        """Short syntax of this volume (``host:container[:ro]``)."""
        head = f"{self.source}:{self.target}" if self.source else self.target
        return f"{head}:{self.options}" if self.options else head


def image_repo(image: str) -> str:
    """``registry/husarion/panther:tag`` -> ``husarion/panther`` (registry and tag dropped)."""
    ref = image.strip().split("@", 1)[0]
    name, sep, tag = ref.rpartition(":")
    if not sep or "/" in tag:
        name = ref
    parts = name.split("/")
    if len(parts) > 2 and ("." in parts[0] or ":" in parts[0] or parts[0] == "localhost"):
        parts = parts[1:]
    return "/".join(parts)


def is_driver_image(image: Any) -> bool:
    return isinstance(image, str) and image_repo(image) in DRIVER_IMAGE_REPOS


def _parse_volume(entry: Any, index: int) -> Volume:
    if isinstance(entry, Mapping):
        return Volume(
            source=None if entry.get("source") is None else str(entry.get("source")),
            target=str(entry.get("target", "")),
            read_only=bool(entry.get("read_only", False)),
            options="",
            long_syntax=True,
            index=index,
        )
    spec = str(entry)
    parts = spec.split(":")
    if len(parts) == 1:
        return Volume(None, parts[0], False, "", False, index)
    source, target = parts[0], parts[1]
    options = ":".join(parts[2:])
    flags = options.split(",") if options else []
    return Volume(source, target, "ro" in flags, options, False, index)


def _env_entry(entry: Any) -> tuple[str, str | None]:
    text = str(entry)
    name, sep, value = text.partition("=")
    return name, (value if sep else None)


def _env_value(value: Any) -> str | None:
    if value is None:
        return None
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


class ComposeFile:
    """A compose file under edit. See the module docstring."""

    def __init__(self, doc: YamlDocument) -> None:
        self.doc = doc
        self._words: dict[tuple[str, str], tuple[str, str]] | None = None
        if not isinstance(doc.to_plain(), dict):
            raise ComposeError("not a compose file: the top level is not a mapping", path=doc.path)

    @classmethod
    def parse(cls, text: str, path: str = "compose.yaml") -> ComposeFile:
        """Parse a compose file.

        Raises:
            DocumentError: invalid YAML (names the line).
            ComposeError: the top level is not a mapping.
        """
        return cls(YamlDocument(text, path))

    @property
    def path(self) -> str:
        return self.doc.path or "compose.yaml"

    def text(self) -> str:
        """The (edited) file text."""
        return self.doc.text

    @property
    def original(self) -> str:
        return self.doc.original

    @property
    def changed(self) -> bool:
        return self.doc.changed

    @property
    def notes(self) -> list[str]:
        """Human notes about the edits made (e.g. an override written instead of the anchor)."""
        return self.doc.notes

    def diff(self) -> str:
        return self.doc.diff(self.path)

    # ----------------------------------------------------------- services

    def services(self) -> list[str]:
        services = self.doc.get("services", None)
        return list(services) if isinstance(services, dict) else []

    def service(self, name: str) -> dict[str, Any]:
        """A service's settings as plain values (``<<`` merges resolved)."""
        value = self.doc.get(("services", name), None)
        if not isinstance(value, dict):
            raise ComposeError(f"no service {name!r}", path=self.path, hint=self._services_hint())
        return value

    def _services_hint(self) -> str:
        names = self.services()
        return "services here: " + (", ".join(names) if names else "none")

    def driver_service(self) -> str:
        """Name of the Panther driver service.

        ``husarion_ugv_ros`` or ``panther_ros`` when present; otherwise the one service whose
        image is ``husarion/panther:*`` or ``husarion/husarion-ugv:*``.

        Raises:
            ComposeError: no such service, or several candidates.
        """
        names = self.services()
        for name in DRIVER_SERVICE_NAMES:
            if name in names:
                return name
        candidates = [n for n in names if is_driver_image(self.service(n).get("image"))]
        if len(candidates) == 1:
            return candidates[0]
        if candidates:
            raise ComposeError(
                "several services run a Panther driver image: " + ", ".join(candidates),
                path=self.path,
                key="services",
                hint="name the service to edit explicitly",
            )
        raise ComposeError(
            "no Panther driver service: expected a service named panther_ros or husarion_ugv_ros, "
            "or one whose image is husarion/panther:<tag> or husarion/husarion-ugv:<tag>",
            path=self.path,
            line=self.doc.line_of("services"),
            key="services",
            hint=self._services_hint(),
        )

    def _svc(self, service: str | None) -> str:
        name = service or self.driver_service()
        if name not in self.services():
            raise ComposeError(f"no service {name!r}", path=self.path, hint=self._services_hint())
        return name

    def add_service(self, name: str, mapping: Mapping[str, Any], *, merge: str | None = None) -> bool:
        """Add a service at the end of ``services:``; the rest of the file stays byte-identical.

        Args:
            name: service name.
            mapping: its settings; use `yamldoc.Block(text, ">")` for a ``>`` command, `Quoted`, `Flow`...
            merge: an anchor to merge (``common-config`` -> ``<<: *common-config``), written
                after ``image`` / ``container_name`` like the driver service does.

        Returns:
            False when an identical service already exists.

        Raises:
            UsageError: bad name, unknown anchor, or a different service of that name exists.
        """
        if not _SERVICE_NAME.match(name):
            raise UsageError(f"invalid compose service name {name!r}", hint="letters, digits, _ . -")
        body: dict[str, Any] = {}
        if merge is not None:
            if merge not in self.doc.anchors():
                known = ", ".join(self.doc.anchors()) or "none"
                raise UsageError(f"no anchor &{merge} in {self.path}", hint=f"anchors here: {known}")
            head = [k for k in ("image", "container_name") if k in mapping]
            body.update({k: mapping[k] for k in head})
            body["<<"] = Alias(merge)
            body.update({k: v for k, v in mapping.items() if k not in head})
        else:
            body.update(mapping)
        if name in self.services():
            probe = YamlDocument(self.doc.text, self.path)
            probe.delete(("services", name))
            probe.set(("services", name), body)
            if probe.get(("services", name)) == self.service(name):
                return False
            raise UsageError(
                f"service {name!r} already exists in {self.path} with other settings",
                hint="remove it first (remove_service) or edit its keys",
            )
        return self.doc.set(("services", name), body)

    def remove_service(self, name: str) -> bool:
        """Remove a service (its lines, and one blank separator line); False if absent."""
        if name not in self.services():
            return False
        return self.doc.delete(("services", name))

    # -------------------------------------------------------------- image

    def image(self, service: str | None = None) -> str:
        name = self._svc(service)
        image = self.service(name).get("image")
        if not isinstance(image, str) or not image:
            raise ComposeError(
                f"service {name} has no image", path=self.path, line=self.doc.line_of(("services", name))
            )
        return image

    @property
    def driver_image(self) -> str:
        return self.image(self.driver_service())

    def stack(self) -> Stack:
        """The stack the driver image runs (`stack.parse_image`).

        Raises:
            ComposeError: no driver service.
            RemoteStateError: the image tag is not a supported Panther stack.
        """
        return parse_image(self.driver_image)

    def set_image(self, image: str, service: str | None = None, *, force: bool = False) -> bool:
        """Set a service's image (the driver's by default).

        For the driver the new image must be a supported Panther stack unless ``force``.

        Raises:
            UsageError: unsupported driver image (message from `stack.parse_image`).
        """
        name = self._svc(service)
        if name == self.driver_service() and not force:
            try:
                parse_image(image)
            except RemoteStateError as exc:
                raise UsageError(exc.message, hint=exc.hint) from exc
        return self.doc.set(("services", name, "image"), image)

    def set_image_tag(self, tag: str, service: str | None = None, *, force: bool = False) -> bool:
        """Keep the image repository, change the tag (``humble-2.1.2-20241125``)."""
        current = self.image(service)
        ref = current.split("@", 1)[0]
        name, sep, old_tag = ref.rpartition(":")
        repo = name if sep and "/" not in old_tag else ref
        return self.set_image(f"{repo}:{tag}", service, force=force)

    # ------------------------------------------------------------ command

    def _command_path(self, name: str) -> tuple[PathPart, ...]:
        return ("services", name, "command")

    def command(self, service: str | None = None) -> LaunchCommand:
        """The service's ``ros2 launch`` command, parsed.

        Raises:
            ComposeError: no command (the image default is not known here).
            InputError: not a ``ros2 launch`` command.
        """
        name = self._svc(service)
        path = self._command_path(name)
        value = self.doc.get(path, None)
        if value is None:
            raise ComposeError(
                f"service {name} has no command: (the image's default command cannot be edited)",
                path=self.path,
                line=self.doc.line_of(("services", name)),
                key=f"services.{name}",
                hint="write the launch command in compose.yaml first",
            )
        info = self.doc.info(path)
        if isinstance(value, list):
            form, argv = CommandForm.LIST, [str(v) for v in value]
        elif isinstance(value, str):
            multiline_plain = info.style is None and "\n" in info.raw
            form = CommandForm.BLOCK if info.style in ("|", ">") or multiline_plain else CommandForm.STRING
            argv = [t.value for t in shell_tokens(value)]
        else:
            raise ComposeError(
                f"services.{name}.command is not a string or a list", path=self.path, line=info.line
            )
        shell, words = launch_words(argv, path=self.path, line=info.line)
        package, launch_file, args, options = parse_launch_argv(words, path=self.path, line=info.line)
        return LaunchCommand(form, info.style, tuple(argv), package, launch_file, args, options, info.line,
                             shell, tuple(words))

    @property
    def args(self) -> dict[str, str]:
        """The driver's launch arguments (``name -> value``, command order)."""
        return dict(self.command().args)

    def set_arg(self, name: str, value: str, service: str | None = None, *, raw: bool = False) -> bool:
        """Set ``name:=value`` in the service's launch command (the driver's by default).

        An existing argument is rewritten in place (keeping its quoting); a new one is
        appended at the end. Returns False when the argument already has that value.

        In a string/block command the value is shell-quoted when needed, so launch gets it
        literally (``name:='$(find pkg)/x.yaml'``). ``raw=True`` writes ``name:=<value>``
        as given (e.g. a shell substitution the image's entrypoint should expand); it must
        still be one word.
        """
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise UsageError(f"invalid launch argument name {name!r}")
        cmd = self.command(service)
        svc = self._svc(service)
        if cmd.args.get(name) == value:
            return False
        path = self._command_path(svc)
        if cmd.shell:
            return self._edit_script(svc, cmd, name, value, self._word_for(svc, name, value, raw))
        if cmd.form is CommandForm.LIST:
            return self._set_list_arg(path, name, value)
        word = self._word_for(svc, name, value, raw)
        if cmd.form is CommandForm.STRING:
            return self._set_string_arg(path, name, value, word)
        return self._edit_block(path, name, value, word)

    def _word_for(self, service: str, name: str, value: str, raw: bool) -> str | None:
        """The word to write: verbatim for ``raw`` or for the value the file had when loaded."""
        if raw:
            word = f"{name}:={value}"
            tokens = shell_tokens(word)
            if len(tokens) != 1:
                raise UsageError(f"{word!r} is not one word; drop raw=True to have it quoted")
            return word
        original = self._original_words().get((service, name))
        if original is not None and original[0] == value:
            return original[1]
        return None

    def _original_words(self) -> dict[tuple[str, str], tuple[str, str]]:
        """``(service, arg) -> (value, word text)`` of the string/block commands (and of the
        ``bash -c`` scripts) as loaded."""
        if self._words is None:
            self._words = {}
            probe = ComposeFile.parse(self.original, self.path)
            for svc in probe.services():
                try:
                    text = probe._words_text(svc)
                    tokens = [] if text is None else shell_tokens(text)
                except InputError:
                    continue
                for tok in tokens:
                    parsed = split_arg(tok.value)
                    if parsed is not None and text is not None:
                        self._words[(svc, parsed[0])] = (parsed[1], text[tok.start : tok.end])
        return self._words

    def _words_text(self, svc: str) -> str | None:
        """The text the launch words of ``svc`` are written in: the command string (its raw
        text when plain), or the script of ``bash -c``; None for a plain list or no command.

        Raises:
            InputError: a script that cannot be split, or cannot be edited in place.
        """
        path = self._command_path(svc)
        value = self.doc.get(path, None)
        if isinstance(value, list):
            return str(value[2]) if launch_words([str(v) for v in value])[0] else None
        if not isinstance(value, str):
            return None
        info = self.doc.info(path)
        text = info.raw if info.style is None else value
        if not launch_words([t.value for t in shell_tokens(text)])[0]:
            return text
        start, end, _ = script_span(text)
        return text[start:end]

    def unset_arg(self, name: str, service: str | None = None) -> bool:
        """Remove every ``name:=...`` from the launch command; False when absent."""
        cmd = self.command(service)
        if name not in cmd.args:
            return False
        path = self._command_path(self._svc(service))
        if cmd.shell:
            return self._edit_script(self._svc(service), cmd, name, None)
        if cmd.form is CommandForm.LIST:
            items = self.doc.get(path)
            for i in range(len(items) - 1, -1, -1):
                parsed = split_arg(str(items[i]))
                if parsed is not None and parsed[0] == name:
                    self.doc.delete((*path, i))
            return True
        if cmd.form is CommandForm.STRING:
            value = self.doc.get(path)
            for tok in reversed(shell_tokens(value)):
                parsed = split_arg(tok.value)
                if parsed is not None and parsed[0] == name:
                    value = remove_word(value, tok)
            return self.doc.set(path, value)
        return self._edit_block(path, name, None)

    def _set_list_arg(self, path: tuple[PathPart, ...], name: str, value: str) -> bool:
        items = self.doc.get(path)
        word = f"{name}:={value}"
        for i in range(len(items) - 1, -1, -1):
            parsed = split_arg(str(items[i]))
            if parsed is not None and parsed[0] == name:
                return self.doc.set((*path, i), word)
        last = self.doc.info((*path, len(items) - 1))
        new: Any = Quoted(word, last.style) if last.kind == "scalar" and last.style in ("'", '"') else word
        return self.doc.append(path, new)

    def _set_string_arg(self, path: tuple[PathPart, ...], name: str, value: str, word: str | None) -> bool:
        text = self.doc.get(path)
        tokens = shell_tokens(text)
        target = last_arg(tokens, name)
        if target is not None:
            new = text[: target.start] + (word or arg_word(name, value, target)) + text[target.end :]
        else:
            end = tokens[-1].end if tokens else len(text)
            new = text[:end] + " " + (word or arg_word(name, value)) + text[end:]
        return self._set_command_text(path, new)

    def _set_command_text(self, path: tuple[PathPart, ...], new: str) -> bool:
        """Set a one-line command string; a note when its YAML quoting has to change."""
        before_style = self.doc.info(path).style
        changed = self.doc.set(path, new)
        after_style = self.doc.info(path).style
        if before_style != after_style:
            self.notes.append(
                f"{format_path(path)}: the new argument cannot be written in a plain scalar; "
                f"the command is now quoted ({after_style})"
            )
        return changed

    def _edit_script(self, svc: str, cmd: LaunchCommand, name: str, value: str | None,
                     word: str | None = None) -> bool:
        """Set (or with ``value`` None remove) ``name:=`` inside the script of a ``bash -c``
        command, keeping the rest of the command as written.

        A new word is quoted for the script's shell (`arg_word`) and refused when the script's
        own quotes would not keep it as written (`check_script_word`); the word the file had
        for this value when loaded is written back as it was.

        Raises:
            InputError: a value the script's quotes cannot hold, or a script not written as
                one quoted string (`script_span`).
        """
        path = self._command_path(svc)
        original = self._original_words().get((svc, name))

        def edit(script: str, quote: str | None) -> str:
            if value is None:
                return remove_args(script, name)

            def make(like: Token | None) -> str:
                new = word or arg_word(name, value, like)
                if original != (value, new):
                    check_script_word(new, quote, name=name, value=value, path=self.path, line=cmd.line)
                return new

            return put_arg(script, name, make)

        expected = dict(cmd.args)
        if value is None:
            expected.pop(name, None)
        else:
            expected[name] = value
        if cmd.form is CommandForm.LIST:
            item = (*path, len(cmd.argv) - 1)
            return self.doc.set(item, edit(str(self.doc.get(item)), None))
        if cmd.form is CommandForm.STRING:
            text = self.doc.get(path)
            start, end, quote = script_span(text, path=self.path, line=cmd.line)
            return self._set_command_text(path, text[:start] + edit(text[start:end], quote) + text[end:])
        info = self.doc.info(path)
        body_start = self._block_body(path)
        region = self.doc.text[body_start : info.end]
        start, end, quote = script_span(region, path=self.path, line=cmd.line)
        return self._replace_block(path, region[:start] + edit(region[start:end], quote) + region[end:], expected)

    def _block_body(self, path: tuple[PathPart, ...]) -> int:
        """Where the text of a ``>`` / ``|`` block (or multi-line plain) command starts."""
        info = self.doc.info(path)
        return self.doc.text.find("\n", info.start) + 1 if info.style in ("|", ">") else info.start

    def _edit_block(
        self, path: tuple[PathPart, ...], name: str, value: str | None, word: str | None = None
    ) -> bool:
        """Edit a ``>`` / ``|`` block (or multi-line plain) command in its raw text.

        ``value`` None removes the argument (its line when it is alone on it).
        """
        info = self.doc.info(path)
        text = self.doc.text
        body_start = self._block_body(path)
        region = text[body_start : info.end]
        tokens = shell_tokens(region)
        before = self.command(str(path[1]))
        expected = dict(before.args)
        if value is None:
            expected.pop(name, None)
            new_region = region
            for tok in reversed(tokens):
                parsed = split_arg(tok.value)
                if parsed is not None and parsed[0] == name:
                    new_region = remove_word(new_region, tok)
        else:
            target = last_arg(tokens, name)
            if target is not None:
                expected[name] = value
                new_region = region[: target.start] + (word or arg_word(name, value, target)) + region[target.end :]
            else:
                expected[name] = value
                last = tokens[-1]
                line_start = text.rfind("\n", 0, body_start + last.start) + 1
                line = text[line_start : body_start + last.start]
                indent = line[: len(line) - len(line.lstrip(" "))]
                new_region = region[: last.end] + "\n" + indent + (word or arg_word(name, value)) + region[last.end :]
        return self._replace_block(path, new_region, expected)

    def _replace_block(self, path: tuple[PathPart, ...], new_region: str, expected: dict[str, str]) -> bool:
        """Write a block command's new text, checked: its launch args must be ``expected``."""
        info = self.doc.info(path)

        def check(new_value: Any) -> bool:
            if not isinstance(new_value, str):
                return False
            words = launch_words([t.value for t in shell_tokens(new_value)])[1]
            args = parse_launch_argv(words)[2]
            return list(args.items()) == list(expected.items())

        try:
            return self.doc.replace_span(self._block_body(path), info.end, new_region, path=path, check=check)
        except DocumentError as exc:
            raise ComposeError(
                f"cannot edit the launch command in place: {exc.message}", path=self.path, line=info.line
            ) from exc

    # ------------------------------------------------------------ volumes

    def _volumes_path(self, name: str) -> tuple[PathPart, ...]:
        return ("services", name, "volumes")

    def list_volumes(self, service: str | None = None) -> list[Volume]:
        """The service's volumes (inherited ones included)."""
        entries = self.service(self._svc(service)).get("volumes") or []
        return [_parse_volume(e, i) for i, e in enumerate(entries)]

    def add_volume(
        self, host: str, container: str, ro: bool = False, service: str | None = None
    ) -> bool:
        """Mount ``host`` at ``container`` (idempotent).

        An entry for the same container path is updated in place (host path / ``:ro``);
        otherwise a new entry is appended in the style of the existing ones (short
        ``host:container[:ro]`` or long syntax; same quoting).

        Raises:
            UsageError: the container path is not absolute.
        """
        if not container.startswith("/"):
            raise UsageError(f"container path {container!r} must be absolute")
        if not host:
            raise UsageError("empty host path")
        name = self._svc(service)
        path = self._volumes_path(name)
        volumes = self.list_volumes(name)
        for vol in volumes:
            if vol.target.rstrip("/") == container.rstrip("/"):
                if vol.source == host and vol.read_only == ro:
                    return False
                if vol.long_syntax:
                    changed = self.doc.set((*path, vol.index, "source"), host)
                    if ro or vol.read_only:
                        changed = self.doc.set((*path, vol.index, "read_only"), ro) or changed
                    return changed
                flags = [f for f in vol.options.split(",") if f and f not in ("ro", "rw")]
                if ro:
                    flags.insert(0, "ro")
                spec = f"{host}:{vol.target}" + (":" + ",".join(flags) if flags else "")
                return self.doc.set((*path, vol.index), spec)
        long = bool(volumes) and all(v.long_syntax for v in volumes)
        new: Any
        if long:
            new = {"type": "bind", "source": host, "target": container}
            if ro:
                new["read_only"] = True
        else:
            spec = f"{host}:{container}" + (":ro" if ro else "")
            new = spec
            if volumes and self.doc.exists(path):
                last = self.doc.info((*path, len(volumes) - 1))
                if last.kind == "scalar" and last.style in ("'", '"'):
                    new = Quoted(spec, last.style)
        return self.doc.append(path, new)

    def remove_volume(self, container_path: str, service: str | None = None) -> bool:
        """Remove the volume mounted at ``container_path``; False when there is none."""
        name = self._svc(service)
        for vol in reversed(self.list_volumes(name)):
            if vol.target.rstrip("/") == container_path.rstrip("/"):
                return self.doc.delete((*self._volumes_path(name), vol.index))
        return False

    # -------------------------------------------------------- environment

    def _env_site(self, name: str, shared: bool) -> tuple[tuple[PathPart, ...], bool]:
        """Where to edit the environment of service ``name``: (path, exists)."""
        own = ("services", name, "environment")
        origin = self.doc.origin(own)
        if origin is None:
            if shared:
                anchor = self._merged_anchor(name)
                if anchor is not None:
                    return (*anchor, "environment"), False
            return own, False
        if origin.startswith("merged:") and shared:
            anchor_path = self.doc.anchor_path(origin.split(":", 1)[1])
            if anchor_path is not None:
                return (*anchor_path, "environment"), True
        return own, True

    def merged_anchor(self, service: str | None = None) -> str | None:
        """The anchor the service merges with ``<<: *anchor`` (the first one; the driver's
        ``common-config`` in every upstream compose file), or None."""
        name = service or self.driver_service()
        if not self.doc.exists(("services", name)):
            return None
        m = _MERGE.search(self.doc.info(("services", name)).raw)
        return m.group(1) if m else None

    def _merged_anchor(self, name: str) -> tuple[PathPart, ...] | None:
        """Path of the anchor the service merges with ``<<: *anchor`` (first one)."""
        anchor = self.merged_anchor(name)
        return self.doc.anchor_path(anchor) if anchor else None

    def environment(self, service: str | None = None) -> dict[str, str | None]:
        """The service's ``environment`` (inherited through ``<<`` included); None = unset value.

        Variables from ``env_file`` (2.2: ``/home/husarion/config/common/.env``) are not
        read here; see `env_files`.
        """
        env = self.service(self._svc(service)).get("environment")
        if env is None:
            return {}
        if isinstance(env, dict):
            return {str(k): _env_value(v) for k, v in env.items()}
        return dict(_env_entry(e) for e in env)

    def get_env(self, key: str, service: str | None = None) -> str | None:
        return self.environment(service).get(key)

    def env_files(self, service: str | None = None) -> list[str]:
        """The service's ``env_file`` entries (inherited included)."""
        value = self.service(self._svc(service)).get("env_file")
        if value is None:
            return []
        if isinstance(value, list):
            return [str(v["path"]) if isinstance(v, dict) else str(v) for v in value]
        return [str(value)]

    def set_env(self, key: str, value: str, service: str | None = None, *, shared: bool = False) -> bool:
        """Set an environment variable of a service (the driver's by default).

        Keeps the form in use (``- KEY=value`` list or ``KEY: value`` mapping) and the
        entry's quoting. When the environment is inherited through ``<<`` the service gets
        its own ``environment`` (copy + change) unless ``shared=True``, which edits the
        anchor's environment instead (every service merging it changes).
        """
        if not _ENV_NAME.match(key):
            raise UsageError(f"invalid environment variable name {key!r}")
        name = self._svc(service)
        path, exists = self._env_site(name, shared)
        if exists and self._site_env(path).get(key) == value:
            return False
        if not shared and self.get_env(key, name) == value:
            return False
        if not exists:
            return self.doc.set(path, [f"{key}={value}"])
        env = self.doc.get(path)
        if isinstance(env, dict):
            return self.doc.set((*path, key), value)
        for i, entry in enumerate(env):
            if _env_entry(entry)[0] == key:
                return self.doc.set((*path, i), f"{key}={value}")
        new: Any = f"{key}={value}"
        if env:
            last = self.doc.info((*path, len(env) - 1))
            if last.kind == "scalar" and last.style in ("'", '"'):
                new = Quoted(new, last.style)
        return self.doc.append(path, new)

    def _site_env(self, path: tuple[PathPart, ...]) -> dict[str, str | None]:
        env = self.doc.get(path, None)
        if env is None:
            return {}
        if isinstance(env, dict):
            return {str(k): _env_value(v) for k, v in env.items()}
        return dict(_env_entry(e) for e in env)

    def unset_env(self, key: str, service: str | None = None, *, shared: bool = False) -> bool:
        """Remove an environment variable (see `set_env` for ``shared``); False when absent."""
        name = self._svc(service)
        path, exists = self._env_site(name, shared)
        if not exists or key not in self._site_env(path):
            return False
        env = self.doc.get(path)
        if isinstance(env, dict):
            return self.doc.delete((*path, key))
        for i, entry in enumerate(env):
            if _env_entry(entry)[0] == key:
                return self.doc.delete((*path, i))
        return False

"""A small ssh_config reader for the common file, answering as paramiko's ``SSHConfig`` does.

Looking a host up in paramiko's ``SSHConfig`` visits every block of the file and asks
``fnmatch`` for each pattern; an inventory's ssh_config with a block per robot makes that
work grow with the square of the fleet, and it needs paramiko loaded first. This reader
keeps the blocks whose ``Host`` line names hosts literally in a dictionary, so a lookup
visits only those naming the host plus the blocks with wildcards or negations, in file
order, and it loads nothing but the standard library.

It reads files made of ``Host`` blocks with plain values, and gives up (``None``: ask
paramiko) on anything else: ``Match``, ``Include``, ``CanonicalizeHostname``, quotes, a
line paramiko cannot parse, or a ``%`` token in a value that paramiko would expand. It
answers only for the settings panther-ops uses (:data:`USED`), with paramiko's rules:
the first value obtained wins, ``IdentityFile`` values add up in order, ``HostName``
defaults to the name looked up and ``~`` in ``IdentityFile`` becomes the home directory.
tests/transport/test_ssh_config_read.py checks it against paramiko on a corpus of files.
"""

from __future__ import annotations

import fnmatch
import os
import re
from dataclasses import dataclass, field

USED = frozenset(
    {"hostname", "port", "user", "identityfile", "userknownhostsfile", "connecttimeout", "proxyjump"}
)
"""The settings a lookup answers for (what ``ssh_config.resolve`` reads)."""

_SETTING = re.compile(r"(\w+)(?:\s*=\s*|\s+)(.+)")  # paramiko's SSHConfig.SETTINGS_REGEX
_UNREAD = frozenset({"match", "include", "canonicalizehostname"})
_TOKENIZED = frozenset({"hostname", "identityfile", "proxyjump"})
"""Used settings in which paramiko expands ``%`` tokens: such a value makes the reader give up."""
_WILD = re.compile(r"[*?\[!]")
_QUOTING = "\"'\\"
"""Quotes and escapes (paramiko strips some, shlex-splits Host lines): the reader gives up."""


@dataclass
class _Block:
    patterns: list[str]
    settings: dict[str, str | list[str]] = field(default_factory=dict)


@dataclass(frozen=True)
class QuickConfig:
    """A parsed ssh_config: every block in order, literal host names indexed."""

    blocks: tuple[_Block, ...]
    by_name: dict[str, tuple[int, ...]]
    """Host name -> indexes of the blocks naming it literally."""
    wild: tuple[int, ...]
    """Indexes of the blocks whose patterns need matching (wildcards, negations)."""

    def lookup(self, host: str) -> dict[str, object]:
        """paramiko's ``SSHConfig.lookup(host)``, restricted to :data:`USED`."""
        found: dict[str, object] = {}
        for i in sorted((*self.by_name.get(host, ()), *self.wild)):
            block = self.blocks[i]
            if i in self.wild and not _matches(block.patterns, host):
                continue
            for key, value in block.settings.items():
                if key not in found:
                    found[key] = list(value) if isinstance(value, list) else value
                elif key == "identityfile":
                    have = found[key]
                    assert isinstance(have, list) and isinstance(value, list)
                    have.extend(v for v in value if v not in have)
        found.setdefault("hostname", host)
        if "identityfile" in found:
            home = os.path.expanduser("~")
            found["identityfile"] = [str(v).replace("~", home) for v in found["identityfile"]]  # type: ignore[attr-defined]
        return found


def _matches(patterns: list[str], host: str) -> bool:
    """paramiko's ``Host`` matching: any pattern matches, unless a negated one does."""
    found = False
    for pattern in patterns:
        if pattern.startswith("!"):
            if fnmatch.fnmatch(host, pattern[1:]):
                return False
        elif fnmatch.fnmatch(host, pattern):
            found = True
    return found


def read_config(text: str) -> QuickConfig | None:
    """Parse ssh_config text; None where the reader gives up (see the module's text)."""
    blocks = [_Block(["*"])]
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        m = _SETTING.match(line)
        if m is None or any(c in line for c in _QUOTING):
            return None
        key, value = m.group(1).lower(), m.group(2)
        if key in _UNREAD:
            return None
        if key == "host":
            blocks.append(_Block(value.split()))
            continue
        if key not in USED:
            continue
        if key in _TOKENIZED and "%" in value:
            return None
        settings = blocks[-1].settings
        if key == "identityfile":
            listed = settings.setdefault(key, [])
            assert isinstance(listed, list)
            listed.append(value)
        else:
            settings.setdefault(key, value)
    by_name: dict[str, list[int]] = {}
    wild: list[int] = []
    for i, block in enumerate(blocks):
        if any(_WILD.search(p) for p in block.patterns):
            wild.append(i)
        else:
            for name in dict.fromkeys(block.patterns):
                by_name.setdefault(name, []).append(i)
    return QuickConfig(tuple(blocks), {k: tuple(v) for k, v in by_name.items()}, tuple(wild))


def read_file(path: str) -> QuickConfig | None:
    """:func:`read_config` of a file (an empty config when it does not exist; None: unreadable)."""
    try:
        with open(path, encoding="utf-8") as fh:
            return read_config(fh.read())
    except FileNotFoundError:
        return read_config("")
    except (OSError, UnicodeDecodeError):
        return None

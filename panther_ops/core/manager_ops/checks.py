"""Before `manager deploy` stands the stock manager down: can ours do what it did on this robot?

The stock C++ safety manager shuts the User Computers of the shutdown hosts file down with the
robot (SSH through libssh on 2.0 - 2.2.0, HTTP on 2.2.1+) and then the robot itself (SSH to
``husarion@localhost`` on 2.0/2.1, D-Bus ``PowerOff`` on 2.2). The deployed manager runs on the
driver's own image and needs, there:

* for SSH hosts: paramiko or an ``ssh`` client (`panther_ops.manager.shutdown_executor.ssh_method`),
  and each host's key in the robot's ``~/.ssh/known_hosts`` (mounted into the container): the
  stock node (libssh) never checks host keys, ours refuses unknown ones, so a host missing there
  would no longer be shut down;
* for the robot's own power-off: the program its command starts (``ssh`` or ``dbus-send``).

`image_probe.probe_image` asks the image once, over the robot's existing connection (``docker exec`` in the
running driver container, which runs that image; else a throw-away container of the image
without network), what it has, and reads the hosts file where only the image has it
(``$(find pkg)/...`` resolved in ``AMENT_PREFIX_PATH`` by the image's entrypoint). `losses` lists
what would silently stop working; deploy refuses (exit 2, nothing written) when it is not empty.
Simulation mode (labs, benches) drives nothing on the robot and is not checked.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass, field

from panther_ops.core.fleet.reads import Reads
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import UsageError
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost

_HOSTS_MARK = "--- panther-ops hosts file ---"
_FILE_MARK = "--- panther-ops file "
IMAGE_PROBE = "image-probe"
"""Fact: what the driver image offers (:class:`ImageFacts`, None: no engine), by hosts file."""
#: $1 = the hosts file as manager.yaml names it (container path or $(find pkg)/rest); then the
#: stock manager's parameter files ($(find pkg)/rest), each printed after its own mark when there
PROBE = r"""
for c in ssh dbus-send python3; do command -v "$c" >/dev/null 2>&1 && echo "has $c"; done
command -v python3 >/dev/null 2>&1 && python3 -c 'import paramiko' >/dev/null 2>&1 && echo "has paramiko"
resolve() {
  f="$1"
  case "$f" in
    '$(find '*)
      pkg=${f#'$(find '}; pkg=${pkg%%)*}; rest=${f#*)}; old_ifs=$IFS; IFS=:
      for p in $AMENT_PREFIX_PATH; do
        if [ -f "$p/share/$pkg$rest" ]; then f="$p/share/$pkg$rest"; break; fi
      done
      IFS=$old_ifs;;
  esac
}
resolve "$1"
show() { cat "$1"; [ -z "$(tail -c 1 "$1")" ] || echo; }  # each mark on a line of its own
if [ -n "$f" ] && [ -f "$f" ]; then echo '--- panther-ops hosts file ---'; show "$f"; fi
shift
for want in "$@"; do
  resolve "$want"
  if [ -n "$f" ] && [ -f "$f" ]; then printf '%s%s ---\n' '--- panther-ops file ' "$want"; show "$f"; fi
done
exit 0
"""


@dataclass
class ImageFacts:
    """What the driver image offers the deployed manager."""

    image: str
    programs: set[str] = field(default_factory=set)
    """among ssh, dbus-send, python3, paramiko (importable by python3)"""
    hosts_text: str | None = None
    """the hosts file as the image sees it (None: not there)"""
    param_texts: dict[str, str] = field(default_factory=dict)
    """the stock manager's parameter files the image has ($(find pkg)/rest -> text)"""

    @property
    def ssh_method(self) -> str | None:
        if "paramiko" in self.programs:
            return "paramiko"
        return "openssh" if "ssh" in self.programs else None

    def describe(self) -> str:
        have = sorted(self.programs - {"python3"})
        return f"{self.image} has {', '.join(have) if have else 'neither paramiko, ssh nor dbus-send'}"


def parse_probe(image: str, output: str) -> ImageFacts:
    programs: set[str] = set()
    parts: dict[str, list[str]] = {}
    current: str | None = None
    for line in output.splitlines(keepends=True):
        bare = line.rstrip("\n")
        if bare == _HOSTS_MARK or (bare.startswith(_FILE_MARK) and bare.endswith(" ---")):
            current = "" if bare == _HOSTS_MARK else bare[len(_FILE_MARK):-4]
            parts[current] = []
        elif current is not None:
            parts[current].append(line)
        elif line.startswith("has "):
            programs.add(line[4:].strip())
    hosts = parts.pop("", None)
    return ImageFacts(image, programs, None if hosts is None else "".join(hosts),
                      {name: "".join(lines) for name, lines in parts.items()})


def ssh_hosts(hosts_text: str | None, source: str) -> list[ShutdownHost]:
    """Every SSH entry of a hosts file's text (HTTP entries need nothing more)."""
    if not hosts_text:
        return []
    import yaml

    from panther_ops.manager.errors import ManagerError
    from panther_ops.manager.shutdown_executor.hosts import Method, parse_shutdown_hosts

    try:
        parsed = parse_shutdown_hosts(yaml.safe_load(hosts_text), source)
    except (yaml.YAMLError, ManagerError):
        return []  # the stock manager could not read it either: nothing of it is lost
    return [h for h in parsed.hosts if h.method is Method.SSH]


def unknown_host_keys(known_hosts_text: str, hosts: list[ShutdownHost]) -> list[ShutdownHost]:
    """The SSH hosts whose key is not in the robot's known_hosts (plain or hashed entries)."""
    from panther_ops.manager.shutdown_executor.knownhosts import is_known

    return [h for h in hosts if not is_known(known_hosts_text, h.ip, h.port)]


def losses(facts: ImageFacts, hosts: list[ShutdownHost], hosts_source: str, localhost_command: str,
           unknown_keys: list[ShutdownHost] | None = None) -> list[str]:
    """What the deployed manager could not do that the stock one does on this robot."""
    lost: list[str] = []
    if hosts and facts.ssh_method is None:
        lost.append(f"shutting down the User Computers of {hosts_source} over SSH "
                    f"({', '.join(h.describe() for h in hosts)}): the manager needs paramiko or an ssh client for that")
    if unknown_keys:
        lost.append(f"shutting down {', '.join(h.describe() for h in unknown_keys)} over SSH: no host key in the "
                    "robot's ~/.ssh/known_hosts (the stock manager does not check host keys; this one refuses "
                    "unknown ones)")
    words = shlex.split(localhost_command) if localhost_command.strip() else []
    program = words[0].rsplit("/", 1)[-1] if words else ""
    if program in ("ssh", "dbus-send") and program not in facts.programs:
        lost.append(f"powering the robot itself off ({program} ...): no {program} in the image")
    return lost


def check_safety(reads: Reads, cfg: RobotConfig, hosts_file: str, hosts_source: str,
                 localhost_command: str) -> tuple[list[str], str | None]:
    """Refuse (UsageError) when the deployed manager would lose a stock safety behaviour.

    Returns (warnings, how SSH hosts will be shut down: ``paramiko``/``openssh``/None).
    """
    facts: ImageFacts | None = reads.fact(IMAGE_PROBE, hosts_file)
    if facts is None:
        return (["not checked whether the image can shut the User Computers and the robot down: "
                 "no docker engine on this robot"], None)
    text = facts.hosts_text
    if hosts_source.startswith("/") and " " not in hosts_source:  # a file on the robot, mounted
        data = reads.file(hosts_source)
        text = data.decode(errors="replace") if data is not None else None
    hosts = ssh_hosts(text, hosts_source)
    unknown: list[ShutdownHost] = []
    if hosts:
        known = reads.file(f"{cfg.home}/.ssh/known_hosts")
        known_text = known.decode(errors="replace") if known is not None else ""
        unknown = unknown_host_keys(known_text, hosts)
    lost = losses(facts, hosts, hosts_source, localhost_command, unknown)
    if lost:
        raise UsageError(
            "deploying the manager would lose what the stock manager does on "
            f"{cfg.stack.label()}: " + "; ".join(lost) + f" ({facts.describe()})",
            hint="use an image with an ssh client (or paramiko); record the hosts' keys on the robot "
                 "(panther-ops shutdown setup / shutdown check); switch the hosts to husarion-shutdown over "
                 "HTTP (2.2.1+); or keep the stock manager. Nothing was changed")
    return [], facts.ssh_method if hosts else None

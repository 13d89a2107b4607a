"""Planner golden corpus: pure inputs (what was read + what was asked) -> the expected plan.

No robot and no transport: each case hands a planner exactly the files and facts it reads
(see tests/golden/golden_plans.py). The plan's diffs are checked against ``<case>.diff`` beside
the case, the rest of it against the case's ``expect``. Set PANTHER_OPS_UPDATE_GOLDEN=1 to rewrite every case's
``expect`` from the current code (then review the changes with git diff before committing).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.fleet.reads import Need
from tests.golden.golden_plans import PLANNERS, PLANS, render, run_case

CASE_FILES = sorted(PLANS.glob("*/*.yaml"))
UPDATE = os.environ.get("PANTHER_OPS_UPDATE_GOLDEN") == "1"


class _Dumper(yaml.SafeDumper):
    pass


def _str(dumper: yaml.SafeDumper, value: str) -> yaml.ScalarNode:
    style = "|" if "\n" in value else None
    return dumper.represent_scalar("tag:yaml.org,2002:str", value, style=style)


_Dumper.add_representer(str, _str)


def _write_expect(case_file: Path, expect: dict[str, Any]) -> None:
    case_file.with_suffix(".diff").write_text(expect.pop("diff"), encoding="utf-8")
    text = case_file.read_text(encoding="utf-8")
    head = text.split("\nexpect:", 1)[0].rstrip("\n")
    body = yaml.dump({"expect": expect}, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=1000)
    case_file.write_text(f"{head}\n{body}", encoding="utf-8")


@pytest.mark.parametrize("case_file", CASE_FILES, ids=[p.stem for p in CASE_FILES])
def test_planner_golden_case(case_file: Path) -> None:
    case = yaml.safe_load(case_file.read_text(encoding="utf-8"))
    plan, reads = run_case(case)
    given = {Need("file", p) for p in reads.files} | set(reads.facts)
    assert reads.asked == given, (f"{case_file.name}: the case's reads are not what the planner reads "
                                  f"(never asked: {sorted(map(str, given - reads.asked))})")
    got = render(plan)
    if UPDATE:
        _write_expect(case_file, got)
        return
    diff = got.pop("diff")
    assert got == case["expect"], f"{case_file.name}: {case.get('description', '')}"
    assert diff == case_file.with_suffix(".diff").read_text(encoding="utf-8"), f"{case_file.stem}.diff"


def test_every_planner_has_a_case() -> None:
    used = {yaml.safe_load(p.read_text(encoding="utf-8"))["planner"] for p in CASE_FILES}
    assert used == set(PLANNERS), f"planners without a golden case: {sorted(set(PLANNERS) - used)}"


def test_trust_planner() -> None:
    """`trust`: the offered key against the recorded ones (pure: types and fingerprints)."""
    from panther_ops.core.fleet.plan_trust import trust_state

    assert trust_state("ssh-ed25519", "SHA256:a", [("ssh-ed25519", "SHA256:a")]) == "known"
    assert trust_state("ssh-ed25519", "SHA256:b", [("ssh-ed25519", "SHA256:a")]) == "changed"
    assert trust_state("ssh-ed25519", "SHA256:b", [("ssh-rsa", "SHA256:c")]) == "new"
    assert trust_state("ssh-ed25519", "SHA256:b", []) == "new"


def test_trust_plans_the_known_hosts_edit() -> None:
    """`trust`: the plan is the exact edit of known_hosts (appended; --replace drops the host's
    plain lines, keeps comments and other hosts); a known key is no change, a changed one refused."""
    from panther_ops.core.fleet.plan_trust import HOST_KEY, OfferedKey, plan_trust
    from panther_ops.core.fleet.reads import Need, Reads
    from panther_ops.errors import HostKeyError

    def reads(known: tuple[tuple[str, str], ...], text: str) -> Reads:
        offered = OfferedKey("10.0.0.7", 2222, "[10.0.0.7]:2222", "ssh-ed25519", "AAAAnew", "SHA256:new", known,
                             "/home/op/.ssh/known_hosts")
        return Reads("panther-07", files={"/home/op/.ssh/known_hosts": text.encode()},
                     facts={Need(HOST_KEY, "panther-07"): offered})

    plan = plan_trust(reads((), "a ssh-rsa AAAAa"), "panther-07", replace=False)
    assert plan.edits[0].after == b"a ssh-rsa AAAAa\n[10.0.0.7]:2222 ssh-ed25519 AAAAnew\n"
    assert plan.data["state"] == "new" and plan.home == "/home/op/.ssh" and plan.edits[0].mode == 0o600
    assert plan_trust(reads((("ssh-ed25519", "SHA256:new"),), ""), "panther-07", replace=False).noop
    changed = reads((("ssh-ed25519", "SHA256:old"),), "# c\n[10.0.0.7]:2222 ssh-ed25519 AAAAold\nb ssh-rsa AAAAb\n")
    with pytest.raises(HostKeyError, match="host key changed"):
        plan_trust(changed, "panther-07", replace=False)
    plan = plan_trust(changed, "panther-07", replace=True)
    assert plan.edits[0].after == b"# c\nb ssh-rsa AAAAb\n[10.0.0.7]:2222 ssh-ed25519 AAAAnew\n"

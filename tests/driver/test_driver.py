"""`driver ...` and `config restore-defaults`: the pure parts with data, and the plans on the
real-shaped compose files of templates/compose/ (the demo fleet: robots that are directories)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.containers.logs import prefix_lines
from panther_ops.core.containers.times import human_duration, parse_timestamp
from panther_ops.core.driver.containers import argv_matches, describe_container, last_line, parse_duration
from panther_ops.core.driver.hub import fetch_hub_tags
from panther_ops.core.driver.images import (
    HUB_TAG,
    HubTag,
    RegistryError,
    local_images,
    newer_tags,
    parse_hub_page,
    parse_target,
    tag_key,
)
from panther_ops.core.driver.read import read_and_plan_restore_defaults, read_and_plan_update
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import Connections, RobotContext
from panther_ops.core.fleet.templates import template_path
from panther_ops.core.robot.compose import ComposeFile
from panther_ops.errors import RemoteStateError, UsageError
from tests.clirun import run_cli
from tests.loopback_http import QuietHandler, serving
from tests.ports import free_port


# A Docker Hub answer in the shape of GET /v2/namespaces/husarion/repositories/husarion-ugv/tags
# (fields as in Docker Hub's published tag schema; tag names from panther-stack.md §0/§2.2, plus
# the kinds of tags the filter must drop). Not fetched here: there is no network, and tests
# must never contact Docker Hub.
def _tag(name: str, last_updated: str, full_size: int, digest: str) -> dict[str, Any]:
    """A tag as Docker Hub lists it, the fields the client reads only (digest: one hex digit, repeated)."""
    return {"name": name, "last_updated": last_updated, "full_size": full_size, "tag_status": "active",
            "digest": "sha256:" + digest * 64}


HUB_PAGE_1: dict[str, Any] = {
    "count": 9,
    "next": "{base}/v2/namespaces/husarion/repositories/husarion-ugv/tags?page=2&page_size=100",
    "previous": None,
    "results": [
        {"creator": 7305247, "id": 889231001, "images": [{"architecture": "arm64", "features": "", "variant": "v8",
                                                           "digest": "sha256:" + "a" * 64, "os": "linux",
                                                           "os_features": "", "os_version": None, "size": 1610612736,
                                                           "status": "active", "last_pulled": "2025-11-02T08:12:44Z",
                                                           "last_pushed": "2025-07-02T11:20:31Z"}],
         "last_updated": "2025-07-02T11:20:33.104845Z", "last_updater": 7305247, "last_updater_username": "husarion",
         "name": "jazzy-2.3.1-20250701", "repository": 21374711, "full_size": 1610612736, "v2": True,
         "tag_status": "active", "tag_last_pulled": "2025-11-02T08:12:44Z", "tag_last_pushed": "2025-07-02T11:20:33Z",
         "media_type": "application/vnd.oci.image.index.v1+json", "content_type": "image",
         "digest": "sha256:" + "1" * 64},
        {"creator": 7305247, "id": 889230877, "images": [], "last_updated": "2025-07-02T10:58:12.771002Z",
         "last_updater": 7305247, "last_updater_username": "husarion", "name": "humble-2.2.2-20250702",
         "repository": 21374711, "full_size": 1593835520, "v2": True, "tag_status": "active",
         "tag_last_pulled": "2025-11-03T17:01:02Z", "tag_last_pushed": "2025-07-02T10:58:12Z",
         "media_type": "application/vnd.oci.image.index.v1+json", "content_type": "image",
         "digest": "sha256:" + "2" * 64},
        _tag("humble-2.2.2-20250702-stable", "2025-07-10T09:00:00.000000Z", 1593835520, "2"),
        _tag("humble", "2025-07-10T09:00:00.000000Z", 1593835520, "2"),
        _tag("humble-nightly", "2025-11-01T02:00:00.000000Z", 1600000000, "3"),
        _tag("latest", "2025-07-02T11:20:33.104845Z", 1610612736, "1"),
    ],
}
HUB_PAGE_2: dict[str, Any] = {
    "count": 9,
    "next": None,
    "previous": "{base}/v2/namespaces/husarion/repositories/husarion-ugv/tags?page=1&page_size=100",
    "results": [
        _tag("humble-2.2.1-20250331", "2025-03-31T12:00:00.000000Z", 1580000000, "4"),
        _tag("humble-2.2.0-20240227", "2025-03-13T12:00:00.000000Z", 1570000000, "5"),
        _tag("humble-2.2.0-rc1", "2025-02-01T12:00:00.000000Z", 1570000000, "6"),
    ],
}


# ------------------------------------------------------------------ tags and images


@pytest.mark.parametrize(("text", "repo", "version"), [
    ("humble-2.1.2-20241125", None, (2, 1, 2)),
    ("humble-2.2.2-20250702", None, (2, 2, 2)),
    ("humble-2.0.4-20240628-stable", None, (2, 0, 4)),
    ("husarion/panther:humble-2.1.1-20240828", "husarion/panther", (2, 1, 1)),
    ("docker.io/husarion/husarion-ugv:humble-2.2.1-20250331", "husarion/husarion-ugv", (2, 2, 1)),
])
def test_parse_target_accepts_humble_tags_and_images(text: str, repo: str | None, version: tuple[int, ...]) -> None:
    t = parse_target(text)
    assert (t.repo, t.version, t.warnings) == (repo, version, ())


@pytest.mark.parametrize(("text", "needle"), [
    ("jazzy-2.4.0-20270101", "jazzy: husarion_ugv 2.3.0, 2.3.1, 2.3.2"),
    ("husarion/husarion-ugv:jazzy-2.2.2-20250702", "jazzy 2.2.2 is not a driver panther-ops supports"),
    ("humble-2.3.0-20260101", "humble 2.3.0 is not a driver panther-ops supports"),
    ("rolling-2.2.2-20250702", "Rolling is not a Panther driver"),
    ("latest", "does not say the driver version"),
    ("humble", "does not say the driver version"),
    ("humble-2.2", "does not say the driver version"),
    ("humble-1.1.0-20230101", "ROS 1"),
    ("husarion/panther@sha256:" + "0" * 64, "digest"),
    ("ubuntu:22.04", "not a Panther driver image"),
    ("husarion/panther:humble-2.2.2-20250702", "published as husarion/husarion-ugv"),
    ("husarion/husarion-ugv:humble-2.1.1-20240828", "published as husarion/panther"),
    ("humble-2.1.1-20240828;reboot", "not a docker image tag"),
    ("humble-2.1.1-20240828 && rm -rf /", "has no tag"),
    ("", "empty"),
])
def test_parse_target_refuses_with_a_reason(text: str, needle: str) -> None:
    with pytest.raises(UsageError) as exc:
        parse_target(text)
    assert needle in str(exc.value)
    assert exc.value.exit_code == 2


def test_parse_target_crossed_pair_hint_names_the_newest_drivers() -> None:
    with pytest.raises(UsageError) as exc:
        parse_target("humble-2.3.1-20250701", force=True)
    assert "humble-2.2.2-20250702" in (exc.value.hint or "") and "jazzy-2.3.2-20260622" in (exc.value.hint or "")
    assert parse_target("jazzy-2.3.2-20260622").version == (2, 3, 2)  # a migration target (tests/driver/migrate/)


def test_repository_mismatch_is_a_warning_with_force() -> None:
    t = parse_target("husarion/panther:humble-2.2.2-20250702", force=True)
    assert t.warnings and "(--force)" in t.warnings[0]
    assert t.ref_for("husarion/panther:humble-2.1.1-20240828") == "husarion/panther:humble-2.2.2-20250702"


@pytest.mark.parametrize(("current", "tag", "expected"), [
    ("husarion/panther:humble-2.0.4-20240628", "humble-2.1.1-20240828", "husarion/panther:humble-2.1.1-20240828"),
    ("husarion/panther:humble-2.1.1-20240828", "humble-2.2.2-20250702",
     "husarion/husarion-ugv:humble-2.2.2-20250702"),
    ("registry.lan:5000/husarion/panther:humble-2.1.1-20240828", "humble-2.1.2-20241125",
     "registry.lan:5000/husarion/panther:humble-2.1.2-20241125"),
    ("husarion/panther@sha256:" + "f" * 64, "humble-2.1.2-20241125", "husarion/panther:humble-2.1.2-20241125"),
])
def test_a_tag_takes_its_version_repository_and_keeps_the_registry(current: str, tag: str, expected: str) -> None:
    assert parse_target(tag).ref_for(current) == expected


def test_tag_order() -> None:
    tags = ["humble-2.1.1-20240828", "humble-2.2.2-20250702", "humble-2.0.4-20240628", "humble-2.1.10-20250101",
            "weird", "humble-2.2.2-20250702-stable"]
    assert sorted(tags, key=tag_key) == ["weird", "humble-2.0.4-20240628", "humble-2.1.1-20240828",
                                         "humble-2.1.10-20250101", "humble-2.2.2-20250702",
                                         "humble-2.2.2-20250702-stable"]


# ------------------------------------------------------------------ durations and times


@pytest.mark.parametrize(("text", "seconds"), [
    ("90", 90), ("90s", 90), ("10m", 600), ("1h30m", 5400), ("2d", 172800), ("1.5h", 5400), (" 5M ", 300),
])
def test_parse_duration(text: str, seconds: float) -> None:
    assert parse_duration(text) == seconds


@pytest.mark.parametrize("text", ["", "-5m", "10 minutes", "1h-30m", "m", "1w"])
def test_parse_duration_refuses(text: str) -> None:
    with pytest.raises(UsageError):
        parse_duration(text)


def test_parse_timestamp_docker_forms() -> None:
    assert parse_timestamp("2025-07-02T10:58:12.771002123Z") == datetime(2025, 7, 2, 10, 58, 12, 771002,
                                                                          tzinfo=timezone.utc)
    assert parse_timestamp("2025-07-02T12:58:12+02:00") == datetime(2025, 7, 2, 10, 58, 12, tzinfo=timezone.utc)
    assert parse_timestamp("0001-01-01T00:00:00Z") is None
    assert parse_timestamp("") is None and parse_timestamp(None) is None and parse_timestamp("yesterday") is None


@pytest.mark.parametrize(("seconds", "text"), [(None, "-"), (0, "0s"), (59.9, "59s"), (3725, "1h 2m"),
                                               (90061, "1d 1h"), (-3, "0s")])
def test_human_duration(seconds: float | None, text: str) -> None:
    assert human_duration(seconds) == text


def test_last_line_and_prefix_lines() -> None:
    assert last_line("a\n\n  b failed \n\n") == "b failed"
    assert last_line("") == ""
    assert prefix_lines("r01", b"one\ntwo") == b"r01 | one\nr01 | two\n"
    assert prefix_lines("r01", b"") == b""


# ------------------------------------------------------------------ container view


CMD = ["ros2", "launch", "panther_bringup", "bringup.launch.py", "wheel_type:=WH02"]


def attrs(**over: Any) -> dict[str, Any]:
    state = {"Status": "running", "Running": True, "Restarting": False, "ExitCode": 0,
             "StartedAt": "2026-11-22T10:00:00.123456789Z", "FinishedAt": "0001-01-01T00:00:00Z"}
    state.update(over.pop("State", {}))
    doc: dict[str, Any] = {"Id": "c0ffee" * 10, "Name": "/panther_ros", "RestartCount": 0, "State": state,
                           "Config": {"Image": "husarion/panther:humble-2.1.1-20240828", "Cmd": list(CMD)}}
    doc.update(over)
    return doc


NOW = datetime(2026, 11, 22, 12, 30, 0, tzinfo=timezone.utc)


def test_running_container_as_compose_says() -> None:
    v = describe_container(attrs(), compose_image="husarion/panther:humble-2.1.1-20240828", compose_argv=CMD, now=NOW)
    assert v.healthy and v.problem is None and v.warnings == []
    assert v.data["uptime_s"] == pytest.approx(9000 - 0.123, abs=0.1)
    assert v.data["state"] == "running" and v.data["command_drift"] is False and v.data["image_drift"] is False
    assert v.data["finished_at"] is None and v.data["container"] == "panther_ros"


def test_drift_and_restarts_are_warnings() -> None:
    v = describe_container(attrs(RestartCount=2, State={"ExitCode": 1}),
                           compose_image="husarion/panther:humble-2.1.2-20241125",
                           compose_argv=[*CMD, "use_ekf:=False"], now=NOW)
    assert v.healthy
    text = "\n".join(v.warnings)
    assert "compose.yaml says husarion/panther:humble-2.1.2-20241125" in text
    assert "launch command differs" in text and "restarted 2 time(s)" in text


def test_a_restarted_running_driver_names_no_exit_code() -> None:
    """docker sets a container's ExitCode to 0 when it starts it again (seen on the lab's dockerd,
    r05's crash loop read between two starts): a running container's code is not its crash's."""
    v = describe_container(attrs(RestartCount=3), compose_image=None, compose_argv=None, now=NOW)
    assert v.healthy
    assert v.warnings == ["restarted 3 time(s) since it was created: panther-ops driver logs shows why it stopped"]


@pytest.mark.parametrize(("state", "problem"), [
    ({"Status": "exited", "Running": False, "ExitCode": 137}, "exited (exit code 137)"),
    ({"Status": "restarting", "Running": True, "Restarting": True, "ExitCode": 1}, "restarting (exit code 1"),
    ({"Health": {"Status": "unhealthy"}}, "unhealthy"),
])
def test_a_driver_not_running_is_a_problem(state: dict[str, Any], problem: str) -> None:
    v = describe_container(attrs(State=state), compose_image=None, compose_argv=None, now=NOW)
    assert not v.healthy and v.problem is not None and v.problem.startswith(problem)
    assert v.data["uptime_s"] is None or state.get("Health")


def test_argv_matches_lets_compose_interpolate() -> None:
    assert argv_matches(["ros2", "launch", "a", "ns:=robot7"], ["ros2", "launch", "a", "ns:=${NS}"])
    assert not argv_matches(["ros2", "launch", "a"], ["ros2", "launch", "a", "x:=1"])
    assert not argv_matches(["ros2", "launch", "b"], ["ros2", "launch", "a"])


def test_argv_matches_compares_a_bash_c_script_word_by_word() -> None:
    """husarion/panther-docker's gamepad: the container's Cmd keeps `$(ros2 pkg prefix ...)` as written."""
    script = ("ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=$(ros2 pkg prefix "
              "joy2twist)/share/joy2twist/config/joy2twist_panther.yaml namespace:=panther")
    compose = ["bash", "-c", script]
    assert argv_matches(["bash", "-c", script], compose)
    assert argv_matches(["bash", "-c", script.replace(" namespace", "   namespace")], compose)
    assert not argv_matches(["bash", "-c", script.replace("namespace:=panther", "namespace:=other")], compose)
    assert not argv_matches(["bash", "-c", script.replace("$(ros2 pkg prefix joy2twist)", "/opt")], compose)
    assert not argv_matches(script.split(), compose)
    assert argv_matches(["bash", "-c", "ros2 launch a b.py ns:=robot7"], ["bash", "-c", "ros2 launch a b.py ns:=${NS}"])


# ------------------------------------------------------------------ local images


def test_local_images_mark_the_reference_in_use_when_tags_share_an_id() -> None:
    same = {"Id": "sha256:" + "e" * 64, "Size": 1993000, "RepoTags": [
        "husarion/panther:humble-2.0.4-20240628", "husarion/panther:humble-2.1.1-20240828",
        "husarion/husarion-ugv:humble-2.2.2-20250702"]}
    other = {"Id": "sha256:" + "9" * 64, "Size": 5, "RepoTags": ["husarion/joy2twist:humble-1.0.0-20240109",
                                                                 "busybox:latest"]}
    got = local_images([other, same], compose_image="husarion/panther:humble-2.1.1-20240828",
                       running_ref="husarion/panther:humble-2.0.4-20240628", running_image_id=same["Id"])
    assert [e["image"] for e in got] == ["husarion/husarion-ugv:humble-2.2.2-20250702",
                                         "husarion/panther:humble-2.1.1-20240828",
                                         "husarion/panther:humble-2.0.4-20240628"]
    assert [e["in_use"] for e in got] == [False, False, True]
    assert [e["in_compose"] for e in got] == [False, True, False]


def test_local_images_fall_back_to_the_image_id() -> None:
    img = {"Id": "sha256:" + "e" * 64, "RepoTags": ["husarion/panther:humble-2.1.1-20240828"]}
    got = local_images([img], compose_image=None, running_ref="sha256:" + "e" * 64, running_image_id=img["Id"])
    assert got[0]["in_use"] is True


# ------------------------------------------------------------------ Docker Hub


def page(doc: dict[str, Any], base: str) -> dict[str, Any]:
    return json.loads(json.dumps(doc).replace("{base}", base))


def test_hub_page_keeps_released_humble_tags_only() -> None:
    tags, nxt = parse_hub_page(page(HUB_PAGE_1, "https://hub.docker.com"), "husarion/husarion-ugv")
    assert [t.name for t in tags] == ["humble-2.2.2-20250702", "humble-2.2.2-20250702-stable"]
    assert tags[0] == HubTag("husarion/husarion-ugv", "humble-2.2.2-20250702", "2025-07-02T10:58:12.771002Z",
                             "sha256:" + "2" * 64, 1593835520)
    assert nxt == "https://hub.docker.com/v2/namespaces/husarion/repositories/husarion-ugv/tags?page=2&page_size=100"
    tags, nxt = parse_hub_page(HUB_PAGE_2, "husarion/husarion-ugv")
    assert [t.name for t in tags] == ["humble-2.2.1-20250331", "humble-2.2.0-20240227"] and nxt is None


@pytest.mark.parametrize("tag", ["humble-2.2.2-20250702", "humble-2.1.2-20241125-stable"])
def test_hub_regex_accepts(tag: str) -> None:
    assert HUB_TAG.match(tag)


@pytest.mark.parametrize("tag", ["jazzy-2.3.1-20250701", "humble", "humble-nightly", "humble-2.2.0-rc1",
                                 "humble-2.2.2-2025070", "humble-2.2.2-20250702-beta", "latest"])
def test_hub_regex_refuses(tag: str) -> None:
    assert not HUB_TAG.match(tag)


@pytest.mark.parametrize("doc", [[], {"results": None}, {"detail": "object not found"}])
def test_hub_page_unexpected_answer(doc: Any) -> None:
    with pytest.raises(RegistryError):
        parse_hub_page(doc, "husarion/panther")


@pytest.fixture
def fake_hub() -> Iterator[tuple[str, list[str]]]:
    """A loopback HTTP server answering like Docker Hub's tag list (two pages); records the paths asked."""
    asked: list[str] = []

    class Handler(QuietHandler):
        def do_GET(self) -> None:
            asked.append(self.path)
            base = f"http://127.0.0.1:{self.server.server_address[1]}"
            if "/husarion-ugv/" in self.path:
                body = page(HUB_PAGE_2 if "page=2" in self.path else HUB_PAGE_1, base)
            elif "/panther/" in self.path:
                body = {"count": 1, "next": None, "results": [{"name": "humble-2.1.2-20241125"},
                                                              {"name": "humble-2.1.1-20240828"}]}
            else:
                self.reply(404, b"")
                return
            self.reply(200, json.dumps(body).encode(), "application/json")

    with serving(Handler) as port:
        yield f"http://127.0.0.1:{port}/v2/namespaces/husarion/repositories/{{repo}}/tags?page_size=100", asked


def test_fetch_follows_pages_and_sorts(fake_hub: tuple[str, list[str]]) -> None:
    url, asked = fake_hub
    tags = fetch_hub_tags("husarion/husarion-ugv", url_template=url, timeout=2)
    assert [t.name for t in tags] == ["humble-2.2.2-20250702-stable", "humble-2.2.2-20250702",
                                      "humble-2.2.1-20250331", "humble-2.2.0-20240227"]
    assert asked == ["/v2/namespaces/husarion/repositories/husarion-ugv/tags?page_size=100",
                     "/v2/namespaces/husarion/repositories/husarion-ugv/tags?page=2&page_size=100"]


def test_fetch_unreachable_is_a_clean_error() -> None:
    url = f"http://127.0.0.1:{free_port()}/v2/namespaces/husarion/repositories/{{repo}}/tags"
    with pytest.raises(RegistryError) as exc:
        fetch_hub_tags("husarion/panther", url_template=url, timeout=2)
    assert str(exc.value).startswith("registry unreachable: ")


def test_fetch_http_error_and_bad_scheme(fake_hub: tuple[str, list[str]]) -> None:
    url, _ = fake_hub
    with pytest.raises(RegistryError, match="HTTP 404"):
        fetch_hub_tags("husarion/nope", url_template=url, timeout=2)
    with pytest.raises(RegistryError, match="not http"):
        fetch_hub_tags("husarion/panther", url_template="file:///etc/{repo}")


def test_newer_tags_stay_in_the_robots_repository() -> None:
    remote = [HubTag("husarion/panther", "humble-2.1.2-20241125"), HubTag("husarion/panther", "humble-2.1.1-20240828"),
              HubTag("husarion/husarion-ugv", "humble-2.2.2-20250702")]
    assert newer_tags("husarion/panther:humble-2.1.1-20240828", remote) == ["husarion/panther:humble-2.1.2-20241125"]
    assert newer_tags("husarion/husarion-ugv:humble-2.2.2-20250702", remote) == []
    assert newer_tags("husarion/panther:custom", remote) == []


# ------------------------------------------------------------------ plans on the demo fleet


def compose_of(demo: Path, robot: str) -> Path:
    return demo / "robots" / robot / "home" / "husarion" / "compose.yaml"


def all_files(demo: Path) -> dict[str, bytes]:
    return {str(p.relative_to(demo)): p.read_bytes() for p in sorted(demo.rglob("*")) if p.is_file()}


def with_ctx(demo: Path, name: str, fn: Any) -> Any:
    inv = load_inventory(str(demo))
    robot = inv.robots[name]
    with Connections(inv) as conns:
        return fn(RobotContext(robot, conns.get(robot), inv))


def changed_lines(diff: str) -> list[str]:
    return [ln for ln in diff.splitlines() if ln[:1] in "+-" and not ln.startswith(("+++", "---"))]


def test_update_plan_changes_only_the_image_line(demo: Path) -> None:
    plan = with_ctx(demo, "panther-01", lambda c: read_and_plan_update(c, parse_target("humble-2.1.2-20241125")))
    (diff,) = plan.diffs
    assert changed_lines(diff.unified) == ["-    image: husarion/panther:humble-2.1.1-20240828",
                                           "+    image: husarion/panther:humble-2.1.2-20241125"]
    assert plan.recreate == ("panther_ros",)
    assert plan.data["image_local"] is None  # a demo robot has no engine to ask
    assert not any("not on the robot" in w for w in plan.warnings)
    # the recreated driver is verified; its command does not change with the image
    assert [(v.service, v.cmd_contains, v.cmd_lacks) for v in plan.verify] == [("panther_ros", (), ())]


def test_update_20_to_21_warns_about_the_led_devices(demo: Path) -> None:
    plan = with_ctx(demo, "panther-02", lambda c: read_and_plan_update(c, parse_target("humble-2.1.1-20240828")))
    assert any("/dev/spiled-channel1/2" in w for w in plan.warnings)
    assert plan.summary == "image husarion/panther:humble-2.0.4-20240628 -> husarion/panther:humble-2.1.1-20240828"
    # the 2.1 robot's compose already has the spiled devices: no such warning
    plan = with_ctx(demo, "panther-01", lambda c: read_and_plan_update(c, parse_target("humble-2.1.2-20241125")))
    assert not any("spiled" in w for w in plan.warnings)


def test_update_to_the_same_image_is_ok(demo: Path) -> None:
    plan = with_ctx(demo, "panther-03", lambda c: read_and_plan_update(c, parse_target("humble-2.2.2-20250702")))
    assert not plan.edits and plan.noop == "compose.yaml already has husarion/husarion-ugv:humble-2.2.2-20250702"


def test_family_change_refused_without_force(demo: Path) -> None:
    with pytest.raises(UsageError) as exc:
        with_ctx(demo, "panther-01", lambda c: read_and_plan_update(c, parse_target("humble-2.2.2-20250702")))
    assert "reinstall" in str(exc.value) and "--force" in (exc.value.hint or "")


def test_forced_family_change_renames_service_and_package_and_migrates_args(demo: Path) -> None:
    path = compose_of(demo, "panther-01")
    path.write_text(path.read_text().replace(
        "command: ros2 launch panther_bringup bringup.launch.py",
        "command: ros2 launch panther_bringup bringup.launch.py led_config_file:=/config/led.yaml"))
    plan = with_ctx(demo, "panther-01", lambda c: read_and_plan_update(c, parse_target("humble-2.2.2-20250702"), force=True))
    (diff,) = plan.diffs
    assert changed_lines(diff.unified) == [
        "-  panther_ros:",
        "-    image: husarion/panther:humble-2.1.1-20240828",
        "-    container_name: panther_ros",
        "+  husarion_ugv_ros:",
        "+    image: husarion/husarion-ugv:humble-2.2.2-20250702",
        "+    container_name: husarion_ugv_ros",
        "-    command: ros2 launch panther_bringup bringup.launch.py led_config_file:=/config/led.yaml",
        "+    command: ros2 launch husarion_ugv_bringup bringup.launch.py animations_config_path:=/config/led.yaml",
    ]
    assert plan.recreate == ("husarion_ugv_ros",) and plan.data["service_from"] == "panther_ros"
    new = ComposeFile.parse(plan.edits[0].after.decode())
    assert new.driver_service() == "husarion_ugv_ros" and new.services() == ["husarion_ugv_ros", "gamepad_controller"]
    assert any("reinstall the OS" in w for w in plan.warnings)
    assert any("led_config_file renamed animations_config_path" in w for w in plan.warnings)


def test_forced_move_back_drops_22_only_args(demo: Path) -> None:
    plan = with_ctx(demo, "panther-03", lambda c: read_and_plan_update(c, parse_target("humble-2.1.1-20240828"), force=True))
    (diff,) = plan.diffs
    assert "+    command: ros2 launch panther_bringup bringup.launch.py" in diff.unified.splitlines()
    assert plan.data["service_from"] == "husarion_ugv_ros" and plan.recreate == ("panther_ros",)
    assert {w.split(":=")[0] for w in plan.warnings if w.startswith("launch argument")} == {
        "launch argument common_dir_path", "launch argument launch_gamepad"}


def test_update_with_no_tag_uses_the_desired_image(demo: Path) -> None:
    plan = with_ctx(demo, "panther-01", lambda c: read_and_plan_update(c, None))
    assert plan.noop == "no TAG given and no desired image in the inventory"


def test_cli_bad_tags_exit_2_and_touch_nothing(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = all_files(demo)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", "jazzy-2.4.0-20270101", "--all", "--yes")
    assert code == 2 and "jazzy: husarion_ugv 2.3.0" in err
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", "humble-2.2.2-20250702", "--all", "--yes")
    assert code == 2 and "reinstall" in err and "nothing was changed on any robot" in err
    assert all_files(demo) == before


def test_cli_update_applies_and_is_recorded(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", "humble-2.1.2-20241125", "-r", "panther-01",
                           "--yes", "--json")
    assert code == 0, doc
    (r,) = doc["robots"]
    assert r["outcome"] == "changed" and r["data"]["backup"]
    assert "image: husarion/panther:humble-2.1.2-20241125" in compose_of(demo, "panther-01").read_text()
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "history", "-r", "panther-01", "--json")
    (entry,) = doc["robots"][0]["data"]["history"]
    assert entry["command"] == "driver update humble-2.1.2-20241125" and entry["status"].startswith("applied")
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", "humble-2.1.2-20241125", "-r", "panther-01",
                           "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"


def test_cli_read_only_commands_skip_demo_robots(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (["driver", "status"], ["driver", "versions"], ["driver", "logs"]):
        code, doc, _, _ = run_cli(capsys, "-i", str(demo), *argv, "--all", "--json")
        assert code == 0, (argv, doc)
        assert {r["outcome"] for r in doc["robots"]} == {"skipped"}
        assert {r["message"] for r in doc["robots"]} == {"demo robot: no docker engine"}
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "status", "-r", "panther-03", "--json")
    assert doc["robots"][0]["data"]["compose_image"] == "husarion/husarion-ugv:humble-2.2.2-20250702"


def test_cli_versions_remote_unreachable_is_a_note(demo: Path, capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PANTHER_OPS_DOCKERHUB_URL", f"http://127.0.0.1:{free_port()}/{{repo}}")
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "versions", "--all", "--remote", "--json")
    assert code == 0
    assert set(doc["data"]["remote"]) == {"husarion/panther", "husarion/husarion-ugv"}
    assert all(v["error"].startswith("registry unreachable") for v in doc["data"]["remote"].values())
    assert len(doc["notes"]) == 2


def test_cli_versions_remote_lists_newer(demo: Path, capsys: pytest.CaptureFixture[str],
                                         monkeypatch: pytest.MonkeyPatch, fake_hub: tuple[str, list[str]]) -> None:
    monkeypatch.setenv("PANTHER_OPS_DOCKERHUB_URL", fake_hub[0])
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "versions", "--all", "--remote", "--json")
    assert code == 0 and doc["notes"] == []
    newer = {r["robot"]: r["data"]["newer"] for r in doc["robots"]}
    assert newer == {"panther-01": ["husarion/panther:humble-2.1.2-20241125"],
                     "panther-02": ["husarion/panther:humble-2.1.2-20241125", "husarion/panther:humble-2.1.1-20240828"],
                     "panther-03": [], "panther-04": []}


def test_cli_restart_needs_yes_and_skips_demo_robots(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "restart", "--all")
    assert code == 2 and "pass --yes" in err
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "restart", "--all", "--dry-run", "--json")
    assert code == 0 and doc["robots"][0]["message"] == (
        "would recreate panther_ros (husarion/panther:humble-2.1.1-20240828)")
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "restart", "--all", "--yes", "--json")
    assert code == 0 and {r["outcome"] for r in doc["robots"]} == {"skipped"}


def test_cli_logs_follow_needs_one_robot(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "logs", "--all", "-f")
    assert code == 2 and "one robot" in err
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "logs", "--all", "--since", "soon")
    assert code == 2 and "not a duration" in err


def test_restore_defaults_21_undoes_config_push(demo: Path, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    template = template_path("compose", "panther-2.1.1.yaml").read_bytes()
    assert compose_of(demo, "panther-01").read_bytes() == template
    mine = tmp_path / "my_controller.yaml"
    mine.write_text("/**:\n  drive_controller:\n    ros__parameters:\n      linear:\n        x:\n"
                    "          max_velocity: 0.8\n")
    code, _, _, _ = run_cli(capsys, "-i", str(demo), "config", "push", str(mine), "--as", "controller", "-r",
                         "panther-01", "--yes")
    assert code == 0 and compose_of(demo, "panther-01").read_bytes() != template
    plan = with_ctx(demo, "panther-01", read_and_plan_restore_defaults)
    assert plan.data["unset_args"] == ["controller_config_path"]
    assert plan.data["removed_mounts"] == [
        "/home/husarion/config/panther_controller/config/my_controller.yaml:"
        "/config/panther_controller/config/my_controller.yaml:ro"]
    assert plan.verify[0].cmd_lacks == ("controller_config_path:=/config/panther_controller/config/my_controller.yaml",)
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "restore-defaults", "-r", "panther-01", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed"
    assert compose_of(demo, "panther-01").read_bytes() == template
    assert (demo / "robots/panther-01/home/husarion/config/panther_controller/config/my_controller.yaml").exists()
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "restore-defaults", "-r", "panther-01", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"
    assert doc["robots"][0]["message"].startswith("nothing panther-ops added")


def test_restore_defaults_21_custom_wheels_unset_too(demo: Path) -> None:
    path = compose_of(demo, "panther-02")
    path.write_text(path.read_text().replace(
        "      - /run/husarion/panther_config.yaml:/run/husarion/panther_config.yaml\n",
        "      - /run/husarion/panther_config.yaml:/run/husarion/panther_config.yaml\n"
        "      - /home/husarion/config/w:/config/w:ro\n").replace(
        "namespace:=panther", "namespace:=panther wheel_type:=custom wheel_config_path:=/config/w/wheel.yaml "
        "controller_config_path:=/config/w/ctrl.yaml use_ekf:=False", 1))
    plan = with_ctx(demo, "panther-02", read_and_plan_restore_defaults)
    assert plan.data["unset_args"] == ["wheel_config_path", "controller_config_path", "wheel_type"]
    assert any("wheel_type:=custom" in w for w in plan.warnings)
    after = plan.edits[0].after.decode()
    assert "use_ekf:=False" in after and "/config/w" not in after


def test_restore_defaults_22_is_an_archive_then_the_image_script(demo: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    plan = with_ctx(demo, "panther-03", read_and_plan_restore_defaults)
    assert plan.edits == [] and plan.data["action"] == "update_config_directory"
    assert plan.data["config_dir"] == "/home/husarion/config"
    # the driver's robot_config.env goes along, so the image's scripts see ROBOT_MODEL_NAME
    assert plan.data["env_mounts"] == ["/run/husarion/robot_config.env:/run/husarion/robot_config.env:ro"]
    before = all_files(demo)
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "restore-defaults", "-r", "panther-03", "--dry-run",
                           "--json")
    assert code == 0 and doc["robots"][0]["message"].startswith("would back up /home/husarion/config and run "
                                                                 "update_config_directory from husarion/husarion-ugv")
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "restore-defaults", "-r", "panther-03", "--yes",
                           "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "skipped"
    assert all_files(demo) == before


def test_restore_defaults_22_refuses_a_tree_that_is_the_home(demo: Path) -> None:
    path = compose_of(demo, "panther-03")
    path.write_text(path.read_text().replace("- /home/husarion/config:/config", "- /home/husarion:/config"))
    with pytest.raises(RemoteStateError, match="refusing to reset it"):
        with_ctx(demo, "panther-03", read_and_plan_restore_defaults)

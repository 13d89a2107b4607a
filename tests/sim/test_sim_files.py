"""`sim gps add`, `sim world show|set`, `sim battery check` on local files, and the same
validators on `config push --as components|battery`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.templates import template_path
from tests.clirun import run
from tests.sim_world import WORLD

COMPONENTS = template_path("config", "panther-2.1", "panther_description", "config", "components.yaml")
BATTERY_21 = template_path("config", "panther-2.1", "panther_gazebo", "config", "battery_plugin_config.yaml")
BATTERY_20 = template_path("config", "panther-2.0", "panther_gazebo", "config", "battery_plugin_config.yaml")


def test_gps_add_the_manuals_entry(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "components.yaml"
    original = COMPONENTS.read_text()
    f.write_text(original)
    code, out, err = run(capsys, "sim", "gps", "add", str(f), "--dry-run")
    assert code == 0 and f.read_text() == original
    # a dry run says "would change" once, as the fleet commands do (not "changed: would change (dry run)")
    assert out.endswith(f"{f}: would change: ANT02 entry added\n") and "changed" not in out.splitlines()[-1]
    assert "note dry run: nothing was written" in err
    code, out, _ = run(capsys, "sim", "gps", "add", str(f), "--yes")
    assert code == 0
    text = f.read_text()
    assert "components:\n  - type: ANT02\n    parent_link: cover_link\n    xyz: 0.185 -0.12 0.0\n" \
           "    rpy: 0.0 0.0 3.14\n    device_namespace: gps\n" in text
    assert text.replace("components:\n  - type: ANT02\n    parent_link: cover_link\n    xyz: 0.185 -0.12 0.0\n"
                        "    rpy: 0.0 0.0 3.14\n    device_namespace: gps\n", "components: []\n") == original
    assert (tmp_path / "components.yaml.panther-ops.bak").read_text() == original
    code, out, _ = run(capsys, "sim", "gps", "add", str(f), "--yes", "--json")
    assert code == 0 and json.loads(out)["robots"][0]["outcome"] == "ok"
    code, out, _ = run(capsys, "sim", "gps", "add", str(f), "--xyz", "0.2 -0.1 0.05", "--yes")
    assert code == 0 and "    xyz: 0.2 -0.1 0.05\n" in f.read_text() and f.read_text().count("\n  - type: ANT02\n") == 1


@pytest.mark.parametrize(("content", "says"), [
    ("components:\n  - type: ANT02\n    colour: red\n", "components[0].colour: unknown key"),
    ("components:\n  - type: antenna\n", "components[0].type"),
    ("components:\n  - type: LDR01\n    xyz: 1 2\n", "components[0].xyz"),
    ("components: 3\n", "components=3 must be a list"),
    ("other: []\n", "other: unknown key (allowed: components)"),
])
def test_components_validator(tmp_path: Path, capsys: pytest.CaptureFixture[str], content: str, says: str) -> None:
    f = tmp_path / "c.yaml"
    f.write_text(content)
    code, _out, err = run(capsys, "sim", "gps", "add", str(f), "--yes")
    assert code == 2 and says in err and f.read_text() == content


def test_gps_add_bad_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "c.yaml"
    f.write_text(COMPONENTS.read_text())
    code, _out, err = run(capsys, "sim", "gps", "add", str(f), "--rpy", "0 0", "--yes")
    assert code == 2 and "--rpy" in err and f.read_text() == COMPONENTS.read_text()


def test_world_show_and_set_keep_formatting(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "w.sdf"
    f.write_text(WORLD)
    code, out, _ = run(capsys, "sim", "world", "show", str(f), "--json")
    sc = json.loads(out)["spherical_coordinates"]
    assert code == 0 and sc["latitude_deg"] == "53.1978" and sc["surface_model_ok"] is True
    code, _out, _ = run(capsys, "sim", "world", "set", str(f), "--latitude", "52.2297", "--longitude", "21.0122",
                        "--heading", "90", "--yes")
    assert code == 0
    want = WORLD.replace("<latitude_deg>53.1978", "<latitude_deg>52.2297").replace(
        "<longitude_deg>18.3732", "<longitude_deg>21.0122").replace(
        "      <elevation>0</elevation>\n", "      <elevation>0</elevation>\n      <heading_deg>90</heading_deg>\n")
    assert f.read_text() == want


def test_world_without_block_gets_the_manuals(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "w.sdf"
    bare = '<sdf version="1.6">\n  <world name="w">\n    <gravity>0 0 -9.8</gravity>\n  </world>\n</sdf>\n'
    f.write_text(bare)
    code, out, _ = run(capsys, "sim", "world", "show", str(f))
    assert code == 0 and "no <spherical_coordinates>" in out
    assert run(capsys, "sim", "world", "set", str(f), "--elevation", "120.5", "--yes")[0] == 0
    text = f.read_text()
    assert "    <spherical_coordinates>\n      <surface_model>EARTH_WGS84</surface_model>\n" in text
    assert "<elevation>120.5</elevation>" in text and "<latitude_deg>53.1978</latitude_deg>" in text


@pytest.mark.parametrize(("argv", "content", "says"), [
    (["--latitude", "91"], WORLD, "--latitude 91"),
    (["--longitude", "-181"], WORLD, "--longitude -181"),
    (["--latitude", "1"], WORLD.replace("EARTH_WGS84", "EARTH_SPHERE"), "EARTH_WGS84"),
    (["--latitude", "1"], "<sdf><world>", "not well-formed XML"),
    ([], WORLD, "nothing to set"),
])
def test_world_set_refuses(tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], content: str,
                           says: str) -> None:
    f = tmp_path / "w.sdf"
    f.write_text(content)
    code, _out, err = run(capsys, "sim", "world", "set", str(f), *argv, "--yes")
    assert code == 2 and says in err and f.read_text() == content


def test_battery_check(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    percent = tmp_path / "percent.yaml"  # panther_ros 2.0.0's form: no fraction note
    percent.write_text("simulate_discharging: false\ninitial_charge_percentage: 70.0\ncharging_time: 6.0\n")
    code, _out, err = run(capsys, "sim", "battery", "check", str(percent))
    assert code == 0 and "0-1 fraction" not in err
    code, _out, err = run(capsys, "sim", "battery", "check", str(BATTERY_20))  # 2.0.1-2.0.4: a fraction
    assert code == 0 and "0-1 fraction of panther_ros 2.0.1+" in err
    code, out, _ = run(capsys, "sim", "battery", "check", str(BATTERY_21), "--json")
    doc = json.loads(out)
    assert code == 0 and any("0-1 fraction" in n and "70 %" in n for n in doc["notes"])
    for content, says in (("simulate_discharging: 1\n", "simulate_discharging"),
                          ("initial_charge_percentage: 140\n", "0-100"),
                          ("charging_time: 0\n", "charging_time"), ("power_load: -5\n", "power_load"),
                          ("capacity: many\n", "capacity"), ("voltage: 12\n", "voltage: unknown key")):
        f = tmp_path / "b.yaml"
        f.write_text(content)
        code, _out, err = run(capsys, "sim", "battery", "check", str(f))
        assert code == 2 and says in err, content


def test_push_uses_the_same_validators(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    bad = tmp_path / "components.yaml"
    bad.write_text("components:\n  - type: ANT02\n    xyz: here\n")
    code, _out, err = run(capsys, "-i", str(tmp_path / "demo"), "config", "push", str(bad), "--as", "components",
                          "-r", "panther-01", "--dry-run")
    assert code == 2 and "components[0].xyz" in err
    battery = tmp_path / "battery.yaml"
    battery.write_text("simulate_discharging: true\ninitial_charge_percentage: 250\n")
    code, _out, err = run(capsys, "-i", str(tmp_path / "demo"), "config", "push", str(battery), "--as", "battery",
                          "-r", "panther-01", "--dry-run")
    assert code == 2 and "initial_charge_percentage" in err


def test_a_file_that_is_not_text_is_refused_naming_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "components.yaml"
    bad.write_bytes(b"components:\n  - type: \xff\xfe\n")
    code, _, err = run(capsys, "sim", "gps", "add", str(bad), "--yes")
    assert code == 2 and str(bad) in err and "not UTF-8 text" in err
    assert bad.read_bytes() == b"components:\n  - type: \xff\xfe\n"
    assert not (tmp_path / "components.yaml.panther-ops.bak").exists()


def test_world_set_checks_the_values_it_does_not_change(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 23, finding 2: a latitude already in the file is checked when only the longitude
    changes (200, or written in degrees-minutes-seconds), naming the key and the fix; the
    edit that sets the bad value itself goes through."""
    f = tmp_path / "w.sdf"
    for bad, says in (("200", "latitude_deg='200' is not a number from -90 to 90 (decimal degrees); fix: "
                              f"panther-ops sim world set {f} --latitude VALUE"),
                      ("53°11'52\"N", f"is degrees, minutes and seconds: Gazebo reads decimal degrees; fix: "
                                      f"panther-ops sim world set {f} --latitude 53.197778")):
        content = WORLD.replace("<latitude_deg>53.1978", f"<latitude_deg>{bad}")
        f.write_text(content)
        (tmp_path / "w.sdf.panther-ops.bak").unlink(missing_ok=True)
        code, _out, err = run(capsys, "sim", "world", "set", str(f), "--longitude", "21.0122", "--yes")
        assert code == 2 and f"{f}: world file refused (1 error)" in err and says in err, err
        assert f.read_text() == content and not (tmp_path / "w.sdf.panther-ops.bak").exists()
        code, _out, err = run(capsys, "sim", "world", "set", str(f), "--latitude", "53.197778", "--yes")
        assert code == 0, err
        assert f.read_text() == WORLD.replace("<latitude_deg>53.1978", "<latitude_deg>53.197778")


def test_world_show_names_what_is_wrong(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "w.sdf"
    f.write_text(WORLD.replace("<latitude_deg>53.1978", "<latitude_deg>200"))
    code, out, err = run(capsys, "sim", "world", "show", str(f))
    assert code == 3 and "latitude_deg: 200" in out
    assert "warning: spherical_coordinates.latitude_deg='200' is not a number from -90 to 90" in err
    code, out, _ = run(capsys, "sim", "world", "show", str(f), "--json")
    assert code == 3 and "-90 to 90" in json.loads(out)["problems"][0]
    f.write_text(WORLD)
    code, out, _ = run(capsys, "sim", "world", "show", str(f), "--json")
    assert code == 0 and json.loads(out)["problems"] == []


def test_world_set_edits_the_block_gazebo_reads_not_a_commented_one(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "w.sdf"
    old = "    <!-- <spherical_coordinates><latitude_deg>1</latitude_deg></spherical_coordinates> -->\n"
    content = WORLD.replace("    <spherical_coordinates>", old + "    <spherical_coordinates>", 1)
    f.write_text(content)
    assert run(capsys, "sim", "world", "set", str(f), "--latitude", "10", "--yes")[0] == 0
    assert f.read_text() == content.replace("<latitude_deg>53.1978", "<latitude_deg>10")
    bare = '<sdf version="1.6">\n  <!-- <world name="old">\n  </world> -->\n  <world name="w">\n  </world>\n</sdf>\n'
    f.write_text(bare)
    assert run(capsys, "sim", "world", "set", str(f), "--elevation", "3", "--yes")[0] == 0
    text = f.read_text()
    head = bare.split('  <world name="w">', maxsplit=1)[0]
    assert text.startswith(head + '  <world name="w">\n    <spherical_coordinates>\n')
    assert "<elevation>3</elevation>" in text


def test_components_xyz_in_ascii_digits(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 23, finding 3: the components file kind and `sim gps add --xyz` take ASCII digits
    only (float() takes '０.1', '1_0'; xacro and the URDF parser do not)."""
    f = tmp_path / "c.yaml"
    for xyz in ("０.1 0 0", "1_0 0 0", "0.1\u30000 0"):
        content = f"components:\n  - type: LDR06\n    parent_link: cover_link\n    xyz: {xyz}\n"
        f.write_text(content)
        code, _out, err = run(capsys, "sim", "gps", "add", str(f), "--yes")
        assert code == 2 and "components[0].xyz=" in err and f.read_text() == content, xyz
    f.write_text(COMPONENTS.read_text())
    code, _out, err = run(capsys, "sim", "gps", "add", str(f), "--xyz", "０.2 0 0", "--yes")
    assert code == 2 and "--xyz '０.2 0 0'" in err and f.read_text() == COMPONENTS.read_text()
    assert run(capsys, "sim", "gps", "add", str(f), "--xyz", "0.2  -1e-1 .05", "--yes")[0] == 0
    assert "    xyz: 0.2 -1e-1 .05\n" in f.read_text()

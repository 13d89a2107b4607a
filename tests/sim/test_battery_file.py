"""Issue 24 finding 8: the simulation battery file's scale per version.

Facts: panther_ros@2.0.0:panther_description/urdf/gazebo.urdf.xacro computes the initial charge
as ``20.0*initial_charge_percentage/100.0`` (percent); from panther_ros@2.0.1 (and at 2.0.4,
2.1.1) as ``initial_charge_percentage*capacity`` (a 0-1 fraction), reading all five keys.
The stock files (panther_ros@2.0.4 and @2.1.1:panther_gazebo/config/battery_plugin_config.yaml)
say simulate_discharging false, capacity 20.0, initial_charge_percentage 0.7, charging_time 6.0,
power_load 120.0.
"""

from __future__ import annotations

import pytest
import yaml

from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.robot.files import config_file
from panther_ops.core.stack import stack_from_version

STOCK = {"simulate_discharging": False, "capacity": 20.0, "initial_charge_percentage": 0.7, "charging_time": 6.0,
         "power_load": 120.0}
PERCENT_200 = b"simulate_discharging: false\ninitial_charge_percentage: 70.0\ncharging_time: 6.0\npower_load: 120.0\n"


@pytest.mark.parametrize("version", ["2.0.1", "2.0.4", "2.1.0", "2.1.1"])
def test_template_is_the_stock_file_and_is_accepted(version: str) -> None:
    stack = stack_from_version(version)
    text = config_file(stack, FileKind.BATTERY).template_text()
    assert yaml.safe_load(text) == STOCK
    assert check_file(FileKind.BATTERY, "b.yaml", text.encode(), target=Target(stack)) == []


@pytest.mark.parametrize("version", ["2.0.1", "2.0.4", "2.1.1"])
def test_percent_is_refused_from_201(version: str) -> None:
    data = yaml.safe_dump({**STOCK, "initial_charge_percentage": 70.0}).encode()
    with pytest.raises(FileKindError, match=r"initial_charge_percentage=70.0 is outside 0-1"):
        check_file(FileKind.BATTERY, "b.yaml", data, target=Target(stack_from_version(version)))


def test_200_takes_percent_and_no_capacity() -> None:
    s200 = stack_from_version("2.0.0")
    assert check_file(FileKind.BATTERY, "b.yaml", PERCENT_200, target=Target(s200)) == []
    assert config_file(s200, FileKind.BATTERY).template is None


def test_every_key_the_urdf_reads_is_required() -> None:
    for key in STOCK:
        data = yaml.safe_dump({k: v for k, v in STOCK.items() if k != key}).encode()
        with pytest.raises(FileKindError, match=f"{key} is required"):
            check_file(FileKind.BATTERY, "b.yaml", data, target=Target(stack_from_version("2.0.4")))

"""The mission campaign's options: positions from the scenario, parameter overrides."""

from __future__ import annotations

import pytest

from sitl.campaign import _positions, _sets


def test_positions_default_to_the_scenarios_own():
    assert _positions("paper_pool", None) == ("2", "3")
    assert _positions("far_diver", None) == ("far-4.5", "far-5")
    assert _positions("paper_pool", "3") == ("3",)


def test_set_overrides_parse_yaml_scalars():
    assert _sets(["sitl.pose_source=blazepose", "sitl.max_sim_time_s=30"]) == {
        "sitl.pose_source": "blazepose", "sitl.max_sim_time_s": 30}
    with pytest.raises(SystemExit, match="KEY=VALUE"):
        _sets(["nope"])

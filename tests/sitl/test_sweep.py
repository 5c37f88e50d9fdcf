"""``python -m sitl.sweep``: the grid, its errors and the per-cell outcome tables (sitl/sweep.py)."""

from __future__ import annotations

import pytest

from sitl import sweep as sweep_module
from sitl.sweep import SweepError, cells, format_tables, parse_grid, sweep


def test_grid_cells_are_every_combination_in_order():
    grid = parse_grid(["selection.method=default,paper", "candidates.lowe_ratio=0.3,0.6,0.8"])
    assert grid == [("selection.method", ["default", "paper"]), ("candidates.lowe_ratio", [0.3, 0.6, 0.8])]
    got = cells(grid)
    assert len(got) == 6 and got[0] == {"selection.method": "default", "candidates.lowe_ratio": 0.3}
    assert got[-1] == {"selection.method": "paper", "candidates.lowe_ratio": 0.8}


@pytest.mark.parametrize("item, message", [
    ("selection.method", "expected KEY=V1,V2"),
    ("no.such_parameter=1,2", "unknown parameter 'no.such_parameter'"),
])
def test_bad_grid_items_name_the_item(item, message):
    with pytest.raises(SweepError, match=message):
        parse_grid([item])


def test_a_parameter_given_twice_is_refused():
    with pytest.raises(SweepError, match="given twice"):
        parse_grid(["selection.method=paper", "selection.method=default"])


def test_every_cell_gets_its_parameters_and_one_table(monkeypatch):
    seen = []

    def fake_run(args):  # (cell index, seed, scenario, sets): the mission stands in for a real one
        cell, seed, scenario, sets = args
        seen.append((cell, seed, dict(sets)))
        outcome = "reached" if sets["selection.method"] == "default" or seed == 1 else "wrong_object"
        return {"cell": cell, "seed": seed, "outcome": outcome, "chosen_id": 1, "target_id": 1,
                "time_to_arrive_s": 10.0 + seed, "range_error_at_arrival_m": 0.1, "sim_time_s": 20.0,
                "wall_time_s": 1.0}

    monkeypatch.setattr(sweep_module, "_run", fake_run)
    grid = parse_grid(["selection.method=default,paper"])
    result = sweep(grid, [0, 1], sets={"sitl.max_sim_time_s": 30.0}, verbose=False)
    assert [c["params"] for c in result["cells"]] == [{"selection.method": "default"}, {"selection.method": "paper"}]
    assert all(s["sitl.max_sim_time_s"] == 30.0 for _, _, s in seen)
    assert result["cells"][0]["outcomes"] == {"reached": 2}
    assert result["cells"][1]["outcomes"] == {"reached": 1, "wrong_object": 1}
    assert result["cells"][0]["median_time_to_arrive_s"] == 10.5
    text = format_tables(result)
    assert text.count("cell selection.method=") == 2 and "summary" in text and "wrong_object" in text

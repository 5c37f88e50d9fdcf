"""Metrics on hand-made results: object assignment, hit/miss, mean +- std, the Table I layout."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from dip3d_vehicle.dataset import FrameAnnotation, load_dataset
from dip3d_vehicle.errors import DatasetError
from dip3d_vehicle.evaluation import (Report, assign_object, format_summary, format_table, frame_outcome,
                                      mean_std)

OBJECTS = {"1": (1300.0, 760.0), "2": (1080.0, 590.0), "3": (950.0, 540.0)}


def _ann(index: int, target: str, position: str = "2", polygons: dict | None = None) -> FrameAnnotation:
    return FrameAnnotation(index, target, dict(OBJECTS), polygons or {}, None, position,
                           {"1": 1.0, "2": 2.0, "3": 3.0}, 2.0)


def _result(px=None, status="ok") -> dict:
    return {"status": status, "target": None if px is None else {"left_px": list(px), "index": 0}}


def test_nearest_object_and_polygon_win():
    ann = _ann(0, "2")
    assert assign_object((1000.0, 560.0), ann) == "3"  # nearer to 3's centre (50, 20) than 2's (80, 30)
    square = np.array([[1060.0, 500.0], [1200.0, 500.0], [1200.0, 640.0], [1060.0, 640.0]])
    ann_poly = _ann(0, "2", polygons={"2": square})
    assert assign_object((1000.0, 560.0), ann_poly) == "3"  # outside every polygon: nearest point
    assert assign_object((1065.0, 505.0), ann_poly) == "2"  # inside 2's outline
    # inside a polygon beats a nearer centre of another object
    ann_big = _ann(0, "1", polygons={"1": np.array([[900.0, 500.0], [1400.0, 500.0], [1400.0, 800.0],
                                                    [900.0, 800.0]])})
    assert assign_object((960.0, 545.0), ann_big) == "1"


def test_outcomes_hit_wrong_and_no_selection():
    ann = _ann(3, "2")
    hit = frame_outcome(ann, _result((1083.0, 594.0)))
    assert hit.correct and hit.chosen == "2" and hit.error_px == pytest.approx(5.0)
    assert hit.miss_reason is None and hit.target_range_m == 2.0
    wrong = frame_outcome(ann, _result((955.0, 540.0)))
    assert not wrong.correct and wrong.chosen == "3" and wrong.miss_reason == "wrong_object"
    assert wrong.error_px == pytest.approx(math.hypot(125.0, 50.0))
    none = frame_outcome(ann, _result(None, "no_pose"))
    assert none.chosen is None and not none.correct and none.miss_reason == "no_pose" and none.error_px is None


def test_mean_std_is_the_population_std():
    assert mean_std([3.0, 5.0]) == (4.0, 1.0, 2)
    m, s, n = mean_std([])
    assert math.isnan(m) and math.isnan(s) and n == 0


def _report() -> Report:
    rep = Report("paper", labels={"1": "1", "2": "2", "3": "3"})
    rows = [("2", "1", (1303.0, 764.0)), ("2", "1", (1300.0, 770.0)), ("2", "2", (950.0, 541.0)),
            ("3", "2", (1080.0, 596.0)), ("3", "3", None), ("3", "3", (950.0, 548.0))]
    for i, (pos, tgt, px) in enumerate(rows):
        rep.outcomes.append(frame_outcome(_ann(i, tgt, pos), _result(px, "ok" if px else "pose_rejected")))
    return rep


def test_report_summary_cells_and_frequencies():
    rep = _report()
    s = rep.summary()
    assert (s["frames"], s["correct"], s["selected"]) == (6, 4, 5)
    assert s["hit_rate"] == pytest.approx(4 / 6)
    assert s["misses"] == {"pose_rejected": 1, "wrong_object": 1}
    errors = [5.0, 10.0, 6.0, 8.0]
    assert s["error_px_mean"] == pytest.approx(np.mean(errors))
    assert s["error_px_std"] == pytest.approx(np.std(errors))
    cell = rep.cell("2", "1")
    assert (cell["frames"], cell["correct"]) == (2, 2) and cell["error_px_mean"] == pytest.approx(7.5)
    assert rep.cell("2", "2")["correct"] == 0
    assert rep.chosen_frequency()[("3", "3")] == {"none": 0.5, "3": 0.5}
    assert rep.chosen_frequency()[("2", "2")] == {"3": 1.0}
    doc = json.loads(json.dumps(rep.to_json()))  # plain JSON, NaN -> null
    assert doc["table"]["2"]["2"]["error_px_mean"] is None and len(doc["frames"]) == 6


def test_table_layout_like_table_one():
    text = format_table(_report())
    lines = text.splitlines()
    assert lines[0].split() == ["position", "target", "1", "target", "2", "target", "3", "all", "targets"]
    assert set(lines[1]) <= {"-", " "}
    assert [ln.split()[0] for ln in lines[2:]] == ["2", "3", "all"]
    assert "7.5 +- 2.5 (2/2)" in lines[2] and "- (0/1)" in lines[2]
    assert "6.0 +- 0.0 (1/1)" in lines[3] and "8.0 +- 0.0 (1/2)" in lines[3]
    assert lines[4].rstrip().endswith("7.2 +- 1.9 (4/6)")
    assert "hit rate 0.667 (4/6)" in format_summary(_report())


def _write(tmp_path, doc, calib=True):
    (tmp_path / "annotations.json").write_text(json.dumps(doc))
    if calib:
        (tmp_path / "calib.yaml").write_text("%YAML:1.0\n")
    return tmp_path


GOOD = {"objects": {"1": {"label": "a"}, "2": {}}, "frames": [{"index": 0, "target": 2,
                                                              "objects": {"1": [1, 2], "2": [3, 4]}}]}


@pytest.mark.parametrize("doc, needle", [
    ({**GOOD, "frames": []}, "frames: expected a non-empty list"),
    ({**GOOD, "frames": [{"index": 0, "target": "3", "objects": {"1": [1, 2]}}]}, "frames[0].target: '3'"),
    ({**GOOD, "frames": [{"index": 0, "target": "1", "objects": {"7": [1, 2]}}]}, "frames[0].objects.7: unknown"),
    ({**GOOD, "frames": [{"index": 0, "target": "1", "objects": {"1": [1]}}]}, "frames[0].objects.1: expected [x, y]"),
    ({**GOOD, "frames": [{"index": -1, "target": "1", "objects": {"1": [1, 2]}}]}, "frames[0].index"),
    ({**GOOD, "frames": GOOD["frames"] * 2}, "index 0 is annotated twice"),
    ({**GOOD, "frames": [{**GOOD["frames"][0], "keypoints": {"left": {}}}]}, "frames[0].keypoints"),
])
def test_dataset_errors_name_the_field(tmp_path, doc, needle):
    with pytest.raises(DatasetError, match="annotations.json") as err:
        load_dataset(_write(tmp_path, doc))
    assert needle in str(err.value)


def test_dataset_missing_files(tmp_path):
    with pytest.raises(DatasetError, match="dataset folder not found"):
        load_dataset(tmp_path / "nope")
    with pytest.raises(DatasetError, match="annotations.json: annotations file not found"):
        load_dataset(tmp_path)
    with pytest.raises(DatasetError, match="calib.yaml: calibration file not found"):
        load_dataset(_write(tmp_path, GOOD, calib=False))
    ds = load_dataset(_write(tmp_path, GOOD))
    assert ds.frames[0].target == "2" and ds.label("1") == "a" and ds.label("2") == "2"
    with pytest.raises(DatasetError, match="no stereo pairs found"):
        list(ds.pairs())


def test_decision_class_keeps_nothing_on_ray_and_abstentions_apart_from_wrong_picks():
    """nothing_on_ray, ambiguous and rejected frames are not wrong picks; confident wrong is split out."""
    from dip3d_vehicle.evaluation import decision_class
    target = {"left_px": [1.0, 2.0]}
    assert decision_class({"status": "ok", "target": target, "selection": {"confidence": 0.9}}, True) == "correct"
    assert decision_class({"status": "nothing_on_ray", "target": None,
                           "selection": {"confidence": 0.9, "none_probability": 0.9}}, False) == "nothing_on_ray"
    assert decision_class({"status": "pose_rejected", "target": None, "selection": None}, False) == "abstained"
    assert decision_class({"status": "ok", "target": target,
                           "selection": {"confidence": 0.5, "ambiguous": True}}, False) == "abstained"
    assert decision_class({"status": "ok", "target": target,
                           "selection": {"confidence": 0.95, "ambiguous": False}}, False) == "wrong_confident"
    assert decision_class({"status": "ok", "target": target,
                           "selection": {"confidence": 0.7, "ambiguous": False}}, False) == "wrong_unsure"

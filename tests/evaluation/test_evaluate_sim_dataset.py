"""evaluate on a tiny simulator dataset: both profiles run, the tables print, both PNGs are written."""

from __future__ import annotations

import json

import cv2

from dip3d_vehicle.cli import main
from dip3d_vehicle.dataset import load_dataset
from dip3d_vehicle.plots import FIG6_FILE, RANGE_FILE


def test_simulator_dataset_is_annotated(sim_dataset):
    ds = load_dataset(sim_dataset)
    assert [f.index for f in ds.frames] == [0, 1, 2, 3]
    assert [(f.diver_position, f.target) for f in ds.frames] == [("2", "2"), ("2", "2"), ("3", "1"), ("3", "1")]
    for f in ds.frames:
        assert set(f.objects) == {"1", "2", "3"} and set(f.polygons) == {"1", "2", "3"}
        assert f.keypoints is not None  # paper_pool's 2 % dropout does not hit these four
        assert 0.9 < f.range_m["1"] < 1.1 and 2.9 < f.range_m["3"] < 3.1
        assert f.diver_range_m is not None
    rig = ds.rig((800, 600))
    assert rig.image_size == (800, 600) and abs(rig.baseline_m - 0.12) < 1e-6


def test_evaluate_prints_both_tables_and_writes_the_plots(sim_dataset, tmp_path, capsys):
    plots = tmp_path / "plots"
    assert main(["evaluate", str(sim_dataset), "--plots", str(plots), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "pose from annotated keypoints" in out  # the dataset's keypoints, whatever pose.backend says
    assert "profile paper: 4 frames" in out and "profile default: 4 frames" in out
    assert out.count("position  target 1") == 2 and "wrote" in out
    for name in (FIG6_FILE, RANGE_FILE):
        image = cv2.imread(str(plots / name))
        assert image is not None and image.shape[0] > 300 and image.shape[1] > 300


def test_evaluate_json_one_profile(sim_dataset, capsys):
    assert main(["evaluate", str(sim_dataset), "--json", "--profile", "default", "--progress"]) == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert list(doc["profiles"]) == ["default"]
    rep = doc["profiles"]["default"]
    assert rep["summary"]["frames"] == 4 and len(rep["frames"]) == 4
    assert set(rep["table"]) == {"2", "3"} and set(rep["table"]["2"]) == {"1", "2"}
    assert "evaluate [" in captured.err  # --progress forces the bar onto a non-TTY stderr
    s = rep["summary"]
    assert s["correct"] + sum(s["misses"].values()) == 4


def test_evaluate_bad_dataset_is_one_line(tmp_path, capsys):
    assert main(["evaluate", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("dip3d-vehicle evaluate: error:") and "annotations.json" in err
    assert "\n" not in err

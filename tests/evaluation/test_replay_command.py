"""replay on a run log written here: same params -> same decisions; other params -> changed ones."""

from __future__ import annotations

import json

import pytest

from dip3d_vehicle.cli import main
from dip3d_vehicle.commands.replay import replay_params
from dip3d_vehicle.config import load_params
from dip3d_vehicle.dataset import load_dataset
from dip3d_vehicle.perception.pipeline import Perception, make_pose_estimator
from dip3d_vehicle.record.mcap_log import McapRunWriter


def _write_log(path, dataset_dir, meta, params):
    """Run perception over the dataset as a run would, logging frames, keypoints and png pairs."""
    ds = load_dataset(dataset_dir)
    decisions = {}
    with McapRunWriter(path, params, meta, image_format="png") as log:
        engine = None
        for ann, frame in ds.pairs():
            if engine is None:
                engine = Perception(ds.rig((frame.left.shape[1], frame.left.shape[0]), params), params,
                                    make_pose_estimator(params, None))
            engine.pose.provide(ann.keypoints)
            out = engine.process(frame.left, frame.right).to_json(engine.rig)
            log.frame({"index": ann.index, "status": out["status"], "target": out["target"],
                       "keypoints": ann.keypoints, "candidates_followed": out["candidates_followed"]})
            log.images(ann.index, frame.left, frame.right)
            decisions[ann.index] = out
    return decisions


@pytest.fixture(scope="module")
def run_log(sim_dataset, tmp_path_factory):
    path = tmp_path_factory.mktemp("replay") / "dive.mcap"
    params = load_params("paper", overrides={"pose.backend": "keypoints"})  # the simulator's pose source
    decisions = _write_log(path, sim_dataset, {"calib": str(sim_dataset / "calib.yaml")}, params)
    return path, decisions


def test_same_params_same_decisions(run_log, capsys):
    path, decisions = run_log
    assert main(["replay", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["frames"] == 4 and doc["changed"] == 0 and doc["ignored_params"] == []
    for row in doc["replayed"]:
        want = decisions[row["index"]]
        assert row["new"]["status"] == want["status"] == row["old"]["status"]
        assert row["new"]["target"] == want["target"]


def test_other_params_change_decisions(run_log, capsys):
    path, decisions = run_log
    assert main(["replay", str(path), "--set", "filters.max_joint_dz_m=0.01"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert sum("CHANGED" in ln for ln in lines) == sum(d["status"] != "pose_rejected" for d in decisions.values())
    assert all("-> pose_rejected" in ln for ln in lines[:4])
    assert "replayed 4 kept pairs" in lines[-1]


def test_params_rebuilt_from_the_header():
    header = {"params": {**load_params("paper", overrides={"pose.backend": "keypoints"}), "old.removed_key": 3}}
    params, unknown = replay_params(header, sets=["selection.extension_factor=2.5"])
    assert unknown == ["old.removed_key"]
    assert params["selection.method"] == "paper" and params["selection.extension_factor"] == 2.5
    assert params["candidates.lowe_ratio"] == 0.3 and params["pose.backend"] == "keypoints"
    params, _ = replay_params(header, profile="default")
    assert params["selection.method"] == "default"


def test_embedded_calibration_and_missing_calibration(sim_dataset, tmp_path, capsys):
    # every frame decided alone, as replay decides it (a run's frames decided on candidates followed
    # from earlier frames are compared on their status only: tests/perception/test_reuse.py)
    params = load_params("default", overrides={"pose.backend": "keypoints", "candidates.reuse_frames": 0})
    text = (sim_dataset / "calib.yaml").read_text()
    embedded = tmp_path / "embedded.mcap"
    decisions = _write_log(embedded, sim_dataset, {"calib_opencv_yaml": text}, params)
    assert main(["replay", str(embedded), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["changed"] == 0
    assert [r["new"]["target"] for r in doc["replayed"]] == [decisions[i]["target"] for i in range(4)]
    bare = tmp_path / "bare.mcap"
    with McapRunWriter(bare, params, {}) as log:
        frame = next(load_dataset(sim_dataset).pairs())[1]
        log.images(0, frame.left, frame.right)
    assert main(["replay", str(bare)]) == 2
    err = capsys.readouterr().err
    assert "bare.mcap: header meta has no 'calib'" in err

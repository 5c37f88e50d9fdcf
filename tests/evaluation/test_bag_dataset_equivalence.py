"""The same pairs from ROS 1 / ROS 2 bags (raw and png-compressed) and from a folder: same results.

Checked at two levels: every perception result (the ``perceive`` contract JSON, timings aside) and
every evaluate outcome, with the paper profile (its single-feature pick is the most sensitive to
any pixel difference). The folder's first pair is also run through the ``perceive`` command itself.
"""

from __future__ import annotations

import json
import shutil

import pytest

from bag_writing import write_stereo_bag
from dip3d_vehicle.cli import main
from dip3d_vehicle.config import load_params
from dip3d_vehicle.dataset import load_dataset
from dip3d_vehicle.evaluation import evaluate_dataset
from dip3d_vehicle.sources import write_folder
from dip3d_vehicle.frames import StereoFrame

PICK = (0, 2)  # one pair of each seed: position 2 -> placard 2, position 3 -> placard 1


def _run(dataset_dir) -> tuple[dict, dict]:
    """Return ({profile: outcomes}, {(profile, index): contract JSON without timings})."""
    results = {}

    def keep(name, ann, result):
        results[(name, ann.index)] = {k: v for k, v in result.items() if k != "timings_ms"}

    profiles = {"paper": load_params("paper")}
    reports = evaluate_dataset(load_dataset(dataset_dir), profiles, on_result=keep)
    return {n: r.outcomes for n, r in reports.items()}, results


@pytest.fixture(scope="module")
def twins(sim_dataset, tmp_path_factory):
    """The picked pairs as a folder dataset and as four bag datasets (same annotations, calib)."""
    root = tmp_path_factory.mktemp("twins")
    doc = json.loads((sim_dataset / "annotations.json").read_text())
    frames = [dict(doc["frames"][i], index=k) for k, i in enumerate(PICK)]
    ds = load_dataset(sim_dataset)
    pairs = {ann.index: (f.left, f.right) for ann, f in ds.pairs()}
    picked = [pairs[i] for i in PICK]
    out = {}
    folder = root / "folder"
    write_folder(folder, [StereoFrame(l, r, 0.1 * k, k) for k, (l, r) in enumerate(picked)])
    out["folder"] = folder
    for version in ("ros1", "ros2"):
        for encoding in ("bgr8", "png"):
            d = root / f"{version}_{encoding}"
            d.mkdir()
            bag = write_stereo_bag(d / ("dive.bag" if version == "ros1" else "dive"), version, picked, encoding)
            out[d.name] = d
            (d / "annotations.json").write_text(json.dumps({**doc, "frames": frames, "source": f"bag:{bag.name}"}))
    (folder / "annotations.json").write_text(json.dumps({**doc, "frames": frames}))
    for d in out.values():
        shutil.copy(sim_dataset / "calib.yaml", d / "calib.yaml")
    return out


@pytest.fixture(scope="module")
def folder_run(twins):
    return _run(twins["folder"])


def test_bags_give_the_folder_results(twins, folder_run):
    want_outcomes, want_results = folder_run
    assert len(want_results) == 2 and any(r["status"] == "ok" for r in want_results.values())
    for name in ("ros1_bgr8", "ros1_png", "ros2_bgr8", "ros2_png"):
        outcomes, results = _run(twins[name])
        assert results == want_results, name
        assert outcomes == want_outcomes, name


def test_perceive_command_on_the_folder_pair_matches(twins, folder_run, tmp_path, capsys):
    folder = twins["folder"]
    ann = load_dataset(folder).frames[0]
    kp = tmp_path / "kp.json"
    kp.write_text(json.dumps(ann.keypoints))
    _, results = folder_run
    for profile in ("paper",):
        assert main(["perceive", "--left", str(folder / "left_000000.png"), "--right",
                     str(folder / "right_000000.png"), "--calib", str(folder / "calib.yaml"),
                     "--keypoints", str(kp), "--profile", profile, "--json"]) == 0
        got = json.loads(capsys.readouterr().out)
        got = {k: v for k, v in got.items() if k not in ("timings_ms", "profile")}
        assert got == results[(profile, 0)], profile

"""Tests of ``dip3d-vehicle pose IMAGE``."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from dip3d_vehicle.cli import main


def test_pose_json_on_photo(shared_dir, capsys):
    path = shared_dir / "data" / "photos" / "astronaut.png"
    reference = json.loads((path.parent / "mediapipe_reference.json").read_text())["images"]
    assert main(["pose", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["found"] is True and out["arm"] == "right"
    assert set(out["keypoints"]) == {"shoulder", "elbow", "wrist"}
    shoulder = np.array(out["keypoints"]["shoulder"])
    assert shoulder.shape == (3,) and 0.0 <= shoulder[2] <= 1.0
    mp = np.array(reference["astronaut.png"]["landmarks_px"][12][:2])
    assert np.linalg.norm(shoulder[:2] - mp) < 5.0


def test_pose_left_arm_text(shared_dir, capsys):
    path = shared_dir / "data" / "photos" / "astronaut.png"
    assert main(["pose", str(path), "--arm", "left"]) == 0
    assert "left arm" in capsys.readouterr().out


def test_pose_auto_arm_reports_the_arm_it_picked(shared_dir, capsys):
    path = shared_dir / "data" / "photos" / "000000196141.jpg"     # the left arm raised, the right one unseen
    assert main(["pose", str(path), "--arm", "auto", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["arm"] == "left"


def test_pose_no_person(tmp_path, capsys):
    path = tmp_path / "grey.png"
    cv2.imwrite(str(path), np.full((200, 300, 3), 128, np.uint8))
    assert main(["pose", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"found": False, "arm": "right", "keypoints": None}


@pytest.mark.parametrize("content", [None, b"not an image"])
def test_pose_bad_image_is_one_line_exit_2(tmp_path, capsys, content):
    path = tmp_path / "bad.png"
    if content is not None:
        path.write_bytes(content)
    assert main(["pose", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("dip3d-vehicle pose: error:") and str(path) in err and "\n" not in err


def test_pose_truncated_jpeg_is_one_line_exit_2(tmp_path, capfd):
    sample = Path(__file__).resolve().parents[1] / "dip3d_vehicle" / "samples" / "left.jpg"
    path = tmp_path / "cut.jpg"
    path.write_bytes(sample.read_bytes()[:60000])  # cut mid-stream, as a copy interrupted
    assert main(["pose", str(path)]) == 2
    captured = capfd.readouterr()
    assert captured.out == "" and "Premature end" not in captured.err
    err = captured.err.strip()
    assert err.startswith("dip3d-vehicle pose: error:") and str(path) in err and "\n" not in err


def test_pose_annotate_writes_the_image_with_the_same_size(tmp_path, capsys):
    sample = Path(__file__).resolve().parents[1] / "dip3d_vehicle" / "samples" / "left.jpg"
    out = tmp_path / "pose.png"
    assert main(["pose", str(sample), "--annotate", str(out), "--json"]) == 0
    found = json.loads(capsys.readouterr().out)["found"]
    img, src = cv2.imread(str(out)), cv2.imread(str(sample))
    assert img.shape == src.shape and (img != src).any()  # something drawn ("no person found" or the arm)


def test_pose_annotate_to_an_unwritable_name_is_one_line_exit_2(tmp_path, capsys):
    sample = Path(__file__).resolve().parents[1] / "dip3d_vehicle" / "samples" / "left.jpg"
    assert main(["pose", str(sample), "--annotate", str(tmp_path / "out.unknown")]) == 2
    err = capsys.readouterr().err.strip()
    assert "out.unknown" in err and "\n" not in err

"""``dip3d-vehicle perceive``: the JSON contract on the bundled sample, and one clear line on bad input."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import cv2
import pytest

from dip3d_vehicle.cli import main

SAMPLE = Path(__file__).resolve().parents[1] / "dip3d_vehicle" / "samples"


def run_cli(args: list[str], capsys) -> tuple[int, str, str]:
    """Run the CLI in-process; return (exit code, stdout, stderr)."""
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


def test_sample_json_contract(capsys):
    """The bundled sample selects the placard the simulated diver points at, in contract form."""
    code, out, _ = run_cli(["perceive", "--sample", "--json"], capsys)
    assert code == 0
    res = json.loads(out)
    assert res["status"] == "ok"
    for key in ("target", "candidates", "arm", "timings_ms"):
        assert key in res
    assert set(res["target"]) >= {"left_px", "xyz_m", "index"}
    assert set(res["arm"]) == {"wrist", "elbow", "shoulder"}
    assert set(res["arm"]["wrist"]) >= {"left_px", "right_px", "xyz_m"}
    assert all(set(c) >= {"left_px", "xyz_m", "score"} for c in res["candidates"])
    truth = json.loads((SAMPLE / "truth.json").read_text())
    polygon = truth["placards"][str(truth["target_id"])]["left_polygon_px"]
    import numpy as np
    inside = cv2.pointPolygonTest(np.asarray(polygon, np.float32), tuple(res["target"]["left_px"]), False)
    assert inside >= 0
    assert res["target"]["xyz_m"][2] > 0


def test_paper_profile_and_annotation(tmp_path, capsys):
    """The paper profile runs and --annotate writes an image of the frame's size."""
    out_png = tmp_path / "ann.png"
    code, out, _ = run_cli(["perceive", "--sample", "--profile", "paper", "--json", "--annotate", str(out_png)], capsys)
    assert code == 0 and json.loads(out)["status"] == "ok"
    img = cv2.imread(str(out_png))
    assert img is not None and img.shape[:2] == (1200, 1600)


def _copy_sample(tmp_path: Path) -> dict:
    """Copy the sample to tmp_path; return its file paths."""
    for f in SAMPLE.iterdir():
        shutil.copy(f, tmp_path / f.name)
    return {k: str(tmp_path / v) for k, v in
            {"left": "left.jpg", "right": "right.jpg", "calib": "calib.yaml", "kp": "keypoints.json"}.items()}


def _args(p: dict) -> list[str]:
    """Return perceive arguments for a set of files."""
    return ["perceive", "--left", p["left"], "--right", p["right"], "--calib", p["calib"], "--keypoints", p["kp"]]


@pytest.mark.parametrize("case", ["missing_image", "corrupt_image", "size_mismatch", "frame_vs_calib",
                                  "bad_calib", "bad_keypoints", "unknown_param", "bad_param_value"])
def test_bad_input_gives_one_line_and_exit_2(tmp_path, capsys, case):
    """Every bad input: exit code 2, one line on stderr naming the file or key, no traceback."""
    p = _copy_sample(tmp_path)
    extra: list[str] = []
    expect = ""
    if case == "missing_image":
        p["left"] = str(tmp_path / "nope.png"); expect = "nope.png"
    elif case == "corrupt_image":
        Path(p["right"]).write_bytes(b"\xff\xd8not a jpeg"); expect = "right.jpg"
    elif case == "size_mismatch":
        img = cv2.imread(p["right"]); cv2.imwrite(p["right"], img[:600, :800]); expect = "right.jpg"
    elif case == "frame_vs_calib":
        for side in ("left", "right"):
            img = cv2.imread(p[side]); cv2.imwrite(p[side], img[:600, :800])
        expect = "calib.yaml"
    elif case == "bad_calib":
        text = Path(p["calib"]).read_text().replace("M1:", "Mx:")
        Path(p["calib"]).write_text(text); expect = "M1"
    elif case == "bad_keypoints":
        Path(p["kp"]).write_text('{"left": {"shoulder": [1, 2]}}'); expect = "keypoints.json"
    elif case == "unknown_param":
        extra = ["--set", "selection.foo=1"]; expect = "selection.foo"
    elif case == "bad_param_value":
        extra = ["--set", "candidates.lowe_ratio=7"]; expect = "candidates.lowe_ratio"
    code, out, err = run_cli(_args(p) + extra, capsys)
    assert code == 2, (out, err)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    assert expect in lines[0], lines[0]


def test_console_script_installed():
    """`pip install .` gives the dip3d-vehicle console command."""
    exe = shutil.which("dip3d-vehicle")
    assert exe, "dip3d-vehicle not on PATH"
    proc = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and "perceive" in proc.stdout

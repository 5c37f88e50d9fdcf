"""``dip3d-vehicle perceive``: the perception core on one stereo pair (DESIGN.md section 3)."""

from __future__ import annotations

import argparse
import json
from importlib import resources
from pathlib import Path

import cv2

from ..config import Params
from ..errors import ImageError
from ..perception.annotate import annotate
from ..perception.calibration_io import load_rig
from ..perception.images import check_pair, read_image
from ..perception.keypoints_file import load_keypoints_file
from ..perception.pipeline import Perception, make_pose_estimator
from ._common import add_params_arguments, params_from_args

NAME = "perceive"
HELP = "run the perception core on one stereo pair and print the pointed-at target"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the perceive arguments."""
    parser.add_argument("--left", help="left image (original, unrectified unless calib.already_rectified)")
    parser.add_argument("--right", help="right image")
    parser.add_argument("--calib", nargs="+", metavar="FILE",
                        help="calibration: OpenCV YAML (one merged file or intrinsics + extrinsics), "
                             "Kalibr camchain.yaml, or two ROS camera_info files")
    parser.add_argument("--keypoints", metavar="KP.json",
                        help="arm keypoints file (selects the keypoints pose backend)")
    parser.add_argument("--sample", action="store_true",
                        help="use the bundled sample (a simulated paper_pool pair, its calibration and its "
                             "ground-truth keypoints) for any input not given")
    add_params_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--annotate", metavar="OUT.png", help="write the left image with the result drawn on it")


def _sample_file(name: str) -> str:
    """Return the path of a bundled sample file."""
    return str(resources.files("dip3d_vehicle") / "samples" / name)


def _inputs(args: argparse.Namespace) -> tuple[str, str, list[str], str | None]:
    """Return (left, right, calib files, keypoints file) from the arguments and --sample."""
    left, right, calib, kp = args.left, args.right, args.calib, args.keypoints
    if args.sample:
        left = left or _sample_file("left.jpg")
        right = right or _sample_file("right.jpg")
        calib = calib or [_sample_file("calib.yaml")]
        kp = kp or _sample_file("keypoints.json")
    missing = [n for n, v in (("--left", left), ("--right", right), ("--calib", calib)) if not v]
    if missing:
        raise ImageError(f"missing {', '.join(missing)} (or use --sample for the bundled pair)")
    return left, right, calib, kp


def run(args: argparse.Namespace) -> int:
    """Run perception on one pair; print JSON or a summary; exit 0 for valid inputs."""
    left_path, right_path, calib, kp_path = _inputs(args)
    params: Params = params_from_args(args)
    keypoints = None
    if kp_path:
        keypoints = load_keypoints_file(kp_path)
        params = params.with_overrides({"pose.backend": "keypoints"}, "--keypoints")
    left, right = read_image(left_path), read_image(right_path)
    check_pair(left, right, left_path, right_path)
    h, w = left.shape[:2]
    rig = load_rig(calib, image_size=(w, h), alpha=params["calib.alpha"],
                   already_rectified=params["calib.already_rectified"])
    rig.check_frame(left, left_path)
    perception = Perception(rig, params, make_pose_estimator(params, keypoints))
    result = perception.process(left, right)
    out = result.to_json(rig)
    out["profile"] = params.profile
    if args.annotate:
        path = Path(args.annotate)
        if not cv2.imwrite(str(path), annotate(left, result, rig, params["selection.extension_factor"])):
            raise ImageError(f"{path}: cannot write the annotated image")
    if args.json:
        print(json.dumps(out))
    else:
        _print_summary(out)
    return 0


def _print_summary(out: dict) -> None:
    """Print a short human-readable result."""
    print(f"status: {out['status']}" + (f" ({out['reason']})" if out["reason"] else ""))
    target = out["target"]
    if target:
        sel = out["selection"]
        print(f"target: left_px {target['left_px']}  xyz_m {target['xyz_m']}  "
              f"({sel['method']}, confidence {sel['confidence']}, margin {sel['ambiguity_margin']}"
              f"{', AMBIGUOUS' if sel['ambiguous'] else ''})")
    print(f"candidates: {len(out['candidates'])} from {out['features']} matched features")
    print("timings_ms: " + ", ".join(f"{k} {v}" for k, v in out["timings_ms"].items()))

"""``dip3d-vehicle pose IMAGE``: run the BlazePose backend on one image and print the arm."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from ..errors import ImageError
from ..perception.values import JOINTS
from ._common import add_params_arguments, params_from_args

NAME = "pose"
HELP = "find the pointing arm's shoulder, elbow and wrist in one image (BlazePose backend)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    parser.add_argument("image", metavar="IMAGE", help="image file (any format OpenCV reads)")
    parser.add_argument("--arm", choices=["right", "left"], default=None,
                        help="arm to report (default: parameter pose.arm)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    add_params_arguments(parser)


def read_image(path: str) -> np.ndarray:
    """Return an image as HxWx3 uint8 BGR; raise ImageError naming the file when it cannot be read."""
    if not Path(path).is_file():
        raise ImageError(f"{path}: image file not found")
    image = cv2.imread(path, cv2.IMREAD_COLOR)
    if image is None or image.size == 0:
        raise ImageError(f"{path}: not an image OpenCV can read")
    return image


def arm_result(landmarks: Any, arm: str) -> dict:
    """Return the command's JSON object for a BlazePose result (None = no person)."""
    if landmarks is None:
        return {"found": False, "arm": arm, "keypoints": None}
    xy, conf = landmarks.arm(arm)
    keypoints = {name: [round(float(x), 2), round(float(y), 2), round(float(c), 4)]
                 for name, (x, y), c in zip(JOINTS, xy, conf)}
    return {"found": True, "arm": arm, "keypoints": keypoints,
            "pose_flag": round(float(landmarks.pose_flag), 4)}


def run(args: argparse.Namespace) -> int:
    """Run the pose backend on IMAGE and print the arm's keypoints in image pixels."""
    from ..perception.blazepose import BlazePose  # onnxruntime loads only for this command

    params = params_from_args(args)
    arm = args.arm or params["pose.arm"]
    image = read_image(args.image)
    result = arm_result(BlazePose.from_params(params).process(image), arm)
    if args.json:
        print(json.dumps(result))
    elif not result["found"]:
        print(f"{args.image}: no person found")
    else:
        print(f"{args.image}: {arm} arm (pose flag {result['pose_flag']:.3f})")
        for name, (x, y, c) in result["keypoints"].items():
            print(f"  {name:<8}  x {x:8.1f}  y {y:8.1f}  confidence {c:.3f}")
    return 0

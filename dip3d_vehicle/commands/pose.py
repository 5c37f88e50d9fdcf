"""``dip3d-vehicle pose IMAGE``: run the BlazePose backend on one image and print the arm."""

from __future__ import annotations

import argparse
import json
from typing import Any

import cv2
import numpy as np

from ..perception.images import read_image as read_checked_image, write_image
from ..perception.pointing_arm import ARMS, AUTO, pointing_arm
from ..perception.values import JOINTS
from ._common import add_params_arguments, params_from_args

NAME = "pose"
HELP = "find the pointing arm's shoulder, elbow and wrist in one image (BlazePose backend)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    parser.add_argument("image", metavar="IMAGE", help="image file (any format OpenCV reads)")
    parser.add_argument("--arm", choices=list(ARMS), default=None,
                        help="arm to report; auto = the one held away from the body (default: parameter pose.arm)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--annotate", metavar="OUT.png", default=None,
                        help="write the image with the arm's joints (and their confidence) drawn on it")
    add_params_arguments(parser)


def read_image(path: str) -> np.ndarray:
    """Return an image as HxWx3 uint8 BGR; raise ImageError naming the file when it cannot be read.

    The same reader as ``perceive``: a corrupt or truncated file is refused (one line, exit 2)
    instead of being decoded in part.
    """
    return read_checked_image(path)


def annotate_arm(image: np.ndarray, result: dict) -> np.ndarray:
    """Return a copy of the image with the arm drawn: joints (with confidence) and the limb segments."""
    img = image.copy()
    scale = max(1, img.shape[1] // 800)
    if not result["found"]:
        cv2.putText(img, "no person found", (10, 30 * scale), cv2.FONT_HERSHEY_SIMPLEX, 0.8 * scale, (0, 0, 255),
                    2 * scale)
        return img
    pts = [(int(round(x)), int(round(y))) for x, y, _ in result["keypoints"].values()]
    cv2.polylines(img, [np.asarray(pts, np.int32)], False, (255, 255, 0), 2 * scale)
    for (name, (x, y, c)), colour in zip(result["keypoints"].items(), ((0, 255, 255), (0, 165, 255), (0, 0, 255))):
        centre = (int(round(x)), int(round(y)))
        cv2.circle(img, centre, 5 * scale, colour, -1)
        cv2.putText(img, f"{name} {c:.2f}", (centre[0] + 8 * scale, centre[1] - 8 * scale), cv2.FONT_HERSHEY_SIMPLEX,
                    0.5 * scale, colour, max(1, scale))
    cv2.putText(img, f"{result['arm']} arm, pose flag {result['pose_flag']:.2f}", (10, 30 * scale),
                cv2.FONT_HERSHEY_SIMPLEX, 0.8 * scale, (255, 255, 255), 2 * scale)
    return img


def arm_result(landmarks: Any, arm: str) -> dict:
    """Return the command's JSON object for a BlazePose result (None = no person); "auto" reports the arm it picked."""
    if landmarks is None:
        return {"found": False, "arm": arm, "keypoints": None}
    if arm == AUTO:
        arm = pointing_arm(landmarks)
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
    if args.annotate:
        write_image(args.annotate, annotate_arm(image, result))
    if args.json:
        print(json.dumps(result))
    elif not result["found"]:
        print(f"{args.image}: no person found")
    else:
        print(f"{args.image}: {arm} arm (pose flag {result['pose_flag']:.3f})")
        for name, (x, y, c) in result["keypoints"].items():
            print(f"  {name:<8}  x {x:8.1f}  y {y:8.1f}  confidence {c:.3f}")
    return 0

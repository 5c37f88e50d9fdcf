"""Draw what the paper's figures show on the left image: arm, pointing vector, candidates, target."""

from __future__ import annotations

import cv2
import numpy as np

from .calibration import StereoRig
from .pipeline import PerceptionResult

__all__ = ["annotate"]

GREEN, WHITE, RED, YELLOW, CYAN = (0, 255, 0), (255, 255, 255), (0, 0, 255), (0, 255, 255), (255, 255, 0)


def _project(rig: StereoRig, xyz_m: np.ndarray) -> np.ndarray:
    """Project rectified-frame 3D points (metres) to ORIGINAL left-image pixels."""
    hom = np.c_[xyz_m, np.ones(len(xyz_m))] @ rig.P1.T
    return rig.to_original(hom[:, :2] / hom[:, 2:3], "left")


def _pt(p) -> tuple[int, int]:
    """Return an integer pixel tuple for cv2 drawing."""
    return int(round(float(p[0]))), int(round(float(p[1])))


def annotate(left: np.ndarray, result: PerceptionResult, rig: StereoRig, extension: float = 3.0) -> np.ndarray:
    """Return a copy of the ORIGINAL left image with the perception result drawn on it.

    Green: the pointing vector (wrist + 0..extension x forearm, projected); white: all candidates
    (objects for the default selector, matched features for the paper's); red: the chosen target;
    yellow/cyan: shoulder, elbow, wrist and the arm.
    """
    img = left.copy()
    scale = max(1, img.shape[1] // 800)
    if result.arm is not None:
        joints = rig.to_original(result.arm.left_px, "left")
        cv2.polylines(img, [np.round(joints).astype(np.int32)], False, CYAN, 2 * scale)
        for p in joints:
            cv2.circle(img, _pt(p), 5 * scale, YELLOW, -1)
    if result.arm3d is not None and np.all(np.isfinite(result.arm3d.xyz_m)):
        w, e = result.arm3d.joint("wrist"), result.arm3d.joint("elbow")
        line = np.array([w + t * (w - e) for t in np.linspace(0.0, extension, 25)])
        line = line[line[:, 2] > 0.05]
        if len(line) > 1:
            cv2.polylines(img, [np.round(_project(rig, line)).astype(np.int32)], False, GREEN, 2 * scale)
    sel = result.selection
    if sel is not None:
        for obj in sel.objects:
            cv2.circle(img, _pt(rig.to_original(obj.left_px, "left")[0]), 4 * scale, WHITE, -1)
        if sel.target is not None:
            p = _pt(rig.to_original(sel.target.left_px, "left")[0])
            cv2.circle(img, p, 14 * scale, RED, 3 * scale)
            label = f"{sel.method} conf {sel.confidence:.2f}"
            cv2.putText(img, label, (p[0] + 16 * scale, p[1]), cv2.FONT_HERSHEY_SIMPLEX, 0.6 * scale, RED, 2 * scale)
    cv2.putText(img, f"status: {result.status}", (10 * scale, 30 * scale), cv2.FONT_HERSHEY_SIMPLEX,
                0.8 * scale, WHITE, 2 * scale)
    return img

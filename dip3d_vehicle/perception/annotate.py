"""Draw what the paper's figures show on the left image: arm, pointing vector, candidates, target."""

from __future__ import annotations

import cv2
import numpy as np

from .calibration import StereoRig
from .pipeline import PerceptionResult

__all__ = ["annotate"]

GREEN, WHITE, RED, YELLOW, CYAN = (0, 255, 0), (255, 255, 255), (0, 0, 255), (0, 255, 255), (255, 255, 0)
MAGENTA, ORANGE, GREY = (255, 0, 255), (0, 165, 255), (150, 150, 150)


def _project(rig: StereoRig, xyz_m: np.ndarray) -> np.ndarray:
    """Project rectified-frame 3D points (metres) to ORIGINAL left-image pixels."""
    hom = np.c_[xyz_m, np.ones(len(xyz_m))] @ rig.P1.T
    return rig.to_original(hom[:, :2] / hom[:, 2:3], "left")


def _pt(p) -> tuple[int, int]:
    """Return an integer pixel tuple for cv2 drawing."""
    return int(round(float(p[0]))), int(round(float(p[1])))


def _corridor(img: np.ndarray, polygon_rect_px: np.ndarray, rig: StereoRig, scale: int) -> None:
    """Outline the pointing corridor (a rectified-pixel polygon), its edges mapped to original pixels."""
    pts = []
    for a, b in zip(polygon_rect_px, np.roll(polygon_rect_px, -1, axis=0)):
        pts.extend(a + (b - a) * t for t in np.linspace(0.0, 1.0, 24, endpoint=False))
    orig = rig.to_original(np.array(pts), "left")
    cv2.polylines(img, [np.round(orig).astype(np.int32)], True, MAGENTA, scale)


def annotate(left: np.ndarray, result: PerceptionResult, rig: StereoRig, extension: float = 3.0,
             corridor_rect_px: np.ndarray | None = None) -> np.ndarray:
    """Return a copy of the ORIGINAL left image with the perception result drawn on it.

    Green: the pointing vector (wrist + 0..extension x forearm, projected); magenta: the pointing
    corridor searched for small, faint objects (when given); white: all candidates (objects for
    the default selector, each with its absolute probability; matched features for the paper's);
    red: the chosen target; orange: "nothing detected along the ray" when that won, and (rings) the
    unrecognised spots found along the corridor outside every object that the selector scored, with their
    probability (part of "nothing detected"); grey rings: spots it did not score (outside the arm's
    image direction, or hidden from the diver by a recognised object); yellow/cyan: shoulder, elbow,
    wrist and the arm.
    """
    img = left.copy()
    scale = max(1, img.shape[1] // 800)
    if corridor_rect_px is not None:
        _corridor(img, corridor_rect_px, rig, scale)
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
    font = cv2.FONT_HERSHEY_SIMPLEX
    spots = result.unrecognised
    for p, xyz in zip(rig.to_original(spots.left_px, "left"), spots.xyz_m) if len(spots) else ():
        at = _pt(p)  # a spot along the corridor no object explains
        q = sel.spot_probability(xyz) if sel is not None else None
        cv2.circle(img, at, 9 * scale, ORANGE if q is not None else GREY, scale)
        if q is not None:
            cv2.putText(img, f"{q:.2f}", (at[0] + 10 * scale, at[1] - 6 * scale), font, 0.4 * scale, ORANGE, scale)
    if sel is not None:
        for i, obj in enumerate(sel.objects):
            p = _pt(rig.to_original(obj.left_px, "left")[0])
            cv2.circle(img, p, 4 * scale, WHITE, -1)
            if sel.method == "default":
                cv2.putText(img, f"{sel.scores[i]:.2f}", (p[0] + 8 * scale, p[1] + 18 * scale), font, 0.45 * scale,
                            WHITE, scale)
        if sel.nothing_on_ray:
            text = f"nothing detected along the ray (P {sel.none_probability:.2f})"
            cv2.putText(img, text, (10 * scale, 62 * scale), font, 0.8 * scale, ORANGE, 2 * scale)
        if sel.target is not None:
            p = _pt(rig.to_original(sel.target.left_px, "left")[0])
            cv2.circle(img, p, 14 * scale, RED, 3 * scale)
            label = f"{sel.method} P {sel.confidence:.2f}" if sel.method == "default" else f"{sel.method} conf 1.00"
            cv2.putText(img, label, (p[0] + 16 * scale, p[1]), cv2.FONT_HERSHEY_SIMPLEX, 0.6 * scale, RED, 2 * scale)
    cv2.putText(img, f"status: {result.status}", (10 * scale, 30 * scale), cv2.FONT_HERSHEY_SIMPLEX,
                0.8 * scale, WHITE, 2 * scale)
    return img

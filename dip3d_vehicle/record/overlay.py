"""What the controller sees, as one plain overlay: drawn on images (live view, video) and written as
Foxglove ImageAnnotations (2D, original left pixels) and a SceneUpdate (3D, rectified left camera).

An overlay is a dict::

    {"status", "state", "arm_px": [[x, y] shoulder, elbow, wrist] | None, "ray_px": [[x, y], ...],
     "candidates": [{"px": [x, y], "p": probability, "xyz_m": [..]}], "target": {"px", "p", "xyz_m"} | None,
     "box_px": [x0, y0, x1, y1] | None (the tracker's search box), "tracked_px": [x, y] | None,
     "arm_xyz_m": [[..] x3] | None, "ray_xyz_m": [[..] x2] | None}
"""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np

__all__ = ["overlay_of", "draw_overlay", "image_annotations", "scene_update"]

RAY_EXTENSION = 3.0  # the paper's s_f: ext = w + 3 (w - e)


def _finite(values) -> bool:
    return values is not None and all(v is not None and math.isfinite(float(v)) for v in np.ravel(values))


def _original(rig, points_rect_px) -> list[list[float]]:
    return [[round(float(x), 1), round(float(y), 1)] for x, y in rig.to_original(points_rect_px, "left")]


def overlay_of(result: Any, rig, state: str = "", tracked_rect_px=None, box_rect_px=None) -> dict:
    """Return the overlay of one perception result (or None) plus the tracker's point and box."""
    out: dict = {"status": "tracking" if result is None else result.status, "state": state, "arm_px": None,
                 "ray_px": [], "candidates": [], "target": None, "box_px": None, "tracked_px": None,
                 "arm_xyz_m": None, "ray_xyz_m": None}
    if result is not None:
        if result.arm is not None:
            out["arm_px"] = _original(rig, result.arm.left_px)
        arm3d = getattr(result, "arm3d", None)
        if arm3d is not None and np.all(np.isfinite(arm3d.xyz_m)):
            xyz = np.asarray(arm3d.xyz_m, float)
            w, e = arm3d.joint("wrist"), arm3d.joint("elbow")
            out["arm_xyz_m"] = np.round(xyz, 4).tolist()
            out["ray_xyz_m"] = np.round([w, w + RAY_EXTENSION * (w - e)], 4).tolist()
            line = np.array([w + t * (w - e) for t in np.linspace(0.0, RAY_EXTENSION, 25)])
            line = line[line[:, 2] > 0.05]
            if len(line) > 1:
                hom = np.c_[line, np.ones(len(line))] @ rig.P1.T
                out["ray_px"] = _original(rig, hom[:, :2] / hom[:, 2:3])
        sel = result.selection
        if sel is not None:
            for i, obj in enumerate(sel.objects):
                p = float(sel.scores[i]) if i < len(sel.scores) else float("nan")
                out["candidates"].append({"px": _original(rig, obj.left_px)[0], "p": _round(p),
                                          "xyz_m": np.round(np.asarray(obj.xyz_m, float), 4).tolist()})
            if sel.index is not None and sel.index < len(out["candidates"]):
                out["target"] = dict(out["candidates"][sel.index], p=_round(float(sel.confidence)),
                                     method=sel.method)
    if tracked_rect_px is not None:
        out["tracked_px"] = _original(rig, np.asarray(tracked_rect_px, float).reshape(1, 2))[0]
    if box_rect_px is not None:
        x0, y0, x1, y1 = box_rect_px
        corners = _original(rig, [[x0, y0], [x1, y1]])
        out["box_px"] = [corners[0][0], corners[0][1], corners[1][0], corners[1][1]]
    return out


def _round(v: float, nd: int = 3) -> float | None:
    return round(v, nd) if math.isfinite(v) else None


# -- drawing (live view, video) -------------------------------------------------------------
_BGR = {"arm": (255, 255, 0), "joint": (0, 255, 255), "ray": (0, 255, 0), "cand": (255, 255, 255),
        "target": (0, 0, 255), "box": (255, 0, 255), "tracked": (0, 165, 255)}


def _pt(p) -> tuple[int, int]:
    return int(round(float(p[0]))), int(round(float(p[1])))


def draw_overlay(image: np.ndarray, ov: dict | None, text: str = "") -> np.ndarray:
    """Return a copy of the ORIGINAL left image with the overlay drawn (colours as in Foxglove)."""
    img = image.copy() if image.ndim == 3 else cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    s = max(1, img.shape[1] // 800)
    if ov:
        if ov.get("box_px"):
            x0, y0, x1, y1 = ov["box_px"]
            cv2.rectangle(img, _pt((x0, y0)), _pt((x1, y1)), _BGR["box"], 2 * s)
        if ov.get("arm_px"):
            cv2.polylines(img, [np.round(ov["arm_px"]).astype(np.int32)], False, _BGR["arm"], 2 * s)
            for p in ov["arm_px"]:
                cv2.circle(img, _pt(p), 5 * s, _BGR["joint"], -1)
        if len(ov.get("ray_px") or []) > 1:
            cv2.polylines(img, [np.round(ov["ray_px"]).astype(np.int32)], False, _BGR["ray"], 2 * s)
        for c in ov.get("candidates", []):
            cv2.circle(img, _pt(c["px"]), 5 * s, _BGR["cand"], -1)
            if c.get("p") is not None:
                cv2.putText(img, f"{c['p']:.2f}", (_pt(c["px"])[0] + 8 * s, _pt(c["px"])[1] - 6 * s),
                            cv2.FONT_HERSHEY_SIMPLEX, 0.5 * s, _BGR["cand"], s)
        if ov.get("target"):
            t = ov["target"]
            cv2.circle(img, _pt(t["px"]), 16 * s, _BGR["target"], 3 * s)
            label = "target" + (f" p={t['p']:.2f}" if t.get("p") is not None else "")
            cv2.putText(img, label, (_pt(t["px"])[0] + 18 * s, _pt(t["px"])[1] + 6 * s), cv2.FONT_HERSHEY_SIMPLEX,
                        0.6 * s, _BGR["target"], 2 * s)
        if ov.get("tracked_px"):
            cv2.drawMarker(img, _pt(ov["tracked_px"]), _BGR["tracked"], cv2.MARKER_CROSS, 30 * s, 2 * s)
    if text:
        cv2.putText(img, text, (10 * s, 30 * s), cv2.FONT_HERSHEY_SIMPLEX, 0.8 * s, (255, 255, 255), 2 * s)
    return img


# -- Foxglove messages ------------------------------------------------------------------------
def _colour(fm, name: str, a: float = 1.0):
    b, g, r = _BGR[name]
    return fm.Color(r=r / 255, g=g / 255, b=b / 255, a=a)


def image_annotations(ov: dict, t_ns: int) -> bytes:
    """Return a foxglove.ImageAnnotations (protobuf bytes) for the left image stamped ``t_ns``."""
    import foxglove.messages as fm

    ts = fm.Timestamp(t_ns // 1_000_000_000, t_ns % 1_000_000_000)
    P2, T = fm.Point2, fm.PointsAnnotationType
    points, circles, texts = [], [], []

    def line(pts, name, kind=T.LineStrip, width=3.0):
        points.append(fm.PointsAnnotation(timestamp=ts, type=kind, points=[P2(x=p[0], y=p[1]) for p in pts],
                                          outline_color=_colour(fm, name), thickness=width))

    if ov.get("arm_px"):
        line(ov["arm_px"], "arm")
        points.append(fm.PointsAnnotation(timestamp=ts, type=T.Points, points=[P2(x=p[0], y=p[1]) for p in ov["arm_px"]],
                                          outline_color=_colour(fm, "joint"), thickness=10.0))
    if len(ov.get("ray_px") or []) > 1:
        line(ov["ray_px"], "ray")
    if ov.get("box_px"):
        x0, y0, x1, y1 = ov["box_px"]
        line([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], "box", T.LineLoop, 2.0)
    for c in ov.get("candidates", []):
        circles.append(fm.CircleAnnotation(timestamp=ts, position=P2(x=c["px"][0], y=c["px"][1]), diameter=12.0,
                                           thickness=2.0, outline_color=_colour(fm, "cand"),
                                           fill_color=_colour(fm, "cand", 0.4)))
        if c.get("p") is not None:
            texts.append(fm.TextAnnotation(timestamp=ts, position=P2(x=c["px"][0] + 10, y=c["px"][1] - 8),
                                           text=f"{c['p']:.2f}", font_size=14.0, text_color=_colour(fm, "cand"),
                                           background_color=fm.Color(r=0, g=0, b=0, a=0.5)))
    if ov.get("target"):
        t = ov["target"]
        circles.append(fm.CircleAnnotation(timestamp=ts, position=P2(x=t["px"][0], y=t["px"][1]), diameter=36.0,
                                           thickness=4.0, outline_color=_colour(fm, "target")))
        texts.append(fm.TextAnnotation(timestamp=ts, position=P2(x=t["px"][0] + 22, y=t["px"][1] + 8),
                                       text=f"target p={t['p']}", font_size=18.0, text_color=_colour(fm, "target"),
                                       background_color=fm.Color(r=0, g=0, b=0, a=0.5)))
    if ov.get("tracked_px"):
        x, y = ov["tracked_px"]
        line([(x - 15, y), (x + 15, y), (x, y - 15), (x, y + 15)], "tracked", T.LineList, 2.0)
    texts.append(fm.TextAnnotation(timestamp=ts, position=P2(x=10, y=30), text=f"{ov.get('state', '')}: "
                                   f"{ov.get('status', '')}", font_size=20.0, text_color=fm.Color(r=1, g=1, b=1, a=1),
                                   background_color=fm.Color(r=0, g=0, b=0, a=0.5)))
    return fm.ImageAnnotations(circles=circles, points=points, texts=texts).encode()


def scene_update(ov: dict, t_ns: int, frame_id: str = "camera") -> bytes:
    """Return a foxglove.SceneUpdate: the triangulated arm, its ray and the candidates (camera frame)."""
    import foxglove.messages as fm

    ts = fm.Timestamp(t_ns // 1_000_000_000, t_ns % 1_000_000_000)
    P3 = fm.Point3

    def pose(xyz=(0.0, 0.0, 0.0)):
        return fm.Pose(position=fm.Vector3(x=xyz[0], y=xyz[1], z=xyz[2]), orientation=fm.Quaternion(w=1.0))

    lines, spheres, texts = [], [], []
    if ov.get("arm_xyz_m"):
        lines.append(fm.LinePrimitive(type=fm.LinePrimitiveLineType.LineStrip, pose=pose(), thickness=0.03,
                                      points=[P3(x=p[0], y=p[1], z=p[2]) for p in ov["arm_xyz_m"]],
                                      color=_colour(fm, "arm")))
        spheres += [fm.SpherePrimitive(pose=pose(p), size=fm.Vector3(x=0.06, y=0.06, z=0.06), color=_colour(fm, "joint"))
                    for p in ov["arm_xyz_m"]]
    if ov.get("ray_xyz_m"):
        lines.append(fm.LinePrimitive(type=fm.LinePrimitiveLineType.LineStrip, pose=pose(), thickness=0.015,
                                      points=[P3(x=p[0], y=p[1], z=p[2]) for p in ov["ray_xyz_m"]],
                                      color=_colour(fm, "ray")))
    for c in ov.get("candidates", []):
        if not _finite(c["xyz_m"]):
            continue
        chosen = ov.get("target") is not None and c["px"] == ov["target"]["px"]
        size = 0.15 if chosen else 0.08
        spheres.append(fm.SpherePrimitive(pose=pose(c["xyz_m"]), size=fm.Vector3(x=size, y=size, z=size),
                                          color=_colour(fm, "target" if chosen else "cand", 0.8)))
        texts.append(fm.TextPrimitive(pose=pose([c["xyz_m"][0], c["xyz_m"][1] - 0.12, c["xyz_m"][2]]), billboard=True,
                                      font_size=14.0, scale_invariant=True, color=_colour(fm, "cand"),
                                      text=f"p={c['p']}" if c.get("p") is not None else "p=?"))
    entity = fm.SceneEntity(timestamp=ts, frame_id=frame_id, id="pointing", lines=lines, spheres=spheres,
                            texts=texts)
    return fm.SceneUpdate(entities=[entity]).encode()

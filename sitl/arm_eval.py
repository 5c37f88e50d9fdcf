"""How far the neural pose's 3D arm direction is from the truth, per way of finding the joints' disparity.

For each seed of a scenario the mission's first frames are rendered (vehicle at its start pose, the
camera's rate, from the start of the hold), ``BlazePoseEstimator`` runs on them as in the mission
(tracking, right-image ROI search), and the arm's right-image x (hence its disparity and depth) is
taken several ways:

- ``landmarks``: the right image's own BlazePose landmarks (``blazepose.joint_disparity: landmarks``);
- ``match``: patch matching around the right landmarks (``joint_disparity: match``);
- ``body``: every joint at the body's disparity (the arm lies in the body's depth plane);
- ``matched``: ``joint_stereo.joint_disparities`` for all three joints (the joint's left patch
  searched along its row within the depth span an arm can reach from the body, with a left-right
  check; a joint without a valid match takes the body's disparity with a wide sigma);
- ``stereo``: ``blazepose.joint_disparity: stereo`` (elbow and wrist as ``matched``, the shoulder
  from the torso: ``shoulder_model.torso_shoulder_disparity``).

Error = the angle between the shoulder-to-wrist direction triangulated from each and the one
triangulated from the truth joints (``meta["keypoints_truth"]``, the body's joint centres; the
left-image positions are BlazePose's in both, so the 2D part of the error is common), degrees; also
per joint, the disparity error (px) and the error divided by the method's own sigma (``z``). With
``--select`` the perception pipeline (candidates, selector) also runs on each frame with each named
method's arm: "right" / "wrong" (a confident choice of the pointed / another placard) or why it
abstained (one frame: the mission fuses several).

With ``--pose-offset`` the frames are rendered from the vehicle's start pose moved (north, east,
down in metres, yaw in degrees): what the arm looks like from where a close-in would take the vehicle.
With ``--select`` each frame also records which way it leans (the pointed placard's probability
against the best other's, ``lean``), since the mission fuses frames that are each ambiguous alone.

    python -m sitl.arm_eval [--scenario paper_pool] [--seeds 0-9] [--frames 6] [--select stereo ...]
                            [--pose-offset DN,DE,DD,DYAW] [--json OUT]
"""

from __future__ import annotations

import argparse
import json
import math
from collections import Counter
from pathlib import Path
from typing import Any, Sequence

import numpy as np

__all__ = ["METHODS", "evaluate_seed", "summarise", "main"]

METHODS = ("landmarks", "match", "body", "matched", "stereo")


def _direction(Q: np.ndarray, left_px: np.ndarray, disparity_px: np.ndarray) -> np.ndarray:
    """Return the unit shoulder-to-wrist direction triangulated from left pixels and disparities."""
    from dip3d_vehicle.perception.triangulation import triangulate

    xyz = triangulate(Q, left_px, disparity_px)
    v = xyz[2] - xyz[0]
    return v / (np.linalg.norm(v) + 1e-12)


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Return the angle between two unit vectors, degrees."""
    return math.degrees(math.acos(float(np.clip(a @ b, -1.0, 1.0))))


def evaluate_seed(scenario: str, seed: int, frames: int, params, select: Sequence[str] = (),
                  pose_offset: Sequence[float] = (0.0, 0.0, 0.0, 0.0)) -> list[dict]:
    """Render ``frames`` frames of one seed and return one row per frame where BlazePose found the arm.

    ``pose_offset``: the vehicle's pose moved from its start by (north m, east m, down m, yaw deg).
    """
    from dip3d_vehicle.perception.blazepose import JOINT_PATCH_M, BlazePoseEstimator, body_disparity
    from dip3d_vehicle.perception.joint_stereo import joint_disparities, match_joint_disparity
    from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
    from dip3d_vehicle.perception.triangulation import normalize_q

    from .render import StereoRenderer
    from .scenario import load_scenario

    sc = load_scenario(scenario, seed)
    rig = sc.rig(params["calib.alpha"])
    Q = normalize_q(rig.Q, rig.disparity_sign)
    est = BlazePoseEstimator.from_params(params)
    perception = None
    if select:
        from dip3d_vehicle.perception.pipeline import Perception
        perception = Perception(rig, params, GivenKeypoints(sc.diver.arm))
    truth_pose = GivenKeypoints(sc.diver.arm)
    period = 1.0 / float(params["sitl.camera_rate_hz"])
    v0, (dn, de, dd, dyaw) = sc.initial_vehicle_pose, pose_offset
    v = v0._replace(north_m=v0.north_m + dn, east_m=v0.east_m + de, depth_m=v0.depth_m + dd,
                    yaw_rad=v0.yaw_rad + math.radians(dyaw))
    rows = []
    with StereoRenderer(sc, params) as renderer:
        for k in range(frames):
            t = sc.diver.start_s + period * k
            frame = renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            left_img, right_img = rig.rectify_image(frame.left, "left"), rig.rectify_image(frame.right, "right")
            arm = est.estimate(left_img, right_img, rig)
            if arm is None or frame.meta["keypoints_truth"] is None:
                continue
            truth_pose.provide(frame.meta["keypoints_truth"])
            truth = truth_pose.estimate(left_img, right_img, rig)
            left_lm = est.last[0]
            sign = rig.disparity_sign
            lxy = arm.left_px
            true_disp = truth.left_px[:, 0] - truth.right_px[:, 0]
            rows_y = np.c_[lxy[:, 0], (lxy[:, 1] + arm.right_px[:, 1]) / 2.0]
            body = body_disparity(left_img, right_img, left_lm, sign, est.max_disparity_px)
            disp: dict[str, np.ndarray] = {"landmarks": lxy[:, 0] - arm.right_px[:, 0]}
            matched = match_joint_disparity(left_img, right_img, lxy, arm.right_px, sign)
            disp["match"] = lxy[:, 0] - matched[:, 0]
            sig: dict[str, np.ndarray] = {}
            if body is not None:
                disp["body"] = np.full(3, sign * body)
                js = joint_disparities(left_img, right_img, lxy, sign * body, sign, rig.focal_px, rig.baseline_m,
                                       patch_m=JOINT_PATCH_M)
                disp["matched"], sig["matched"] = js.disparity_px, js.sigma_px
                st = est.stereo_joints(left_img, right_img, left_lm, rig)
                disp["stereo"], sig["stereo"] = st.disparity_px, st.sigma_px
            t_dir = _direction(Q, truth.left_px, true_disp)
            row: dict[str, Any] = {"seed": seed, "position": sc.diver.position_name, "t_s": round(t, 2),
                                   "true_disparity_px": true_disp.round(2).tolist(),
                                   "arm_found": bool(arm.min_confidence() >= float(params["pose.min_confidence"])),
                                   "left_px_err": np.linalg.norm(lxy - truth.left_px, axis=1).round(1).tolist()}
            # the 2D part alone: BlazePose's left pixels with the TRUE disparities
            row["deg_2d_only"] = round(_angle_deg(_direction(Q, rows_y, true_disp), t_dir), 1)
            for name, d in disp.items():
                row[name] = {"deg": round(_angle_deg(_direction(Q, rows_y, d), t_dir), 1),
                             "disp_err_px": (d - true_disp).round(2).tolist()}
                if name in sig:
                    row[name]["sigma_px"] = sig[name].round(2).tolist()
            if perception is not None:
                for name in (m for m in disp if m in select):
                    row[name]["select"], row[name]["p"] = _select(perception, frame.meta, rig, left_img, right_img, arm,
                                                                  disp[name], sig.get(name), name == "landmarks")
            rows.append(row)
    return rows


def _placard_probabilities(selection, meta: dict, rig) -> list[float]:
    """Return [p(pointed placard), p(best other placard), p(nothing detected)] of one frame's selection."""
    p: dict[Any, float] = {}
    for obj, score in zip(selection.objects, selection.scores):
        best, best_d = None, 0.5
        for pid, info in meta["placards"].items():
            d = float(np.linalg.norm(rig.R1 @ np.asarray(info["xyz_cam_m"]) - obj.xyz_m))
            if d < best_d:
                best, best_d = pid, d
        p[best] = p.get(best, 0.0) + float(score)
    target = meta["target_id"]
    other = max([v for k, v in p.items() if k != target] + [0.0])
    return [round(p.get(target, 0.0), 3), round(other, 3), round(float(selection.none_probability), 3)]


def _select(perception, meta: dict, rig, left_img: np.ndarray, right_img: np.ndarray, arm, disparity_px: np.ndarray,
            sigma_px: np.ndarray | None, keep_right: bool) -> tuple[str, list[float] | None]:
    """Return one frame's selection with this arm: "right", "wrong" (confident), or why it abstained;
    and [p(pointed placard), p(best other placard), p(nothing)] when the selector scored objects."""
    from dataclasses import replace

    if keep_right:
        given = arm
    else:
        floor = float(perception.params.get("blazepose.disparity_floor_px", 1.5))
        given = replace(arm, right_px=np.c_[arm.left_px[:, 0] - disparity_px, arm.left_px[:, 1]],
                        disparity_sigma_px=None if sigma_px is None else np.maximum(sigma_px, floor))
    checked = perception.check_arm(given)
    if checked.status != "ok":
        return checked.status, None
    cands = perception.detector.detect(left_img, right_img, given, rig)
    cands = perception.add_corridor(left_img, right_img, given, cands)
    res = perception.decide(checked, cands)
    probs = None if res.selection is None or res.selection.method != "default" else \
        _placard_probabilities(res.selection, meta, rig)
    if res.status != "ok":
        return res.status, probs
    if res.selection.ambiguous:
        return "ambiguous", probs
    xyz = res.selection.target.xyz_m
    best, best_d = None, 0.5
    for pid, info in meta["placards"].items():
        d = float(np.linalg.norm(rig.R1 @ np.asarray(info["xyz_cam_m"]) - xyz))
        if d < best_d:
            best, best_d = pid, d
    return ("right" if best == meta["target_id"] else "wrong"), probs



def summarise(rows: list[dict]) -> dict:
    """Return per method: frames, median / p90 / max of the direction error (deg), |disparity error| per joint."""
    out: dict[str, Any] = {"frames": len(rows)}
    for name in ("deg_2d_only",) + METHODS:
        if name == "deg_2d_only":
            deg = np.array([r[name] for r in rows])
            errs = None
        else:
            have = [r[name] for r in rows if name in r]
            deg = np.array([h["deg"] for h in have])
            errs = np.abs(np.array([h["disp_err_px"] for h in have])) if have else None
        if len(deg) == 0:
            continue
        res = {"n": int(len(deg)), "median_deg": round(float(np.median(deg)), 1),
               "p90_deg": round(float(np.percentile(deg, 90)), 1), "max_deg": round(float(deg.max()), 1),
               "over_20deg": int(np.sum(deg > 20.0))}
        if errs is not None:
            res["disp_err_median_px"] = np.median(errs, axis=0).round(1).tolist()
        if name in ("matched", "stereo"):
            have = [r[name] for r in rows if name in r and "sigma_px" in r[name]]
            z = np.abs(np.array([h["disp_err_px"] for h in have])) / np.array([h["sigma_px"] for h in have])
            res["z_p90"] = np.percentile(z, 90, axis=0).round(2).tolist()
        if name in METHODS:
            chosen = [r[name]["select"] for r in rows if name in r and "select" in r[name]]
            if chosen:  # the selector's per-frame outcomes with this method's arm (--select)
                res["select"] = dict(sorted(Counter(chosen).items()))
            probs = np.array([r[name]["p"] for r in rows if name in r and r[name].get("p") is not None])
            if len(probs):  # which way the frames lean: the pointed placard's probability vs the best other's
                res["lean"] = {"right": int(np.sum(probs[:, 0] > probs[:, 1])), "wrong": int(np.sum(probs[:, 0] < probs[:, 1])),
                               "tie": int(np.sum(probs[:, 0] == probs[:, 1])),
                               "p_pointed_median": round(float(np.median(probs[:, 0])), 2),
                               "p_best_other_median": round(float(np.median(probs[:, 1])), 2)}
        out[name] = res
    return out


def _seeds(text: str) -> list[int]:
    """Return seeds from '0-9' or '0,3,5'."""
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def main(argv: Sequence[str] | None = None) -> None:
    """Command line (see the module docstring)."""
    from dip3d_vehicle.config import load_params

    from .scenario import load_scenario
    from .simulation import sim_params

    ap = argparse.ArgumentParser(prog="python -m sitl.arm_eval")
    ap.add_argument("--scenario", default="paper_pool")
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--select", nargs="*", default=[], metavar="METHOD",
                    help="also run the selector per frame with these methods' arms")
    ap.add_argument("--pose-offset", default="0,0,0,0", metavar="DN,DE,DD,DYAW",
                    help="render from the vehicle's start pose moved by north, east, down (m) and yaw (deg)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    offset = [float(v) for v in args.pose_offset.split(",")]
    if len(offset) != 4:
        ap.error(f"--pose-offset: {args.pose_offset!r} is not four comma-separated numbers (north, east, down m, yaw deg)")
    from .campaign import _sets

    sets = _sets(args.set)
    sets.setdefault("sitl.pose_source", "blazepose")
    base = load_params(overrides=sets)
    rows: list[dict] = []
    for seed in _seeds(args.seeds):
        params = sim_params(base, load_scenario(args.scenario, seed))
        got = evaluate_seed(args.scenario, seed, args.frames, params, args.select, offset)
        rows += got
        line = {m: [r[m]["deg"] for r in got if m in r] for m in METHODS}
        print(f"seed {seed}: {len(got)} frames " + " ".join(f"{m} {np.median(v):.0f}" for m, v in line.items() if v),
              flush=True)
    by_pos: dict[str, Any] = {}
    for pos in sorted({r["position"] for r in rows}):
        by_pos[pos] = summarise([r for r in rows if r["position"] == pos])
    by_pos["all"] = summarise(rows)
    print(json.dumps(by_pos, indent=1))
    if args.json:
        Path(args.json).write_text(json.dumps({"summary": by_pos, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()

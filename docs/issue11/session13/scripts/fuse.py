"""Replay fusion rules over recorded points (``points.py``): decisions, wrong picks, calibration.

Each point's frames go, in order, through ``behaviours.fusion.PointFusion`` exactly as the mission
adds them; after each frame from the 4th (``behaviour.vote_frames``) on, ``decide`` runs and the
first decision ends the point (the mission acts on it). A point no rule decided in its frames is
"undecided". A decided object is right when its latest sighting lay on the pointed placard; "none"
is right when no object of the point lay on it, and always in the undetectable family (as the
families count ``nothing_on_ray`` there).

Usage: python docs/issue11/session13/scripts/fuse.py FILE.jsonl ... [--rule NAME=K:V,K:V ...]
"""
import argparse
import gzip
import json
import sys
from types import SimpleNamespace as NS

import numpy as np

sys.path.insert(0, ".")
from behaviours.blackboard import BehaviourConfig  # noqa: E402
from behaviours.fusion import PointFusion  # noqa: E402


def load_points(paths: list[str]) -> list[dict]:
    """Return the points of ``points.py`` files, gzipped (.gz) or not."""
    out = []
    for path in paths:
        with (gzip.open if path.endswith(".gz") else open)(path, "rt") as fh:
            out += [json.loads(line) for line in fh if line.strip()]
    return out


_C = BehaviourConfig()
BASE = dict(radius_m=_C.vote_radius_m, temper=_C.fusion_temper, floor_p=_C.fusion_floor_p,
            no_objects_none_p=_C.fusion_no_objects_none_p, max_effective_frames=_C.fusion_max_effective_frames,
            min_shared_posterior=_C.fusion_min_shared_posterior, shared_rule=_C.fusion_shared_rule)
"""PointFusion's arguments as the mission builds them from the behaviour defaults."""


def fake_result(rec: dict):
    """Return a stand-in PerceptionResult carrying one recorded frame's selection."""
    objs = [NS(xyz_m=np.array(o[:3]), on_target=bool(o[4])) for o in rec["objects"]]
    sel = NS(method="default", scores=[o[3] for o in rec["objects"]], none_probability=rec["none"] or 0.0,
             objects=objs, index=None)
    status = rec["status"] if rec["status"] in ("ok", "nothing_on_ray") else "pose_rejected"
    return NS(status=status, selection=sel if objs else None, arm=NS(keypoint_sigma_m=0.0), arm3d=None,
              candidates=None)


def replay(point: dict, rule: dict, min_posterior: float, min_led: int, vote_frames: int):
    """Return (kind, right, frames used, posterior of the decision) for one point under one rule."""
    opts = dict(BASE)
    opts.update({k: v for k, v in rule.items() if k in BASE})
    fusion = PointFusion(**opts)
    truth_detected = any(o[4] for f in point["frames"] for o in f["objects"])
    latest = int(rule.get("latest", 0))
    for i, rec in enumerate(point["frames"]):
        fusion.add(fake_result(rec), 0.1 * i)
        if len(fusion.frames) < vote_frames:
            continue
        if latest:  # the last frames (each decided with the mean arm of the point) counted as one look
            out = latest_look(fusion, latest, min_posterior, truth_detected, point["family"])
            if out is not None:
                return out
            continue
        d = fusion.decide(min_posterior, min_led)
        if d.kind == "object":
            return "object", bool(d.winner.obj.on_target), len(fusion.frames), d.posterior[d.best]
        if d.kind == "none":  # right where the target cannot be detected (the families' nothing_on_ray rule)
            right = point["family"] == "undetectable" or not truth_detected
            return "none", right, len(fusion.frames), d.posterior[d.best]
    return "undecided", None, len(fusion.frames), None


def latest_look(fusion: PointFusion, k: int, min_posterior: float, truth_detected: bool, family: str):
    """Return a decision from the last ``k`` frames' mean log probabilities (one look), or None."""
    keys = [h.key for h in fusion.hypotheses] + ["none"]
    frames = fusion.frames[-k:]
    logs = np.array([[np.log(max(f.probabilities.get(key, 0.0), fusion.floor_p)) for key in keys] for f in frames])
    z = logs.mean(axis=0)
    post = np.exp(z - z.max())
    post /= post.sum()
    best = int(np.argmax(post))
    if post[best] < min_posterior:
        return None
    n = len(fusion.frames)
    if keys[best] == "none":
        return "none", family == "undetectable" or not truth_detected, n, float(post[best])
    h = fusion.hypothesis(keys[best])
    return "object", bool(h.obj.on_target), n, float(post[best])


def parse_rule(text: str) -> tuple[str, dict]:
    """Parse NAME=key:value,key:value."""
    name, _, body = text.partition("=")
    out = {}
    for kv in filter(None, body.split(",")):
        k, v = kv.split(":")
        out[k] = v if k == "shared_rule" else float(v)
    return name, out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="+")
    ap.add_argument("--rule", action="append", default=[])
    ap.add_argument("--min-posterior", type=float, default=_C.fusion_min_posterior)
    ap.add_argument("--min-led", type=int, default=_C.min_votes)
    ap.add_argument("--vote-frames", type=int, default=_C.vote_frames)
    ap.add_argument("--frames", type=int, default=0, help="use only the first N frames of each point")
    ap.add_argument("--scenes", type=int, default=0, help="use only each family's first N scenes")
    a = ap.parse_args()
    points = load_points(a.files)
    if a.scenes:
        points = [p for p in points if p["scene"] < a.scenes]
    if a.frames:
        for p in points:
            p["frames"] = p["frames"][:a.frames]
    rules = [("current", {})] + [parse_rule(r) for r in a.rule]
    for name, rule in rules:
        cells = {}
        for p in points:
            kind, right, n, post = replay(p, rule, rule.get("min_posterior", a.min_posterior), a.min_led, a.vote_frames)
            det = "und" if p["family"] == "undetectable" else "det"
            key = (det, p["noise"])
            c = cells.setdefault(key, {"points": 0, "right": 0, "wrong_object": 0, "wrong_none": 0, "undecided": 0,
                                       "frames": []})
            c["points"] += 1
            if kind == "undecided":
                c["undecided"] += 1
            elif right:
                c["right"] += 1
                c["frames"].append(n)
            elif kind == "object":
                c["wrong_object"] += 1
            else:
                c["wrong_none"] += 1
        print(f"rule {name} {rule}")
        for key in sorted(cells):
            c = cells[key]
            fr = np.median(c["frames"]) if c["frames"] else float("nan")
            print(f"  {key[0]} {key[1]:.0f}px  points {c['points']:4d}  right {c['right'] / c['points']:6.1%}  "
                  f"wrong object {c['wrong_object'] / c['points']:6.1%}  wrong none {c['wrong_none'] / c['points']:6.1%}  "
                  f"undecided {c['undecided'] / c['points']:6.1%}  median frames {fr:.0f}")


if __name__ == "__main__":
    main()

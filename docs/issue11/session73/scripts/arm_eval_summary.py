"""One line per sitl.arm_eval JSON (issue 14 session 73): frames, arm found, BlazePose's 2D and the stereo arm's
direction error (median / p90, deg), the left-image shoulder / elbow / wrist error (median px) and the per-frame
selector outcome with the stereo arm (right / ambiguous / nothing_on_ray / wrong ...):
    python docs/issue11/session73/scripts/arm_eval_summary.py FILE.json ... [--seeds LO-HI]"""
import json
import sys

import numpy as np


def summary(path: str, lo: int = 0, hi: int = 10 ** 9) -> str:
    """Return the one line of an arm_eval JSON, seeds lo..hi."""
    rows = [r for r in json.load(open(path))["rows"] if lo <= r["seed"] <= hi]
    stereo = [r["stereo"]["deg"] for r in rows if "stereo" in r]
    d2 = [r["deg_2d_only"] for r in rows]
    err = np.median([r["left_px_err"] for r in rows], axis=0).round(1).tolist()
    sel = [str(r["stereo"].get("select")) for r in rows if "stereo" in r]
    counts = {k: sel.count(k) for k in sorted(set(sel))}
    return (f"{path}: frames {len(rows)} found {sum(r['arm_found'] for r in rows)} 2d {np.median(d2):.1f} "
            f"stereo {np.median(stereo):.1f} / {np.percentile(stereo, 90):.1f} deg, err {err} px, select {counts}")


if __name__ == "__main__":
    args = sys.argv[1:]
    lo, hi = 0, 10 ** 9
    if "--seeds" in args:
        k = args.index("--seeds")
        lo, hi = (int(v) for v in args[k + 1].split("-"))
        del args[k:k + 2]
    for p in args:
        print(summary(p, lo, hi))

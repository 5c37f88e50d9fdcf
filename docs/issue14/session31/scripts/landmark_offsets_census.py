"""Per BlazePose frame: each arm landmark's 2D offset from the body's joint centre, in metres at the body.

    python docs/issue14/session31/scripts/landmark_offsets_census.py OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS

Frames as ``wrist_census.py`` (every 0.6 s of the hold, from the start pose, ``pose.arm: auto``). Per frame: the
left image's shoulder / elbow / wrist offsets (landmark - truth, pixels), the image scale at the body's depth
(pixels per metre, from the truth shoulder's disparity), and the truth shoulder-to-wrist direction in the image.
"""
import json, sys
import numpy as np
from census_frames import census_args, held_frames

out, names, seeds, step = census_args(sys.argv)
with open(out, "w") as fh:
    for f in held_frames(names, seeds, step):
        disp = float(f.truth.left_px[0, 0] - f.truth.right_px[0, 0])
        row = {"scenario": f.scenario, "seed": f.seed, "t": round(f.t_s, 2),
               "offset_px": (f.arm.left_px - f.truth.left_px).round(2).tolist(),
               "px_per_m": round(abs(disp) / f.rig.baseline_m, 2),
               "truth_px": f.truth.left_px.round(1).tolist(), "conf": np.round(f.arm.left_conf, 3).tolist()}
        fh.write(json.dumps(row) + "\n")
        fh.flush()

"""Print, per tracked frame, the ROI and how many matches of each pass lie near the predicted target (px).

    TRACE=1 PYTHONPATH=. python docs/issue11/session38/scripts/trace_roi.py SCENARIO SEED OUTDIR [--set K=V ...]
(run through proto_pool.py's hooks when POOL=1)
"""
import os
import runpy

import numpy as np

import behaviours.loop as loop
import behaviours.machine as machine

_uv = {}
_orig_roi = machine.Mission.track_roi


def _roi(self, rig, image_size):
    """Remember the predicted pixel."""
    out = _orig_roi(self, rig, image_size)
    xyz = self.bb.tracker.predicted_xyz(self.bb.now_s, self.bb.command) if self.bb.tracker.active else None
    if xyz is not None and xyz[2] > 0.2:
        f = rig.focal_px
        cx, cy = rig.principal_point_px
        _uv["uv"] = (f * xyz[0] / xyz[2] + cx, f * xyz[1] / xyz[2] + cy, f * 0.15 / xyz[2])
    return out


def _detect_in(p, left, right, roi):
    """Count the passes' matches near the prediction."""
    if roi is None or "uv" not in _uv:
        return loop_orig(p, left, right, roi)
    u, v, r = _uv["uv"]
    x0, y0, x1, y1 = roi
    main = p.detector.detect(left[y0:y1, x0:x1], right[y0:y1, x0:x1], None, p.rig)
    near_main = int(np.sum(np.hypot(main.left_px[:, 0] + x0 - u, main.left_px[:, 1] + y0 - v) < r)) if len(main) else 0
    box = p.corridor.detect_box(left, right, roi, p.rig) if p.corridor is not None else None
    near_box = int(np.sum(np.hypot(box.left_px[:, 0] - u, box.left_px[:, 1] - v) < r)) if box is not None and len(box) else 0
    scale = p.corridor._scale([roi]) if p.corridor is not None else 0
    print(f"ROI {roi} {x1 - x0}x{y1 - y0} uv=({u:.0f},{v:.0f}) r={r:.0f} main {len(main)} near {near_main}; "
          f"box {0 if box is None else len(box)} near {near_box} scale {scale:.2f}", flush=True)
    return loop_orig(p, left, right, roi)


loop_orig = loop._detect_in
machine.Mission.track_roi = _roi
loop._detect_in = _detect_in
here = os.path.dirname(__file__)
runpy.run_path(os.path.join(here, "proto_pool.py" if os.environ.get("POOL") else "trace_tracker.py"),
               run_name="__main__")

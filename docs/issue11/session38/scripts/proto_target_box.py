"""Prototype: the tracker's search also scans a tight box around the predicted target at the zoom scale.

    PYTHONPATH=. python docs/issue11/session38/scripts/proto_target_box.py SCENARIO SEED OUTDIR [--set K=V ...]
(TRACE=1 also prints the tracker's looks, as trace_tracker.py.)
"""
import os
import sys


import behaviours.loop as loop
import behaviours.machine as machine
from dip3d_vehicle.perception import corridor as cor
from dip3d_vehicle.perception.corridor import merge_candidates

HALF_M = float(os.environ.get("TB_HALF_M", "0.3"))
MARGIN_PX = float(os.environ.get("TB_MARGIN_PX", "30"))
_box = {}
_orig_roi = machine.Mission.track_roi


def _roi(self, rig, image_size):
    """Remember the tight box, then return the usual ROI."""
    out = _orig_roi(self, rig, image_size)
    _box.clear()
    if out is None:
        return out
    tracker = self.bb.tracker
    xyz = tracker.predicted_xyz(self.bb.now_s, self.bb.command)
    f = rig.focal_px
    cx, cy = rig.principal_point_px
    u, v = f * xyz[0] / xyz[2] + cx, f * xyz[1] / xyz[2] + cy
    half = f * HALF_M / xyz[2] + MARGIN_PX * (2.0 if tracker.misses else 1.0)
    w, h = image_size
    box = (int(max(0, u - half)), int(max(0, v - half)), int(min(w, u + half)), int(min(h, v + half)))
    if box[2] - box[0] >= 16 and box[3] - box[1] >= 16:
        _box["box"], _box["disp"] = box, f * abs(rig.baseline_m) / xyz[2]
    return out


_orig_detect_in = loop._detect_in


def _detect_in(p, left, right, roi):
    """The usual ROI search, plus the tight box at the zoom scale."""
    cands = _orig_detect_in(p, left, right, roi)
    if roi is None or p.corridor is None or "box" not in _box:
        return cands
    c, rig = p.corridor, p.rig
    box = _box["box"]
    fb = rig.focal_px * rig.baseline_m
    rbox = cor._zoom_right_box(box, _box["disp"], fb, left.shape[1], rig.disparity_sign)
    scale = c._scale([box], c.zoom_scale, cor.ZOOM_MAX_AREA_PX)
    tight = c._match_boxes(left, right, [box], [None], rig, scale=scale, right_masks=[None], right_boxes=[rbox])
    if os.environ.get("TRACE"):
        print(f"TB box={box} scale={scale:.2f} tight={len(tight)} roi={len(cands)}", flush=True)
    return merge_candidates(cands, tight)


machine.Mission.track_roi = _roi
loop._detect_in = _detect_in
if os.environ.get("TRACE"):
    sys.argv = [sys.argv[0]] + sys.argv[1:]
    import runpy
    runpy.run_path(os.path.join(os.path.dirname(__file__), "trace_tracker.py"), run_name="__main__")
else:
    from dip3d_vehicle import cli
    scen, seed, out = sys.argv[1:4]
    sys.exit(cli.main(["sitl", "--scenario", scen, "--seed", seed, "--json", "--no-plots", "--out", out,
                       *sys.argv[4:]]))

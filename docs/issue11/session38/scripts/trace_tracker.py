"""Run one sitl mission in-process and print every tracker look (objects in the gate, matches, distances).

    PYTHONPATH=. python docs/issue11/session38/scripts/trace_tracker.py SCENARIO SEED OUTDIR [--set K=V ...]
"""
import sys

import numpy as np

import behaviours.tracker as tr
from dip3d_vehicle import cli

_orig_find = tr.TargetTracker._find
_orig_group = tr.group_objects


def _find(self, candidates, xyz_m, predicted, stamp_s):
    """Print the gate's view of the frame, then find as usual."""
    found = _orig_find(self, candidates, xyz_m, predicted, stamp_s)
    c = self.config
    objects = _orig_group(candidates, xyz_m, self.rig, c.group_radius_px, c.group_radius_m, c.min_object_features) \
        if len(candidates) else []
    first = self._matched_descriptors(self._first, candidates.descriptors) if len(candidates) > 1 else np.array([])
    since = stamp_s - (self.last_seen_s if self.last_seen_s is not None else stamp_s)
    gate = min(c.gate_m + c.gate_growth_m_s * max(since, 0.0), c.gate_max_m)
    rows = []
    for obj in objects:
        m = list(obj.members)
        d = float(np.linalg.norm(obj.xyz_m - predicted))
        if d < 1.5:
            rows.append(f"[{np.round(obj.xyz_m, 2).tolist()} n{len(m)} a{tr._distinct(first[m])} d{d:.2f}]")
    print(f"TRK t={stamp_s:.2f} pred={np.round(predicted, 2).tolist()} gate={gate:.2f} n={len(candidates)} "
          f"model={len(self._first)}/{len(self._latest)} misses={self.misses} found="
          f"{None if found is None else np.round(found.xyz_m, 2).tolist()} objs: {' '.join(rows)}", flush=True)
    return found


tr.TargetTracker._find = _find
scen, seed, out = sys.argv[1:4]
sys.exit(cli.main(["sitl", "--scenario", scen, "--seed", seed, "--no-plots", "--out", out, *sys.argv[4:]]))

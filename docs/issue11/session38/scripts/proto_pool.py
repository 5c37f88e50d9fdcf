"""Prototype: the tracker's first model pools the winning hypothesis's sightings over the select frames
(each frame's features on it), a descriptor kept only when no kept one lies within POOL_DEDUP (L2).

    PYTHONPATH=. python docs/issue11/session38/scripts/proto_pool.py SCENARIO SEED OUTDIR [--set K=V ...]
TRACE=1 prints the tracker's looks; TB=1 adds proto_target_box's tight box.
"""
import os
import runpy
import sys

import numpy as np

import behaviours.fusion as fu
import behaviours.tracker as tr

DEDUP = float(os.environ.get("POOL_DEDUP", "200"))
_pools: dict = {}
_orig_add = fu.PointFusion.add
_orig_match = fu.PointFusion.match


def _add(self, result, stamp_s, arm_frames=1):
    """Fuse as usual, and pool the descriptors of every object that fell on a hypothesis."""
    ev = _orig_add(self, result, stamp_s, arm_frames)
    probs = fu.frame_probabilities(result, self.no_objects_none_p)
    if probs is None or len(result.candidates.descriptors) != len(result.candidates):
        return ev
    for obj, _p in probs[0]:
        h = _orig_match(self, np.asarray(obj.xyz_m, float))
        if h is None:
            continue
        pool = _pools.setdefault((id(self), h.key), [])
        pool.append(np.asarray(result.candidates.descriptors[list(obj.members)], np.float32))
        _pools[id(h.obj)] = (id(self), h.key)
    return ev


_orig_reset = fu.PointFusion.reset


def _reset(self):
    """Forget this fusion's pools."""
    for k in [k for k in _pools if isinstance(k, tuple) and k[0] == id(self)]:
        del _pools[k]
    _orig_reset(self)


_orig_start = tr.TargetTracker.start


def _dedup(first: np.ndarray, extra: list) -> np.ndarray:
    """Return ``first`` plus the pooled descriptors with no kept one within DEDUP."""
    kept = [d for d in first]
    for block in extra:
        for d in block:
            if kept and np.min(np.linalg.norm(np.asarray(kept) - d, axis=1)) < DEDUP:
                continue
            kept.append(d)
    return np.asarray(kept, np.float32)


def _start(self, obj, candidates, stamp_s):
    """Start as usual, then widen the first model with the pooled sightings."""
    _orig_start(self, obj, candidates, stamp_s)
    key = _pools.get(id(obj))
    if key is None or key not in _pools:
        return
    n0 = len(self._first)
    self._first = _dedup(self._first, _pools[key][::-1])[: self.config.model_size]
    print(f"POOL model {n0} -> {len(self._first)} from {len(_pools[key])} sightings", flush=True)


fu.PointFusion.add = _add
fu.PointFusion.reset = _reset
tr.TargetTracker.start = _start
here = os.path.dirname(__file__)
if os.environ.get("TB"):
    runpy.run_path(os.path.join(here, "proto_target_box.py"), run_name="__main__")
elif os.environ.get("TRACE"):
    runpy.run_path(os.path.join(here, "trace_tracker.py"), run_name="__main__")
else:
    from dip3d_vehicle import cli
    scen, seed, out = sys.argv[1:4]
    sys.exit(cli.main(["sitl", "--scenario", scen, "--seed", seed, "--json", "--no-plots", "--out", out,
                       *sys.argv[4:]]))

"""Experiment (session 68; landed in session 69 as ``selection.prior_per_target``, ``grouping.target_groups``, which
gives the same per-frame output): the default selector's prior shared per TARGET, not per cluster of features.
Kept as the record of what session 68 measured, on trees that predate the parameter.

A placard split into K clusters gets K prior shares today (``OpenSet.log_prior(n_objects)`` per object), and the
frame's and the fusion's fragments add up: in murky water ``variant_41_15``'s far placard 1 came as 4 clusters and
led most frames over the pointed placard 3 (one cluster), 5 deg from the arm against 16 deg.
Here objects that could be one target (their features' union at most ``selection.target_max_extent_m`` across the
line of sight, their depths within 0.3 m + 2 sigma) form a group; a group holds one share, split among its members.

    PYTHONPATH=TREE python prior_per_target.py SCRIPT ARGS...      (runs SCRIPT, e.g. story.py, with the patch)
    PYTHONPATH=TREE python prior_per_target.py -m MODULE ARGS...   (e.g. -m sitl.point_campaign mission ...)
"""
import math
import runpy
import sys

import numpy as np

import dip3d_vehicle.perception.selection as sel
from dip3d_vehicle.perception.grouping import extent_m

_SHARE: dict[int, float] = {}
_GROUPS = {"n": None}


def target_groups(objects, candidates, focal_px: float, max_extent_m: float) -> np.ndarray:
    """Return a group label per object: greedy from the largest, objects that fit in one target with it."""
    labels = np.full(len(objects), -1)
    order = sorted(range(len(objects)), key=lambda i: -len(objects[i].members))
    g = 0
    for i in order:
        if labels[i] >= 0:
            continue
        labels[i], members = g, list(objects[i].members)
        for j in order:
            if labels[j] >= 0:
                continue
            dz = abs(float(objects[i].xyz_m[2] - objects[j].xyz_m[2]))
            if dz > 0.3 + 2.0 * math.hypot(objects[i].depth_sigma_m, objects[j].depth_sigma_m):
                continue
            union = members + list(objects[j].members)
            depth = float(np.median([objects[i].xyz_m[2], objects[j].xyz_m[2]]))
            if extent_m(candidates.left_px[union], depth, focal_px) <= max_extent_m:
                labels[j], members = g, union
        g += 1
    return labels


orig_group = sel.group_objects


def grouped(candidates, xyz_m, rig, *args, **kwargs):
    """Group as before, then record each object's share of its target's prior."""
    objects = orig_group(candidates, xyz_m, rig, *args, **kwargs)
    _SHARE.clear()
    if objects:
        labels = target_groups(objects, candidates, rig.focal_px, args[-1] if args else 0.6)
        sizes = np.bincount(labels)
        for o, lab in zip(objects, labels):
            _SHARE[id(o)] = float(sizes[lab])
        _GROUPS["n"] = int(labels.max()) + 1
    return objects


sel.group_objects = grouped
orig_log_odds = sel.DefaultSelector._log_odds


def log_odds(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad=None, n_objects=None):
    """Each object's log odds with its target's share of the prior (the spots: one share of the targets')."""
    n = _GROUPS["n"] or n_objects
    out = orig_log_odds(self, costs, arm_cost, objects, arm, arm3d, pointing_sigma_rad, n)
    return out - np.log([_SHARE.get(id(o), 1.0) for o in objects])


sel.DefaultSelector._log_odds = log_odds
if sys.argv[1] == "-m":
    module, sys.argv = sys.argv[2], sys.argv[2:]
    runpy.run_module(module, run_name="__main__", alter_sys=True)
else:
    script, sys.argv = sys.argv[1], sys.argv[1:]
    runpy.run_path(script, run_name="__main__")

"""Test helper for the behaviour tests (a uniquely named module): one compact synthetic object as the tracker sees it."""

from __future__ import annotations

import numpy as np

from dip3d_vehicle.perception.values import Candidates, ObjectCandidate


def target_frame(rig, n: int = 8, xyz=(0.3, 0.0, 2.0), px=(900.0, 600.0), seed: int = 7):
    """Return (candidates, their 3D points, the object): ``n`` matched features of one identity.

    The features lie within 20 px of ``px`` in the left image with the disparity of depth ``xyz[2]``,
    and carry fixed random descriptors, so the same call always gives the same object to track.
    """
    rng = np.random.default_rng(seed)
    left = np.asarray(px) + rng.uniform(-20, 20, (n, 2))
    disparity = rig.focal_px * abs(rig.baseline_m) / xyz[2]
    cands = Candidates(left, left - [disparity, 0.0], rng.random((n, 128), np.float32), np.full(n, 4.0))
    pts = np.tile(np.asarray(xyz, float), (n, 1)) + rng.normal(0.0, 0.01, (n, 3))
    return cands, pts, ObjectCandidate(left.mean(0), pts.mean(0), 0.02, tuple(range(n)))

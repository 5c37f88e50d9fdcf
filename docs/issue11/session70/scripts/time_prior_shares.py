"""Time the default selector's frame with one prior share per object and per target (issue 11 session 70):
    cd tests/perception && PYTHONPATH=. python ../../docs/issue11/session70/scripts/time_prior_shares.py [PLACARDS ...]
A scene of N placards (N/2 whole, N/2 each broken into 4 clusters) around the arm, exact candidates; prints the
median select() time in ms over 30 calls, option off and on, for each N placards (objects = whole + 4 x broken)."""
import sys
import time

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.pipeline import Perception
from test_selection import RIG, _arm_right, candidates_of, cluster


def scene(n: int) -> tuple:
    """Return the arm and the features of ``n`` placards spread -20..20 deg about it, 2.2 m from the shoulder."""
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    pts = []
    for k, deg in enumerate(np.linspace(-20.0, 20.0, n)):
        a = np.radians(deg)
        c = shoulder + 2.2 * np.array([np.cos(a) * u[0] - np.sin(a) * u[1], np.sin(a) * u[0] + np.cos(a) * u[1], 0])
        if k % 2:
            pts += [cluster(c + [dx, dy, 0.0], 12, 0.03, seed=10 * k + j)
                    for j, (dx, dy) in enumerate([(-0.12, -0.12), (0.12, -0.12), (-0.12, 0.12), (0.12, 0.12)])]
        else:
            pts.append(cluster(c, 80, 0.15, seed=10 * k))
    return arm, np.vstack(pts)


def median_ms(arm, pts, per_target: bool, calls: int = 30) -> tuple[float, int]:
    """Return the median select() time (ms) and the number of objects."""
    cands, xyz = candidates_of(pts)
    perception = Perception(RIG, load_params("default", overrides={"selection.prior_per_target": str(per_target)}),
                            None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    times, sel = [], None
    for _ in range(calls):
        t0 = time.perf_counter()
        sel = perception.selector.select(arm, arm3d, cands, xyz, RIG)
        times.append(time.perf_counter() - t0)
    return 1e3 * float(np.median(times)), len(sel.objects)


if __name__ == "__main__":
    for n in [int(a) for a in sys.argv[1:]] or [2, 4, 6]:
        arm, pts = scene(n)
        (off, k), (on, _) = median_ms(arm, pts, False), median_ms(arm, pts, True)
        print(f"{n} placards, {k} objects: off {off:.2f} ms, on {on:.2f} ms, +{on - off:.2f} ms")

"""Check that two versions of behaviours/clearance.py plan the same way on random scenes (the review's check of
7e756a1's vectorised sieve).

    git show 43311c6:behaviours/clearance.py > /tmp/s53/clearance_old.py
    cd /tmp/s53 && PYTHONPATH=/work/main python /work/main/docs/issue11/session53/scripts/same_way.py
"""
import sys

import numpy as np

sys.path.insert(0, ".")  # clearance_old.py in the current directory
import clearance_old as old  # noqa: E402
from behaviours.clearance import plan_way  # noqa: E402

rng = np.random.default_rng(0)
n = diff = held = 0
for _ in range(3000):
    t = np.array([rng.uniform(-1, 1), rng.uniform(-.3, .3), rng.uniform(1.2, 5)])
    k = rng.integers(1, 8)
    objs = t * rng.uniform(0, 1.1, (k, 1)) + rng.normal(0, 0.4, (k, 3))
    if rng.random() < 0.2:
        objs[0] = [rng.uniform(-.4, .4), 0, rng.uniform(-.3, .1)]
    args = (t, objs, 1.0, 0.6, 0.35, float(rng.choice([-1, 0, 1])), float(rng.uniform(-.5, .5)))
    a, b = old.plan_way(*args), plan_way(*args)
    n += 1
    diff += (a is None) != (b is None) or (a is not None and (a.angle_rad, a.standoff_m, a.margin_m, a.index)
                                           != (b.angle_rad, b.standoff_m, b.margin_m, b.index))
    held += a is not None and a.standoff_m > 1.0
print(n, "scenes; differ", diff, "; held short", held)

"""The default selector's results on the bench frames, to compare two checkouts exactly.

Usage (from the repository root of each checkout):
    PYTHONPATH=. python docs/issue16/session15/selector_same.py capture INPUTS.pkl     # once
    PYTHONPATH=. python docs/issue16/session15/selector_same.py run INPUTS.pkl OUT.pkl  # per checkout
    python docs/issue16/session15/selector_same.py compare A.pkl B.pkl
``capture`` records every ``DefaultSelector.select`` call of the bench's default profile (its
frames rendered as in bench_variant); ``run`` replays them (and times them alone, ms per frame).
"""
import pickle
import sys
import time
from pathlib import Path

import numpy as np


def capture(path: str) -> None:
    """Record the select calls of one bench_variant run of the default profile."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "session14"))
    import bench_variant
    from dip3d_vehicle.perception import selection
    calls, select = [], selection.DefaultSelector.select

    def recorded(self, *args):
        calls.append(args)
        return select(self, *args)

    selection.DefaultSelector.select = recorded
    sys.argv = [sys.argv[0], "default"]
    bench_variant.main()
    with open(path, "wb") as fh:
        pickle.dump(calls, fh)


def run(inputs: str, out: str) -> None:
    """Replay the recorded calls; write each result's fields, print the time per call."""
    from dip3d_vehicle.config import load_params
    from dip3d_vehicle.perception.selection import make_selector
    with open(inputs, "rb") as fh:
        calls = pickle.load(fh)
    selector = make_selector(load_params("default"))
    results = [selector.select(*args) for args in calls]
    for _ in range(3):
        t0 = time.perf_counter()
        for args in calls:
            selector.select(*args)
        print(f"{(time.perf_counter() - t0) * 1e3 / len(calls):.2f} ms per select")
    rows = [(r.index, r.confidence, r.none_probability, np.asarray(r.scores), r.ambiguous, r.reason) for r in results]
    with open(out, "wb") as fh:
        pickle.dump(rows, fh)


def compare(a_path: str, b_path: str) -> None:
    """Print how many results are the same and the largest difference of any probability."""
    a, b = (pickle.load(open(p, "rb")) for p in (a_path, b_path))
    same = sum(x[0] == y[0] and x[4] == y[4] and x[5] == y[5] for x, y in zip(a, b))
    diff = max(max(abs(x[1] - y[1]), abs(x[2] - y[2]), float(np.max(np.abs(x[3] - y[3]), initial=0.0)))
               for x, y in zip(a, b))
    print(f"{same} of {len(a)} the same (index, ambiguous, reason); largest probability difference {diff}")


if __name__ == "__main__":
    {"capture": capture, "run": run, "compare": compare}[sys.argv[1]](*sys.argv[2:])

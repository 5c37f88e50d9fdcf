"""How far each placard lies from the diver's TRUE arm (shoulder -> wrist, with the pointing error) over the hold.

    PYTHONPATH=. python docs/issue11/session25/scripts/truth_ray.py SCENARIO|FILE SEED
"""
import math
import sys

import numpy as np

from sitl.scenario import load_scenario


def main() -> None:
    """Print the pointing error and, every 0.4 s, each placard's angle from the arm (deg)."""
    sc = load_scenario(sys.argv[1], int(sys.argv[2]))
    d = sc.diver
    target = np.asarray(next(p for p in sc.placards if p.id == d.target_id).centre_ned_m, float)
    print(f"target {d.target_id}, pointing error {math.degrees(d.pointing_error_rad):.1f} deg, start {d.start_s} s")
    for t in np.arange(d.start_s, d.start_s + 7.2, 0.4):
        j = d.joints(target, t)
        ray = j["wrist"] - j["shoulder"]
        angles = []
        for p in sc.placards:
            v = np.asarray(p.centre_ned_m, float) - j["shoulder"]
            angles.append(math.degrees(math.acos(np.clip(v @ ray / np.linalg.norm(v) / np.linalg.norm(ray), -1, 1))))
        print(f"t {t:4.1f} raised {d.raised_fraction(t):.2f} " + " ".join(f"p{p.id} {a:5.1f}" for p, a in zip(sc.placards, angles)))


if __name__ == "__main__":
    main()

"""Angle between the diver's truth arm (shoulder -> wrist, t = 5 s) and each placard's centre, per seed, degrees.

    python docs/issue11/session47/scripts/pointing_angles.py SCENARIO SEEDS
"""
import sys
import numpy as np
from sitl.scenario import load_scenario

name, seeds = sys.argv[1], sys.argv[2]
lo, hi = (int(x) for x in seeds.split("-"))
for seed in range(lo, hi + 1):
    sc = load_scenario(name, seed)
    target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
    j = sc.diver.joints(target, t_s=5.0)
    u = j["wrist"] - j["shoulder"]
    u /= np.linalg.norm(u)
    angles = {}
    for p in sc.placards:
        d = np.asarray(p.centre_ned_m) - j["shoulder"]
        angles[p.id] = float(np.degrees(np.arccos(np.clip(d @ u / np.linalg.norm(d), -1, 1))))
    nearest = min(angles, key=angles.get)
    print(f"seed {seed} position {sc.diver.position_name} target {sc.target_id}: "
          + ", ".join(f"placard {k} {v:.1f}" for k, v in sorted(angles.items()))
          + (f"  <- arm nearer placard {nearest}" if nearest != sc.target_id else ""))

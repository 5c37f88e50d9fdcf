"""How far a link-cut mission turned and travelled from the cut to the re-enable, and whether the pointed placard
was in the left camera at the re-enable; one line per seed:
    python docs/issue11/session62/scripts/cut_turn.py PLAN SEED [SEED ...]   (PYTHONPATH=TREE; paper_pool)"""
import math
import sys

import numpy as np

from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission
from sitl.world import VehiclePose, left_camera_pose, project_pinhole


def in_view(sim, target_id: int, t_s: float) -> str:
    """Placard ``target_id`` in the left camera at the trajectory row nearest ``t_s`` (as session 61's
    reenable_view.py)."""
    sc, row = sim.scenario, min(sim.trajectory, key=lambda r: abs(r[0] - t_s))
    cam = sc.camera
    pose = left_camera_pose(VehiclePose(row[1], row[2], row[3], row[4]), cam.mount_frd_m, cam.mount_pitch_rad,
                            cam.mount_yaw_rad)
    p = pose.to_cam(np.asarray(sc.placard(target_id).centre_ned_m, float))
    u, v = project_pinhole(p, cam.K)[0]
    w, h = cam.image_size
    return "in view" if p[0, 2] > 0 and 0 <= u < w and 0 <= v < h else "OUT of view"


plan = sys.argv[1]
for seed in [int(a) for a in sys.argv[2:]]:
    result, sim = run_faulted_mission("paper_pool", seed, plan, load_params())
    ev = next(e for e in sim.fault_events.applied if e["kind"] == "link_cut")
    rows = [r for r in sim.trajectory if ev["onset_s"] <= r[0] <= ev["recover_from_s"]]
    turned = sum(math.atan2(math.sin(b[4] - a[4]), math.cos(b[4] - a[4])) for a, b in zip(rows, rows[1:]))
    moved = math.hypot(rows[-1][1] - rows[0][1], rows[-1][2] - rows[0][2])
    print(f"seed {seed} {result.outcome}: cut {ev['onset_s']:.1f}-{ev['clear_s']:.1f} s, re-enable "
          f"{ev['recover_from_s']:.1f} s; turned {math.degrees(turned):+.0f} deg, moved {moved:.2f} m; target at the "
          f"re-enable {in_view(sim, result.target_id, ev['recover_from_s'])}", flush=True)

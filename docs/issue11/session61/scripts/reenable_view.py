"""Where the pointed placard is at a link-cut mission's re-enable: in the left camera (pixels, range) or not, and
what the mission said; one line per seed:
    python docs/issue11/session61/scripts/reenable_view.py PLAN SEED [SEED ...] [KEY=VALUE ...]   (PYTHONPATH=TREE)"""
import re
import sys

import numpy as np

from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission
from sitl.world import VehiclePose, left_camera_pose, project_pinhole


def view_at(sim, target_id: int, t_s: float) -> str:
    """Placard ``target_id``'s left-camera pixel and depth at the trajectory row nearest ``t_s``."""
    sc = sim.scenario
    row = min(sim.trajectory, key=lambda r: abs(r[0] - t_s))
    cam = sc.camera
    pose = left_camera_pose(VehiclePose(row[1], row[2], row[3], row[4]), cam.mount_frd_m, cam.mount_pitch_rad,
                            cam.mount_yaw_rad)
    target = sc.placard(target_id).centre_ned_m
    p = pose.to_cam(np.asarray(target, float))
    u, v = project_pinhole(p, cam.K)[0]
    w, h = cam.image_size
    inside = p[0, 2] > 0 and 0 <= u < w and 0 <= v < h
    return f"t={row[0]:.1f} z={p[0, 2]:.2f} m px=({u:.0f},{v:.0f}) {'in view' if inside else 'OUT of view'}"


if __name__ == "__main__":
    plan = sys.argv[1]
    seeds = [int(a) for a in sys.argv[2:] if "=" not in a]
    sets = dict(a.split("=", 1) for a in sys.argv[2:] if "=" in a)
    for seed in seeds:
        result, sim = run_faulted_mission("paper_pool", seed, plan, load_params(overrides=sets) if sets else load_params())
        story = result.story
        sus = next((i for i, l in enumerate(story) if "-> suspended" in l), None)
        line = f"seed {seed} {result.outcome}"
        if sus is not None:
            t_sus = float(re.match(r"t=([\d.]+)", story[sus]).group(1))
            eng = next((l for l in story[sus:] if "engaged in" in l), None)
            said = [l for l in story[sus:] if "resum" in l or "last seen" in l or "not tracked" in l][:2]
            line += f" | suspended {view_at(sim, result.target_id, t_sus)}"
            if eng:
                t_eng = float(re.match(r"t=([\d.]+)", eng).group(1))
                line += f" | re-engaged {view_at(sim, result.target_id, t_eng)}"
            line += " | " + " / ".join(s.split(" ", 1)[1] for s in said)
        print(line, flush=True)

"""Print one simulated run: its outcome, its trajectory every ``every_s`` (state, NED, yaw, distance to the diver's
body and, with ``faces``, to each placard's face) and its story. Shared by ``fw_story.py`` and ``fault_story.py``."""
import numpy as np
from sitl.clearance import body_distance_m, square_distance_m


def print_run(sc, result, trajectory, every_s: float = 0.5, faces: bool = False) -> None:
    """Print ``result`` (a ``SimResult``) and ``trajectory`` (the simulation's rows) of scenario ``sc``."""
    aim = np.asarray(sc.placard(result.target_id).centre_ned_m, float)
    print(result.outcome, result.time_to_arrive_s, "closest diver", result.closest_diver_m, result.closest_m)
    last = -1.0
    for r in trajectory:
        if r[0] - last >= every_s - 1e-9:
            last = r[0]
            where = (" faces " + " ".join(f"{p.id}:{float(square_distance_m(np.array(r[1:4]), p)[0]):.2f}"
                                          for p in sc.placards)) if faces else ""
            print(f"{r[0]:6.2f} {r[6]:14s} ned {np.round(r[1:4], 2)} yaw {np.degrees(r[4]):6.1f} "
                  f"body {body_distance_m(r[1:4], sc.diver.joints(aim, r[0])):.2f}{where}")
    for line in result.story:
        if "pilot heard" not in line and "frames:" not in line:
            print(line)

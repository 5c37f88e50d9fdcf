"""One paper_pool mission on the ArduSub SITL firmware, traced per tracking frame: the tracked target's position
against the truth (the chosen placard's centre, rectified left camera frame, metres) and how many of the frame's
objects lay within 0.3 m of it (fragments of one placard), then the error's mean and sd over the frames nearer than
1.3 m, the arrival and the state changes.

    python docs/issue11/session54/scripts/firmware_range_trace.py SEED [KEY=VALUE ...]
    (e.g. behaviour.track_surface_slope=0 for the tracker before session 54; firmware at speedup 0.5, instance 34,
    90 s of mission at most; the binary from $DIP3D_ARDUSUB or ../shared/ardusub-sitl/ardusub)
"""
import sys

import numpy as np

sys.path.insert(0, "tests/sitl")
import behaviours.approach_states as A  # noqa: E402
import behaviours.tracker as T  # noqa: E402
from dip3d_vehicle.config import load_params  # noqa: E402
from sitl.firmware_world import FirmwareSimulation  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402
from sitl.simulation import sim_params  # noqa: E402
from test_conformance import firmware_binary  # noqa: E402

seed = int(sys.argv[1])
sets = dict(a.split("=", 1) for a in sys.argv[2:])
objects, errors = [], []
group_objects, steer = T.group_objects, A._Steering.steer


def grouped(*args, **kwargs):
    """The tracker's grouping, its objects kept for the trace."""
    objects[:] = group_objects(*args, **kwargs)
    return objects


def traced(self, bb, found):
    """Steer as the mission does, then print the target against the truth."""
    dt = steer(self, bb, found)
    pid = sim.chosen_placard()
    if pid is None:
        return dt
    truth = sim.rig.R1 @ np.asarray(sim.last_meta["placards"][pid]["xyz_cam_m"])
    near = sum(np.linalg.norm(o.xyz_m - found.xyz_m) < 0.3 for o in objects)
    if truth[2] < 1.3:
        errors.append(np.asarray(found.xyz_m) - truth)
    e = bb.errors
    print(f"t={bb.now_s:.2f} {self.name:7s} px={e.pixel_px:5.1f} range_err={e.range_m:+.3f} "
          f"xyz={np.round(found.xyz_m, 3)} truth={np.round(truth, 3)} objects_within_0.3m={near}", flush=True)
    return dt


T.group_objects, A._Steering.steer = grouped, traced
sc = load_scenario("paper_pool", seed)
params = sim_params(load_params(overrides=sets) if sets else load_params(), sc, **{"sitl.max_sim_time_s": 90.0})
sim = FirmwareSimulation(sc, params, firmware_binary(), speedup=0.5, instance=34)
try:
    r = sim.run()
finally:
    sim.close()
if errors:
    err = np.array(errors)
    print(f"{len(err)} frames nearer than 1.3 m: z error mean {err[:, 2].mean():+.3f} sd {err[:, 2].std():.3f} "
          f"max {np.abs(err[:, 2]).max():.3f} m; x error mean {err[:, 0].mean():+.3f} sd {err[:, 0].std():.3f} m")
print(f"arrived {r.arrived} at {r.time_to_arrive_s} s, chosen {r.chosen_id}, target {r.target_id}, "
      f"closest {r.closest_m}")
for line in r.story:
    if " state " in line:
        print(line)

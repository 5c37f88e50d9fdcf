"""What the two session 49 trace scripts share: the scenario and seed from argv, the renderer tapped for each frame's
truth placards, and the nearest truth placard of a point.

``setup()`` returns (scenario, seed, last); ``near(last, xyz_m, R1)`` names the placard nearest ``xyz_m`` (camera
frame, metres) with its distance, or "?" before the first rendered frame.
"""
import sys
import numpy as np
sys.path.insert(0, "docs/issue11/session47/scripts")
from sim_tap import run_mission, tap_placards  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402

__all__ = ["run_mission", "setup", "near"]  # run_mission: re-exported for the scripts


def setup() -> tuple:
    """Return (scenario, seed, last, R1) from argv, with the renderer tapped into ``last``."""
    name, seed = sys.argv[1], int(sys.argv[2])
    last: dict = {}
    tap_placards(last)
    return name, seed, last, load_scenario(name, seed).rig().R1


def near(last: dict, xyz_m: np.ndarray, R1: np.ndarray) -> str:
    """Return the truth placard nearest ``xyz_m`` (camera frame, m) and its distance, as "id(d m)"."""
    truth = {p: R1 @ x for p, x in last.get("placards", {}).items()}
    if not truth:
        return "?"
    p = min(truth, key=lambda k: np.linalg.norm(truth[k] - xyz_m))
    return f"{p}({np.linalg.norm(truth[p] - np.asarray(xyz_m)):.2f} m)"

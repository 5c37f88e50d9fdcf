"""What the two trace scripts share: the rendered frames' truth placards, and one mission run.

``tap_placards(last)`` keeps each rendered frame's placards (camera frame, metres) in ``last["placards"]``;
``run_mission(name, seed)`` runs the mission (truth pose) and prints its outcome.
"""
import numpy as np
from sitl import render as R
from sitl.point_campaign import _simulation


def tap_placards(last: dict) -> None:
    """Wrap the renderer so that ``last["placards"]`` holds the latest frame's truth placards (camera frame, m)."""
    orig_render = R.StereoRenderer.render

    def render(self, *a, **k):
        frame = orig_render(self, *a, **k)
        last["placards"] = {p: np.asarray(i["xyz_cam_m"]) for p, i in frame.meta["placards"].items()}
        return frame

    R.StereoRenderer.render = render


def run_mission(name: str, seed: int) -> None:
    """Run one mission of the scenario and seed, and print pointed placard, chosen placard, arrived."""
    sim = _simulation(name, seed, {})
    try:
        result = sim.run()
    finally:
        sim.close()
    print("outcome", result.target_id, result.chosen_id, result.arrived)

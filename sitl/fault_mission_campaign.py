"""The full-loop tier's campaign: whole missions (paper_pool seeds, or another scenario's) under a fault plan;
arrivals, outcomes, log records written vs read back, and the safety of every fault event.

    python -m sitl.fault_campaign missions [--seeds 10] [--plan FILE] [--scenario NAME|FILE] [--first-seed 0]
                                           [--jobs N | --ray ADDRESS]
"""

from __future__ import annotations

import tempfile
import time
import traceback
from pathlib import Path
from typing import Any, Mapping

from dip3d_vehicle.config import load_params
from dip3d_vehicle.record.mcap_log import McapRunReader, McapRunWriter

from .fault_bounds import BOUNDS_S, FAULT_DIR
from .fault_mission import run_faulted_mission

__all__ = ["mission_campaign"]


def _mission_one(args: tuple) -> dict:
    seed, plan_path, overrides, scenario = args
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "run.mcap"
        params = load_params()
        wall0 = time.perf_counter()
        try:
            with McapRunWriter(path, None, {"command": "fault_campaign missions"}, overwrite=True) as log:
                result, sim = run_faulted_mission(scenario, seed, plan_path, params, log=log, **overrides)
        except Exception as exc:  # noqa: BLE001
            return {"seed": seed, "crashed": f"{exc.__class__.__name__}: {exc}", "traceback": traceback.format_exc()[-1500:]}
        with McapRunReader(path) as reader:
            read = {"frames": sum(1 for _ in reader.frames()), "telemetry": sum(1 for _ in reader.telemetry())}
        out = result.to_json()
        out.update({"crashed": "", "log_written": sim.log_counts, "log_read": read,
                    "relay": sim.relay.counts() if sim.relay else None, "guard_rejected": dict(sim.guard.rejected),
                    "fault_events": sim.fault_events.applied, "link_bad_data": sim.link.stats.bad_data,
                    "disengagements": [e for e in sim.link.events if "disengaged" in e],
                    "wall_s": round(time.perf_counter() - wall0, 1)})
        out.pop("states", None)
        safety = []
        for ev in sim.fault_events.applied:
            onset, end = ev["onset_s"], ev["recover_from_s"]
            if ev["kind"] == "camera_out_of_order":
                end = ev["clear_s"]
            recv = [r.t_s for r in sim.received if r.motion and onset <= r.t_s < end]
            sent = [t for t, _, eng, motion in sim.ticks if eng and motion and onset <= t < end]
            again = [r.t_s for r in sim.received if r.motion and r.t_s >= end]
            safety.append({**ev, "last_motion_received_s": round(max(recv) - onset, 3) if recv else 0.0,
                           "last_motion_sent_s": round(max(sent) - onset, 3) if sent else 0.0,
                           "bound_s": BOUNDS_S.get(ev["kind"]),
                           "moving_again_after_s": round(again[0] - end, 3) if again else None})
        out["fault_safety"] = safety
        return out


def mission_campaign(seeds: int = 10, plan: str | Path = FAULT_DIR / "link_loss.yaml", jobs: int = 1,
                     overrides: Mapping[str, Any] | None = None, verbose: bool = True, first_seed: int = 0,
                     ray: str | None = None, scenario: str = "paper_pool") -> dict:
    """Whole missions (``scenario``'s seeds first_seed.. +seeds) under a plan; arrivals and safety counters.

    Runs here (``jobs`` 1), in ``jobs`` processes, or on Ray (``ray``: see sitl/parallel.py).
    """
    from .parallel import map_runs

    items = [(s, str(plan), dict(overrides or {}), str(scenario)) for s in range(first_seed, first_seed + seeds)]
    runs = []
    for r in map_runs(_mission_one, items, jobs, ray):
        runs.append(r)
        if verbose:
            _print_mission(r)
    reached = sum(r.get("outcome") == "reached" for r in runs)
    outcomes: dict[str, int] = {}
    for r in runs:
        word = "crashed" if r.get("crashed") else r.get("outcome", "?")
        outcomes[word] = outcomes.get(word, 0) + 1
    return {"plan": str(plan), "scenario": str(scenario), "seeds": seeds, "arrived": sum(bool(r.get("arrived")) for r in runs),
            "reached": reached, "outcomes": outcomes, "crashes": sum(bool(r.get("crashed")) for r in runs),
            "runs": runs}


def _print_mission(r: dict) -> None:
    print(f"seed {r['seed']} outcome {r.get('outcome')} t {r.get('time_to_arrive_s')} "
          f"sim {r.get('sim_time_s')} wall {r.get('wall_s')} log {r.get('log_written')} / {r.get('log_read')} "
          f"relay {r.get('relay')} dis {r.get('disengagements')} guard {r.get('guard_rejected')} "
          f"safety {r.get('fault_safety')} crash '{r.get('crashed', '')[:100]}'", flush=True)

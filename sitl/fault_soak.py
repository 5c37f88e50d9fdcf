"""The soak: the fast tier with no fault for simulated hours; memory (RSS, live objects, optionally
tracemalloc) and the largest gaps between heartbeats on both sides.

    python -m sitl.fault_campaign soak [--hours 1] [--trace] [--json FILE]
"""

from __future__ import annotations

import gc
import resource
import time
import tracemalloc
from typing import Any, Mapping

from dip3d_vehicle.config import load_params

from .fault_trial import ControllerTrial, event_time_s, max_gap_s
from .faults import FaultPlan

__all__ = ["soak"]


def soak(hours: float = 1.0, params: Mapping[str, Any] | None = None, plan: FaultPlan | None = None,
         sample_every_s: float = 60.0, verbose: bool = True, trace: bool = False) -> dict:
    """Run the fast tier for ``hours`` simulated, engaged and streaming; measure memory and heartbeats.

    Memory: RSS and the number of live Python objects (gc) at every sample; with ``trace`` also
    tracemalloc (which slows the run 2-4x).
    """
    params = params if params is not None else load_params()
    plan = plan or FaultPlan()
    if trace:
        tracemalloc.start()
    trial = ControllerTrial(plan, params, 0, None)
    wall0 = time.perf_counter()
    samples = []
    try:
        trial.run_until(5.0)  # handed over, engaged
        warm = trial.clock.now() + 55.0
        trial.run_until(warm)
        # the trial keeps a tick/command history for scoring; trim it like a rolling buffer in the soak
        base = None
        end = warm + hours * 3600.0
        gaps = {"ap": 0.0, "ctrl": 0.0}
        n_hb = {"ap": 0, "ctrl": 0}
        del trial.ap_heard_controller_hb[:-1], trial.ctrl_heard_ap_hb[:-1]
        while trial.clock.now() < end - 1e-9:
            trial.run_until(min(trial.clock.now() + sample_every_s, end))
            del trial.ticks[:-100]
            del trial.received[:-100]
            for k, lst in (("ap", trial.ap_heard_controller_hb), ("ctrl", trial.ctrl_heard_ap_hb)):
                gaps[k] = max(gaps[k], max_gap_s(lst) if len(lst) > 1 else 0.0)
                n_hb[k] += len(lst) - 1
                del lst[:-1]  # keep the last one for the next gap
            gc.collect()
            cur = tracemalloc.get_traced_memory()[0] if trace else len(gc.get_objects())
            rss = _rss_kib()
            if base is None:
                base = (cur, rss)
            samples.append((round(trial.clock.now(), 1), cur, rss))
            if verbose and len(samples) % 10 == 0:
                print(f"soak t={trial.clock.now():7.1f} s {'traced KiB' if trace else 'objects'} "
                      f"{cur / 1024 if trace else cur:.0f} rss {rss} KiB "
                      f"engaged {trial.link.engaged} wall {time.perf_counter() - wall0:.0f} s", flush=True)
        ap_gap, ctrl_gap = gaps["ap"], gaps["ctrl"]
        disengaged = [e for e in trial.link.events if "disengaged" in e and event_time_s(e) >= warm]
        engaged_at_end = trial.link.engaged
    finally:
        trial.close()
        if trace:
            tracemalloc.stop()
    first, last = samples[0], samples[-1]
    what = "traced_kib" if trace else "python_objects"
    scale = 1024 if trace else 1
    return {"sim_hours": hours, "wall_s": round(time.perf_counter() - wall0, 1),
            f"{what}_first": round(first[1] / scale), f"{what}_last": round(last[1] / scale),
            f"{what}_growth_pct": round(100.0 * (last[1] - first[1]) / first[1], 2),
            "rss_first_kib": first[2], "rss_last_kib": last[2],
            "rss_growth_pct": round(100.0 * (last[2] - first[2]) / first[2], 2),
            "controller_heartbeats_heard_by_autopilot": n_hb["ap"],
            "max_gap_controller_hb_at_autopilot_s": round(ap_gap, 3),
            "autopilot_heartbeats_heard_by_controller": n_hb["ctrl"],
            "max_gap_autopilot_hb_at_controller_s": round(ctrl_gap, 3),
            "disengagements": disengaged, "engaged_at_end": engaged_at_end,
            "engaged_fraction_last_100_ticks": sum(e for _, e, _ in trial.ticks) / max(len(trial.ticks), 1),
            "autopilot_motion_commands_last_100": sum(m for _, m in trial.received),
            "samples": samples[:: max(1, len(samples) // 20)]}


def _rss_kib() -> int:
    """Return this process's resident memory, KiB (/proc; else the peak from getrusage)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss

"""Closed-loop campaigns: the mission over many seeds, and the safety figures over many trials.

    python -m sitl.campaign mission [--per-position 10] [--jobs 2] [--json FILE] [--scenario NAME]
                                    [--positions A,B] [--set KEY=VALUE ...] [--ray auto|local[:N]|ADDRESS]
    python -m sitl.campaign safety  [--trials 20] [--jobs 2] [--json FILE] [--ray ...]

``mission``: ``paper_pool`` (or ``--scenario``) seeds 0, 1, 2, ... until ``--per-position`` seeds of
each diver position (paper_pool: the paper's 2 and 3) have run; a run succeeds when the mission arrived at the placard the diver
points at with the true range at arrival within ``behaviour.arrive_tolerance_m`` of the stand-off.
Prints one line per run and the arrivals per position, time to arrive and range errors.

``safety``: faults injected at a seeded time while the vehicle is moving (during the acknowledge
nod or the servo), counted on the AUTOPILOT's side (every MANUAL_CONTROL /
SET_POSITION_TARGET_LOCAL_NED it received, motion = not neutral / not all zero). In GUIDED the
simulated pilot's joystick streams centred sticks (as QGC does), which are never motion:

1. autopilot silent (its messages stop reaching the controller): time from the silence to the
   last motion command the autopilot received (must be <= 1 s);
2. pilot changes mode (MANUAL) or disarms: motion commands received after the controller was told
   (the autopilot's next HEARTBEAT; must be 0), and the time from the change to the last one;
3. guided_velocity (vehicle with DVL, GUIDED), disengaged by the operator or by stale perception
   mid-yaw: the vehicle's true yaw rate from 1 s after disengaging to the end of the trial (must be
   ~0: ArduSub keeps a GUIDED yaw rate forever unless told zero);
4. perception stalls (manual_control and guided_velocity): motion commands received once the newest
   result is older than the stale limit (must be 0).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from collections import Counter
from typing import Any

__all__ = ["mission_campaign", "safety_campaign", "main"]

SAFETY_OVERRIDES = {"sitl.camera_rate_hz": 10 / 3, "sitl.perception_latency_s": 0.1, "sitl.max_sim_time_s": 25.0}
"""Safety trials: a slower camera (cheaper) with a shorter latency (newest result stays < 0.5 s old)."""
GUIDED = {"link.output_mode": "guided_velocity", "sim.has_position": True}


def _run_one(args: tuple) -> dict:
    """Run one mission (in a worker process); return its JSON result (+ safety numbers)."""
    from dip3d_vehicle.config import load_params
    from sitl.simulation import Fault, run_mission

    seed, fault, overrides = args[:3]
    scenario, sets = (args[3], args[4]) if len(args) > 3 else ("paper_pool", {})
    params = load_params(overrides=sets) if sets else load_params()
    result, _ = run_mission(scenario, seed, params, fault=Fault(**fault) if fault else None, **overrides)
    out = result.to_json()
    out["story_tail"] = result.story[-12:]
    return out


def _pool_map(items: list, jobs: int, ray: str | None = None):
    """Yield ``_run_one`` of every item, in order: here, in ``jobs`` processes or on Ray (sitl/parallel.py)."""
    from .parallel import map_runs

    yield from map_runs(_run_one, items, jobs, ray)


def _stats(values: list[float]) -> str:
    """Return 'mean +- sd (min..max), n' of some numbers."""
    vals = [v for v in values if v is not None and math.isfinite(v)]
    if not vals:
        return "n/a"
    sd = statistics.stdev(vals) if len(vals) > 1 else 0.0
    return f"{statistics.mean(vals):.3f} +- {sd:.3f} (min {min(vals):.3f}, max {max(vals):.3f}), n={len(vals)}"


def mission_campaign(per_position: int = 10, jobs: int = 2, max_seed: int = 200,
                     positions: tuple[str, ...] = ("2", "3"), scenario: str = "paper_pool",
                     sets: dict | None = None, ray: str | None = None) -> dict:
    """Run ``scenario`` until ``per_position`` seeds per diver position; return the summary.

    ``sets``: parameter overrides (``key: value``) for every run, e.g. ``sitl.pose_source``.
    ``ray``: run on Ray (``auto``, ``local[:N]`` or an address; see sitl/parallel.py) instead of ``jobs`` processes.
    """
    from sitl.scenario import load_scenario

    chosen: dict[str, list[int]] = {p: [] for p in positions}
    for seed in range(max_seed):
        pos = load_scenario(scenario, seed).diver.position_name
        if pos in chosen and len(chosen[pos]) < per_position:
            chosen[pos].append(seed)
        if all(len(v) >= per_position for v in chosen.values()):
            break
    seeds = sorted(s for v in chosen.values() for s in v)
    runs = []
    print(f"mission campaign: {scenario} seeds {seeds} {sets or ''}", flush=True)
    for r in _pool_map([(s, None, {}, scenario, dict(sets or {})) for s in seeds], jobs, ray):
        runs.append(r)
        print(f"seed {r['seed']:3d} pos {r['diver_position']} target {r['target_id']} chosen {r['chosen_id']} "
              f"outcome {r['outcome']} t_arrive {r['time_to_arrive_s']} "
              f"range@arrival {r['range_at_arrival_m']} err {r['range_error_at_arrival_m']} "
              f"final {r['final_range_m']} px {r['final_pixel_error_px']} sim {r['sim_time_s']} "
              f"wall {r['wall_time_s']} pose {r.get('pose_source')}", flush=True)
    summary: dict[str, Any] = {"runs": runs, "per_position": {}}
    for pos in positions:
        rs = [r for r in runs if r["diver_position"] == pos]
        ok = [r for r in rs if r["outcome"] == "reached"]
        summary["per_position"][pos] = {
            "seeds": [r["seed"] for r in rs], "reached": len(ok), "of": len(rs),
            "wrong_target": sum(1 for r in rs if r["outcome"] == "wrong_object"),
            "outcomes": dict(Counter(r["outcome"] for r in rs)),
            "time_to_arrive_s": _stats([r["time_to_arrive_s"] for r in ok]),
            "range_error_at_arrival_m": _stats([r["range_error_at_arrival_m"] for r in ok]),
            "abs_range_error_at_arrival_m": _stats([abs(r["range_error_at_arrival_m"]) for r in ok]),
            "final_range_error_m": _stats([r["final_range_error_m"] for r in ok]),
            "final_pixel_error_px": _stats([r["final_pixel_error_px"] for r in ok]),
        }
    for pos, s in summary["per_position"].items():
        print(f"diver position {pos}: reached {s['reached']} / {s['of']} (wrong target {s['wrong_target']}; "
              f"outcomes {s['outcomes']})")
        for k in ("time_to_arrive_s", "range_error_at_arrival_m", "abs_range_error_at_arrival_m",
                  "final_range_error_m", "final_pixel_error_px"):
            print(f"    {k}: {s[k]}")
    return summary


def _fault(kind: str, seed: int) -> dict:
    """A fault at a seeded moment while the vehicle moves: during the acknowledge nod (yawing left
    and right for 2 s), 0.1 to 1.9 s after it starts (the nod is the first motion of the mission,
    which keeps the trials short)."""
    return {"kind": kind, "state": "acknowledge", "after_s": 0.1 + (seed * 0.37) % 1.8, "run_after_s": 2.5}


def safety_campaign(trials: int = 20, jobs: int = 2, ray: str | None = None) -> dict:
    """Run the safety trials; return the per-figure numbers."""
    half = max(trials // 2, 1)
    plan = []  # (figure, seed, fault, overrides)
    for s in range(trials):
        plan.append(("autopilot_silent", s, _fault("autopilot_silent", s), SAFETY_OVERRIDES))
    for s in range(trials):
        plan.append(("pilot_takes_over", s, _fault("mode_change" if s < half else "disarm", s), SAFETY_OVERRIDES))
    for s in range(trials):
        kind = "disable" if s < half else "perception_stall"
        plan.append(("guided_yaw", s, _fault(kind, s), {**SAFETY_OVERRIDES, **GUIDED}))
    for s in range(half):
        plan.append(("stale_manual", s, _fault("perception_stall", s), SAFETY_OVERRIDES))
    results: dict[str, list[dict]] = {}
    items = [(seed, fault, over) for _, seed, fault, over in plan]
    for (figure, seed, fault, _), r in zip(plan, _pool_map(items, jobs, ray)):
        r["figure"] = figure
        results.setdefault(figure, []).append(r)
        sf = r.get("safety", {})
        print(f"{figure:17s} seed {seed:2d} {fault['kind']:16s} in {fault['state']:11s} "
              f"+{fault['after_s']:.2f}s: {json.dumps(sf)}", flush=True)
    return summarise_safety(results)


def summarise_safety(results: dict[str, list[dict]]) -> dict:
    """Return and print the figures from the per-trial safety numbers."""
    out: dict[str, Any] = {}
    silent = [r["safety"] for r in results.get("autopilot_silent", []) if r["safety"].get("fault_at_s") is not None]
    if silent:
        delays = [s["last_motion_after_fault_s"] for s in silent]
        out["autopilot_silent"] = {"trials": len(silent), "max_s": max(delays),
                                   "within_1s": sum(d <= 1.0 for d in delays), "delays": _stats(delays)}
    take = [r["safety"] for r in results.get("pilot_takes_over", []) if r["safety"].get("fault_at_s") is not None]
    if take:
        after_told = [s.get("motion_commands_after_told") for s in take]
        delays = [s["last_motion_after_fault_s"] for s in take]
        out["pilot_takes_over"] = {"trials": len(take),
                                   "trials_with_motion_after_told": sum(1 for a in after_told if a),
                                   "motion_commands_after_told_total": sum(a or 0 for a in after_told),
                                   "untold": sum(1 for a in after_told if a is None),
                                   "last_motion_after_change_s": _stats(delays)}
    guided = [r["safety"] for r in results.get("guided_yaw", []) if r["safety"].get("fault_at_s") is not None]
    if guided:
        rates = [s.get("max_abs_yaw_rate_1s_after_disengage") for s in guided]
        zeros = [s.get("zero_yaw_rate_sent_after_s") for s in guided]
        out["guided_yaw"] = {"trials": len(guided), "max_abs_yaw_rate_rad_s_from_1s": max(r for r in rates if r is not None),
                             "trials_under_0.01": sum(1 for r in rates if r is not None and r < 0.01),
                             "first_zero_setpoint_after_disengage_s": _stats([z for z in zeros if z is not None]),
                             "motion_commands_after_fault": _stats([s["motion_commands_after_fault"] for s in guided])}
    stale = [r["safety"] for fig in ("stale_manual", "guided_yaw") for r in results.get(fig, [])
             if r.get("fault", {}).get("kind") == "perception_stall" and r["safety"].get("fault_at_s") is not None]
    if stale:
        out["perception_stale"] = {"trials": len(stale),
                                   "motion_commands_while_stale_total": sum(s["motion_commands_while_stale"] for s in stale),
                                   "last_motion_after_stall_s": _stats([s["last_motion_after_fault_s"] for s in stale])}
    print(json.dumps(out, indent=2))
    return out


def _positions(scenario: str, text: str | None) -> tuple[str, ...]:
    """Return the diver positions to run: the given ones, or every position the scenario lists."""
    if text:
        return tuple(text.split(","))
    from sitl.scenario import load_scenario

    doc = load_scenario(scenario, 0).raw["diver"]["positions"]
    return tuple(str(p.get("name", i + 1)) for i, p in enumerate(doc))


def _sets(items: list[str]) -> dict:
    """Return ``KEY=VALUE`` overrides as typed values, checked against the parameter schema.

    A malformed item exits with a message naming it; an unknown key or a bad value raises ParamsError.
    """
    from dip3d_vehicle.config import load_params

    for item in items:
        if "=" not in item:
            raise SystemExit(f"--set {item!r}: expected KEY=VALUE")
    params = load_params(overrides=items)
    return {key: params[key] for key in (item.partition("=")[0].strip() for item in items)}


def main(argv: list[str] | None = None) -> int:
    """Command line: ``mission`` or ``safety``."""
    from .parallel import add_executor_arguments

    ap = argparse.ArgumentParser(prog="python -m sitl.campaign", description=__doc__.split("\n")[0])
    ap.add_argument("which", choices=["mission", "safety"])
    ap.add_argument("--per-position", type=int, default=10)
    ap.add_argument("--positions", default=None,
                    help="diver positions, comma-separated (mission; default: every position of the scenario)")
    ap.add_argument("--scenario", default="paper_pool", help="built-in scenario name or file (mission)")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="parameter override for every run (mission; repeatable), e.g. sitl.pose_source=blazepose")
    ap.add_argument("--trials", type=int, default=20)
    add_executor_arguments(ap, jobs_default=2)
    ap.add_argument("--json", metavar="FILE")
    args = ap.parse_args(argv)
    if args.which == "mission":
        out = mission_campaign(args.per_position, args.jobs, positions=_positions(args.scenario, args.positions),
                               scenario=args.scenario, sets=_sets(args.sets), ray=args.ray)
    else:
        out = safety_campaign(args.trials, args.jobs, ray=args.ray)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())

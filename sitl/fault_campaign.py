"""Fault campaigns: every fault of ``sitl/faults.py`` over randomised trials, the lossy-link missions, a soak.

    python -m sitl.fault_campaign trials  [--trials 20] [--json FILE]     # fast tier, every fault
    python -m sitl.fault_campaign missions [--seeds 10] [--plan FILE] [--scenario S] [--json FILE]  # full loop
    python -m sitl.fault_campaign soak    [--hours 1] [--json FILE]

Two tiers, because a closed-loop mission costs ~1 wall second per simulated second (SIFT on both
images of every frame), too slow for 20 trials x 13 faults on a shared machine:

- ``trials`` (``ControllerTrial``): the REAL simulated autopilot (sitl.Autopilot), the router and the
  simulated pilot/GCS of ``sitl.simulation``, the ``LossyRelay``, ``VehicleLink`` and the
  ``FrameGuard`` at the perception boundary, with a stand-in for perception + servo: small synthetic
  camera frames (through ``CameraFaults``), and a constant forward-and-turn command while the newest
  accepted frame is fresh (as ``behaviours.loop.Controller`` passes ``bb.command`` only when fresh).
  This measures what the issue asks per fault: the time from the fault's onset to the last motion
  command (sent by the controller, and received by the autopilot), crashes, log records written vs
  read back, and recovery (re-engaged and moving again after the fault clears and the pilot hands
  over again, per the link's enable-latch policy).
- ``missions`` (``FaultSimulation``): the whole mission (``sitl.simulation.Simulation``) with a fault
  plan: the relay sits between the controller and the router, camera faults act on the rendered
  frames before the ``FrameGuard``, timed events act on the autopilot / pilot.
- ``soak``: the fast tier, no faults, for simulated hours: memory (tracemalloc and RSS) and the gaps
  between heartbeats on both sides.

The modules: ``fault_bounds`` (the promised bound and expected outcome per fault), ``fault_events``
(a plan's timed events applied to a run), ``fault_trial`` and ``fault_trial_campaign`` (the fast
tier), ``fault_mission`` and ``fault_mission_campaign`` (the full loop), ``fault_soak``; this one is
the command line and re-exports their public names.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

# re-exported: callers import these from here (``__all__`` is unchanged)
from .fault_bounds import BOUNDS_S, EXPECTED, FAULT_DIR, TRIAL_PLANS
from .fault_mission import make_simulation, run_faulted_mission
from .fault_mission_campaign import mission_campaign
from .fault_soak import soak
from .fault_trial import ControllerTrial, TrialResult, run_trial
from .fault_trial_campaign import markdown_table, trial_campaign
from .faults import load_fault_plan

__all__ = ["BOUNDS_S", "ControllerTrial", "FaultSimulation", "run_faulted_mission", "trial_campaign",
           "mission_campaign", "soak", "markdown_table", "make_simulation", "main"]


def __getattr__(name: str) -> Any:
    """Return ``FaultSimulation`` from ``sitl.fault_mission`` (built there on first use)."""
    if name == "FaultSimulation":
        from . import fault_mission
        return fault_mission.FaultSimulation
    raise AttributeError(name)


def main(argv: list[str] | None = None) -> int:
    """Command line: trials / missions / soak (see the module doc)."""
    from .parallel import add_executor_arguments

    ap = argparse.ArgumentParser(prog="python -m sitl.fault_campaign", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    t = sub.add_parser("trials")
    t.add_argument("--trials", type=int, default=20)
    t.add_argument("--fault", action="append", choices=list(BOUNDS_S))
    add_executor_arguments(t)
    m = sub.add_parser("missions")
    m.add_argument("--seeds", type=int, default=10)
    m.add_argument("--plan", default=str(FAULT_DIR / "link_loss.yaml"))
    m.add_argument("--scenario", default="paper_pool", help="built-in scenario name or scenario file (default paper_pool)")
    add_executor_arguments(m)
    m.add_argument("--first-seed", type=int, default=0)
    s = sub.add_parser("soak")
    s.add_argument("--hours", type=float, default=1.0)
    s.add_argument("--trace", action="store_true", help="also measure with tracemalloc (2-4x slower)")
    for p in (t, m, s):
        p.add_argument("--json", metavar="FILE")
    args = ap.parse_args(argv)
    if args.what == "trials":
        out = trial_campaign(args.trials, args.fault, jobs=args.jobs, ray=args.ray)
        for k, v in out["summary"].items():
            print(k, json.dumps(v))
        print(markdown_table(out["summary"]))
    elif args.what == "missions":
        _check_mission_inputs(ap, args.plan, args.scenario, args.first_seed)
        out = mission_campaign(args.seeds, args.plan, args.jobs, first_seed=args.first_seed, ray=args.ray,
                               scenario=args.scenario)
        print(f"reached the pointed placard {out['reached']} / {out['seeds']} (outcomes {out['outcomes']}; "
              f"arrived anywhere {out['arrived']}), crashes {out['crashes']}")
    else:
        out = soak(args.hours, trace=args.trace)
        print(json.dumps({k: v for k, v in out.items() if k != "samples"}))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1, default=str))
    return 0


def _check_mission_inputs(ap: argparse.ArgumentParser, plan: str, scenario: str, seed: int) -> None:
    """Exit with the file and field at fault when the plan or the scenario cannot be loaded, before any run."""
    from dip3d_vehicle.errors import ScenarioError

    from .scenario import load_scenario

    try:
        load_fault_plan(plan, seed=seed)
        load_scenario(scenario, seed)
    except ScenarioError as exc:
        ap.error(str(exc))


if __name__ == "__main__":
    sys.exit(main())

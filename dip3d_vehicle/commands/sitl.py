"""``dip3d-vehicle sitl``: the whole mission closed-loop against the simulated ArduSub over MAVLink.

The simulated pilot arms the vehicle, selects the engage mode and enables the controller; the
diver points; the controller waits for the arm, confirms the point, selects the target by votes,
nods, servoes to the stand-off and reports. Writes to ``--out`` (default ``sitl.out_dir``): the run
log ``run.log`` (replayable: ``dip3d-vehicle replay``), ``trajectory.png`` (top view and depth
over time, placards and diver marked) and ``final_view.png`` (the last left frame, target marked).
Exit code 0 whether or not the vehicle arrived; 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path

from ..errors import Dip3dError
from ._common import add_params_arguments, params_from_args

NAME = "sitl"
HELP = "run the whole mission closed-loop against the simulated ArduSub (real MAVLink sockets)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --scenario, --seed, --json, --speed, --out, --no-plots and the parameter options."""
    parser.add_argument("--scenario", default="paper_pool", metavar="NAME|FILE",
                        help="built-in scenario name or scenario YAML file (default paper_pool)")
    parser.add_argument("--seed", type=int, default=0, help="scenario seed (diver position, target, noise)")
    parser.add_argument("--json", action="store_true", help="print one JSON object with the outcome")
    parser.add_argument("--speed", type=float, default=None, metavar="X",
                        help="run at X times real time (default: as fast as possible)")
    parser.add_argument("--out", metavar="DIR", default=None, help="output folder (default: sitl.out_dir)")
    parser.add_argument("--no-plots", action="store_true", help="do not write trajectory.png / final_view.png")
    parser.add_argument("--faults", metavar="FILE", default=None,
                        help="inject the faults of a fault plan (e.g. sitl/faults/link_cut.yaml): lossy link, "
                             "autopilot reboot, pilot actions, ground-station loss, camera faults")
    parser.add_argument("--ardusub", metavar="PATH", default=None,
                        help="fly against this ArduSub SITL binary instead of the built-in autopilot "
                             "(wall-clock time; see sitl.ardusub_speedup)")
    add_params_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run one simulated mission and print its outcome."""
    from dip3d_vehicle.perception.calibration_io import write_opencv_calibration
    from dip3d_vehicle.runlog import RunLogWriter
    from sitl.scenario import load_scenario
    from sitl.fault_campaign import load_fault_plan, make_simulation
    from sitl.simulation import sim_params

    import logging
    logging.getLogger("dip3d_vehicle.link").setLevel(logging.ERROR)  # its warnings are in the story
    if args.speed is not None and not args.speed > 0:
        raise Dip3dError(f"--speed {args.speed}: must be > 0")
    params = params_from_args(args)
    if args.faults:
        load_fault_plan(args.faults, seed=args.seed)  # a bad plan fails before anything starts
    scenario = load_scenario(args.scenario, args.seed)
    params = sim_params(params, scenario)
    out = Path(args.out or params["sitl.out_dir"])
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise Dip3dError(f"{out}: cannot create output folder ({exc.strerror})") from None
    with tempfile.TemporaryDirectory() as tmp:
        calib_text = write_opencv_calibration(scenario.rig(params["calib.alpha"]), Path(tmp) / "calib.yaml").read_text()
    keep = params["runlog.keep_images_every"]
    if params.source("runlog.keep_images_every") == "schema default":
        keep = 10  # a 1600x1200 pair per frame would dominate the run time; every 10th frame
    meta = {"command": "sitl", "scenario": scenario.name, "seed": args.seed, "calib_opencv_yaml": calib_text,
            "image_size": list(scenario.camera.image_size), "target_id": scenario.target_id}
    with RunLogWriter(out / "run.log", params, meta, keep_images_every=keep, overwrite=True) as log:
        ardusub = args.ardusub or params["sitl.ardusub_path"]
        if ardusub:
            from sitl.firmware_world import make_firmware_simulation
            sim = make_firmware_simulation(scenario, params, ardusub, log=log)
        else:
            sim = make_simulation(scenario, params, args.faults, args.seed, speed=args.speed, log=log)
        try:
            result = sim.run()
        finally:
            sim.close()
        for line in result.story:
            log.event(line)
    if not args.no_plots:
        write_trajectory_plot(sim, result, out / "trajectory.png")
        write_final_view(sim, result, out / "final_view.png")
    if args.json:
        doc = result.to_json()
        doc["out_dir"] = str(out)
        print(json.dumps(doc))
    else:
        print_story(result, out)
    return 0


def print_story(result, out: Path) -> None:
    """Print the run's story (time-stamped states and events) and its outcome."""
    print(f"sitl: scenario {result.scenario} seed {result.seed}: diver at position {result.diver_position} "
          f"points at placard {result.target_id}")
    for line in result.story:
        print("  " + (line[:160] + " ..." if len(line) > 170 else line))
    if result.arrived:
        which = "the pointed placard" if result.chosen_id == result.target_id else f"placard {result.chosen_id} (WRONG)"
        print(f"sitl: ARRIVED at {which} {result.time_to_arrive_s:.1f} s into the run; true range at arrival "
              f"{_fmt(result.range_at_arrival_m, 'm')} (error {_fmt(result.range_error_at_arrival_m, 'm')}), at the end "
              f"{_fmt(result.final_range_m, 'm')}; {'within' if result.reached else 'OUTSIDE'} the stand-off tolerance")
    else:
        tracked = f"tracking placard {result.chosen_id}" if result.chosen_id is not None else "no target chosen"
        print(f"sitl: did NOT arrive ({tracked}); pointed placard {result.target_id} at "
              f"{_fmt(result.final_range_m, 'm')} at the end")
    print(f"sitl: {result.sim_time_s:.1f} s simulated in {result.wall_time_s:.1f} s")
    print(f"sitl: wrote {out / 'run.log'}, {out / 'trajectory.png'}, {out / 'final_view.png'}")


def _fmt(v, unit: str) -> str:
    return "n/a" if v is None else f"{v:.2f} {unit}"


def write_trajectory_plot(sim, result, path: Path) -> None:
    """Top view (north up, east right) with placards and diver, and depth over time with the states."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    traj = sim.trajectory
    t = [r[0] for r in traj]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [1.1, 1]})
    ax.plot([r[2] for r in traj], [r[1] for r in traj], "-", color="tab:blue", label="vehicle")
    for r in traj[:: max(1, len(traj) // 25)]:
        ax.arrow(r[2], r[1], 0.15 * math.sin(r[4]), 0.15 * math.cos(r[4]), head_width=0.04, color="tab:blue", alpha=0.5)
    for p in sim.scenario.placards:
        n, e, _ = p.centre_ned_m
        colour = "tab:green" if p.id == result.target_id else ("tab:gray" if p.role == "distractor" else "tab:orange")
        ax.plot(e, n, "s", color=colour, ms=10)
        ax.annotate(f"{p.id}" + (" (target)" if p.id == result.target_id else ""), (e, n), xytext=(6, 4),
                    textcoords="offset points")
    dn, de, _ = sim.scenario.diver.chest_ned_m
    ax.plot(de, dn, "o", color="k", ms=9, label=f"diver (position {result.diver_position})")
    ax.plot(traj[0][2], traj[0][1], "^", color="tab:blue", ms=8, label="start")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"{result.scenario} seed {result.seed}: {'arrived' if result.arrived else 'not arrived'}")
    ax2.plot(t, [r[3] for r in traj], color="tab:blue", label="vehicle")
    for p in sim.scenario.placards:
        ax2.axhline(p.centre_ned_m[2], color="tab:green" if p.id == result.target_id else "tab:orange", lw=0.8,
                    ls="--")
    depths = [r[3] for r in traj] + [p.centre_ned_m[2] for p in sim.scenario.placards]
    ax2.set_ylim(max(depths) + 0.2, min(depths) - 0.2)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("depth (m)")
    ax2.grid(alpha=0.3)
    states = result.states
    colours = plt.get_cmap("tab20")
    names = sorted({s["state"] for s in states})
    for i, s in enumerate(states):
        end = states[i + 1]["t_s"] if i + 1 < len(states) else result.sim_time_s
        ax2.axvspan(s["t_s"], end, color=colours(names.index(s["state"]) % 20), alpha=0.25, lw=0)
        ax2.text(s["t_s"], ax2.get_ylim()[1], s["state"], rotation=90, va="top", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_final_view(sim, result, path: Path) -> None:
    """Write the last left frame with the placards' outlines, the target and the tracked point."""
    import cv2
    import numpy as np

    frame = sim.last_frame
    if frame is None:
        return
    img = frame.left.copy()
    for pid, info in frame.meta["placards"].items():
        poly = info.get("left_polygon_px")
        if poly is None:
            continue
        colour = (0, 200, 0) if pid == result.target_id else (0, 165, 255)
        cv2.polylines(img, [np.asarray(poly, np.int32)], True, colour, 3)
        c = np.mean(np.asarray(poly), axis=0).astype(int)
        cv2.putText(img, str(pid), (int(c[0]) - 10, int(c[1]) - 20), cv2.FONT_HERSHEY_SIMPLEX, 1.2, colour, 3)
    target = sim.mission.bb.target
    if target is not None:
        u, v = sim.rig.to_original(target.left_px, "left")[0]
        cv2.drawMarker(img, (int(u), int(v)), (0, 0, 255), cv2.MARKER_CROSS, 40, 3)
    w, h = img.shape[1], img.shape[0]
    cv2.drawMarker(img, (w // 2, h // 2), (255, 255, 255), cv2.MARKER_SQUARE, 30, 1)
    text = (f"t={result.sim_time_s:.1f}s state={sim.mission.state} target={result.target_id} "
            f"chosen={result.chosen_id} range={_fmt(result.final_range_m, 'm')}")
    cv2.putText(img, text, (20, 50), cv2.FONT_HERSHEY_SIMPLEX, 1.1, (255, 255, 255), 3)
    cv2.imwrite(str(path), cv2.resize(img, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA))

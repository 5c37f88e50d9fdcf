"""``dip3d-vehicle sitl``: the whole mission closed-loop against the simulated ArduSub over MAVLink.

The simulated pilot arms the vehicle, selects the engage mode and enables the controller; the
diver points; the controller waits for the arm, confirms the point, selects the target by votes,
nods, servoes to the stand-off and reports. The story is printed as it happens (with a progress
line on a terminal; nothing but one JSON object with ``--json``). Every run writes into its own new
folder (``<sitl.out_dir>/<UTC time>_<scenario>_s<seed>/``, or ``--out`` if new or empty): the run
record ``run.mcap`` (Foxglove; replayable: ``dip3d-vehicle replay``), the MAVLink log ``mav.tlog``,
``trajectory.png`` (top view, depth and states over time) and ``final_view.png`` (the last left
frame, target marked). The run ends in one outcome word (sitl/outcome.py); the exit code is 0 only
for ``reached`` (3 wrong_object, 4 outside_tolerance, 5 not_arrived, 6 no_decision, 7 aborted,
8 suspended); 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import textwrap
from pathlib import Path

from ..errors import Dip3dError
from ..run_folder import explicit_run_folder, new_run_folder
from ._common import add_params_arguments, params_from_args
from ._record import add_record_arguments, close_recorder, open_recorder

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
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="output folder, new or empty (default: a new folder under sitl.out_dir)")
    parser.add_argument("--no-plots", action="store_true", help="do not write trajectory.png / final_view.png")
    parser.add_argument("--faults", metavar="FILE", default=None,
                        help="inject the faults of a fault plan (e.g. sitl/faults/link_cut.yaml): lossy link, "
                             "autopilot reboot, pilot actions, ground-station loss, camera faults")
    parser.add_argument("--ardusub", metavar="PATH", default=None,
                        help="fly against this ArduSub SITL binary instead of the built-in autopilot "
                             "(wall-clock time; see sitl.ardusub_speedup)")
    add_record_arguments(parser)
    add_params_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run one simulated mission and print its outcome."""
    from dip3d_vehicle.perception.calibration_io import write_opencv_calibration
    from sitl.scenario import load_scenario
    from sitl.fault_mission import make_simulation
    from sitl.faults import load_fault_plan
    from sitl.live import LiveStory
    from sitl.outcome import OUTCOME_EXIT_CODES
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
    out = explicit_run_folder(args.out) if args.out else new_run_folder(params["sitl.out_dir"], scenario.name, args.seed)
    if not args.json:
        print(f"sitl: scenario {scenario.name} seed {args.seed}: diver at position {scenario.diver.position_name} "
              f"points at placard {scenario.target_id}; writing {out}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        calib_text = write_opencv_calibration(scenario.rig(params["calib.alpha"]), Path(tmp) / "calib.yaml").read_text()
    keep = params["runlog.keep_images_every"]
    if params.source("runlog.keep_images_every") == "schema default":
        keep = 10  # a 1600x1200 pair per frame would dominate the run time; every 10th frame
    if params.source("runlog.video_fps") == "schema default":  # one video frame per camera frame
        params = params.with_overrides({"runlog.video_fps": params["sitl.camera_rate_hz"]}, "sitl")
    meta = {"command": "sitl", "scenario": scenario.name, "seed": args.seed, "calib_opencv_yaml": calib_text,
            "image_size": list(scenario.camera.image_size), "target_id": scenario.target_id}
    log, lines = open_recorder(args, out / "run.mcap", params, meta, command="sitl", keep_images_every=keep,
                               overwrite=True)
    try:
        for line in lines:
            print(line, file=sys.stderr, flush=True)
        ardusub = args.ardusub or params["sitl.ardusub_path"]
        if ardusub:
            from sitl.firmware_world import make_firmware_simulation
            sim = make_firmware_simulation(scenario, params, ardusub, log=log)
        else:
            sim = make_simulation(scenario, params, args.faults, args.seed, speed=args.speed, log=log)
        log.rig = sim.rig
        log.attach_link(sim.link)
        live = None if args.json else LiveStory(sim)
        sim.on_step = live
        try:
            result = sim.run()
        finally:
            sim.close()
            if live is not None:
                live.finish()
        log.story(sim.link.events + sim.mission.bb.story)  # the lines of the link's close
        log.event(f"t={result.sim_time_s:.2f} outcome {result.outcome}: {result.outcome_reason}")
    finally:
        close_recorder(log)
    if not args.no_plots:
        write_trajectory_plot(sim, result, out / "trajectory.png")
        write_final_view(sim, result, out / "final_view.png")
    if args.json:
        doc = result.to_json()
        doc["out_dir"] = str(out)
        doc["exit_code"] = OUTCOME_EXIT_CODES[result.outcome]
        print(json.dumps(doc))
    else:
        print_outcome(result, out, plots=not args.no_plots)
    return OUTCOME_EXIT_CODES[result.outcome]


def print_outcome(result, out: Path, plots: bool = True) -> None:
    """Print the run's outcome (one word and its reason), the numbers behind it and the files written."""
    from sitl.outcome import OUTCOME_EXIT_CODES

    chosen = "none" if result.chosen_id is None else f"placard {result.chosen_id}"
    arrival = (f" at {result.time_to_arrive_s:.1f} s, true range at arrival {_fmt(result.range_at_arrival_m, 'm')} "
               f"(error {_fmt(result.range_error_at_arrival_m, 'm')}"
               + (f" from the stand-off held short by {result.held_short_m:.1f} m to keep clear)" if result.held_short_m
                  else ")") if result.arrived else "")
    end_of = chosen if result.chosen_id is not None else f"placard {result.target_id}"
    lines = [f"sitl: outcome {result.outcome.upper()} (exit code {OUTCOME_EXIT_CODES[result.outcome]}): "
             f"{result.outcome_reason}",
             f"sitl: pointed placard {result.target_id}, chosen {chosen}; the mission arrived (state done): "
             f"{'yes' if result.arrived else 'no'}{arrival}; at the end {_fmt(result.final_range_m, 'm')} from {end_of}",
             _closest_line(result),
             f"sitl: {result.sim_time_s:.1f} s simulated in {result.wall_time_s:.1f} s",
             "sitl: wrote " + ", ".join(str(out / f) for f in ["run.mcap", "mav.tlog"] + (["trajectory.png", "final_view.png"]
                                                                             if plots else []))]
    width = shutil.get_terminal_size((100, 24)).columns - 1 if sys.stdout.isatty() else 100
    for line in lines:
        print("\n".join(textwrap.wrap(line, max(40, width), subsequent_indent="      ", break_long_words=False,
                                      break_on_hyphens=False)))


def _closest_line(result) -> str:
    """Return the line naming the placard (other than the pointed one) the vehicle's centre came nearest, and how
    near it came to the diver, metres."""
    diver = "" if result.closest_diver_m is None else f"; to the diver's body axes {result.closest_diver_m:.2f} m"
    others = {pid: d for pid, d in result.closest_m.items() if pid != result.target_id}
    if not others:
        return f"sitl: no other placard in the scene{diver}"
    pid = min(others, key=others.get)
    return (f"sitl: nearest the vehicle came to another placard: {others[pid]:.2f} m (placard {pid}; "
            f"vehicle centre to its face; {result.closest_m.get(result.target_id, float('nan')):.2f} m to the pointed "
            f"one){diver}")


def _fmt(v, unit: str) -> str:
    return "n/a" if v is None else f"{v:.2f} {unit}"


def write_trajectory_plot(sim, result, path: Path) -> None:
    """Top view with placards and diver, depth over time and the state lane (dip3d_vehicle.plots.plot_mission)."""
    from ..plots import MissionPlacard, MissionPlot, plot_mission

    sc = sim.scenario
    plot_mission(MissionPlot(
        track=[tuple(r[:5]) for r in sim.trajectory],
        placards=[MissionPlacard(p.id, *map(float, p.centre_ned_m), role=p.role) for p in sc.placards],
        diver_north_east_m=(float(sc.diver.chest_ned_m[0]), float(sc.diver.chest_ned_m[1])),
        states=[(s["t_s"], s["state"]) for s in result.states], sim_time_s=result.sim_time_s,
        scenario=result.scenario, seed=result.seed, diver_position=result.diver_position,
        target_id=result.target_id, chosen_id=result.chosen_id, outcome=result.outcome,
        outcome_reason=result.outcome_reason), path)


def write_final_view(sim, result, path: Path) -> None:
    """Write the last left frame with the placards' outlines, the target and the tracked point.

    The ids are written above each outline (not over the placard's own printed number); the time,
    state, outcome and a key to the marks go in a band above the image.
    """
    import cv2
    import numpy as np

    frame = sim.last_frame
    if frame is None:
        return
    img = frame.left.copy()
    wrong = result.chosen_id is not None and result.chosen_id != result.target_id
    for pid, info in frame.meta["placards"].items():
        poly = info.get("left_polygon_px")
        if poly is None:
            continue
        colour = (0, 200, 0) if pid == result.target_id else ((0, 0, 230) if wrong and pid == result.chosen_id
                                                              else (0, 165, 255))
        pts = np.asarray(poly, np.int32)
        cv2.polylines(img, [pts], True, colour, 3)
        x, y = int(pts[:, 0].min()), int(pts[:, 1].min())
        label = f"{pid}" + (" pointed" if pid == result.target_id else (" WRONG" if wrong and pid == result.chosen_id
                                                                          else ""))
        cv2.putText(img, label, (x, max(30, y - 12)), cv2.FONT_HERSHEY_SIMPLEX, 0.9, colour, 2)
    target = sim.mission.bb.target
    if target is not None:
        u, v = sim.rig.to_original(target.left_px, "left")[0]
        cv2.drawMarker(img, (int(u), int(v)), (0, 0, 255), cv2.MARKER_CROSS, 40, 3)
    w, h = img.shape[1], img.shape[0]
    cv2.drawMarker(img, (w // 2, h // 2), (255, 255, 255), cv2.MARKER_SQUARE, 30, 1)
    band = np.zeros((130, w, 3), np.uint8)
    ok = result.outcome == "reached"
    for text, y, size, colour, thick in (
            (f"{result.outcome.upper()}  t={result.sim_time_s:.1f}s state={sim.mission.state} pointed={result.target_id} "
             f"chosen={result.chosen_id} range={_fmt(result.final_range_m, 'm')}", 50, 1.1,
             (255, 255, 255) if ok else (80, 80, 255), 3),
            ("green: pointed placard   red: chosen, wrong   orange: other placards   red +: tracked target   "
             "white square: image centre", 105, 0.85, (220, 220, 220), 2)):
        fit = min(size, size * (w - 40) / cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, size, thick)[0][0])
        cv2.putText(band, text, (20, y), cv2.FONT_HERSHEY_SIMPLEX, fit, colour, thick)
    img = np.vstack([band, img])
    cv2.imwrite(str(path), cv2.resize(img, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA))

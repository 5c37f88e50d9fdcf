"""``dip3d-vehicle run``: the onboard mission loop with a real stereo camera and a real autopilot.

    dip3d-vehicle run --connect udpin:0.0.0.0:14770 --camera sbs:/dev/video0 --calib stereo.yaml --params P

The tick loop (``behaviour.tick_rate_hz``) polls the link, takes the newest perception result from
the perception worker (a thread on the newest camera frame; older frames are dropped and counted),
ticks the mission machine and streams the command; it never waits for perception. The operator
enables the controller from the ground station (MAV_CMD_USER_1 to the controller's component) or
with ``--enable`` (``link.auto_enable``). Ctrl-C stops: the link sends the stop value and closes.
"""

from __future__ import annotations

import argparse
import itertools
import time
from pathlib import Path

from ..errors import Dip3dError
from ._common import add_params_arguments, params_from_args

NAME = "run"
HELP = "onboard mission loop: stereo camera + ArduSub autopilot over MAVLink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --connect, --camera, --calib, --enable, --duration, --log and the parameter options."""
    parser.add_argument("--connect", metavar="URL", help="MAVLink URL of the autopilot (default: link.url)")
    parser.add_argument("--camera", required=True, metavar="SOURCE", help="stereo source spec (see sources)")
    parser.add_argument("--calib", required=True, nargs="+", metavar="CALIB", help="stereo calibration file(s)")
    parser.add_argument("--enable", action="store_true", help="give the operator's enable at start (link.auto_enable)")
    parser.add_argument("--duration", type=float, default=None, metavar="S", help="stop after S seconds")
    parser.add_argument("--log", metavar="FILE", default=None, help="write a run log (replayable)")
    add_params_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run the mission until Ctrl-C, the end of the source or --duration."""
    from behaviours.loop import Controller, FrameProcessor, PerceptionWorker, build_mission, observation_summary
    from dip3d_vehicle.clock import WallClock
    from dip3d_vehicle.link import VehicleLink
    from dip3d_vehicle.perception.calibration_io import load_rig
    from dip3d_vehicle.perception.pipeline import Perception, make_pose_estimator
    from dip3d_vehicle.sources import open_source

    params = params_from_args(args)
    over = {}
    if args.connect:
        over["link.url"] = args.connect
    if args.enable:
        over["link.auto_enable"] = True
    if over:
        params = params.with_overrides(over, "command line")
    source = open_source(args.camera, params)
    frames = iter(source)
    try:
        first = next(frames)
    except StopIteration:
        raise Dip3dError(f"{args.camera}: the source gave no frames") from None
    size = (first.left.shape[1], first.left.shape[0])
    calib = args.calib[0] if len(args.calib) == 1 else args.calib
    rig = load_rig(calib, image_size=size, alpha=params["calib.alpha"],
                   already_rectified=params["calib.already_rectified"])
    pose = make_pose_estimator(params)
    perception = Perception(rig, params, pose)

    def before(frame) -> None:
        if hasattr(pose, "provide") and "keypoints" in frame.meta:
            pose.provide(frame.meta["keypoints"])

    clock = WallClock()
    link = VehicleLink(params, clock)
    link.open()
    mission = build_mission(params, rig, size, clock.now())
    controller = Controller(link, mission, clock)
    worker = PerceptionWorker(itertools.chain([first], frames), FrameProcessor(perception, before),
                              lambda: mission.needs, clock, params["mission.max_frame_age_s"],
                              roi=lambda: mission.track_roi(rig, size), image_size=tuple(rig.image_size))
    log = None
    if args.log:
        from dip3d_vehicle.runlog import RunLogWriter
        log = RunLogWriter(Path(args.log), params, {"command": "run", "camera": args.camera,
                                                   "calib": args.calib, "image_size": list(size)})
    period = 1.0 / params["behaviour.tick_rate_hz"]
    printed = 0
    t_end = None if args.duration is None else clock.now() + args.duration
    print(f"run: camera {args.camera}, calibration {rig.source}, {size[0]}x{size[1]}, link {link.config.url}; "
          f"Ctrl-C to stop", flush=True)
    worker.start()
    next_tick = clock.now()
    try:
        while t_end is None or clock.now() < t_end:
            obs = worker.take()
            rec = controller.tick(obs)
            if log is not None and obs is not None:
                log.frame({**observation_summary(obs), "state": rec.state, "engaged": rec.engaged})
            printed = _print_new(link.events + mission.bb.story, printed)
            if worker.error is not None:
                raise Dip3dError(f"perception: {worker.error}")
            if worker.ended.is_set() and obs is None and worker.take() is None and not worker.busy:
                break
            next_tick += period
            delay = next_tick - clock.now()
            if delay > 0:
                time.sleep(delay)
            else:
                next_tick = clock.now()
    except KeyboardInterrupt:
        print("run: stopping", flush=True)
    finally:
        worker.stop()
        link.close()
        source.close()
        if log is not None:
            for line in link.events + mission.bb.story:
                log.event(line)
            log.close()
    print(f"run: frames in {worker.frames_in}, dropped {worker.dropped_frames} (newest wins), stale "
          f"{worker.stale_frames}, results dropped {worker.dropped_results}; arrivals {mission.bb.arrivals}")
    return 0


def _print_new(lines: list[str], printed: int) -> int:
    """Print story lines not printed yet (sorted by time) and return the new count."""
    if len(lines) > printed:
        for line in sorted(lines, key=_t)[printed:]:
            print("  " + line, flush=True)
    return len(lines)


def _t(line: str) -> float:
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return 0.0

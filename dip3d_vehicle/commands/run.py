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
import math
import sys
import time
from pathlib import Path

from ..errors import Dip3dError
from ._common import add_params_arguments, params_from_args
from ._record import add_record_arguments, close_recorder, open_recorder

NAME = "run"
HELP = "onboard mission loop: stereo camera + ArduSub autopilot over MAVLink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --connect, --camera, --calib, --enable, --duration, --log and the parameter options."""
    parser.add_argument("--connect", metavar="URL", help="MAVLink URL of the autopilot (default: link.url)")
    parser.add_argument("--camera", required=True, metavar="SOURCE", help="stereo source spec (see sources)")
    parser.add_argument("--calib", required=True, nargs="+", metavar="CALIB", help="stereo calibration file(s)")
    parser.add_argument("--enable", action="store_true", help="give the operator's enable at start (link.auto_enable)")
    parser.add_argument("--duration", type=float, default=None, metavar="S", help="stop after S seconds")
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="output folder: run.mcap (Foxglove, replayable), mav.tlog (every MAVLink message)")
    parser.add_argument("--log", metavar="FILE", default=None,
                        help="write the run record (MCAP) to FILE instead (mav.tlog beside it)")
    add_record_arguments(parser)
    add_params_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run the mission until Ctrl-C, the end of the source or --duration."""
    from behaviours.loop import Controller, FrameProcessor, build_mission, observation_summary
    from dip3d_vehicle.frames import FrameGuard
    from dip3d_vehicle.clock import WallClock
    from dip3d_vehicle.link import VehicleLink
    from dip3d_vehicle.perception.calibration_io import load_rig
    from dip3d_vehicle.perception.pipeline import Perception, make_pose_estimator
    from dip3d_vehicle.sources import open_source
    from dip3d_vehicle.worker import CameraFeed, PerceptionWorker

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
    perception = Perception(rig, params, pose, live=True)

    def before(frame) -> None:
        if hasattr(pose, "provide") and "keypoints" in frame.meta:
            pose.provide(frame.meta["keypoints"])

    clock = WallClock()
    log = None
    if args.log or args.out:
        from dip3d_vehicle.record.recorder import MCAP_NAME, RecordingProcessor

        path = Path(args.log) if args.log else Path(args.out) / MCAP_NAME
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise Dip3dError(f"{path.parent}: cannot create output folder ({exc.strerror})") from None
        log, lines = open_recorder(args, path, params, {"command": "run", "camera": args.camera, "calib": args.calib,
                                                        "image_size": list(size)}, rig, "run", clock=clock)
        for line in lines:
            print(line, file=sys.stderr, flush=True)
    elif args.view or args.foxglove or args.video:
        raise Dip3dError("--view / --foxglove / --video: need --out DIR (or --log FILE)")
    link = VehicleLink(params, clock, recorder=log)
    link.open()
    mission = build_mission(params, rig, size, clock.now(), perception)
    controller = Controller(link, mission, clock)
    processor = FrameProcessor(perception, before)
    if log is not None:
        log.attach_link(link)
        processor = RecordingProcessor(processor, log)
    def perceive(frame, stamp_s: float):
        need = mission.needs  # what the current state needs: the full core or the tracker's features
        roi = mission.track_roi(rig, size) if need == "track" else None
        return processor.process(frame, need, stamp_s, roi)

    guard = FrameGuard(tuple(rig.image_size))  # missing/black eye, wrong size, out of order: no 3D decision
    worker = PerceptionWorker(perceive, max_age_s=math.inf, clock=clock.now, name="dip3d-perceive",
                              max_frame_age_s=params["mission.max_frame_age_s"], accept=guard.check, stamped=True)
    feed = CameraFeed(itertools.chain([first], frames), worker, name="dip3d-grab")
    period = 1.0 / params["behaviour.tick_rate_hz"]
    printed = 0
    t_end = None if args.duration is None else clock.now() + args.duration
    print(f"run: camera {args.camera}, calibration {rig.source}, {size[0]}x{size[1]}, link {link.config.url}; "
          f"Ctrl-C to stop", flush=True)
    worker.start()
    feed.start()
    next_tick = clock.now()
    try:
        while t_end is None or clock.now() < t_end:
            done = worker.take_new()
            obs = None if done is None else done.result
            rec = controller.tick(obs)
            if log is not None:
                if obs is not None:
                    log.frame({**observation_summary(obs), "state": rec.state, "engaged": rec.engaged,
                               "target": _target(obs, rig)})
                log.tick(rec.t_s, rec, mission, obs, link)
            printed = _print_new(link.events + mission.bb.story, printed)
            error = worker.last_error or feed.error
            if error is not None:
                raise Dip3dError(f"perception: {error}")
            if feed.ended.is_set() and obs is None and worker.idle and not worker.has_new():
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
        feed.stop()
        worker.stop()
        link.close()
        source.close()
        if log is not None:
            log.story(link.events + mission.bb.story)
            close_recorder(log)
    c = worker.counters
    print(f"run: frames in {feed.frames_in}, dropped {c.dropped_frames} (newest wins), stale "
          f"{c.stale_frames}, rejected {dict(guard.rejected)}, results dropped {c.dropped_results}; "
          f"arrivals {mission.bb.arrivals}")
    return 0


def _target(obs, rig) -> dict | None:
    """The observation's chosen target in original left pixels (what replay compares), or None."""
    r = obs.result
    if r is None or r.target_rect_px is None:
        return None
    return {"left_px": [float(v) for v in rig.to_original(r.target_rect_px, "left")[0]]}


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

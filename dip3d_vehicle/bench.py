"""Perception speed benchmark: the parameter profiles on the same stereo frames, in one process.

For every profile (``paper`` first, then the project's profiles) the perception core runs on the
same sequence of stereo frames (rendered by the simulator, or read from a folder with its
calibration) and the report gives: frames per second end-to-end (frames / summed wall time of
``Perception.process``, one frame after another), each stage's median and p99 (rectify, pose,
candidates = features, match, triangulate, select), end-to-end latency p50/p99, peak memory,
selection accuracy and the ratio of each profile's frame rate to ``paper``'s. A profile whose
keyframes run in the background (``follow.background``, e.g. ``fast``) gets the frames at their
camera rate (``BenchFrames.rate_hz``; the wall time counts the processing only): fed back to back,
its followed frames race ahead and only 9 of 120 frames became keyframes instead of 24.

Pose: every profile's pose backend is BlazePose, timed for real on every frame (``paper`` runs it
as the paper ran MediaPipe: detection on both images every frame, no tracking). The simulator's
diver is a skinned human mesh (``sitl/body.py``) that BlazePose finds; should it miss the diver
on a frame, or give an arm below ``pose.min_confidence``, the rest of the pipeline uses the
simulator's noisy truth keypoints (``meta["keypoints"]``) for that frame and the report counts
which frames used which (``pose_source``; on the bundled scenes every frame is BlazePose's). The
hybrid is ``BenchPose`` below, not a pose backend.

Accuracy (simulated frames): a frame is correct when the selected target's left-image point
(original pixels) lies inside the intended placard's polygon (``meta["placards"][id]``).
``accuracy_blazepose`` is the same over the frames whose pose was BlazePose's (no truth fallback;
a followed frame counts with its keyframe's source).

Memory: peak resident set size (Linux ``VmHWM``) while the profile runs, reset before each profile
through ``/proc/self/clear_refs``; reported absolute and above the RSS at the profile's start.
Where the reset is not available the process's ``ru_maxrss`` is reported (monotonic).

Latency (``latency_run``): frames arrive at the camera rate (15 Hz by default) through a
``CameraFeed`` into the project's one ``PerceptionWorker`` (``worker.py``, the one ``run`` uses;
newest frame wins); a setpoint tick at ``setpoint_hz`` consumes the newest result; frame-to-setpoint
latency = send time of the first setpoint using a result - capture time of its frame (results
older than ``max_age_s`` are stale: never used, counted); capture-to-result = when the worker
finished a frame - its capture time, for every result.
"""

from __future__ import annotations

import gc
import math
import resource
import threading
import time
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Mapping, Sequence

import cv2
import numpy as np

from .config import load_params
from .evaluation import decision_class
from .frames import StereoFrame
from .perception.calibration import StereoRig
from .perception.keypoints_file import GivenKeypoints
from .perception.pipeline import Perception, make_pose_estimator
from .perception.pose import PoseEstimator
from .perception.values import ArmKeypoints
from .run_memory import proc_status_mib
from .worker import CameraFeed, PerceptionWorker

__all__ = ["BenchPose", "BenchFrames", "simulated_frames", "folder_frames", "run_profile", "run_bench",
           "latency_run", "format_table", "STAGES", "PAPER_STATIC_POSE"]

STAGES = ("rectify", "pose", "candidates", "match", "corridor", "triangulate", "select", "track")
"""Stages reported, in pipeline order (candidates = feature extraction, match = matching, track =
following the chosen object between keyframes, ``PROFILE+followN`` only)."""

PAPER_STATIC_POSE = {"pose.backend": "blazepose", "blazepose.tracking": False, "blazepose.stereo_search": "detect"}
"""Overrides for ``paper``: BlazePose detection on both images every frame (MediaPipe static mode)."""

TRACKING_POSE = {"pose.backend": "blazepose"}
"""Overrides for the project's profiles: BlazePose with their own tracking / stereo-search settings."""


# ---------------------------------------------------------------------------------------------
# Frames


@dataclass
class BenchFrames:
    """A sequence of stereo frames with their rig; ``sequences`` marks where tracking restarts."""

    rig: StereoRig
    frames: list[StereoFrame]
    sequences: list[int]                 # index of the first frame of each sequence
    description: str
    rate_hz: float | None = None         # the camera rate the frames were taken at (None: unknown)

    def __len__(self) -> int:
        return len(self.frames)


def simulated_frames(scenario: str = "paper_pool", seeds: Sequence[int] = (1, 2, 3, 4),
                     frames_per_seed: int = 10, rate_hz: float = 10.0, start_s: float = 1.2,
                     approach_m_s: float = 0.1, size: tuple[int, int] | None = None) -> BenchFrames:
    """Render ``frames_per_seed`` frames at ``rate_hz`` per seed: the vehicle creeps toward the placards.

    Args:
        scenario: built-in scenario name or file.
        seeds: one sequence per seed (diver position, target, noise vary with the seed).
        frames_per_seed: frames per sequence.
        rate_hz: camera rate (scenario time between frames = 1 / rate_hz).
        start_s: scenario time of the first frame (the diver points from ``diver.start_s``).
        approach_m_s: forward speed of the vehicle (a servoing-like slow approach), m/s.
        size: (width, height) to render at instead of the scenario's camera (tests); the focal
            length and principal point are scaled with it.
    """
    from sitl.render import StereoRenderer
    from sitl.scenario import load_scenario

    frames: list[StereoFrame] = []
    starts: list[int] = []
    rig = None
    for seed in seeds:
        sc = _resized(load_scenario(scenario, seed), size)
        rig = sc.rig()
        v = sc.initial_vehicle_pose
        starts.append(len(frames))
        with StereoRenderer(sc) as renderer:
            for k in range(frames_per_seed):
                t = start_s + k / rate_hz
                north = v.north_m + approach_m_s * k / rate_hz * math.cos(v.yaw_rad)
                east = v.east_m + approach_m_s * k / rate_hz * math.sin(v.yaw_rad)
                yaw = v.yaw_rad + 0.02 * math.sin(0.7 * t)
                frames.append(renderer.render(north, east, v.depth_m, yaw, t))
    w, h = rig.image_size
    return BenchFrames(rig, frames, starts, f"simulator {scenario}, seeds {list(seeds)}, {frames_per_seed} frames "
                       f"each at {rate_hz:g} Hz, {w}x{h}", rate_hz)


def _resized(sc: Any, size: tuple[int, int] | None) -> Any:
    """Return the scenario with its camera scaled to ``size`` (None: unchanged)."""
    if size is None:
        return sc
    import dataclasses

    cam = sc.camera
    s = size[0] / cam.image_size[0]
    new_cam = dataclasses.replace(cam, image_size=(int(size[0]), int(size[1])), fx=cam.fx * s, fy=cam.fy * s,
                                  cx=(cam.cx + 0.5) * s - 0.5, cy=(cam.cy + 0.5) * s - 0.5)
    return dataclasses.replace(sc, camera=new_cam)


def folder_frames(spec: str, calib: str | Sequence[str], max_frames: int = 0) -> BenchFrames:
    """Read a folder (or any ``open_source`` spec) of stereo pairs with its calibration (no accuracy)."""
    from .perception.calibration_io import load_rig
    from .sources import open_source

    rig = load_rig(calib)
    frames = []
    with open_source(spec) as source:
        for frame in source:
            frames.append(frame)
            if max_frames and len(frames) >= max_frames:
                break
    return BenchFrames(rig, frames, [0], f"{spec} ({len(frames)} frames)")


# ---------------------------------------------------------------------------------------------
# The bench's pose: BlazePose timed for real, simulator truth where it finds nobody


class BenchPose(PoseEstimator):
    """BlazePose on every frame; the frame's given keypoints when BlazePose gives no usable arm.

    Usable = a person found and every arm keypoint's confidence at least ``min_confidence`` (the
    pipeline's ``pose.min_confidence``). ``provide(keypoints)`` before each frame (None when the source has none).
    ``last_source`` is "blazepose", "truth (no person)", "truth (low confidence)" or "none";
    ``counts`` sums them.
    """

    name = "bench"
    SOURCES = ("blazepose", "truth (no person)", "truth (low confidence)", "none")

    def __init__(self, backend: PoseEstimator, arm: str, min_confidence: float = 0.0) -> None:
        self.backend = backend
        self.given = GivenKeypoints(arm)
        self.min_confidence = float(min_confidence)
        self.last_source = "none"
        self.counts = dict.fromkeys(self.SOURCES, 0)

    def provide(self, keypoints: dict | None) -> None:
        """Set the fallback keypoints of the next frame."""
        self.given.provide(keypoints)

    def estimate(self, left_rect: np.ndarray, right_rect: np.ndarray, rig: StereoRig) -> ArmKeypoints | None:
        """Return BlazePose's arm if usable, else the given keypoints (rectified pixels), else None."""
        arm = self.backend.estimate(left_rect, right_rect, rig)
        if arm is not None and arm.min_confidence() >= self.min_confidence:
            self.last_source = "blazepose"
        else:
            why = "truth (no person)" if arm is None else "truth (low confidence)"
            given = self.given.estimate(left_rect, right_rect, rig)
            self.last_source = why if given is not None else "none"
            arm = given if given is not None else arm
        self.counts[self.last_source] += 1
        return arm

    def reset(self) -> None:
        """Forget the backend's tracking state."""
        self.backend.reset()

    def set_early_arm_listener(self, listener: Callable[[ArmKeypoints], None] | None) -> None:
        """Pass the early-arm listener to the backend (see ``PoseEstimator``)."""
        self.backend.set_early_arm_listener(listener)


# ---------------------------------------------------------------------------------------------
# Measuring one profile


def profile_params(profile: str, overrides: Mapping[str, Any] | None = None):
    """Return a profile's parameters with the bench's pose overrides (BlazePose everywhere)."""
    sets = dict(PAPER_STATIC_POSE if profile == "paper" else TRACKING_POSE)
    sets.update(overrides or {})
    return load_params(profile, (), sets)


def make_perception(profile: str, rig: StereoRig, overrides: Mapping[str, Any] | None = None
                    ) -> tuple[Any, BenchPose]:
    """Return the profile's perception core with the bench's hybrid pose.

    ``PROFILE+followN`` (e.g. ``fast+follow5``) wraps the core in ``FollowingPerception``: the core on
    every N-th frame (keyframes), the chosen object followed by optical flow in between;
    ``PROFILE+followNbg`` runs the keyframes in a background thread (no frame waits for them).
    """
    base, sep, follow = profile.partition("+follow")
    background = follow.endswith("bg")
    follow = follow[:-2] if background else follow
    params = profile_params(base, overrides)
    pose = BenchPose(make_pose_estimator(params), params["pose.arm"], params["pose.min_confidence"])
    core = Perception(rig, params, pose, live=True)
    from .perception.follow import FollowingPerception, with_following
    if sep:
        return FollowingPerception(core, keyframe_interval=int(follow or 5), background=background), pose
    return with_following(core, params), pose


def _params_of(runner: Any):
    return runner.core.params if hasattr(runner, "core") else runner.params


WARMUP_FRAMES = 6
"""Frames of the last sequence run before a profile is measured: beyond one frame (onnxruntime's and
OpenCV's first allocations), a followed sequence's own first uses (the candidate reuse's background
pass and flow on frames 2-5, ``candidates.reuse_frames`` 4) would otherwise land on the measured frames."""


def warm_up(runner: Any, pose: BenchPose, data: BenchFrames) -> None:
    """Run the first ``WARMUP_FRAMES`` frames of the last sequence, then start afresh (not measured)."""
    start = max(data.sequences) if data.sequences else 0
    for frame in data.frames[start:start + WARMUP_FRAMES]:
        pose.provide(frame.meta.get("keypoints"))
        runner.process(frame.left, frame.right)
    _reset(runner, pose)


def _reset(runner: Any, pose: BenchPose) -> None:
    """Start a new frame sequence: forget tracking (and the followed object)."""
    (runner.reset if hasattr(runner, "reset") else pose.reset)()


def frame_correct(result_json: Mapping[str, Any], meta: Mapping[str, Any]) -> bool | None:
    """Return whether the chosen target lies in the intended placard (None: no ground truth)."""
    placards = meta.get("placards")
    if not placards or meta.get("target_id") is None:
        return None
    target = result_json.get("target")
    poly = placards[meta["target_id"]].get("left_polygon_px")
    if target is None or poly is None or None in target["left_px"]:
        return False
    x, y = target["left_px"]
    return cv2.pointPolygonTest(np.asarray(poly, np.float32).reshape(-1, 1, 2), (float(x), float(y)), False) >= 0


def _pct(values: Iterable[float], q: float) -> float | None:
    arr = np.asarray(list(values), float)
    return None if arr.size == 0 else round(float(np.percentile(arr, q)), 2)

    return None

class _PeakMemory:
    """Peak RSS (VmHWM) while a block runs, reset before it where Linux allows; MiB."""

    def __init__(self) -> None:
        self.method = "VmHWM (reset via /proc/self/clear_refs)"

    @staticmethod
    def _status(key: str) -> float | None:
        return proc_status_mib(key)

    def __enter__(self) -> "_PeakMemory":
        gc.collect()
        try:
            with open("/proc/self/clear_refs", "w") as f:
                f.write("5")
        except OSError:
            self.method = "ru_maxrss (process peak, not reset per profile)"
        self.start_mib = self._status("VmRSS")
        return self

    def __exit__(self, *exc) -> None:
        peak = self._status("VmHWM")
        if peak is None or self.method.startswith("ru_maxrss"):
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        self.peak_mib = peak


def run_profile(profile: str, data: BenchFrames, overrides: Mapping[str, Any] | None = None,
                warmup: bool = True) -> dict:
    """Run one profile over every frame; return its measurements (see the module doc)."""
    perception, pose = make_perception(profile, data.rig, overrides)
    if warmup and data.frames:  # first-run allocations (onnxruntime, OpenCV) are not the frame rate
        warm_up(perception, pose, data)
        pose.counts = dict.fromkeys(pose.counts, 0)
        if hasattr(perception, "counts"):
            perception.counts = dict.fromkeys(perception.counts, 0)
    starts = set(data.sequences)
    # background keyframes get the frames at their camera rate: fed back to back, the followed
    # frames (a few ms each) race ahead and a keyframe completes only every ~13 frames instead of 5
    pace_hz = data.rate_hz if getattr(perception, "background", False) else None
    due = time.perf_counter()
    wall, stages, sources, statuses, correct = [], {s: [] for s in STAGES}, [], {}, []
    decisions: dict[str, int] = {}
    correct_neural: list[bool] = []  # scored frames whose pose was BlazePose's (no truth fallback)
    cpu0 = time.process_time()
    with _PeakMemory() as mem:
        for i, frame in enumerate(data.frames):
            if i in starts:
                _reset(perception, pose)
            pose.provide(frame.meta.get("keypoints"))
            if pace_hz:
                time.sleep(max(0.0, due - time.perf_counter()))
                due = max(due, time.perf_counter()) + 1.0 / pace_hz
            t0 = time.perf_counter()
            result = perception.process(frame.left, frame.right)
            wall.append((time.perf_counter() - t0) * 1e3)
            for s in STAGES:
                if s in result.timings_ms:
                    stages[s].append(result.timings_ms[s])
            sources.append(pose.last_source)
            statuses[result.status] = statuses.get(result.status, 0) + 1
            doc = result.to_json(data.rig)
            ok = frame_correct(doc, frame.meta)
            if ok is not None:
                correct.append(ok)
                if pose.last_source == "blazepose":
                    correct_neural.append(ok)
                kind = decision_class(doc, ok)
                decisions[kind] = decisions.get(kind, 0) + 1
                if kind == "correct" and (doc.get("selection") or {}).get("ambiguous"):  # counted apart as well
                    decisions["correct_flagged_ambiguous"] = decisions.get("correct_flagged_ambiguous", 0) + 1
    cpu_ms = (time.process_time() - cpu0) * 1e3
    total_s = sum(wall) / 1e3
    p = _params_of(perception)
    follow = getattr(perception, "counts", None)
    return {
        "follow": None if follow is None else dict(follow, keyframe_interval=perception.keyframe_interval,
                                                   paced_hz=pace_hz),
        "profile": profile,
        "frames": len(wall),
        "fps": round(len(wall) / total_s, 3) if total_s > 0 else None,
        "cpu_ms_per_frame": round(cpu_ms / max(len(wall), 1), 1),
        "latency_ms": {"p50": _pct(wall, 50), "p99": _pct(wall, 99), "max": _pct(wall, 100)},
        "stages_ms": {s: {"median": _pct(v, 50), "p99": _pct(v, 99), "frames": len(v)} for s, v in stages.items()},
        "peak_rss_mib": round(mem.peak_mib, 1), "rss_at_start_mib": round(mem.start_mib or 0.0, 1),
        "memory_method": mem.method,
        "accuracy": None if not correct else round(sum(correct) / len(correct), 4),
        "correct": int(sum(correct)), "scored_frames": len(correct),
        "accuracy_blazepose": None if not correct_neural else round(sum(correct_neural) / len(correct_neural), 4),
        "correct_blazepose": int(sum(correct_neural)), "scored_blazepose_frames": len(correct_neural),
        "status": statuses,
        "decisions": decisions,
        "pose_source": dict(pose.counts),
        "pose_settings": {"tracking": p["blazepose.tracking"], "stereo_search": p["blazepose.stereo_search"],
                          "threads": p["blazepose.threads"]},
        "candidates_settings": {k: p[f"candidates.{k}"] for k in ("matcher", "image_scale", "max_features")},
        "selection": p["selection.method"],
    }


def run_bench(data: BenchFrames, profiles: Sequence[str] = ("paper", "default", "fast"),
              latency_profile: str | Sequence[str] | None = ("fast",), latency_s: float = 10.0,
              camera_hz: float = 15.0, run_memory_profiles: Sequence[str] = ()) -> dict:
    """Run every profile on the same frames; add each one's fps ratio to ``paper``'s.

    ``latency_profile``: profile name(s) of the worker latency run(s) (``latency``: the first one,
    ``latency_runs``: all).
    """
    out = {"frames": data.description, "n_frames": len(data), "cpu_count": _cpus(),
           "load_average_1min_at_start": round(_load(), 2), "profiles": {}}
    for name in profiles:
        out["profiles"][name] = run_profile(name, data)
    base = out["profiles"].get("paper", {}).get("fps")
    for res in out["profiles"].values():
        res["fps_ratio_to_paper"] = round(res["fps"] / base, 2) if base and res["fps"] else None
    names = [latency_profile] if isinstance(latency_profile, str) else list(latency_profile or ())
    runs = [latency_run(name, data, camera_hz=camera_hz, duration_s=latency_s) for name in names if name]
    if runs:
        out["latency"], out["latency_runs"] = runs[0], runs
    if run_memory_profiles:  # the onboard loop's peak RSS, on the first sequence written as a paced folder
        from .run_memory import run_memory

        first = data.frames[:data.sequences[1]] if len(data.sequences) > 1 else data.frames
        out["run_memory"] = run_memory(first, data.rig, run_memory_profiles, camera_hz)
    out["load_average_1min_at_end"] = round(_load(), 2)
    return out


def _cpus() -> int:
    import os

    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def _load() -> float:
    import os

    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


# ---------------------------------------------------------------------------------------------
# Frame-to-setpoint latency through a newest-frame-wins worker


def paced_frames(frames: Sequence[StereoFrame], rate_hz: float, stop: threading.Event,
                 clock: Callable[[], float] = time.monotonic) -> Iterable[StereoFrame]:
    """Yield ``frames`` cyclically at ``rate_hz`` (a camera that costs nothing) until ``stop`` is set."""
    period, k, t_next = 1.0 / rate_hz, 0, clock()
    while not stop.is_set():
        yield frames[k % len(frames)]
        k += 1
        t_next += period
        stop.wait(max(0.0, t_next - clock()))


def latency_run(profile: str, data: BenchFrames, camera_hz: float = 15.0, setpoint_hz: float = 20.0,
                duration_s: float = 10.0, max_age_s: float = 0.5) -> dict:
    """Stream frames at ``camera_hz`` into a PerceptionWorker; a ``setpoint_hz`` tick uses the newest result.

    Frames are pre-rendered (a camera costs the computer nothing) and cycled. The setpoint tick
    sends a (mock) setpoint every period whatever perception is doing; ``latency`` is, per result,
    the send time of the first setpoint built from it minus its frame's capture time; ``age`` is the
    age of the result behind every setpoint sent.
    """
    perception, pose = make_perception(profile, data.rig)
    warm_up(perception, pose, data)

    def process(frame: StereoFrame):
        pose.provide(frame.meta.get("keypoints"))
        return perception.process(frame.left, frame.right)

    clock = time.monotonic
    worker = PerceptionWorker(process, max_age_s=max_age_s, clock=clock).start()
    stop = threading.Event()
    cam = CameraFeed(paced_frames(data.frames, camera_hz, stop, clock), worker)
    latencies, ages, ticks, empty, tick_late = [], [], 0, 0, []
    processing, seen_seq = [], -1
    period, t_end = 1.0 / setpoint_hz, clock() + duration_s
    cam.start()
    t_next = clock()
    while clock() < t_end:
        t_next += period
        delay = t_next - clock()
        if delay > 0:
            time.sleep(delay)
        now = clock()
        tick_late.append((now - t_next) * 1e3)
        newest = worker.peek()
        if newest is not None and newest.seq != seen_seq:
            seen_seq = newest.seq
            processing.append((newest.done_s - newest.stamp_s) * 1e3)
        new = worker.take_new()
        ticks += 1
        if new is not None:
            latencies.append((now - new.stamp_s) * 1e3)
        found = worker.latest()
        if found is None:
            empty += 1
        else:
            ages.append((now - found[1]) * 1e3)
    stop.set()
    cam.stop()
    worker.stop()
    c = worker.counters
    return {"profile": profile, "camera_hz": camera_hz, "setpoint_hz": setpoint_hz, "duration_s": duration_s,
            "frame_to_setpoint_ms": {"p50": _pct(latencies, 50), "p99": _pct(latencies, 99),
                                     "max": _pct(latencies, 100), "results": len(latencies)},
            "capture_to_result_ms": {"p50": _pct(processing, 50), "p99": _pct(processing, 99),
                                     "results": len(processing)},
            "setpoint_result_age_ms": {"p50": _pct(ages, 50), "p99": _pct(ages, 99)},
            "setpoints_sent": ticks, "setpoints_without_result": empty,
            "setpoint_tick_lateness_ms": {"p50": _pct(tick_late, 50), "p99": _pct(tick_late, 99)},
            "frames_submitted": c.submitted, "frames_processed": c.processed,
            "frames_dropped": c.dropped_frames, "stale_results": c.stale_results, "errors": c.errors}


# ---------------------------------------------------------------------------------------------
# Text report


def format_table(report: Mapping[str, Any]) -> str:
    """Return the human-readable report."""
    lines = [f"frames: {report['frames']}",
             f"cpus: {report['cpu_count']}  load average (1 min) at start {report['load_average_1min_at_start']}, "
             f"at end {report.get('load_average_1min_at_end')}"]
    head = (f"{'profile':<16}{'fps':>8}{'x paper':>9}{'p50 ms':>9}{'p99 ms':>9}{'cpu ms':>9}{'peak MiB':>10}"
            f"{'accuracy':>10}{'blazepose':>11}  pose source")
    lines += ["", head, "-" * len(head)]
    for name, r in report["profiles"].items():
        acc = "n/a" if r["accuracy"] is None else f"{r['correct']}/{r['scored_frames']}"
        neural = "n/a" if r.get("accuracy_blazepose") is None else \
            f"{r['correct_blazepose']}/{r['scored_blazepose_frames']}"
        src = ", ".join(f"{k} {v}" for k, v in r["pose_source"].items() if v)
        lines.append(f"{name:<16}{r['fps']:>8.2f}{_fmt(r['fps_ratio_to_paper']):>9}{_fmt(r['latency_ms']['p50']):>9}"
                     f"{_fmt(r['latency_ms']['p99']):>9}{_fmt(r['cpu_ms_per_frame']):>9}{r['peak_rss_mib']:>10.0f}"
                     f"{acc:>10}{neural:>11}  {src}")
    lines += ["", "decisions per scored frame (nothing_on_ray and abstentions apart from wrong picks; "
                  "correct_flagged_ambiguous: correct picks the selector flagged ambiguous, also in correct)"]
    for name, r in report["profiles"].items():
        lines.append(f"{name:<16}" + ", ".join(f"{k} {v}" for k, v in sorted(r.get("decisions", {}).items())))
    lines += ["", "stage ms, median / p99"]
    lines.append(f"{'profile':<16}" + "".join(f"{s:>16}" for s in STAGES))
    for name, r in report["profiles"].items():
        cells = "".join(f"{_fmt(r['stages_ms'][s]['median']) + ' / ' + _fmt(r['stages_ms'][s]['p99']):>16}"
                        for s in STAGES)
        lines.append(f"{name:<16}{cells}")
    for lat in report.get("latency_runs", []):
        fl = lat["frame_to_setpoint_ms"]
        lines += ["", f"latency ({lat['profile']}, camera {lat['camera_hz']:g} Hz, setpoints {lat['setpoint_hz']:g} Hz, "
                  f"{lat['duration_s']:g} s): frame-to-setpoint p50 {_fmt(fl['p50'])} ms, p99 {_fmt(fl['p99'])} ms "
                  f"({fl['results']} fresh results used; capture-to-result p50 "
                  f"{_fmt(lat['capture_to_result_ms']['p50'])} p99 {_fmt(lat['capture_to_result_ms']['p99'])} ms); "
                  f"frames submitted {lat['frames_submitted']}, processed "
                  f"{lat['frames_processed']}, dropped {lat['frames_dropped']}, stale results {lat['stale_results']}; "
                  f"setpoints {lat['setpoints_sent']} ({lat['setpoints_without_result']} without a result)"]
    mem = report.get("run_memory")
    if mem:
        lines += ["", f"dip3d-vehicle run on a folder ({mem['frames']} pairs at {mem['rate_hz']:g} Hz), peak RSS: " +
                  ", ".join(f"{p} {r['peak_rss_mib']:.0f} MiB" for p, r in mem["profiles"].items())]
    follows = {n: r["follow"] for n, r in report["profiles"].items() if r.get("follow")}
    for name, counts in follows.items():
        lines.append(f"{name}: keyframes {counts['keyframes']}, followed frames {counts['followed']}, lost "
                     f"{counts['lost']}, frames that waited for a keyframe {counts['waited']} "
                     f"(fast profile + FollowingPerception, keyframe every {counts['keyframe_interval']} frames"
                     f"{', in the background' if name.endswith('bg') else ''})")
    first = next(iter(report["profiles"].values()), None)
    if first:
        lines.append(f"memory: peak RSS per profile, {first['memory_method']}; cpu ms = process CPU time "
                     f"(all threads) per frame")
    return "\n".join(lines)


def _fmt(value: float | None) -> str:
    return "-" if value is None else f"{value:.1f}" if abs(value) < 1000 else f"{value:.0f}"

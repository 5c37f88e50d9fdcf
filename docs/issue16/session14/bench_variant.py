"""One bench profile with parameter overrides on the bench's frames: fps, CPU, latency, right, stages, slowest frames.

Usage (from the repository root):
    PYTHONPATH=. python docs/issue16/session14/bench_variant.py PROFILE [KEY=VALUE ...]
e.g. ``default candidates.image_scale=0.25``. The frames are the bench's own (paper_pool seeds 1-4,
30 frames each); set FRAMES_CACHE=FILE to pickle them once and reuse them between runs.
"""
import json
import os
import pickle
import sys
import time

from dip3d_vehicle import bench


def frames() -> bench.BenchFrames:
    """Return the bench's frames, from FRAMES_CACHE when it exists (written there otherwise)."""
    cache = os.environ.get("FRAMES_CACHE")
    if cache and os.path.exists(cache):
        with open(cache, "rb") as fh:
            return pickle.load(fh)
    data = bench.simulated_frames(frames_per_seed=30)
    if cache:
        with open(cache, "wb") as fh:
            pickle.dump(data, fh)
    return data


def main() -> None:
    profile, over = sys.argv[1], dict(kv.split("=", 1) for kv in sys.argv[2:])
    walls = []
    make = bench.make_perception

    def timed_perception(*args, **kwargs):
        """The bench's perception, each frame's wall time, stages and reuse recorded."""
        core, pose = make(*args, **kwargs)
        process = core.process

        def timed(left, right):
            t0 = time.perf_counter()
            res = process(left, right)
            walls.append(((time.perf_counter() - t0) * 1e3, res.timings_ms, getattr(res, "candidates_followed", None)))
            return res

        core.process = timed
        return core, pose

    bench.make_perception = timed_perception
    r = bench.run_profile(profile, frames(), over or None)
    walls = walls[bench.WARMUP_FRAMES:]
    for i in sorted(range(len(walls)), key=lambda k: -walls[k][0])[:6]:
        ms, stages, followed = walls[i]
        print(f"frame {i}: {ms:.0f} ms, followed {followed}, " + ", ".join(f"{k} {v:.1f}" for k, v in stages.items()))
    print(json.dumps({"over": over, "fps": r["fps"], "cpu": r["cpu_ms_per_frame"], "p50": r["latency_ms"]["p50"],
                      "p99": r["latency_ms"]["p99"], "correct": r["correct"], "status": r["status"],
                      "stages": {k: v["median"] for k, v in r["stages_ms"].items()}}))


if __name__ == "__main__":
    main()

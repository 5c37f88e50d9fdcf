"""Why frames of the bench's default profile were computed afresh, with parameter overrides.

Usage (from the repository root):
    PYTHONPATH=. python docs/issue16/session15/fresh_frames.py default [KEY=VALUE ...]
e.g. ``default candidates.reuse_frames=8``. Prints bench_variant's summary, then the reasons the
candidate reuse gave for each frame computed afresh and its counters. FRAMES_CACHE as in bench_variant.
"""
import collections
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "session14"))

import bench_variant  # noqa: E402
from dip3d_vehicle.perception import pipeline  # noqa: E402

REASONS: list[str] = []
COUNTS: dict = {}
_process = pipeline.Perception.process_rectified


def _noted(self, left, right, timings=None):
    """The core's frame, noting why the reuse could not follow (if it could not)."""
    result = _process(self, left, right, timings)
    if self.reuse is not None:
        if not result.candidates_followed:
            REASONS.append(self.reuse.last_reason)
        COUNTS.update(self.reuse.counts)
    return result


if __name__ == "__main__":
    pipeline.Perception.process_rectified = _noted
    bench_variant.main()
    print(dict(collections.Counter(REASONS)), COUNTS)

"""The diver's stop gesture: both wrists above the head, held for ``behaviour.stop_gesture_hold_s``.

Judged in the rectified left image (y down) from the pose's optional extra joints
(``ArmKeypoints.extra_left_px``: "head", "other_wrist") and the pointing arm's wrist, each wrist above the
head by a margin in pixels and one in metres at the pointing wrist's depth (from its stereo disparity): a
pose model that sees only part of a diver at the image's edge squeezes every landmark into a few centimetres
around the head, some wrists "above" it (issue 14 session 72). A frame without
the pose, or without those joints, says nothing either way: it breaks the hold only when no frame
showed the gesture for more than ``behaviour.stop_gesture_gap_s`` (a pose model misses single frames,
and a diver's stop must not depend on it not blinking); a pose that shows the arms otherwise breaks
it at once. Stopping needs the gesture seen over the whole hold time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from dip3d_vehicle.perception.values import ArmKeypoints

__all__ = ["stop_gesture_seen", "metric_margin_px", "StopGestureWatch"]


def stop_gesture_seen(arm: ArmKeypoints | None, margin_px: float = 0.0, margin_m: float = 0.0,
                      baseline_m: float = 0.0) -> bool:
    """Return True when both wrists are above the head in the left image, by ``margin_px`` pixels and by
    ``margin_m`` metres at the pointing wrist's depth (``margin_m`` x its disparity / ``baseline_m`` pixels;
    skipped without a baseline or a disparity).

    Examples:
        >>> import numpy as np
        >>> px = np.array([[100.0, 300], [110, 200], [115, 100]])
        >>> a = ArmKeypoints("right", px, px, np.ones(3), np.ones(3), extra_left_px={"head": (60, 250),
        ...                  "other_wrist": (20, 110)})
        >>> stop_gesture_seen(a), stop_gesture_seen(None)
        (True, False)
    """
    if arm is None:
        return False
    extra = arm.extra_left_px or {}
    if "head" not in extra or "other_wrist" not in extra:
        return False
    margin = max(margin_px, metric_margin_px(arm, margin_m, baseline_m))
    head_y = float(extra["head"][1])
    return bool(float(arm.joint("wrist", "left")[1]) < head_y - margin
                and float(extra["other_wrist"][1]) < head_y - margin)


def metric_margin_px(arm: ArmKeypoints, margin_m: float, baseline_m: float) -> float:
    """Return ``margin_m`` metres in pixels at the depth of the arm's wrist (0 without a baseline or a disparity).

    At depth Z a length L spans focal x L / Z pixels, and Z = focal x baseline / disparity, so it spans
    L x disparity / baseline: no focal length needed.

    Examples:
        >>> import numpy as np
        >>> left = np.array([[100.0, 300], [110, 200], [115, 100]])
        >>> a = ArmKeypoints("right", left, left - [60.0, 0.0], np.ones(3), np.ones(3))
        >>> round(metric_margin_px(a, 0.1, 0.12), 1), metric_margin_px(a, 0.1, 0.0)
        (50.0, 0.0)
    """
    disparity = abs(float(arm.joint("wrist", "left")[0]) - float(arm.joint("wrist", "right")[0]))
    if margin_m <= 0.0 or baseline_m <= 0.0 or not math.isfinite(disparity):
        return 0.0
    return margin_m * disparity / baseline_m


@dataclass
class StopGestureWatch:
    """Counts how long the gesture has been seen without a break, on the frames' capture times.

    Args:
        hold_s: the gesture must be seen this long (first to latest showing frame).
        margin_px: wrists must be this far above the head, pixels.
        gap_s: frames without the joints for up to this long (seconds) do not break the hold.
        margin_m: wrists must be this far above the head at the wrist's depth, metres (with ``baseline_m``,
            the stereo baseline, metres).
    """

    hold_s: float = 1.0
    margin_px: float = 0.0
    gap_s: float = 0.5
    margin_m: float = 0.0
    baseline_m: float = 0.0
    since_s: float | None = None
    last_seen_s: float | None = None

    def shows(self, arm: ArmKeypoints | None) -> bool:
        """Return True when one frame's pose shows the gesture by this watch's margins (pixels and metres)."""
        return stop_gesture_seen(arm, self.margin_px, self.margin_m, self.baseline_m)

    def update(self, arm: ArmKeypoints | None, stamp_s: float) -> bool:
        """Count one frame's pose (None = no pose); return True once the gesture was held long enough."""
        if not self.shows(arm):
            silent = arm is None or not {"head", "other_wrist"} <= set(arm.extra_left_px or {})
            if not silent or self.last_seen_s is None or stamp_s - self.last_seen_s > self.gap_s + 1e-9:
                self.since_s = self.last_seen_s = None
            return False
        if self.since_s is None or self.last_seen_s is None or stamp_s - self.last_seen_s > self.gap_s + 1e-9:
            self.since_s = stamp_s
        self.last_seen_s = stamp_s
        return stamp_s - self.since_s >= self.hold_s - 1e-9

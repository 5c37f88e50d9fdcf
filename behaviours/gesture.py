"""The diver's stop gesture: both wrists above the head, held for ``behaviour.stop_gesture_hold_s``.

Judged in the rectified left image (y down) from the pose's optional extra joints
(``ArmKeypoints.extra_left_px``: "head", "other_wrist") and the pointing arm's wrist. A frame without
the pose, or without those joints, says nothing either way: it breaks the hold only when no frame
showed the gesture for more than ``behaviour.stop_gesture_gap_s`` (a pose model misses single frames,
and a diver's stop must not depend on it not blinking); a pose that shows the arms otherwise breaks
it at once. Stopping needs the gesture seen over the whole hold time.
"""

from __future__ import annotations

from dataclasses import dataclass

from dip3d_vehicle.perception.values import ArmKeypoints

__all__ = ["stop_gesture_seen", "StopGestureWatch"]


def stop_gesture_seen(arm: ArmKeypoints | None, margin_px: float = 0.0) -> bool:
    """Return True when both wrists are above the head (by ``margin_px``) in the left image.

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
    head_y = float(extra["head"][1])
    return bool(float(arm.joint("wrist", "left")[1]) < head_y - margin_px
                and float(extra["other_wrist"][1]) < head_y - margin_px)


@dataclass
class StopGestureWatch:
    """Counts how long the gesture has been seen without a break, on the frames' capture times.

    Args:
        hold_s: the gesture must be seen this long (first to latest showing frame).
        margin_px: wrists must be this far above the head.
        gap_s: frames without the joints for up to this long (seconds) do not break the hold.
    """

    hold_s: float = 1.0
    margin_px: float = 0.0
    gap_s: float = 0.5
    since_s: float | None = None
    last_seen_s: float | None = None

    def update(self, arm: ArmKeypoints | None, stamp_s: float) -> bool:
        """Count one frame's pose (None = no pose); return True once the gesture was held long enough."""
        if not stop_gesture_seen(arm, self.margin_px):
            silent = arm is None or not {"head", "other_wrist"} <= set(arm.extra_left_px or {})
            if not silent or self.last_seen_s is None or stamp_s - self.last_seen_s > self.gap_s + 1e-9:
                self.since_s = self.last_seen_s = None
            return False
        if self.since_s is None or self.last_seen_s is None or stamp_s - self.last_seen_s > self.gap_s + 1e-9:
            self.since_s = stamp_s
        self.last_seen_s = stamp_s
        return stamp_s - self.since_s >= self.hold_s - 1e-9

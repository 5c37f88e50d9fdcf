"""FrameGuard: frames that cannot be trusted never reach perception."""

from __future__ import annotations

import numpy as np

from dip3d_vehicle.frames import FrameGuard, StereoFrame


def _frame(i: float, size=(40, 30), right=True, value=100) -> StereoFrame:
    img = np.full((size[1], size[0], 3), value, np.uint8)
    return StereoFrame(img, img.copy() if right else None, float(i), int(i))


def test_guard_rejects_each_untrusted_kind_and_accepts_good_frames():
    """Missing eye, black, wrong size, stamps going back / repeated are rejected and counted."""
    g = FrameGuard((40, 30))
    assert g.check(_frame(1)) == ""
    assert g.check(_frame(2, right=False)) == "right eye missing"
    assert g.check(_frame(3, value=0)) == "black frame"
    assert g.check(_frame(4, size=(20, 30))) == "wrong image size"
    assert g.check(_frame(0.5)) == "stamp not increasing"
    assert g.check(_frame(5)) == ""
    assert g.accepted == 2 and sum(g.rejected.values()) == 4

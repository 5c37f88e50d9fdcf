"""Shared helpers for the source tests: small deterministic stereo frames."""

from __future__ import annotations

import numpy as np
import pytest

from dip3d_vehicle.frames import StereoFrame


def make_frames(n: int = 5, width: int = 40, height: int = 32, seed: int = 0,
                gray: bool = False) -> list[StereoFrame]:
    """Return ``n`` textured stereo frames (gray frames have three equal channels)."""
    rng = np.random.default_rng(seed)
    frames = []
    for i in range(n):
        left = rng.integers(0, 256, (height, width, 3), dtype=np.uint8)
        right = np.roll(left, -3, axis=1) ^ np.uint8(i)
        if gray:
            left = np.repeat(left[:, :, :1], 3, axis=2)
            right = np.repeat(right[:, :, :1], 3, axis=2)
        frames.append(StereoFrame(left=left, right=right, stamp_s=100.0 + 0.1 * i, index=i))
    return frames


@pytest.fixture()
def frames() -> list[StereoFrame]:
    return make_frames()


@pytest.fixture(name="make_frames")
def make_frames_fixture():
    """The frame factory, for tests that need other sizes, counts or gray frames."""
    return make_frames

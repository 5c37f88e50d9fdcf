"""The unrecognised spots of a held point's frames, kept for the objects they turn out to lie on.

A frame's selector scores the compact spots along the arm that no recognised object explains
(``Selection.spots``); their probability is part of the frame's "nothing detected". A faint far
placard is recognised in some frames of a point only: in the others it shows as spots on its face,
which voted "nothing detected" (issue 11 session 63). ``PointFusion`` (``spot_support``) gives such a
spot's probability to the object hypothesis it lies on instead: in the frame itself when the
hypothesis is already known, and back in the earlier frames when the object is first recognised
late (else a 4 cm target recognised only after the vehicle closed in started from the floor in
every earlier frame, and the spots that had stood for it there went to nobody: ``near_miss``
seed 3 then chose the decoy at fused 0.95). This module keeps the ledger; the fusion's arithmetic
stays in ``fusion.py``.

Pure data: positions in the camera frame (metres), probabilities in [0, 1].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = ["FrameSpots", "SpotLedger"]


@dataclass
class FrameSpots:
    """One fused frame's spots no hypothesis has claimed, its "none" probability and which key led it."""

    spots: list = field(default_factory=list)
    none_p: float = 0.0
    leader: str | None = None


class SpotLedger:
    """Each fused frame's unclaimed spots, in the fusion's frame order."""

    def __init__(self, radius_m: float) -> None:
        self.radius_m = radius_m
        self.frames: list[FrameSpots] = []

    def clear(self) -> None:
        """Forget every frame (a new point, or a new viewpoint)."""
        self.frames = []

    def claim(self, spots, match: Callable[[np.ndarray], object], found: set) -> tuple[dict, list]:
        """Split one frame's spots ((xyz, probability), ...) into support per hypothesis key and the rest.

        ``match(xyz)`` returns the hypothesis a point falls on (or None); a spot on a hypothesis in
        ``found`` (keys this frame recognised an object on) is that object's surroundings, not the object
        seen short of recognition, and stays unclaimed.
        """
        support: dict[str, float] = {}
        rest = []
        for xyz, p in spots:
            xyz = np.asarray(xyz, float)
            h = match(xyz)
            if h is None or h.key in found or p <= 0.0:
                rest.append((xyz, float(p)))
                continue
            support[h.key] = support.get(h.key, 0.0) + float(p)
        return support, rest

    def record(self, spots: list, none_p: float, leader: str | None) -> None:
        """Append a fused frame's unclaimed spots, its "none" probability and its leader."""
        self.frames.append(FrameSpots(list(spots), float(none_p), leader))

    def claim_back(self, xyz_m: np.ndarray) -> list[tuple[int, float]]:
        """Take every earlier frame's unclaimed spots within ``radius_m`` of ``xyz_m``; return (frame index, sum)."""
        out = []
        for j, frame in enumerate(self.frames):
            near = [float(np.linalg.norm(xyz - xyz_m)) <= self.radius_m for xyz, _ in frame.spots]
            taken = sum(p for (_, p), hit in zip(frame.spots, near) if hit)
            if taken > 0.0:
                frame.spots = [s for s, hit in zip(frame.spots, near) if not hit]
                out.append((j, taken))
        return out

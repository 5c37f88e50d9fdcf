"""A weak lean carried across a bounded move: the second view must agree before the vehicle acts on it.

A fused object decision whose one look (its posterior with the point's frames counted as one,
``fusion.py``) is below ``behaviour.close_in_weak_one_look`` is a weak lean: the frames of a still
vehicle share their errors, and fused they claim far more than one look holds (``variant_9_19``
seed 2 with ``corridor.zoom_boxes=2``: one look 0.53, fused 0.93, the wrong placard; issue 11,
session 36). Before acting on one the mission takes one more view of the point with fresh frames.

A nearer view (close in, ``close_in.py``) decides on its own: the arm's depth error is smaller
there, and the far lean was the doubtful one (``variant_9_19`` seeds 0 and 1 lean differently at
3.4 m and decide the pointed placard from 2.8 m). Else a second look from beside or above, as far
as before: the weak winner is kept here, its position moved into the camera frame after the step
(the vehicle keeps its heading, so a still point moves by minus the camera's offset). A weak
decision from the new view is acted on only when its winner is the hypothesis the fusion matches to
that prediction (``PointFusion.match``: the nearest within ``behaviour.vote_radius_m``, the radius
within which it takes a sighting for the same object): the two views agree. A clear decision from the new view is acted on
whatever the old lean said.

Pure data and geometry in the rectified left camera frame (metres): no clock, no link.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fusion import FusedDecision

__all__ = ["WeakLean", "is_weak"]


@dataclass(frozen=True)
class WeakLean:
    """The winner of a weak decision, in the camera frame of the current viewpoint.

    Attributes:
        key: the winner's hypothesis key when it was decided (for the story).
        xyz_m: its camera-frame position, metres, moved with every move since (``moved``).
        one_look: its one-look posterior when it was decided.
        moves: the moves made since, in order ("second_look").
    """

    key: str
    xyz_m: np.ndarray
    one_look: float
    moves: tuple[str, ...] = ()

    @classmethod
    def of(cls, decision: FusedDecision) -> "WeakLean":
        """Return the winner of an object ``decision`` as a lean at the current viewpoint."""
        return cls(decision.winner.key, np.asarray(decision.winner.xyz_m, float).copy(), float(decision.one_look))

    def moved(self, offset_m, move: str) -> "WeakLean":
        """Return the lean seen after the camera moved by ``offset_m`` (camera frame, m; heading kept)."""
        return WeakLean(self.key, self.xyz_m - np.asarray(offset_m, float), self.one_look, (*self.moves, move))


def is_weak(decision: FusedDecision, weak_one_look: float) -> bool:
    """True for an object decision whose one-look posterior is below ``weak_one_look``."""
    return decision.kind == "object" and decision.one_look is not None and decision.one_look < weak_one_look

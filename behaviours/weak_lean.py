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
within which it takes a sighting for the same object): the two views agree. A clear decision from the new view for
another object is acted on only when it outweighs the old lean: the two views taken as two independent looks
(``two_view_p``) must still give its winner ``behaviour.close_in_weak_one_look`` against the lean. Else a clear but
narrow second view overruled the first (``variant_34_05`` seed 2, issue 11 session 64: the lean 0.52 on the pointed
placard, the new view 0.61 on the placard beside it, the diver's sway seen at another phase: the wrong placard).

Pure data and geometry in the rectified left camera frame (metres): no clock, no link.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fusion import NONE, FusedDecision

__all__ = ["WeakLean", "is_weak", "two_view_p"]


@dataclass(frozen=True)
class WeakLean:
    """The winner of a weak decision, in the camera frame of the current viewpoint.

    Attributes:
        key: the winner's hypothesis key when it was decided (for the story).
        xyz_m: its camera-frame position, metres, moved with every move since (``moved``).
        one_look: its one-look posterior when it was decided.
        moves: the moves made since, in order ("second_look").
        others: the other object hypotheses of that decision as (camera-frame position m, moved likewise;
            one-look posterior).
        none_p: that decision's one-look posterior of "nothing detected".
    """

    key: str
    xyz_m: np.ndarray
    one_look: float
    moves: tuple[str, ...] = ()
    others: tuple[tuple[np.ndarray, float], ...] = ()
    none_p: float = 0.0

    @classmethod
    def of(cls, decision: FusedDecision, positions: dict) -> "WeakLean":
        """Return the winner of an object ``decision`` as a lean at the current viewpoint (``positions``: hypothesis
        key -> camera-frame position, m, of the decision's other objects)."""
        post = decision.one_look_posterior
        others = tuple((np.asarray(positions[k], float).copy(), float(p)) for k, p in post.items()
                       if k in positions and k != decision.best)
        return cls(decision.winner.key, np.asarray(decision.winner.xyz_m, float).copy(), float(decision.one_look),
                   others=others, none_p=float(post.get(NONE, 0.0)))

    def moved(self, offset_m, move: str) -> "WeakLean":
        """Return the lean seen after the camera moved by ``offset_m`` (camera frame, m; heading kept)."""
        offset = np.asarray(offset_m, float)
        return WeakLean(self.key, self.xyz_m - offset, self.one_look, (*self.moves, move),
                        tuple((xyz - offset, p) for xyz, p in self.others), self.none_p)

    def p_at(self, xyz_m: np.ndarray, radius_m: float) -> float:
        """The lean's view's one-look posterior of an object at ``xyz_m`` (camera frame, m): the nearest other object
        within ``radius_m``; none there: its "nothing detected" (the object was not one it saw)."""
        near = [(float(np.linalg.norm(xyz - xyz_m)), p) for xyz, p in self.others]
        near = [dp for dp in near if dp[0] <= radius_m]
        return min(near)[1] if near else self.none_p


def two_view_p(new_winner_p: float, new_lean_p: float, old_winner_p: float, old_lean_p: float) -> float:
    """The new winner's probability against the old lean with two views taken as independent looks (each view's
    one-look posteriors multiplied, normalised over the two objects).

    Examples:
        >>> round(two_view_p(0.61, 0.3, 0.35, 0.52), 2)
        0.58
    """
    a, b = new_winner_p * old_winner_p, new_lean_p * old_lean_p
    return a / (a + b) if a + b > 0 else 0.0


def is_weak(decision: FusedDecision, weak_one_look: float) -> bool:
    """True for an object decision whose one-look posterior is below ``weak_one_look``."""
    return decision.kind == "object" and decision.one_look is not None and decision.one_look < weak_one_look

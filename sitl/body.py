"""The diver's body: a skinned human mesh (MakeHuman's, CC0) posed by the scenario's skeleton.

The mesh (``assets/human_body.npz``, made by ``tools/make_body.py``; provenance and licence in
``assets/README.md``) holds vertices in the model frame (metres; x = the body's LEFT, y = up,
z = forward), triangles with a material each (suit, hood, skin, mask, glove, tank, fin), 13 bones
(torso with the head, then upper arm, forearm, hand, thigh, shin, foot per side) with their rest
head and tail joints, and 4 bone weights per vertex.

Posing (``pose_body``): the scenario's diver gives its joints in the world (``Diver.joints``:
shoulder, elbow, wrist of both arms, hips, knees, ankles, fins, chest, heading). The torso is a
rigid transform (heading, chest between the shoulders, scale ``BODY_SCALE``); every limb bone is
rotated from its rest direction (carried by the torso) onto its target segment by the smallest
rotation and stretched along its axis to the target length, so the posed skeleton's joints ARE
the scenario's joints: the truth keypoints are the body's own shoulder / elbow / wrist joint
centres. Vertices follow by linear blend skinning: ``x = sum_k w_k A_k [x_rest; 1]``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Mapping

import numpy as np

from .world import unit

__all__ = ["BodyModel", "load_body", "pose_body", "PosedBody", "BODY_FILE", "BODY_SCALE", "POINTING_HAND_SCALE", "POINTING_FIST_WIDTH"]

BODY_FILE = Path(__file__).resolve().parent / "assets" / "human_body.npz"
"""The packaged body (vertices, faces, materials, bones, weights)."""

BODY_SCALE = 1.05
"""Scale of the torso and head (MakeHuman's default body is 1.67 m tall: the diver is 1.75 m)."""

POINTING_HAND_SCALE = 0.45
"""Length of the pointing hand relative to the open hand: a gloved fist, about 9 cm from the wrist
(the mesh has no finger bones to curl)."""

POINTING_FIST_WIDTH = 0.85
"""Width of the pointing fist relative to the open hand."""


@dataclass(frozen=True)
class BodyModel:
    """The rest-pose body (model frame, metres), as read from ``BODY_FILE``."""

    vertices_m: np.ndarray       # (V, 3)
    faces: np.ndarray            # (F, 3) int
    face_material: np.ndarray    # (F,) index into materials
    materials: tuple[str, ...]
    bone_names: tuple[str, ...]
    bone_index: np.ndarray       # (V, 4)
    bone_weight: np.ndarray      # (V, 4)
    bone_head_m: np.ndarray      # (B, 3)
    bone_tail_m: np.ndarray      # (B, 3)
    landmark_names: tuple[str, ...]
    landmark_m: np.ndarray       # (L, 3), on the torso bone

    def bone(self, name: str) -> int:
        """Return the index of a bone by name."""
        return self.bone_names.index(name)


@lru_cache(maxsize=2)
def load_body(path: str | None = None) -> BodyModel:
    """Load (once) the packaged body, or the one at ``path``."""
    with np.load(str(path or BODY_FILE)) as d:
        return BodyModel(
            vertices_m=d["vertices_m"].astype(np.float64), faces=d["faces"].astype(np.int64),
            face_material=d["face_material"].astype(np.int64),
            materials=tuple(str(m) for m in d["material_names"]),
            bone_names=tuple(str(b) for b in d["bone_names"]), bone_index=d["bone_index"].astype(np.int64),
            bone_weight=d["bone_weight"].astype(np.float64), bone_head_m=d["bone_head_m"].astype(np.float64),
            bone_tail_m=d["bone_tail_m"].astype(np.float64),
            landmark_names=tuple(str(n) for n in d["landmark_names"]),
            landmark_m=d["landmark_m"].astype(np.float64))


@dataclass(frozen=True)
class PosedBody:
    """A posed body in the world (NED, metres)."""

    vertices_ned_m: np.ndarray       # (V, 3)
    landmarks_ned_m: dict            # name -> (3,): nose, left_eye, right_eye, head_top


def _align(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return the smallest rotation taking unit vector ``a`` onto unit vector ``b``."""
    v = np.cross(a, b)
    c = float(a @ b)
    if c < -1.0 + 1e-9:  # opposite: half a turn about any perpendicular axis
        p = unit(np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0]))
        return 2.0 * np.outer(p, p) - np.eye(3)
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


def _bone_transform(R_torso: np.ndarray, head0: np.ndarray, tail0: np.ndarray, head_w: np.ndarray,
                    tail_w: np.ndarray | None, stretch: bool, across: float = 1.0) -> np.ndarray:
    """Return the (3, 4) transform of a limb bone: rest segment -> target segment (model -> world).

    The rest direction carried by the torso is rotated onto the target direction by the smallest
    rotation; with ``stretch`` the bone is scaled along its axis to the target length, and by
    ``across`` perpendicular to it.
    """
    axis0 = unit(tail0 - head0)
    d0 = R_torso @ axis0                      # includes the uniform body scale
    scale = float(np.linalg.norm(d0))
    d0 = d0 / scale
    R = _align(d0, unit(tail_w - head_w)) @ R_torso if tail_w is not None else R_torso
    M = R.copy()
    if stretch and tail_w is not None:
        k = float(np.linalg.norm(tail_w - head_w)) / (scale * float(np.linalg.norm(tail0 - head0)))
        M = R @ (across * np.eye(3) + (k - across) * np.outer(axis0, axis0))
    return np.hstack([M, (head_w - M @ head0)[:, None]])


def pose_body(model: BodyModel, joints: Mapping[str, np.ndarray], heading_rad: float, arm: str) -> PosedBody:
    """Return the body posed on the scenario's joints (``Diver.joints``) facing ``heading_rad``.

    Args:
        model: the rest-pose body.
        joints: world NED joints: "chest", "shoulder"/"elbow"/"wrist"/"hand" (pointing arm),
            "o_shoulder"/"o_elbow"/"o_wrist" (other arm), "hip_r"/"knee_r"/"ankle_r"/"fin_r" and
            the "_l" ones.
        heading_rad: direction the diver faces (0 = north, clockwise +).
        arm: the pointing arm, "right" or "left" (the body's own side).
    """
    fwd = np.array([np.cos(heading_rad), np.sin(heading_rad), 0.0])
    right = np.array([-np.sin(heading_rad), np.cos(heading_rad), 0.0])
    down = np.array([0.0, 0.0, 1.0])
    # model axes (x = left, y = up, z = forward) in the world, with the body scale
    R_torso = BODY_SCALE * np.stack([-right, -down, fwd], axis=1)
    b = model.bone
    mid0 = 0.5 * (model.bone_head_m[b("upperarm.R")] + model.bone_head_m[b("upperarm.L")])
    torso = np.hstack([R_torso, (np.asarray(joints["chest"], float) - R_torso @ mid0)[:, None]])
    A = np.repeat(torso[None], len(model.bone_names), axis=0)
    own = {"R": "" if arm == "right" else "o_", "L": "" if arm == "left" else "o_"}
    for side in ("R", "L"):
        p = own[side]
        sh, el, wr = (np.asarray(joints[p + n], float) for n in ("shoulder", "elbow", "wrist"))
        k_hand = b(f"hand.{side}")
        hand_len = POINTING_HAND_SCALE if p == "" else 1.0
        hand_len *= BODY_SCALE * float(np.linalg.norm(model.bone_tail_m[k_hand] - model.bone_head_m[k_hand]))
        hand_dir = unit(np.asarray(joints["hand"], float) - wr) if p == "" else unit(wr - el)
        hand = wr + hand_len * hand_dir
        leg = side.lower()
        hip, knee, ankle, fin = (np.asarray(joints[f"{n}_{leg}"], float) for n in ("hip", "knee", "ankle", "fin"))
        fist = POINTING_FIST_WIDTH if p == "" else 1.0
        for name, head, tail, stretch, across in (
                (f"upperarm.{side}", sh, el, True, 1.0), (f"lowerarm.{side}", el, wr, True, 1.0),
                (f"hand.{side}", wr, hand, True, fist), (f"upperleg.{side}", hip, knee, True, 1.0),
                (f"lowerleg.{side}", knee, ankle, True, 1.0), (f"foot.{side}", ankle, fin, False, 1.0)):
            k = b(name)
            A[k] = _bone_transform(R_torso, model.bone_head_m[k], model.bone_tail_m[k], head, tail, stretch, across)
    rest_h = np.hstack([model.vertices_m, np.ones((len(model.vertices_m), 1))])
    per_bone = np.einsum("bij,vj->vbi", A, rest_h)                       # (V, B, 3)
    picked = np.take_along_axis(per_bone, model.bone_index[:, :, None], axis=1)
    verts = np.einsum("vk,vki->vi", model.bone_weight, picked)
    lm = model.landmark_m @ torso[:, :3].T + torso[:, 3]
    return PosedBody(verts, dict(zip(model.landmark_names, lm)))

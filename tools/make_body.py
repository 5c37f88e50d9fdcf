"""Convert MakeHuman's base mesh, default skeleton and skin weights into ``sitl/assets/human_body.npz``.

Dev-time only (needs ``fast-simplification``: ``pip install .[body]``); the simulator
reads the ``.npz``. Inputs, from https://github.com/makehumancommunity/makehuman at commit
a8bc2d54ff0ac92e78ff71431b1023eda42bf482 (assets CC0 1.0, ``LICENSE.ASSETS.md``):

- ``makehuman/data/3dobjs/base.obj`` (the base mesh; only its ``body`` group is kept),
- ``makehuman/data/rigs/default.mhskel`` (163-bone default skeleton: joints as vertex groups),
- ``makehuman/data/rigs/default_weights.mhw`` (its skin weights).

Steps: joints = mean of their vertex groups (``.mhskel``); the 163 bones are merged into the 13 the
simulator poses (torso with head, upper arm, forearm, hand, thigh, shin, foot per side: a merged
bone's weights are summed); the body is decimated (quadric, fast-simplification) to about
``--faces`` triangles, each new vertex taking the weights of the nearest original vertex; every
vertex keeps its 4 largest weights. Scaled to metres (MakeHuman units are decimetres) with the
model's axes unchanged: x = the body's LEFT, y = up, z = forward (the face). Then, in the same
frame, a diver's equipment is added as separate triangles: a tank on the back (torso) and a fin
on each foot. Faces carry a material index (``MATERIALS``) for the renderer's colours: suit, hood,
skin (face), mask, glove, tank, fin.

Usage::

    git clone https://github.com/makehumancommunity/makehuman /tmp/makehuman  # or any copy
    python tools/make_body.py --makehuman /tmp/makehuman --out sitl/assets/human_body.npz
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

BONES = ("torso", "upperarm.R", "lowerarm.R", "hand.R", "upperarm.L", "lowerarm.L", "hand.L",
         "upperleg.R", "lowerleg.R", "foot.R", "upperleg.L", "lowerleg.L", "foot.L")
MATERIALS = ("suit", "hood", "skin", "mask", "glove", "tank", "fin")

# (bone, head joint, tail joint) of MakeHuman's skeleton for each simulator bone
_BONE_JOINTS = {
    "torso": ("root____head", "neck01____head"),
    "upperarm.R": ("upperarm01.R____head", "lowerarm01.R____head"),
    "lowerarm.R": ("lowerarm01.R____head", "wrist.R____head"),
    "hand.R": ("wrist.R____head", "finger3-3.R____tail"),
    "upperarm.L": ("upperarm01.L____head", "lowerarm01.L____head"),
    "lowerarm.L": ("lowerarm01.L____head", "wrist.L____head"),
    "hand.L": ("wrist.L____head", "finger3-3.L____tail"),
    "upperleg.R": ("upperleg01.R____head", "lowerleg01.R____head"),
    "lowerleg.R": ("lowerleg01.R____head", "foot.R____head"),
    "foot.R": ("foot.R____head", "toe3-1.R____head"),
    "upperleg.L": ("upperleg01.L____head", "lowerleg01.L____head"),
    "lowerleg.L": ("lowerleg01.L____head", "foot.L____head"),
    "foot.L": ("foot.L____head", "toe3-1.L____head"),
}


def _merged_bone(name: str) -> str:
    """Return the simulator bone a MakeHuman bone's weights go to."""
    for side in ("R", "L"):
        if name in (f"upperarm01.{side}", f"upperarm02.{side}"):
            return f"upperarm.{side}"
        if name in (f"lowerarm01.{side}", f"lowerarm02.{side}"):
            return f"lowerarm.{side}"
        if name.endswith(f".{side}") and name.startswith(("wrist", "finger", "metacarpal")):
            return f"hand.{side}"
        if name in (f"upperleg01.{side}", f"upperleg02.{side}"):
            return f"upperleg.{side}"
        if name in (f"lowerleg01.{side}", f"lowerleg02.{side}"):
            return f"lowerleg.{side}"
        if name.endswith(f".{side}") and name.startswith(("foot", "toe")):
            return f"foot.{side}"
    return "torso"


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Return (all vertices, triangles of the ``body`` group) of MakeHuman's base.obj."""
    verts, faces, group = [], [], None
    for line in path.read_text().splitlines():
        if line.startswith("v "):
            verts.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("g "):
            group = line.split()[1]
        elif line.startswith("f ") and group == "body":
            idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
            faces += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    return np.array(verts), np.array(faces, np.int64)


def weights_matrix(mhw: dict, n_vertices: int) -> np.ndarray:
    """Return (n_vertices, len(BONES)) skin weights merged into the simulator's bones, rows summing to 1."""
    w = np.zeros((n_vertices, len(BONES)))
    for bone, pairs in mhw["weights"].items():
        col = BONES.index(_merged_bone(bone))
        for v, x in pairs:
            w[v, col] += x
    empty = w.sum(1) == 0
    w[empty, 0] = 1.0
    return w / w.sum(1, keepdims=True)


def materials(verts: np.ndarray, weights: np.ndarray, joints: dict) -> np.ndarray:
    """Return each vertex's material index: glove on the hands, skin / mask / hood on the head, else suit."""
    mat = np.full(len(verts), MATERIALS.index("suit"))
    hands = weights[:, [BONES.index("hand.R"), BONES.index("hand.L")]].sum(1) > 0.5
    mat[hands] = MATERIALS.index("glove")
    neck_y = joints["neck01____tail"][1]
    head = verts[:, 1] > neck_y
    eye_y = 0.5 * (joints["eye.L____head"][1] + joints["eye.R____head"][1])
    front = verts[:, 2] > joints["head____head"][2] + 0.05
    mat[head] = MATERIALS.index("hood")
    face = head & front & (verts[:, 1] < eye_y + 0.055) & (np.abs(verts[:, 0]) < 0.065)
    mat[face] = MATERIALS.index("skin")
    mask = head & front & (np.abs(verts[:, 1] - eye_y) < 0.03) & (np.abs(verts[:, 0]) < 0.075)
    mat[mask] = MATERIALS.index("mask")
    return mat


def _cylinder(c0: np.ndarray, c1: np.ndarray, radius: float, n: int = 14,
              rings: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Return (vertices, outward-wound triangles) of a closed cylinder from ``c0`` up to ``c1`` (axis y).

    The side is cut into ``rings`` bands so that no triangle is long (the painter's order uses
    each triangle's mean depth).
    """
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.stack([radius * np.cos(a), np.zeros(n), radius * np.sin(a)], 1)
    v = np.vstack([c0 + (c1 - c0) * (r / rings) + ring for r in range(rings + 1)] + [c0[None], c1[None]])
    bottom, top = (rings + 1) * n, (rings + 1) * n + 1
    f = []
    for r in range(rings):
        for k in range(n):
            k1 = (k + 1) % n
            a0, a1, b0, b1 = r * n + k, r * n + k1, (r + 1) * n + k, (r + 1) * n + k1
            f += [[a0, b1, a1], [a0, b0, b1]]
    for k in range(n):
        k1 = (k + 1) % n
        f += [[bottom, k, k1], [top, rings * n + k1, rings * n + k]]
    return v, np.array(f, np.int64)


def _fin(ankle: np.ndarray, toe: np.ndarray, side: float) -> tuple[np.ndarray, np.ndarray]:
    """Return (vertices, triangles) of a flat fin blade from the toes forward, two-sided."""
    d = toe - ankle
    d = d / np.linalg.norm(d)
    lat = np.array([1.0, 0.0, 0.0])
    base = toe - 0.03 * d
    tip = toe + 0.42 * d
    v = np.array([base - 0.055 * lat, base + 0.055 * lat, tip + 0.11 * lat, tip - 0.11 * lat,
                  toe - 0.12 * d - 0.05 * lat + [0, 0.02, 0], toe - 0.12 * d + 0.05 * lat + [0, 0.02, 0]])
    f = [[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2], [4, 5, 1], [4, 1, 0], [4, 1, 5], [4, 0, 1]]
    del side
    return v, np.array(f, np.int64)


def build(makehuman: Path, faces_target: int) -> dict[str, np.ndarray]:
    """Return the arrays of the body file (see the module docstring)."""
    import fast_simplification
    from scipy.spatial import cKDTree

    data = makehuman / "makehuman" / "data"
    verts, tris = read_obj(data / "3dobjs" / "base.obj")
    skel = json.loads((data / "rigs" / "default.mhskel").read_text())
    mhw = json.loads((data / "rigs" / "default_weights.mhw").read_text())
    scale = 0.1  # decimetres -> metres
    joints = {name: verts[idx].mean(0) * scale for name, idx in skel["joints"].items()}
    weights = weights_matrix(mhw, len(verts))
    used = np.unique(tris)
    remap = -np.ones(len(verts), np.int64)
    remap[used] = np.arange(len(used))
    body_v, body_f, body_w = verts[used] * scale, remap[tris], weights[used]
    dv, df = fast_simplification.simplify(body_v.astype(np.float32), body_f.astype(np.int32),
                                          target_reduction=1.0 - faces_target / len(body_f))
    dv = dv.astype(np.float64)
    nearest = cKDTree(body_v).query(dv)[1]
    dw = body_w[nearest]
    mat_v = materials(dv, dw, joints)
    df = np.asarray(df, np.int64)
    # a face's material: the most common of its vertices' (ties: the first vertex's)
    fm = mat_v[df]
    face_mat = np.where(fm[:, 1] == fm[:, 2], fm[:, 1], fm[:, 0])
    parts_v, parts_f, parts_w, parts_m = [dv], [df], [dw], [face_mat]
    n = len(dv)

    def add(v, f, bone, mat):
        nonlocal n
        w = np.zeros((len(v), len(BONES)))
        w[:, BONES.index(bone)] = 1.0
        parts_v.append(v)
        parts_f.append(f + n)
        parts_w.append(w)
        parts_m.append(np.full(len(f), MATERIALS.index(mat)))
        n += len(v)

    back_z = dv[(np.abs(dv[:, 0]) < 0.05) & (np.abs(dv[:, 1] - 0.35) < 0.05), 2].min()
    tank_c = np.array([0.0, 0.0, back_z - 0.105])
    add(*_cylinder(tank_c + [0, -0.06, 0], tank_c + [0, 0.5, 0], 0.09), "torso", "tank")
    for side, s in (("R", -1.0), ("L", 1.0)):
        add(*_fin(joints[f"foot.{side}____head"], joints[f"toe3-1.{side}____head"], s), f"foot.{side}", "fin")
    all_w = np.vstack(parts_w)
    top = np.argsort(-all_w, axis=1)[:, :4]
    top_w = np.take_along_axis(all_w, top, 1)
    top_w /= top_w.sum(1, keepdims=True)
    bone_heads = np.array([joints[_BONE_JOINTS[b][0]] for b in BONES])
    bone_tails = np.array([joints[_BONE_JOINTS[b][1]] for b in BONES])
    head_top = dv[dv[:, 1].argmax()]
    nose = dv[(dv[:, 1] > joints["head____head"][1])][:, 2].argmax()
    nose = dv[dv[:, 1] > joints["head____head"][1]][nose]
    return {
        "vertices_m": np.vstack(parts_v).astype(np.float32),
        "faces": np.vstack(parts_f).astype(np.int32),
        "face_material": np.concatenate(parts_m).astype(np.uint8),
        "bone_index": top.astype(np.uint8),
        "bone_weight": top_w.astype(np.float32),
        "bone_names": np.array(BONES),
        "bone_head_m": bone_heads.astype(np.float32),
        "bone_tail_m": bone_tails.astype(np.float32),
        "material_names": np.array(MATERIALS),
        "landmark_names": np.array(["nose", "left_eye", "right_eye", "head_top"]),
        "landmark_m": np.array([nose, joints["eye.L____head"], joints["eye.R____head"], head_top], np.float32),
        "landmark_bone": np.zeros(4, np.uint8),
        "source": np.array("MakeHuman base.obj + default.mhskel + default_weights.mhw, "
                           "makehumancommunity/makehuman@a8bc2d54ff0ac92e78ff71431b1023eda42bf482, CC0 1.0"),
    }


def main() -> None:
    """Command line (see the module docstring)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--makehuman", type=Path, required=True, help="a checkout of makehumancommunity/makehuman")
    ap.add_argument("--out", type=Path, default=Path("sitl/assets/human_body.npz"))
    ap.add_argument("--faces", type=int, default=5000, help="triangles of the decimated body")
    args = ap.parse_args()
    arrays = build(args.makehuman, args.faces)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **arrays)
    print(f"{args.out}: {len(arrays['vertices_m'])} vertices, {len(arrays['faces'])} triangles, "
          f"{args.out.stat().st_size / 1e6:.2f} MB")


if __name__ == "__main__":
    main()

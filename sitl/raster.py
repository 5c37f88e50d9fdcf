"""A small triangle rasteriser on OpenCV: flat-shaded meshes painted far to near into an image.

Triangles facing away from the camera are culled; the rest are sorted by their mean depth and
filled one by one (``cv2.fillConvexPoly``, 1/16 px vertex precision) from the farthest, so nearer
triangles cover farther ones (the painter's algorithm: exact for a closed, culled mesh except where
two triangles overlap in depth range, which at the body's few-centimetre triangles is a pixel-level
matter). Vertices are projected with the camera's lens distortion; triangles are small, so their
straight edges follow the distorted image closely.

Shading (``shade_faces``): Lambert light from the surface (straight up) and from the vehicle's
lights (toward the camera) over an ambient floor, then the water's colour model per face
(observed = albedo * light(d) * exp(-c d) + veil * (1 - exp(-c d)), d = the face's distance).
"""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["face_normals", "shade_faces", "draw_mesh"]


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Return the (F, 3) unit normals of triangles (right-handed winding)."""
    v0, v1, v2 = (vertices[faces[:, k]] for k in range(3))
    n = np.cross(v1 - v0, v2 - v0)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)


def shade_faces(albedo_bgr: np.ndarray, normals_cam: np.ndarray, centres_cam: np.ndarray,
                up_cam: np.ndarray, water, unshaded: np.ndarray | None = None) -> np.ndarray:
    """Return (F, 3) observed BGR colours of flat-shaded faces seen through the water.

    Args:
        albedo_bgr: (F, 3) surface colours, 0-255.
        normals_cam: (F, 3) unit normals in the camera frame.
        centres_cam: (F, 3) face centres in the camera frame, metres.
        up_cam: (3,) the world's up direction in the camera frame.
        water: the scenario's ``Water``.
        unshaded: (F,) bool, faces lit evenly (no facets: e.g. small, matte parts), or None.
    """
    dist = np.linalg.norm(centres_cam, axis=1)
    to_cam = -centres_cam / np.maximum(dist[:, None], 1e-9)
    sky = np.clip(normals_cam @ up_cam, 0.0, 1.0)
    lamp = np.clip(np.einsum("ij,ij->i", normals_cam, to_cam), 0.0, 1.0)
    light_shape = 0.35 + 0.45 * sky + 0.5 * lamp
    if unshaded is not None:
        light_shape = np.where(unshaded, 0.8, light_shape)
    c = np.asarray(water.attenuation_per_m, float) + water.turbidity_per_m
    t = np.exp(-np.outer(dist, c))
    a = water.ambient_light
    illum = a + (1.0 - a) / (1.0 + water.light_falloff_per_m2 * dist ** 2)
    veil = np.asarray(water.colour_bgr, float)
    out = albedo_bgr * (light_shape * illum)[:, None] * t + veil * (1.0 - t)
    return np.clip(out, 0, 255)


def draw_mesh(image: np.ndarray, uv_px: np.ndarray, vertices_cam: np.ndarray, faces: np.ndarray,
              colours_bgr: np.ndarray, near_m: float = 0.1) -> int:
    """Paint a mesh's front-facing triangles far to near; return how many were drawn.

    Args:
        image: HxWx3 uint8, painted in place.
        uv_px: (V, 2) projected vertices, pixels.
        vertices_cam: (V, 3) vertices in the camera frame (for culling and depth order).
        faces: (F, 3) vertex indices.
        colours_bgr: (F, 3) colour of each face.
        near_m: triangles with a vertex nearer than this are skipped.
    """
    h, w = image.shape[:2]
    x, y = uv_px[:, 0], uv_px[:, 1]
    lim = 8 * (w + h)
    ok_v = (vertices_cam[:, 2] > near_m) & (x > -lim) & (x < lim) & (y > -lim) & (y < lim)
    fx, fy = x[faces], y[faces]                                   # (F, 3) each
    a, b, c = fx[:, 0], fx[:, 1], fx[:, 2]
    on_x = (np.maximum(np.maximum(a, b), c) >= 0) & (np.minimum(np.minimum(a, b), c) < w)
    a, b, c = fy[:, 0], fy[:, 1], fy[:, 2]
    on_y = (np.maximum(np.maximum(a, b), c) >= 0) & (np.minimum(np.minimum(a, b), c) < h)
    ok = ok_v[faces]
    keep = ok[:, 0] & ok[:, 1] & ok[:, 2] & on_x & on_y
    idx = np.flatnonzero(keep)
    if len(idx) == 0:
        return 0
    f = faces[idx]
    v0, v1, v2 = vertices_cam[f[:, 0]], vertices_cam[f[:, 1]], vertices_cam[f[:, 2]]
    front = np.einsum("ij,ij->i", np.cross(v1 - v0, v2 - v0), v0) < 0.0
    idx, f = idx[front], f[front]
    if len(idx) == 0:
        return 0
    depth = vertices_cam[f, 2].sum(axis=1)
    sort = np.argsort(-depth, kind="stable")
    order = idx[sort]
    pts = np.round(uv_px[f[sort]] * 16.0).astype(np.int32)
    cols = colours_bgr[order].tolist()
    fill = cv2.fillConvexPoly
    for p, c in zip(pts, cols):
        fill(image, p, c, cv2.LINE_8, 4)
    return len(order)

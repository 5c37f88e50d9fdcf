"""Stereo renderer of a scenario: left/right images from the vehicle's pose, plus the truth.

How a frame is made, per camera, directly in the original (distorted) image; everything static
is precomputed in the constructor, so a frame costs a few small warps and drawing calls:

1. the background: water (a vertical blue-green gradient) and, where rays hit it, the pool floor,
   attenuated with distance; computed at low resolution from each pixel's ray and resized (it is
   smooth), cached while the camera depth is unchanged;
2. the track line, the placards and the diver are painted far to near. A placard is
   one cv2.remap of a mip level of its texture (colour attenuated for its distance) over its
   bounding box only: distorted pixel -> undistorted pixel (a map computed once per camera,
   exact inverse of the lens model) -> texture pixel (the placard's homography). The diver is a
   skinned human mesh (``body.py``: MakeHuman's body posed on the scenario's joints, with a tank,
   fins, hood and mask) painted triangle by triangle, flat-shaded and seen through the water
   (``raster.py``), its vertices projected with the lens distortion;
3. optional blur, then sensor noise from precomputed noise tiles at seeded random offsets.

The truth in ``frame.meta`` (see ``StereoRenderer.render``) uses cv2.projectPoints with the same
K and distortion, so keypoints and placard polygons agree with the pixels.

Benchmark: ``python -m sitl.render --bench [--scenario NAME]``.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Mapping

import cv2
import numpy as np

from dip3d_vehicle.frames import StereoFrame

from .body import PosedBody, load_body, pose_body
from .diver import Diver
from .raster import draw_mesh, face_normals, shade_faces
from .scenario import load_scenario
from .scenario_model import Placard, Scenario, Water
from .textures import mip_levels, placard_texture
from .world import (CameraPose, VehiclePose, left_camera_pose, project_distorted, project_pinhole,
                    right_camera_pose)

__all__ = ["StereoRenderer", "world_params", "KEYPOINT_SOURCE"]

KEYPOINT_SOURCE = "sim-truth+noise"
"""Label of the simulated pose source in ``meta["keypoints"]``: ground truth plus noise."""

_ARM_JOINTS = ("shoulder", "elbow", "wrist")
_MAP_CACHE: dict[tuple, tuple] = {}


def world_params(params: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Return the ``world.*`` parameters (without the prefix): schema defaults unless given."""
    from dip3d_vehicle.config import schema

    out = {k[6:]: p.default for k, p in schema().items() if k.startswith("world.")}
    if params is not None:
        out.update({k[6:]: v for k, v in params.items() if k.startswith("world.")})
    return out


def _undistort_map(K: np.ndarray, D: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Return an (H, W, 2) float32 map: each original (distorted) pixel -> its undistorted pixel.

    The inverse lens model is solved exactly (cv2.undistortPointsIter) on a 16 px grid and
    interpolated with a bicubic spline (error < 1e-4 px for ordinary lenses). Cached per (K, D, size).
    """
    from scipy.interpolate import RectBivariateSpline

    key = (K.tobytes(), D.tobytes(), tuple(size))
    if key not in _MAP_CACHE:
        w, h = size
        if not np.any(D != 0):
            xs, ys = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
            _MAP_CACHE[key] = np.stack([xs, ys], -1)
            return _MAP_CACHE[key]
        gx = np.linspace(0, w - 1, max(4, w // 16 + 1))
        gy = np.linspace(0, h - 1, max(4, h // 16 + 1))
        mx, my = np.meshgrid(gx, gy)
        crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 40, 1e-10)
        und = cv2.undistortPointsIter(np.stack([mx, my], -1).reshape(-1, 1, 2), K, D, None, K, crit)
        und = und.reshape(len(gy), len(gx), 2)
        out = np.empty((h, w, 2), np.float32)
        for c in range(2):
            out[..., c] = RectBivariateSpline(gy, gx, und[..., c])(np.arange(h), np.arange(w))
        _MAP_CACHE[key] = out
    return _MAP_CACHE[key]


class _View:
    """One camera's static rendering data: undistortion map and background rays."""

    def __init__(self, K: np.ndarray, D: np.ndarray, size: tuple[int, int], R_body: np.ndarray,
                 bg_scale: int) -> None:
        self.K, self.D, self.size = K, D, size
        self.und = _undistort_map(K, D, size)
        w, h = size
        s = max(1, int(bg_scale))
        lw, lh = max(2, w // s), max(2, h // s)
        u = np.clip(((np.arange(lw) + 0.5) * w / lw - 0.5).round().astype(int), 0, w - 1)
        v = np.clip(((np.arange(lh) + 0.5) * h / lh - 0.5).round().astype(int), 0, h - 1)
        ideal = self.und[v][:, u].astype(np.float64)
        rays = np.stack([(ideal[..., 0] - K[0, 2]) / K[0, 0], (ideal[..., 1] - K[1, 2]) / K[1, 1],
                         np.ones(ideal.shape[:2])], -1)
        rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
        # Down component of each unit ray in the world: the vehicle only yaws, so it is static.
        self.ray_down = (rays @ R_body.T)[..., 2].astype(np.float32)
        self._bg_key: tuple | None = None
        self._bg: np.ndarray | None = None

    def background(self, water: Water, cam_depth_m: float) -> np.ndarray:
        """Return the background (water gradient + floor) for a camera depth (cached per cm)."""
        key = (round(cam_depth_m, 2),)
        if key != self._bg_key:
            self._bg = cv2.resize(_background_low(water, self.ray_down, cam_depth_m), self.size,
                                  interpolation=cv2.INTER_LINEAR)
            self._bg_key = key
        return self._bg

    def project(self, points_cam: np.ndarray) -> np.ndarray:
        """Project (N, 3) camera-frame points to original pixels (with distortion)."""
        return project_distorted(points_cam, self.K, self.D)


def _background_low(water: Water, ray_down: np.ndarray, cam_depth_m: float) -> np.ndarray:
    """Return the low-resolution background: water gradient, and the floor where rays hit it."""
    veil = np.asarray(water.colour_bgr, np.float32)
    up = np.clip(-ray_down, -1, 1)[..., None]
    out = veil * (0.8 + 0.35 * up)
    if water.floor_depth_m is not None and water.floor_depth_m > cam_depth_m:
        h = np.float32(water.floor_depth_m - cam_depth_m)
        hit = ray_down > 1e-3
        dist = np.minimum(h / np.maximum(ray_down, np.float32(1e-3)), np.float32(1e3))[..., None]
        c = np.asarray(water.attenuation_per_m, np.float32) + np.float32(water.turbidity_per_m)
        t = np.exp(-c * dist)
        a = np.float32(water.ambient_light)
        light = a + (1 - a) / (1 + np.float32(water.light_falloff_per_m2) * dist ** 2)
        floor = np.asarray(water.floor_bgr, np.float32) * light * t + veil * (1 - t)
        out = np.where(hit[..., None], floor, out)
    return np.clip(out, 0, 255).astype(np.uint8)


class StereoRenderer:
    """Renders the scenario's stereo pair from a vehicle pose, with ground truth in ``meta``.

    Args:
        scenario: the resolved scenario.
        params: parameters (``world.*`` keys used: render_noise, pose_noise, texture_px,
            background_scale, threads); schema defaults when None.
    """

    def __init__(self, scenario: Scenario, params: Mapping[str, Any] | None = None) -> None:
        self.scenario = scenario
        self.params = world_params(params)
        cam = scenario.camera
        self.size = cam.image_size
        self.K = cam.K
        self.R, self.T = cam.R, cam.T
        zero = VehiclePose(0.0, 0.0, 0.0, 0.0)
        R_left = left_camera_pose(zero, cam.mount_frd_m, cam.mount_pitch_rad, cam.mount_yaw_rad).R_cw.T
        R_right = R_left @ self.R.T
        scale = int(self.params["background_scale"])
        self.views = (_View(self.K, cam.D1, self.size, R_left, scale),
                      _View(self.K, cam.D2, self.size, R_right, scale))
        tex_px = int(self.params["texture_px"])
        self.textures = {p.id: mip_levels(placard_texture(p.id, p.texture_seed, tex_px))
                         for p in scenario.placards}
        self._noise = _noise_tiles(scenario.water.noise_sigma, self.size, scenario.seed)
        self.body = load_body()
        self._body_albedo = _body_albedo(self.body, scenario.diver)
        self._gloves = self.body.face_material == self.body.materials.index("glove")
        threads = int(self.params["threads"])
        self._pool = ThreadPoolExecutor(2) if threads > 1 else None
        self._count = 0

    def close(self) -> None:
        """Release the worker threads (rendering still works afterwards, single-threaded)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def __enter__(self) -> "StereoRenderer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- public ----------------------------------------------------------------------------
    def camera_poses(self, pose: VehiclePose) -> tuple[CameraPose, CameraPose]:
        """Return the (left, right) camera poses for a vehicle pose."""
        cam = self.scenario.camera
        left = left_camera_pose(pose, cam.mount_frd_m, cam.mount_pitch_rad, cam.mount_yaw_rad)
        return left, right_camera_pose(left, self.R, self.T)

    def render(self, north_m: float, east_m: float, depth_m: float, yaw_rad: float,
               t_s: float) -> StereoFrame:
        """Render the stereo pair seen from the vehicle pose at scenario time ``t_s``.

        Returns:
            A StereoFrame (original, distorted BGR images; ``stamp_s = t_s``) whose ``meta`` holds:
            ``keypoints`` (the simulated pose source: truth + noise, with dropouts; None when the
            diver's arm is not in both images or dropped out; ``"source": "sim-truth+noise"``),
            ``keypoints_truth`` (the same without noise and dropouts), ``pointing`` (bool),
            ``target_id``, ``placards`` ({id: {"xyz_cam_m", "left_polygon_px", "visible",
            "range_m", "role"}}), ``vehicle_pose`` (dict), ``joints_cam_m`` (shoulder, elbow,
            wrist in the left optical frame), ``diver_visible`` (bool), ``body_truth`` (both
            arms' shoulder / elbow / wrist, the nose and the eyes, BlazePose names such as
            ``right_wrist``: ``{"left": {name: [x, y]}, "right": ..., "xyz_cam_m": {name: [x, y, z]}}``,
            an eye None when a point is behind it), ``stop_gesture`` (bool: both wrists held above
            the head). The arm joints are the body's own skeleton joint centres.
        """
        pose = VehiclePose(float(north_m), float(east_m), float(depth_m), float(yaw_rad))
        poses = self.camera_poses(pose)
        sc = self.scenario
        target = sc.placard(sc.target_id)
        joints = sc.diver.joints(np.asarray(target.centre_ned_m), t_s)
        body = pose_body(self.body, joints, sc.diver.heading_rad, sc.diver.arm)
        ms = int(round(t_s * 1000.0)) % (2 ** 32)
        rng = np.random.default_rng([sc.seed, ms, 2])
        offsets = rng.integers(0, 64, size=(2, 2)) if self._noise is not None else None
        if self._pool is not None:
            futures = [self._pool.submit(self._render_view, i, poses[i], joints, body, offsets) for i in range(2)]
            left, right = (f.result() for f in futures)
        else:
            left, right = (self._render_view(i, poses[i], joints, body, offsets) for i in range(2))
        meta = self._truth(pose, poses, joints, t_s, ms)
        meta["body_truth"] = self._body_truth(poses, joints, body)
        meta["stop_gesture"] = sc.diver.stop_gesture_at(t_s)
        self._count += 1
        return StereoFrame(left=left, right=right, stamp_s=float(t_s), index=self._count - 1, meta=meta)

    # -- images ----------------------------------------------------------------------------
    def _render_view(self, i: int, cam: CameraPose, joints: dict, body: PosedBody, offsets) -> np.ndarray:
        """Render one camera's original (distorted) image."""
        view = self.views[i]
        water = self.scenario.water
        image = view.background(water, float(cam.centre_w[2])).copy()
        self._draw_track(image, view, cam)
        items = [(d, "placard", p) for p in self.scenario.placards
                 if (d := float(np.linalg.norm(cam.to_cam(p.centre_ned_m)))) > 0]
        items.append((float(np.linalg.norm(cam.to_cam(joints["chest"]))), "body", body))
        for dist, kind, obj in sorted(items, key=lambda it: -it[0]):
            if kind == "placard":
                self._draw_placard(image, view, cam, obj, dist)
            else:
                self._draw_body(image, view, cam, obj)
        if water.blur_px > 0:
            cv2.GaussianBlur(image, (0, 0), water.blur_px, dst=image)
        if offsets is not None and self.params["render_noise"]:
            pos, neg = self._noise
            (ox, oy), (h, w) = offsets[i], image.shape[:2]
            cv2.add(image, pos[oy:oy + h, ox:ox + w], dst=image)
            cv2.subtract(image, neg[oy:oy + h, ox:ox + w], dst=image)
        return image

    def _draw_body(self, image: np.ndarray, view: _View, cam: CameraPose, body: PosedBody) -> None:
        """Paint the diver's posed body mesh (flat-shaded, through the water)."""
        verts = cam.to_cam(body.vertices_ned_m)
        if verts[:, 2].max() < 0.1:
            return
        faces = self.body.faces
        front = verts[:, 2] > 0.05
        uv = np.full((len(verts), 2), -1e6)
        uv[front] = view.project(verts[front])
        normals = face_normals(verts, faces)
        centres = verts[faces].mean(axis=1)
        up_cam = -cam.R_cw[:, 2]
        colours = shade_faces(self._body_albedo, normals, centres, up_cam, self.scenario.water, self._gloves)
        draw_mesh(image, uv, verts, faces, colours)

    def _body_truth(self, poses: tuple[CameraPose, CameraPose], joints: dict, body: PosedBody) -> dict:
        """Return both arms' joints, the shoulders and the nose (BlazePose names) in both images."""
        arm = self.scenario.diver.arm
        other = "left" if arm == "right" else "right"
        names = {f"{arm}_shoulder": "shoulder", f"{arm}_elbow": "elbow", f"{arm}_wrist": "wrist",
                 f"{other}_shoulder": "o_shoulder", f"{other}_elbow": "o_elbow", f"{other}_wrist": "o_wrist"}
        pts = {k: np.asarray(joints[v], float) for k, v in names.items()}
        pts.update({k: np.asarray(body.landmarks_ned_m[k], float) for k in ("nose", "left_eye", "right_eye")})
        keys = list(pts)
        world = np.array([pts[k] for k in keys])
        out: dict[str, Any] = {"xyz_cam_m": {k: [float(v) for v in p] for k, p in zip(keys, poses[0].to_cam(world))}}
        cam = self.scenario.camera
        for side, cpose, D in (("left", poses[0], cam.D1), ("right", poses[1], cam.D2)):
            pc = cpose.to_cam(world)
            if np.any(pc[:, 2] < 0.1):
                out[side] = None
                continue
            px = project_distorted(pc, self.K, D)
            out[side] = {k: [float(x), float(y)] for k, (x, y) in zip(keys, px)}
        return out

    def _draw_track(self, image: np.ndarray, view: _View, cam: CameraPose) -> None:
        """Paint the track line on the floor (drawn first: it lies under everything else)."""
        pts = self.scenario.track_line_ned_m
        if len(pts) < 2:
            return
        samples = []
        for a, b in zip(pts[:-1], pts[1:]):
            a, b = np.asarray(a), np.asarray(b)
            n = max(2, int(np.linalg.norm(b - a) / 0.25))
            samples.append(a + np.linspace(0, 1, n)[:, None] * (b - a))
        pc = cam.to_cam(np.vstack(samples))
        front = pc[:, 2] > 0.1
        uv = np.zeros((len(pc), 2))
        uv[front] = view.project(pc[front])
        water = self.scenario.water
        h, w = image.shape[:2]
        for k in range(len(pc) - 1):
            if not (front[k] and front[k + 1]) or np.abs(uv[k:k + 2]).max() > 4 * (w + h):
                continue
            z = 0.5 * (pc[k, 2] + pc[k + 1, 2])
            colour = water.apply((30, 40, 45), float(np.linalg.norm(pc[k])))
            thick = max(1, int(round(0.05 * view.K[0, 0] / z)))
            p = np.round(uv[k:k + 2] * 16).astype(np.int64)
            cv2.line(image, (int(p[0, 0]), int(p[0, 1])), (int(p[1, 0]), int(p[1, 1])), colour, thick,
                     cv2.LINE_AA, 4)

    def _draw_placard(self, image: np.ndarray, view: _View, cam: CameraPose, placard: Placard,
                      dist: float) -> None:
        """Paint one placard: its texture remapped over its bounding box, attenuated for distance."""
        corners = cam.to_cam(placard.corners_ned())
        if np.any(corners[:, 2] < 0.05):
            return
        # Bounding box in the distorted image from points along the edges (edges bow).
        t = np.linspace(0.0, 1.0, 9)[:-1, None]
        edges = np.vstack([corners[k] + t * (corners[(k + 1) % 4] - corners[k]) for k in range(4)])
        edge_px = view.project(edges)
        h, w = image.shape[:2]
        x0, y0 = np.floor(edge_px.min(0)).astype(int) - 2
        x1, y1 = np.ceil(edge_px.max(0)).astype(int) + 3
        x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, w), min(y1, h)
        if x1 <= x0 or y1 <= y0:
            return
        water = self.scenario.water
        gain, offset = water.gain_offset(dist)
        normal_cam = cam.R_cw @ np.asarray(placard.normal_ned)
        ideal = project_pinhole(corners, view.K).astype(np.float32)
        levels = self.textures[placard.id]
        if normal_cam @ corners.mean(0) >= 0:  # we see its back: plain grey
            levels = [np.full((4, 4, 3), 90, np.uint8)]
        side_px = float(np.max(np.linalg.norm(ideal - np.roll(ideal, 1, axis=0), axis=1)))
        level = levels[0]
        for lv in levels:
            if lv.shape[0] >= side_px:
                level = lv
        s = level.shape[0]
        src = np.float32([[-0.5, -0.5], [s - 0.5, -0.5], [s - 0.5, s - 0.5], [-0.5, s - 0.5]])
        H_inv = cv2.getPerspectiveTransform(ideal, src)  # undistorted pixel -> texture pixel
        tex_xy = cv2.perspectiveTransform(view.und[y0:y1, x0:x1].reshape(-1, 1, 2), H_inv)
        tex_xy = tex_xy.reshape(y1 - y0, x1 - x0, 2)
        lut = np.clip(np.arange(256.0)[:, None] * gain + offset, 0, 255).astype(np.uint8)
        tex = cv2.LUT(level, lut.reshape(256, 1, 3))
        cv2.remap(tex, tex_xy, None, cv2.INTER_LINEAR, dst=image[y0:y1, x0:x1],
                  borderMode=cv2.BORDER_TRANSPARENT)

    # -- truth -----------------------------------------------------------------------------
    def _truth(self, pose: VehiclePose, poses: tuple[CameraPose, CameraPose], joints: dict, t_s: float,
               ms: int) -> dict:
        """Return the frame's ground truth and simulated pose-source output."""
        sc = self.scenario
        cam = sc.camera
        w, h = self.size
        arm_w = np.array([joints[j] for j in _ARM_JOINTS])
        truth: dict[str, Any] = {"rectified": False, "source": "sim-truth"}
        visible = True
        for side, cpose, D in (("left", poses[0], cam.D1), ("right", poses[1], cam.D2)):
            pc = cpose.to_cam(arm_w)
            if np.any(pc[:, 2] < 0.1):
                visible = False
                continue
            px = project_distorted(pc, self.K, D)
            inside = (px[:, 0] >= 0) & (px[:, 0] <= w - 1) & (px[:, 1] >= 0) & (px[:, 1] <= h - 1)
            visible &= bool(np.all(inside))
            truth[side] = {j: [float(x), float(y)] for j, (x, y) in zip(_ARM_JOINTS, px)}
            if side == "left":
                truth[side].update(_extra_truth(cpose, joints, self.K, D, (w, h)))
        keypoints = None
        if visible:
            rng = np.random.default_rng([sc.seed, ms, 1])
            use_noise = bool(self.params["pose_noise"])
            dropped = use_noise and rng.random() < sc.pose_source.dropout
            if not dropped:
                sigma = sc.pose_source.noise_px if use_noise else 0.0
                keypoints = {"rectified": False, "source": KEYPOINT_SOURCE}
                for side in ("left", "right"):
                    noise = rng.normal(0.0, sigma, size=(3, 2)) if sigma > 0 else np.zeros((3, 2))
                    keypoints[side] = {j: [truth[side][j][0] + float(n[0]), truth[side][j][1] + float(n[1])]
                                       for j, n in zip(_ARM_JOINTS, noise)}
                _add_extra_joints(keypoints, truth, rng, sigma)
        placards = {}
        for p in sc.placards:
            c = poses[0].to_cam(p.centre_ned_m)[0]
            corners = poses[0].to_cam(p.corners_ned())
            poly = project_distorted(corners, self.K, cam.D1) if np.all(corners[:, 2] > 0.05) else None
            facing = float((poses[0].R_cw @ np.asarray(p.normal_ned)) @ c) < 0
            in_img = poly is not None and bool(np.all((poly[:, 0] >= 0) & (poly[:, 0] <= w - 1)
                                                      & (poly[:, 1] >= 0) & (poly[:, 1] <= h - 1)))
            placards[p.id] = {"xyz_cam_m": [float(v) for v in c],
                              "left_polygon_px": None if poly is None else poly.tolist(),
                              "visible": bool(in_img and facing), "range_m": float(np.linalg.norm(c)),
                              "role": p.role}
        joints_cam = poses[0].to_cam(arm_w)
        return {
            "keypoints": keypoints,
            "keypoints_truth": truth if visible else None,
            "pointing": sc.diver.pointing_at(t_s),
            "target_id": sc.target_id,
            "placards": placards,
            "vehicle_pose": pose._asdict(),
            "joints_cam_m": {j: [float(v) for v in joints_cam[k]] for k, j in enumerate(_ARM_JOINTS)},
            "diver_visible": visible,
            "scenario": sc.name,
            "seed": sc.seed,
        }


_EXTRA_JOINTS = {"head": "head", "other_wrist": "o_wrist"}
"""The pose source's optional extra joints (for the stop gesture): keypoint name -> body joint."""


def _extra_truth(cpose, joints: dict, K: np.ndarray, D: np.ndarray, size: tuple[int, int]) -> dict:
    """Return the extra joints inside the left image, original pixels, by keypoint name."""
    out = {}
    for name, joint in _EXTRA_JOINTS.items():
        pc = cpose.to_cam(np.asarray([joints[joint]]))
        if pc[0, 2] < 0.1:
            continue
        x, y = project_distorted(pc, K, D)[0]
        if 0 <= x <= size[0] - 1 and 0 <= y <= size[1] - 1:
            out[name] = [float(x), float(y)]
    return out


def _add_extra_joints(keypoints: dict, truth: dict, rng: np.random.Generator, sigma: float) -> None:
    """Copy the left image's extra joints into the noisy keypoints (after the arm's draws: same arm noise)."""
    for name in _EXTRA_JOINTS:
        if name in truth["left"]:
            n = rng.normal(0.0, sigma, size=2) if sigma > 0 else np.zeros(2)
            keypoints["left"][name] = [truth["left"][name][0] + float(n[0]), truth["left"][name][1] + float(n[1])]


def _noise_tiles(sigma: float, size: tuple[int, int], seed: int):
    """Return (positive, negative) uint8 Gaussian noise tiles 64 px larger than the image, or None."""
    if sigma <= 0:
        return None
    w, h = size
    rng = np.random.default_rng([seed, 99])
    noise = rng.normal(0.0, sigma, size=(h + 64, w + 64, 3)).astype(np.float32)
    pos = np.clip(np.round(noise), 0, 255).astype(np.uint8)
    neg = np.clip(np.round(-noise), 0, 255).astype(np.uint8)
    return pos, neg


_MATERIAL_BGR = {"hood": None, "skin": (125.0, 145.0, 190.0), "mask": (75.0, 65.0, 55.0),
                 "glove": (32.0, 30.0, 28.0), "fin": (22.0, 22.0, 24.0)}


def _body_albedo(model, diver: Diver) -> np.ndarray:
    """Return the (F, 3) albedo of the body's faces: the scenario's suit and tank, the rest fixed."""
    table = []
    for name in model.materials:
        if name == "suit":
            table.append(diver.suit_bgr)
        elif name == "hood":
            table.append(tuple(0.8 * c for c in diver.suit_bgr))
        elif name == "tank":
            table.append(diver.tank_bgr)
        else:
            table.append(_MATERIAL_BGR[name])
    return np.asarray(table, float)[model.face_material]


def _bench(argv: list[str] | None = None) -> None:
    """Command line: ``python -m sitl.render --bench [--scenario NAME] [--frames N] [--out DIR]``."""
    ap = argparse.ArgumentParser(prog="python -m sitl.render")
    ap.add_argument("--scenario", default="paper_pool")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bench", action="store_true", help="time rendering and print the median")
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--out", default=None, help="write left/right PNGs of the first frame here")
    args = ap.parse_args(argv)
    sc = load_scenario(args.scenario, args.seed)
    params = None if args.threads is None else {"world.threads": args.threads}
    t0 = time.perf_counter()
    renderer = StereoRenderer(sc, params)
    setup_ms = (time.perf_counter() - t0) * 1e3
    pose = sc.initial_vehicle_pose
    times = []
    for k in range(args.frames if args.bench else 1):
        t = 2.0 + 0.1 * k
        t0 = time.perf_counter()
        frame = renderer.render(pose.north_m, pose.east_m + 0.001 * k, pose.depth_m, pose.yaw_rad, t)
        times.append((time.perf_counter() - t0) * 1e3)
        if k == 0 and args.out:
            from pathlib import Path

            out = Path(args.out)
            out.mkdir(parents=True, exist_ok=True)
            cv2.imwrite(str(out / f"{sc.name}_{args.seed}_left.png"), frame.left)
            cv2.imwrite(str(out / f"{sc.name}_{args.seed}_right.png"), frame.right)
    renderer.close()
    w, h = sc.camera.image_size
    print(f"{sc.name} seed {args.seed}: {w}x{h} stereo pair, setup {setup_ms:.0f} ms, "
          f"median {np.median(times):.1f} ms, min {min(times):.1f} ms, max {max(times):.1f} ms "
          f"over {len(times)} frames")


if __name__ == "__main__":
    _bench()

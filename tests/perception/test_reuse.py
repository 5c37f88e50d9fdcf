"""Candidates reused between frames: followed by optical flow, refreshed in the background or when the scene changed."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.reuse import disparity_outliers, follow_pairs, polygon_cover, views_of

W, H = 640, 480
F_PX, BASELINE_M = 500.0, 0.1
ARM = {"left": {"shoulder": [60.0, 300.0], "elbow": [110.0, 290.0], "wrist": [160.0, 280.0]},
       "right": {"shoulder": [35.0, 300.0], "elbow": [85.0, 290.0], "wrist": [135.0, 280.0]}}
# textured objects: (x0, y0) of an 80 px square in the left image, disparity px, texture seed
OBJECTS = {"a": (300, 140, 20.0, 1), "b": (450, 250, 25.0, 2), "c": (260, 330, 18.0, 3)}


def _rig() -> StereoRig:
    p1 = [[F_PX, 0, W / 2, 0], [0, F_PX, H / 2, 0], [0, 0, 1, 0]]
    p2 = [[F_PX, 0, W / 2, -F_PX * BASELINE_M], [0, F_PX, H / 2, 0], [0, 0, 1, 0]]
    return StereoRig.from_rectified(p1, p2, (W, H))


def _texture(seed: int, size: int = 80) -> np.ndarray:
    """A high-contrast blob texture (SIFT finds tens of features on it)."""
    noise = np.random.default_rng(seed).random((size, size))
    tex = cv2.GaussianBlur(noise, (0, 0), 2.0)
    tex = (tex - tex.min()) / (tex.max() - tex.min())
    return (40 + 200 * tex).astype(np.uint8)


def _render(shift=(0, 0), objects=OBJECTS, extra_seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Return a rectified grey pair: a smooth background and the objects, everything moved by ``shift`` (px)."""
    yy, xx = np.mgrid[0:H, 0:W]
    rng = np.random.default_rng(100 + extra_seed)
    back = (60 + 20 * np.sin((xx + shift[0]) / 90.0) + 10 * np.cos((yy + shift[1]) / 70.0)).astype(np.float64)
    left, right = back.copy(), back.copy()
    for x0, y0, disparity, seed in objects.values():
        tex = _texture(seed).astype(np.float64)
        x, y = x0 + shift[0], y0 + shift[1]
        for img, xs in ((left, x), (right, x - disparity)):
            xi, yi = int(round(xs)), int(round(y))
            img[yi:yi + 80, xi:xi + 80] = tex
    noise = rng.normal(0.0, 0.5, (2, H, W))
    return tuple(np.clip(img + n, 0, 255).astype(np.uint8) for img, n in zip((left, right), noise))


def _core(reuse_frames: int = 3) -> Perception:
    params = load_params("default", (), {"pose.backend": "keypoints", "candidates.reuse_frames": reuse_frames})
    return Perception(_rig(), params, GivenKeypoints("right", ARM))


def _in_box(cands, x0, y0, size=80) -> int:
    p = cands.left_px
    return int(np.sum((p[:, 0] >= x0) & (p[:, 0] < x0 + size) & (p[:, 1] >= y0) & (p[:, 1] < y0 + size)))


def test_followed_pairs_move_with_the_camera():
    """A 3 px / 2 px camera shift: every pair followed, each moved by the shift."""
    core = _core(0)
    a, b = _render(), _render(shift=(3, 2))
    arm = core.pose.estimate(*a, core.rig)
    cands = core.detector.detect(*a, arm, core.rig)
    assert len(cands) > 40
    moved, keep = follow_pairs(views_of(*a), views_of(*b), cands, 1.5, 3.0)
    assert keep.mean() > 0.95
    step = moved.left_px[keep] - cands.left_px[keep]
    assert np.median(np.abs(step - [3, 2])) < 0.2
    assert np.allclose(moved.disparity_px[keep], cands.disparity_px[keep], atol=1.0)


def test_pairs_that_leave_their_row_are_dropped():
    """The right image alone moves down 6 px (not a rigid scene): no pair stays on one row."""
    core = _core(0)
    a = _render()
    b_left, _ = _render()
    _, b_right = _render(shift=(0, 6))
    arm = core.pose.estimate(*a, core.rig)
    cands = core.detector.detect(*a, arm, core.rig)
    _, keep = follow_pairs(views_of(*a), views_of(b_left, b_right), cands, 1.5, 3.0)
    assert keep.mean() < 0.05


def test_first_frame_is_the_full_pass_exactly():
    """A single frame (no sequence) gives exactly what the core without reuse gives."""
    frame = _render()
    with_reuse, without = _core(3), _core(0)
    assert without.reuse is None
    r1, r0 = with_reuse.process_rectified(*frame), without.process_rectified(*frame)
    assert with_reuse.reuse.counts["fresh"] == 1
    np.testing.assert_array_equal(r1.candidates.left_px, r0.candidates.left_px)
    np.testing.assert_array_equal(r1.candidates.right_px, r0.candidates.right_px)


def test_a_steady_scene_is_followed_and_refreshed_in_the_background():
    """Frames 1.. are followed; an object that appears is found by the background pass, not before."""
    core = _core(3)
    first = core.process_rectified(*_render())            # frame 0: fresh
    assert core.reuse.counts == {"fresh": 1, "reused": 0, "refreshed": 0, "lost": 0, "corridor_scans": 0,
                                 "start_passes": 0}
    assert not first.candidates_followed
    with_d = dict(OBJECTS, d=(520, 100, 22.0, 4))
    seen = []
    for k in range(1, 9):                                 # the camera drifts 1 px per frame; "d" appears at frame 2
        frame = _render(shift=(k, 0), objects=OBJECTS if k < 2 else with_d)
        result = core.process_rectified(*frame)
        seen.append(_in_box(result.candidates, 520 + k, 100))
        assert result.candidates_followed and result.to_json(core.rig)["candidates_followed"]
    counts = core.reuse.counts
    assert counts["fresh"] == 1 and counts["lost"] == 0 and counts["reused"] == 8
    # background passes start on frames 1, 4, 7 and are taken 3 frames later (frames 4 and 7): the
    # pass of frame 1 predates "d"; the one of frame 4 (taken at frame 7) has it
    assert counts["refreshed"] == 3
    assert seen[:6] == [0] * 6
    assert seen[6] > 5 and seen[7] > 5


def test_a_moved_object_triggers_a_fresh_frame():
    """Object "a" jumps 120 px: its pairs are lost and the frame is computed afresh (= the single-frame result)."""
    core = _core(3)
    core.process_rectified(*_render())
    core.process_rectified(*_render(shift=(1, 0)))
    assert core.reuse.counts["reused"] == 1
    moved = dict(OBJECTS, a=(OBJECTS["a"][0], OBJECTS["a"][1] + 120, *OBJECTS["a"][2:]))
    frame = _render(shift=(1, 0), objects=moved)
    result = core.process_rectified(*frame)
    assert core.reuse.counts["lost"] == 1 and core.reuse.counts["fresh"] == 2
    reference = _core(0).process_rectified(*frame)
    np.testing.assert_array_equal(result.candidates.left_px, reference.candidates.left_px)
    assert _in_box(result.candidates, 301, 260) > 5                # found where it is now


def test_a_camera_jump_triggers_a_fresh_frame():
    core = _core(3)
    core.process_rectified(*_render())
    core.process_rectified(*_render(shift=(-150, 40)))
    assert core.reuse.counts["lost"] == 1 and core.reuse.counts["fresh"] == 2


def test_reset_starts_a_new_sequence():
    core = _core(3)
    core.process_rectified(*_render())
    core.reset()
    core.process_rectified(*_render())
    assert core.reuse.counts["fresh"] == 2 and core.reuse.counts["reused"] == 0


def test_reset_forgets_the_arm_that_predicts_the_features():
    """A new sequence's features are not prefetched in columns the previous sequence's arm predicted."""
    params = load_params("default", (), {"pose.backend": "blazepose", "candidates.reuse_frames": 0})
    core = Perception(_rig(), params, GivenKeypoints("right", ARM))   # overlap on; this pose gives no early arm
    hints = []
    core.detector.prefetch = lambda left, right, hint, *a: hints.append(hint)
    core.process_rectified(*_render())
    core.process_rectified(*_render())
    assert len(hints) == 1                       # the second frame: from the first frame's arm
    core.reset()
    core.process_rectified(*_render())
    assert len(hints) == 1                       # after the reset: not from the old sequence's arm


def test_a_disparity_change_unlike_its_neighbours_is_an_outlier():
    """A rigid approach changes every disparity alike (even by 6 px); one pair that slid 4 px along its row stands out."""
    rng = np.random.default_rng(0)
    pts = rng.uniform(0, 400, (60, 2))
    change = 6.0 + rng.normal(0, 0.2, 60)
    assert not disparity_outliers(pts, change, np.ones(60, bool), 2.0).any()
    change[17] += 4.0
    out = disparity_outliers(pts, change, np.ones(60, bool), 2.0)
    assert out[17] and out.sum() == 1
    one = np.zeros(60, bool)
    one[3] = True                                              # a lone followed pair has nothing to be checked against
    assert disparity_outliers(pts, change, one, 2.0).all()


def test_polygon_cover():
    square = np.array([[100, 100], [200, 100], [200, 200], [100, 200]], float)
    assert polygon_cover(square, square, W, H) == pytest.approx(1.0)
    assert polygon_cover(square, square + [50, 0], W, H) == pytest.approx(0.5)
    assert polygon_cover(square, square + [300, 0], W, H) == pytest.approx(0.0)
    outside = square + [0, 330]                                   # half below the image: only its visible half counts
    assert polygon_cover(outside, square + [0, 280], W, H) == pytest.approx(1.0)


def test_replay_compares_a_followed_frame_on_its_status_only():
    """Replay decides each kept pair alone: a run's followed frame may differ by a few px, not in status."""
    from dip3d_vehicle.commands.replay import changed
    old = {"status": "ok", "target": {"left_px": [100.0, 100.0]}, "candidates_followed": True}
    assert not changed(old, {"status": "ok", "target": {"left_px": [106.0, 100.0]}}, 2.0)
    assert changed(old, {"status": "nothing_on_ray", "target": None}, 2.0)
    fresh = dict(old, candidates_followed=False)
    assert changed(fresh, {"status": "ok", "target": {"left_px": [106.0, 100.0]}}, 2.0)


def _live(reuse_frames: int = 3, start_scale: float = 0.35) -> Perception:
    params = load_params("default", (), {"pose.backend": "keypoints", "candidates.reuse_frames": reuse_frames,
                                         "candidates.reuse_start_image_scale": start_scale})
    return Perception(_rig(), params, GivenKeypoints("right", ARM), live=True)


def test_a_live_sequence_starts_on_the_quicker_pass():
    """Frame 0 of a live sequence: main pass at the start scale; the full pass starts on it and is taken K frames later."""
    frame = _render()
    live, alone = _live(3), _core(3)
    first, full = live.process_rectified(*frame), alone.process_rectified(*frame)
    assert live.reuse.counts["start_passes"] == 1 and live.reuse.counts["refreshed"] == 1   # scheduled on frame 0
    assert alone.reuse.counts["start_passes"] == 0 and alone.reuse.counts["refreshed"] == 0
    assert 0 < len(first.candidates) < len(full.candidates)
    later = [live.process_rectified(*frame) for _ in range(3)]   # frame 3 takes frame 0's full pass
    assert all(r.candidates_followed for r in later)
    assert len(first.candidates) - 2 <= len(later[1].candidates) <= len(first.candidates)   # the start pass, followed
    assert len(full.candidates) - 2 <= len(later[2].candidates) <= len(full.candidates)     # the full pass, followed
    live.reset()
    live.process_rectified(*frame)
    assert live.reuse.counts["start_passes"] == 2


def test_the_start_pass_is_off_at_zero_and_for_single_frames():
    """``reuse_start_image_scale`` 0, or a core that is not live (perceive, evaluate): the full pass on frame 0."""
    frame = _render()
    full = _core(3).process_rectified(*frame)
    for core in (_live(3, 0.0), _core(3)):
        assert core.start_detector is None
        np.testing.assert_array_equal(core.process_rectified(*frame).candidates.left_px, full.candidates.left_px)


ARM_UP = {"left": {"shoulder": [60.0, 300.0], "elbow": [110.0, 275.0], "wrist": [160.0, 250.0]},
          "right": {"shoulder": [35.0, 300.0], "elbow": [85.0, 275.0], "wrist": [135.0, 250.0]}}


def test_a_later_corridor_rescan_outlives_the_pass_in_flight():
    """The arm turns while a background pass is in flight: the corridor is scanned afresh once; the pass,
    taken later, brings its main matches but keeps that newer corridor (no second rescan)."""
    core = _core(3)
    frame = _render()
    core.process_rectified(*frame)                 # frame 0: fresh
    core.process_rectified(*frame)                 # frame 1: the pass starts (taken at frame 4)
    core.pose.provide(ARM_UP)
    for _ in range(5):                             # frames 2-6: rescanned on frame 2 only
        result = core.process_rectified(*frame)
    counts = core.reuse.counts
    assert counts["corridor_scans"] == 1 and counts["refreshed"] >= 2 and counts["lost"] == 0
    reference = _core(0)
    reference.pose.provide(ARM_UP)
    fresh = reference.process_rectified(*frame)
    assert result.status == fresh.status
    assert abs(len(result.candidates) - len(fresh.candidates)) <= 2


def test_a_moved_corridor_is_scanned_only_beyond_the_scanned_wedge():
    """The arm turns on a followed frame: the corridor's followed matches inside the new wedge are kept and only
    its new part is scanned; the frame's candidates are those of a frame computed afresh (a few edge features apart)."""
    from dip3d_vehicle.perception.corridor import BEYOND_OVERLAP_PX
    from dip3d_vehicle.perception.reuse import inside_polygon
    core = _core(3)
    frame = _render()
    core.process_rectified(*frame)
    old_wedge = core.reuse._state.wedge
    core.corridor.detect = lambda *a, **k: pytest.fail("the whole wedge was scanned again")
    scanned = []
    beyond = core.corridor.detect_beyond
    core.corridor.detect_beyond = lambda *a, **k: scanned.append(beyond(*a, **k)) or scanned[-1]
    core.pose.provide(ARM_UP)
    result = core.process_rectified(*frame)
    assert core.reuse.counts["corridor_scans"] == 1 and result.candidates_followed
    new = scanned[0]
    assert len(new) > 0
    # nothing found deep inside the old wedge (it was scanned, its matches followed); the mask is applied
    # at the scan's scale (0.5 here: 2 px cells, keypoints rounded to them)
    deep = inside_polygon(new.left_px, old_wedge) & ~_near_edge(new.left_px, old_wedge, BEYOND_OVERLAP_PX + 6)
    assert not deep.any()
    reference = _core(0)
    reference.pose.provide(ARM_UP)
    fresh = reference.process_rectified(*frame)
    assert result.status == fresh.status
    assert abs(len(result.candidates) - len(fresh.candidates)) <= max(3, 0.05 * len(fresh.candidates))


def _near_edge(points: np.ndarray, poly: np.ndarray, dist_px: float) -> np.ndarray:
    """Return which points lie within ``dist_px`` of the polygon's boundary."""
    contour = np.asarray(poly, np.float32).reshape(-1, 1, 2)
    return np.array([abs(cv2.pointPolygonTest(contour, (float(x), float(y)), True)) <= dist_px for x, y in points], bool)


def _panning(core: Perception, px_per_frame: float, frames: int) -> list[bool]:
    """Decide a sequence whose camera pans ``px_per_frame`` (the scene moves left); return which frames were followed."""
    return [core.process_rectified(*_render(shift=(-px_per_frame * k, 0))).candidates_followed for k in range(frames)]


def test_a_pass_taken_frames_later_is_followed_from_where_the_scene_has_moved(monkeypatch):
    """A 22 px / frame pan: a pass taken 4 frames after its own frame (88 px away) is followed from the
    motion the followed pairs showed meanwhile; without that prediction the flow loses it (a fresh frame)."""
    core = _core(4)
    assert _panning(core, 22.0, 7) == [False] + [True] * 6
    assert core.reuse.counts["lost"] == 0 and core.reuse.counts["refreshed"] >= 2
    blind = _core(4)
    monkeypatch.setattr(blind.reuse, "_motion_since", lambda anchor: None)
    _panning(blind, 22.0, 7)
    assert blind.reuse.counts["lost"] >= 1


def test_scene_motion_predicts_a_point_from_its_followed_neighbours():
    """Two regions moved differently (parallax): a point moves as its nearest followed pairs did."""
    from dip3d_vehicle.perception.reuse import Anchor, SceneMotion

    rng = np.random.default_rng(0)
    near, far = rng.uniform(0, 100, (20, 2)), rng.uniform(400, 500, (20, 2))
    pts = np.vstack([near, far])
    anchor = Anchor(np.arange(40), pts, pts - [30.0, 0.0])
    shift = np.where(np.arange(40)[:, None] < 20, [12.0, 1.0], [4.0, 0.0])
    kept = np.arange(0, 40, 2)                       # half of them still followed, in another order
    motion = SceneMotion.between(anchor, kept[::-1], (pts + shift)[kept[::-1]], (pts - [30.0, 0.0] + shift)[kept[::-1]])
    left, right = motion.moved(np.array([[50.0, 50.0], [450.0, 450.0]]), np.array([[20.0, 50.0], [420.0, 450.0]]))
    np.testing.assert_allclose(left, [[62.0, 51.0], [454.0, 450.0]])
    np.testing.assert_allclose(right, [[32.0, 51.0], [424.0, 450.0]])
    assert SceneMotion.between(anchor, np.arange(3), pts[:3], pts[:3]) is None   # too few to tell

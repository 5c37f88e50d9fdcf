"""A given arm's joint disparities: the keypoints' own, measured again by matching image patches.

For a pose source that places each image's keypoints independently (a keypoints file, the simulator's
truth plus noise), ``match_arm`` matches each left joint's patch along its rectified row and combines
the match with the given disparity (``pose.match_disparity``). The matching itself, and the limb and
body checks it shares with BlazePose's ``joint_disparity: stereo``, are ``joint_stereo``'s.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .joint_stereo import (HEAD_PATCHES_M, head_match, head_stand_in, joint_disparities, limb_switches, matched_on_body,
                           on_background)
from .shoulder_model import head_torso_shoulder, mirrored_shoulder_px, side_log_odds, two_way
from .values import ArmKeypoints

__all__ = ["match_arm", "torso_shoulder", "MATCH_GROSS_SIGMAS", "SHOULDER_MATCH_SIGMA_M", "SHOULDER_SURFACE_M",
           "WRIST_HAND_SHARE", "OTHER_SHOULDER_SIGMA_M"]

SHOULDER_MATCH_SIGMA_M = 0.05
"""One-sigma depth error (metres) of a given arm's matched shoulder, once moved back by
``SHOULDER_SURFACE_M``. With the 0.06 m patch (``pose.match_disparity_patch_m``) the raw match lies
0.02-0.035 m in front of the joint (median per family, 2 px keypoint noise), p10-p90 within
-0.1 / +0.08 m of the joint (issue 11, session 23, ``docs/issue11/session23/scripts/raw_match.py``).
It was 0.1 m for the 0.12 m patch, which held the torso and the back behind the shoulder (0.12 m
behind the joint, median): kept, it let the given keypoints' noisy disparity outweigh the match at
close range (final shoulder error p90 2.7 px where the raw match's was under 1 px)."""

SHOULDER_SURFACE_M = 0.03
"""How far (metres) the shoulder's joint centre lies behind the surface its patch matches: the
deltoid's near side (the raw match lies 0.02-0.035 m in front of the joint, median, in every
generated family; 0.03-0.05 m in the mission scenarios, issue 11 session 22)."""

WRIST_HAND_SHARE = 0.08
"""How far beyond the wrist its patch matches, as a share of the shoulder-to-wrist disparity difference: the
patch holds the hand, which lies beyond the wrist along the arm (~0.045 m along a ~0.57 m arm), so the raw match
overstates the arm's tilt toward or away from the camera. Against the truth joints (open-set families, 2 px, seed
500, 160 draws each) the wrist's raw match error rose with the truth shoulder-to-wrist disparity difference by
0.04 / 0.08 / 0.07 px per px (``far`` / ``line_of_sight`` / ``elbow``; correlation 0.37 / 0.83 / 0.57). Moved back by
this share (from the shoulder's own match, else its given disparity) the raw wrist's |error| median / p90 went
0.44 / 0.79 -> 0.24 / 0.79, 0.37 / 0.98 -> 0.24 / 0.72 and 0.57 / 1.14 -> 0.35 / 0.89 px (issue 11, session 34,
``docs/issue11/session34/scripts/wrist_share.py``)."""

OTHER_SHOULDER_SIGMA_M = 0.05
"""Depth doubt (metres) added to the other shoulder's match when it votes on the torso's side (``head_torso``): on the
far side it hides behind the torso, and its patch shows the torso's flank."""

MATCH_GROSS_SIGMAS = 3.0
"""A joint's match further than this many combined sigmas from the given keypoints' disparity is a wrong
match (an elbow's patch locked on the torso behind it) and is dropped."""


def torso_shoulder(arm: ArmKeypoints, left: np.ndarray, right: np.ndarray, sign: int, focal_px: float,
                   baseline_m: float, principal_x_px: float, body_px: float, given_sigma_px: float,
                   head: tuple[float, float], own: tuple[float, float] | None) -> tuple[float, float]:
    """Return the pointing shoulder's disparity and sigma from the head and the torso's turn (pixels).

    ``shoulder_model.head_torso_shoulder`` gives it on either side of the torso from the head's own match
    (``head``: disparity, sigma, ``joint_stereo.head_match``); which side is weighed by the given disparity
    (``given_sigma_px``), the shoulder's own match (``own``, or None) and the other shoulder's match where
    the head mirrors the shoulder (0.12 m patch, ``OTHER_SHOULDER_SIGMA_M`` added): a two-way mixture by
    their likelihoods.
    """
    head_px = arm.extra_left_px["head"]
    landmark_px = given_sigma_px / math.sqrt(2.0)
    near, far = head_torso_shoulder(head, head_px, arm.left_px[0], focal_px, baseline_m, principal_x_px, landmark_px)
    log_far = side_log_odds((float(arm.left_px[0, 0] - arm.right_px[0, 0]), given_sigma_px), near, far)
    if own is not None:
        log_far += side_log_odds(own, near, far)
    other_px = mirrored_shoulder_px(head_px, arm.left_px[0])
    other = joint_disparities(left, right, other_px[None], body_px, sign, focal_px, baseline_m,
                              patch_m=HEAD_PATCHES_M[0])
    if other.matched[0]:
        o_near, o_far = head_torso_shoulder(head, head_px, other_px, focal_px, baseline_m, principal_x_px, landmark_px)
        doubt = other.disparity_px[0] ** 2 / (focal_px * baseline_m) * OTHER_SHOULDER_SIGMA_M
        log_far -= side_log_odds((float(other.disparity_px[0]), math.hypot(other.sigma_px[0], doubt)), o_near, o_far)
    return two_way(near, far, 1.0 / (1.0 + math.exp(-float(np.clip(log_far, -50.0, 50.0)))))


def match_arm(arm: ArmKeypoints, left: np.ndarray, right: np.ndarray, sign: int, focal_px: float,
              baseline_m: float, floor_px: float, given_sigma_px: float, patch_m: float = 0.06,
              principal_px: tuple[float, float] | None = None,
              limbs_m: tuple[tuple[float, float], tuple[float, float]] | None = None,
              shoulder_from: str = "patch") -> ArmKeypoints:
    """Return an arm with no disparity sigma of its own, each joint's disparity matched along its row (pixels).

    For a pose source that places each image's keypoints independently (a keypoints file, the
    simulator's truth plus noise): their left/right disagreement (2 px each: ~2.8 px of disparity,
    ~0.15 m of depth at 2.5 m) is what leaves the arm's tilt toward the camera uncertain. The
    left joint's patch is searched along the same rectified row of the right image, within the
    depths an arm reaches from the body (the keypoints' median disparity), as BlazePose's
    ``joint_disparity: stereo`` does (``joint_disparities``, patches ``patch_m`` wide at the body's
    depth; the head's is ``HEAD_PATCHES_M``). The match's sigma is its own, at least
    ``floor_px`` times ``JOINT_FLOOR_FACTOR`` (the patch shows the limb's near surface, a few
    centimetres before the joint's centre; the elbow's often holds the torso behind it), and for
    the shoulder at least ``SHOULDER_MATCH_SIGMA_M`` of depth (its patch matches the deltoid's
    surface: the match moves back by ``SHOULDER_SURFACE_M``). A shoulder whose flat patch does not
    match takes the given head's match instead (``head_stand_in``). The wrist's match holds the hand beyond it
    and moves back toward the shoulder's disparity by ``WRIST_HAND_SHARE`` of their difference (the shoulder's
    own match, else its given disparity). A wrist whose background beside the forearm matches at its disparity as
    well is set aside (``on_background``: its patch shows a placard behind or in front of it). An elbow / wrist matched
    on the body behind it is set aside (``matched_on_body``; the body's depth from the head, else
    the shoulder's match). A match
    within ``MATCH_GROSS_SIGMAS`` of the given disparity (sigma ``given_sigma_px``) is combined with
    it by inverse variance: the joint moves to the left joint's row at that disparity, with that
    sigma; a farther one, or none, leaves the joint as given. Given the principal point and the
    limbs' plausible lengths (``limbs_m``: upper arm, forearm, metres), matches that make a limb
    impossible are dropped, or a match the gross check set aside is taken after all, whichever of the
    fewest makes every limb plausible (``limb_switches``: a wrist matched on the object behind it; a given
    wrist 8 px off its right match). The limbs are judged on the matches themselves, not on their
    combination with the given disparities (with noisy keypoints, 4 px, the combination pulls a right
    match off).
    With ``shoulder_from`` "head_torso" (and the principal point) the shoulder is ``torso_shoulder``'s wherever
    the head matched (its own match only votes on the torso's side); "patch" (the default) is the above.
    The arm is returned unchanged when its keypoints give no positive disparity.
    """
    disparity = arm.left_px[:, 0] - arm.right_px[:, 0]
    body = float(np.median(disparity))
    if not math.isfinite(body) or sign * body <= 0.5:
        return arm
    found = joint_disparities(left, right, arm.left_px, body, sign, focal_px, baseline_m, patch_m=patch_m)
    found = on_background(found, left, right, arm.left_px, body, sign, focal_px, baseline_m, patch_m)
    match_sigma = found.floored_sigma_px(floor_px)
    fb = focal_px * baseline_m
    if found.matched[2]:   # the hand beyond the wrist, along the arm
        shoulder = found.disparity_px[0] if found.matched[0] else disparity[0]
        found.disparity_px[2] -= WRIST_HAND_SHARE * (found.disparity_px[2] - shoulder)
    if found.matched[0]:   # the deltoid's surface: the joint lies behind it
        found.disparity_px[0] = sign * fb / (fb / abs(found.disparity_px[0]) + SHOULDER_SURFACE_M)
    match_sigma[0] = max(match_sigma[0], found.disparity_px[0] ** 2 / fb * SHOULDER_MATCH_SIGMA_M)
    matched = found.matched.copy()
    head_own = head_match((arm.extra_left_px or {}).get("head"), left, right, body, sign, focal_px, baseline_m)
    if shoulder_from == "head_torso" and principal_px is not None and head_own is not None:
        own = (float(found.disparity_px[0]), float(match_sigma[0])) if matched[0] else None
        (found.disparity_px[0], match_sigma[0]), matched[0] = torso_shoulder(
            arm, left, right, sign, focal_px, baseline_m, principal_px[0], body, given_sigma_px, head_own, own), True
    head = None if head_own is None else head_stand_in(head_own, focal_px, baseline_m)
    if head is not None and not matched[0]:
        found.disparity_px[0], match_sigma[0], matched[0] = head[0], head[1], True
    body_ref = head[0] if head is not None else (found.disparity_px[0] if matched[0] else body)
    matched &= ~matched_on_body(arm.left_px, found.disparity_px, matched, body_ref, focal_px, baseline_m)
    given = max(float(given_sigma_px), 1e-3)
    m = matched & (np.abs(found.disparity_px - disparity) <= MATCH_GROSS_SIGMAS * np.hypot(match_sigma, given))
    w_match, w_given = 1.0 / match_sigma ** 2, 1.0 / given ** 2
    combined = (w_match * found.disparity_px + w_given * disparity) / (w_match + w_given)
    final_sigma = 1.0 / np.sqrt(w_match + w_given)
    if principal_px is not None and limbs_m is not None and np.any(matched):
        flip = limb_switches(arm.left_px, np.where(m, found.disparity_px, disparity), np.where(m, match_sigma, given),
                             np.where(m, disparity, found.disparity_px), np.where(m, given, match_sigma), matched, m,
                             focal_px, baseline_m, principal_px, limbs_m)
        restored = flip & ~m      # a match the gross check set aside: its own disparity, not pulled by the given
        combined[restored], final_sigma[restored] = found.disparity_px[restored], match_sigma[restored]
        m = m ^ flip
    if not np.any(m):
        return arm
    right_px = np.array(arm.right_px, dtype=float, copy=True)
    right_px[m, 0] = arm.left_px[m, 0] - combined[m]
    right_px[m, 1] = arm.left_px[m, 1]
    sigma = np.where(m, final_sigma, np.nan)
    return dataclasses.replace(arm, right_px=right_px, disparity_sigma_px=sigma, disparity_matched=m.copy())

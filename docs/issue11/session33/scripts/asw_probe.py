"""Raw joint matches vs truth (px): the project's NCC patch match vs an adaptive-support (colour-weighted) NCC."""
import math, os, sys, tempfile
import numpy as np
import cv2
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import draws as dr
from dip3d_vehicle.perception import joint_stereo as JS

GC = float(os.environ.get("GC", "12")); GP = float(os.environ.get("GP", "0.5"))

def asw_match(left, right, x, y, d_lo, d_hi, sign, half):
    h, w = left.shape[:2]
    if not (half <= y < h - half and half <= x < w - half):
        return None
    Tc = left[y-half:y+half+1, x-half:x+half+1].astype(np.float32)
    lab = cv2.cvtColor(left[y-half:y+half+1, x-half:x+half+1], cv2.COLOR_BGR2LAB).astype(np.float32) if Tc.ndim == 3 else Tc[..., None]
    c0 = lab[half, half]
    dc = np.linalg.norm(lab - c0, axis=-1)
    yy, xx = np.mgrid[-half:half+1, -half:half+1]
    W = np.exp(-dc / GC - np.hypot(yy, xx) / (GP * (2 * half + 1)))
    T = JS._grey(left[y-half:y+half+1, x-half:x+half+1]).astype(np.float32)
    xa, xb = sorted((x - sign * int(math.ceil(d_hi)) - 1, x - sign * int(math.floor(d_lo)) + 1))
    xa, xb = max(xa, half), min(xb + 1, w - half)
    if xb - xa < 3:
        return None
    strip = JS._grey(right[y-half:y+half+1, xa-half:xb+half]).astype(np.float32)
    win = np.lib.stride_tricks.sliding_window_view(strip, (2*half+1, 2*half+1))[0]  # (L, H, W)
    sw = W.sum()
    mT = (W * T).sum() / sw
    Td = T - mT
    mP = (win * W).sum((1, 2)) / sw
    Pd = win - mP[:, None, None]
    num = (W * Td * Pd).sum((1, 2))
    den = np.sqrt((W * Td**2).sum() * (W * Pd**2).sum((1, 2))) + 1e-6
    s = num / den
    k = int(np.argmax(s))
    if k in (0, len(s) - 1) or s[k] < 0.6:
        return None
    xr = xa + JS.subpixel_peak(s, k)
    return float(sign * (x - xr))

fam, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
E = {"ncc": [], "asw": []}
with tempfile.TemporaryDirectory() as tmp:
    for rig, left, right, raw, body, dt in dr.given_arms(tmp, fam, n, seed0, sigma):
        fb = rig.focal_px * rig.baseline_m
        found = JS.joint_disparities(left, right, raw.left_px, body, rig.disparity_sign, rig.focal_px, rig.baseline_m, patch_m=0.06)
        d_lo, d_hi = JS.reach_disparities(body, fb)
        half = JS.patch_half_px(body, rig.baseline_m, float(os.environ.get("PATCH", "0.06")))
        a = np.full(3, np.nan)
        for j in range(3):
            m = asw_match(left, right, int(round(raw.left_px[j, 0])), int(round(raw.left_px[j, 1])), d_lo, d_hi, rig.disparity_sign, half)
            if m is not None:
                a[j] = rig.disparity_sign * m
        E["ncc"].append(np.where(found.matched, found.disparity_px - dt, np.nan))
        E["asw"].append(a - dt)
for key, v in E.items():
    v = np.array(v)
    ab = np.abs(v)
    print(f"{fam} {seed0} {key} GC {GC} GP {GP} matched {np.isfinite(v).sum(0).tolist()}/{len(v)} signed median {np.round(np.nanmedian(v,0),2).tolist()} |err| median {np.round(np.nanmedian(ab,0),2).tolist()} p90 {np.round(np.nanpercentile(ab,90,0),2).tolist()}")

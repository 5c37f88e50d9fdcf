"""Per frame of one mission, a given arm's joint depths: truth, the keypoints' own (given) and after match_arm (m):
    python docs/issue11/session65/scripts/wrist_trace.py SCENARIO SEED T0 T1"""
import os, runpy, sys
import numpy as np
import dip3d_vehicle.perception.pipeline as pipeline
import dip3d_vehicle.perception.joint_stereo as js
import sitl.render as render

T0, T1 = float(sys.argv[3]), float(sys.argv[4])
NOW = {"t": 0.0, "truth": None}
orig_render = render.StereoRenderer.render

def traced_render(self, n, e, d, yaw, t_s):
    frame = orig_render(self, n, e, d, yaw, t_s)
    NOW["t"], NOW["truth"] = t_s, frame.meta.get("joints_cam_m")
    return frame

render.StereoRenderer.render = traced_render
orig_match, orig_bg = pipeline.match_arm, js.on_background
BG = {"set_aside": False}

def traced_bg(found, *a, **k):
    out = orig_bg(found, *a, **k)
    BG["set_aside"] = out is not found
    return out

import dip3d_vehicle.perception.given_arm as given_arm
given_arm.on_background = traced_bg

def traced_match(arm, left, right, sign, focal_px, baseline_m, *a, **k):
    BG["set_aside"] = False
    out = orig_match(arm, left, right, sign, focal_px, baseline_m, *a, **k)
    if T0 <= NOW["t"] <= T1 and NOW["truth"] is not None:
        fb = focal_px * baseline_m
        z = lambda d: fb / np.maximum(np.abs(d), 1e-6)
        truth = [NOW["truth"][j][2] for j in ("shoulder", "elbow", "wrist")]
        given = z(arm.left_px[:, 0] - arm.right_px[:, 0])
        final = z(out.left_px[:, 0] - out.right_px[:, 0])
        m = out.disparity_matched if out.disparity_matched is not None else [False] * 3
        sig = out.disparity_sigma_px if out.disparity_sigma_px is not None else [np.nan] * 3
        print(f"t={NOW['t']:.2f} truth z {np.round(truth, 2)} given {np.round(given, 2)} final {np.round(final, 2)} "
              f"matched {list(map(bool, m))} sigma_px {np.round(sig, 2)} wrist_bg_set_aside {BG['set_aside']}")
    return out

pipeline.match_arm = traced_match
sys.argv = ["story", sys.argv[1], sys.argv[2]]
runpy.run_path(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "session58", "scripts", "story.py"),
               run_name="__main__")

"""The scene loop shared by shoulder_offset.py and wrist_offset.py: each family scene at 0 px with its raw joint match."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402
from dip3d_vehicle.perception.joint_stereo import joint_disparities  # noqa: E402


def raw_scenes(families, n, seed0):
    """Yield (family, k, meta, rig, truth disparities px, raw 0.06 m patch match) per scene, truth keypoints."""
    with tempfile.TemporaryDirectory() as tmp:
        for family in families:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
                td = arm.left_px[:, 0] - arm.right_px[:, 0]
                raw = joint_disparities(left, right, arm.left_px, float(np.median(td)), rig.disparity_sign,
                                        rig.focal_px, rig.baseline_m, patch_m=0.06)
                yield family, k, scene.frame.meta, rig, arm, td, raw

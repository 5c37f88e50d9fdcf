import sys, tempfile
from pathlib import Path
sys.path.insert(0, "tests/perception")
import test_synthetic_accuracy as t
import dip3d_vehicle.config as cfg
ov = tuple(sys.argv[2:])
orig = cfg.load_params
t.load_params = lambda profile, overrides=(): orig(profile, overrides=tuple(overrides) + ov)
with tempfile.TemporaryDirectory() as tmp:
    per_scene = list(t.scene_counts(Path(tmp), int(sys.argv[1]), True, draws=8, seed0=1000))
    print("1-3 m, scenes (seed0 1000)", ov)
    print(t.table(t.total(per_scene)))

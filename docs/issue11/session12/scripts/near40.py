"""The earlier 1-3 m table (40 scenes, seed0 1000, 8 draws) with KEY=VALUE overrides for both profiles."""
import sys, tempfile
from pathlib import Path
sys.path.insert(0, "tests/perception")
import test_synthetic_accuracy as t
ov = tuple(sys.argv[2:])
with tempfile.TemporaryDirectory() as tmp:
    per_scene = list(t.scene_counts(Path(tmp), int(sys.argv[1]), True, draws=8, seed0=1000, overrides=ov))
    print("1-3 m, scenes (seed0 1000)", ov)
    print(t.table(t.total(per_scene)))

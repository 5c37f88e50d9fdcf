"""How far a link-cut mission turned and travelled from the cut to the re-enable, and whether the pointed placard
was in the left camera at the re-enable; one line per seed:
    python docs/issue11/session62/scripts/cut_turn.py PLAN SEED [SEED ...]   (PYTHONPATH=TREE; paper_pool)"""
import math
import sys
from pathlib import Path

from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session61" / "scripts"))
from reenable_view import view_at  # noqa: E402  (session 61's: the target in the left camera)

plan = sys.argv[1]
for seed in [int(a) for a in sys.argv[2:]]:
    result, sim = run_faulted_mission("paper_pool", seed, plan, load_params())
    ev = next(e for e in sim.fault_events.applied if e["kind"] == "link_cut")
    rows = [r for r in sim.trajectory if ev["onset_s"] <= r[0] <= ev["recover_from_s"]]
    turned = sum(math.atan2(math.sin(b[4] - a[4]), math.cos(b[4] - a[4])) for a, b in zip(rows, rows[1:]))
    moved = math.hypot(rows[-1][1] - rows[0][1], rows[-1][2] - rows[0][2])
    view = "OUT of view" if "OUT" in view_at(sim, result.target_id, ev["recover_from_s"]) else "in view"
    print(f"seed {seed} {result.outcome}: cut {ev['onset_s']:.1f}-{ev['clear_s']:.1f} s, re-enable "
          f"{ev['recover_from_s']:.1f} s; turned {math.degrees(turned):+.0f} deg, moved {moved:.2f} m; target at the "
          f"re-enable {view}", flush=True)

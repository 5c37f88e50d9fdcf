"""Arrived runs that went back from arrive to servo, and how often, over a campaign folder's run rows.

    python docs/issue11/session56/scripts/flaps.py DIR [DIR ...]
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session45" / "scripts"))
from compare_missions import run_lines  # noqa: E402  (session 45's reader of the run lines)

for top in sys.argv[1:]:
    arrived = [row for row in run_lines(Path(top)).values() if row.get("arrived")]
    backs = [sum(1 for a, b in zip(s, s[1:]) if (a, b) == ("arrive", "servo")) for s in (r["states"] for r in arrived)]
    print(f"{top}: {sum(b > 0 for b in backs)} of {len(arrived)} arrived runs went back from arrive to servo "
          f"({sum(backs)} times)")

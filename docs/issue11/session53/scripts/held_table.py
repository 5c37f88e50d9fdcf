"""Session 52's safety table (outcomes, how near another placard and the diver) with, per file, how many arrivals
held short of the stand-off and by how much (``held_short_m``: the way found no clear way to the stand-off).

    python docs/issue11/session53/scripts/held_table.py DIR [BEFORE_DIR]
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session52" / "scripts"))
from safety_table import main  # noqa: E402


def held(rs) -> str:
    """Return 'N (max M m)' for the arrivals held short, '0' for none."""
    h = [r["held_short_m"] for r in rs if r["outcome"] == "arrived" and (r.get("held_short_m") or 0) > 0]
    return f"{len(h)} (max {max(h):.1f} m)" if h else "0"


if __name__ == "__main__":
    main(held, "arrivals held short")

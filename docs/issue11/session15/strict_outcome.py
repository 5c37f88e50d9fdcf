"""The open-set scene families scored with a pick flagged ambiguous counted as abstained, even inside the placard.

Usage (from the repository root): PYTHONPATH=. python docs/issue11/session15/strict_outcome.py SCENES SEED [KEY=VALUE ...]
(the arguments of ``tests/perception/test_synthetic_accuracy.py ... families``). The team's scorer
(``scene_families.outcome``) counts any pick inside the pointed placard as correct, flagged ambiguous
or not; the issue lists "ambiguous" among the abstentions. This prints the same tables with that reading.
"""
import runpy
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "tests" / "perception"))
sys.path.insert(0, str(ROOT))

import scene_families  # noqa: E402

_outcome = scene_families.outcome


def strict_outcome(scene, result, rig) -> str:
    """The team's outcome, except that an ambiguous pick is an abstention."""
    sel = result.selection
    if result.status == "ok" and sel is not None and sel.target is not None and sel.ambiguous:
        return "abstained"
    return _outcome(scene, result, rig)


if __name__ == "__main__":
    scene_families.outcome = strict_outcome
    sys.argv = [str(ROOT / "tests/perception/test_synthetic_accuracy.py"), sys.argv[1], "families", *sys.argv[2:]]
    runpy.run_path(sys.argv[0], run_name="__main__")

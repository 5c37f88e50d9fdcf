"""default only, given noise levels, with KEY=VALUE overrides: detectable / undetectable / confidently wrong.

    python docs/issue11/session33/scripts/fam.py N SEED0 NOISE[,NOISE...] [KEY=VALUE ...]

``tally_default`` and ``summary`` are also what ``grid_fam.py`` and ``oracle_depth.py`` run and print;
``record_truth`` and ``truth_joints_px`` are the oracles' view of each draw's truth.
"""
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402


def tally_default(n: int, seed0: int, noise: tuple, over=()) -> "sf.Tally":
    """Return the five families' tally for ``default`` alone: ``n`` scenes each, 8 draws per noise level (pixels)."""
    tally = sf.Tally()
    with tempfile.TemporaryDirectory() as tmp:
        for family in sf.FAMILIES:
            sf.tally_family(Path(tmp), family, n, 8, seed0, noise_px=noise, profiles=("default",), tally=tally,
                            overrides=over)
    return tally


def record_truth(state: dict) -> None:
    """Wrap ``scene_families.noisy`` so that ``state["truth"]`` holds each draw's truth keypoints (original px)."""
    drawn = sf.noisy

    def noisy(keypoints, sigma_px, rng):
        state["truth"] = keypoints
        return drawn(keypoints, sigma_px, rng)
    sf.noisy = noisy


def truth_joints_px(rig, truth: dict, side: str):
    """Return the truth shoulder, elbow and wrist in ``side``'s rectified image, (3, 2) pixels."""
    import numpy as np
    return rig.to_rectified(np.array([truth[side][n] for n in ("shoulder", "elbow", "wrist")], float), side)


def summary(tally: "sf.Tally", label: str, noise: tuple) -> str:
    """Return one line per noise level (detectable / undetectable / confidently wrong), then the per-family table."""
    lines = []
    for s in noise:
        det = tally.merged("default", s, ("line_of_sight", "far", "elbow", "far_diver"))
        und = tally.merged("default", s, ("undetectable",))
        allc = tally.merged("default", s)
        lines.append(f"{label} noise {s}: detectable {det} correct {sf.rate(det, 'correct'):.1%}; undetectable "
                     f"{sf.rate(und, 'correct'):.1%} {und}; conf wrong {sf.rate(allc, 'confident_wrong'):.2%}")
    return "\n".join(lines) + "\n" + sf.report(tally, noise_px=noise)


if __name__ == "__main__":
    n, seed0 = int(sys.argv[1]), int(sys.argv[2])
    noise = tuple(float(x) for x in sys.argv[3].split(","))
    over = sys.argv[4:]
    print(summary(tally_default(n, seed0, noise, over), f"{seed0} {' '.join(over)}", noise))

"""Scenario files nobody tuned on: random layouts for a generalization check of the whole mission.

    python -m sitl.variants --count 20 --seed 7 --out DIR [--water clear,murky] [--min-apart-deg 15]
                            [--small-share 0.5]

Each file (``DIR/variant_SEED_NN.yaml``) starts from a built-in (``paper_pool`` for clear water,
``murky``) and replaces the layout: 3-5 placards (0.25-0.35 m, 1.0-4.0 m from the camera, 0.7-1.4 m
deep) on one side of the image and the diver (1.8-3.5 m, pointing with the arm on the placards'
side: the right arm when the diver stands on the left, the left arm when on the right) on the
other. Layouts are drawn until every two placards are at least ``--min-apart-deg`` apart as seen
from the diver's chest (a scene the arm can decide: the diver's pointing error is 5 deg) and, seen
from the camera, neither hides the other (their centres farther apart than their half-diagonals plus
``CAMERA_GAP_DEG``), all of them inside the camera's view. The target is the scenario's ``random``:
each mission seed picks one.

``--small-share F``: in that share of the layouts (drawn by a generator of its own, so the other
layouts stay those of ``--seed``) the diver points at a placard of ``SMALL_SIZE_M`` (4 cm, as in the
built-in ``nothing_there``) placed ``SMALL_RANGE_M`` from the camera under the same rules, beside 2-4
ordinary ones: too small to be detected from the start, so the right answer is "nothing there" (or
that placard, if it is found); a mission that drives to another placard is confidently wrong.

Run a file like a built-in: ``python -m sitl.point_campaign mission --scenario DIR/variant_7_00.yaml
--seeds 0-2``. The layouts depend only on ``--seed`` (numpy's generator), so a study can be re-made.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["Layout", "draw_layout", "layout_yaml", "write_variants", "main"]

BASES = {"clear": "paper_pool", "murky": "murky"}
"""The built-in each water kind starts from (camera, water, pose source)."""

DIVER_DEPTH_M = 1.0
"""Depth of the diver's chest, metres."""

CAMERA_DEPTH_M = 1.0
"""Depth of the camera at the start, metres (both built-in bases start the vehicle at 1.0 m)."""

MAX_BEARING_DEG = 32.0
"""Largest bearing of anything placed, degrees (the camera's half view is 41 deg; the vehicle yaws a little)."""

CAMERA_GAP_DEG = 3.0
"""Smallest gap between two placards seen from the camera, beyond their half-diagonals, degrees."""

SMALL_SIZE_M = 0.04
"""Side of the pointed placard of a ``--small-share`` layout, metres (``nothing_there``'s)."""

SMALL_RANGE_M = (1.8, 4.0)
"""Range from the camera of that placard, metres (17-37 px wide from the start: not detected)."""


@dataclass(frozen=True)
class Layout:
    """One drawn layout (metres and degrees, range and bearing from the camera)."""

    placards: list[tuple[float, float, float, float]]   # (range_m, bearing_deg, depth_m, size_m) each
    diver: tuple[float, float]                          # (range_m, bearing_deg)
    arm: str
    water: str
    target: int | None = None                           # placard id (1-based), None = each seed picks


def _xyz(range_m: float, bearing_deg: float, depth_m: float) -> np.ndarray:
    """Return a point (forward, right, down) in metres from its range, bearing and depth."""
    b = math.radians(bearing_deg)
    return np.array([range_m * math.cos(b), range_m * math.sin(b), depth_m])


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Return the angle between two vectors, degrees."""
    c = float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def _apart(points: list[np.ndarray], seen_from: np.ndarray, min_deg: float,
           radii_m: list[float] | None = None) -> bool:
    """True when every two points are at least ``min_deg`` apart as seen from ``seen_from`` (degrees).

    ``radii_m``: each point's half-size (metres); the angle they subtend there is added to ``min_deg``.
    """
    rays = [p - seen_from for p in points]
    reach = [0.0] * len(rays) if radii_m is None else [
        math.degrees(math.atan2(r, float(np.linalg.norm(ray)))) for r, ray in zip(radii_m, rays)]
    return all(_angle_deg(rays[i], rays[j]) >= min_deg + reach[i] + reach[j]
               for i in range(len(rays)) for j in range(i))


def draw_layout(rng: np.random.Generator, water: str, min_apart_deg: float, tries: int = 2000,
                small_target: bool = False) -> Layout:
    """Return one layout drawn until it meets the separation rules (RuntimeError after ``tries`` draws).

    ``small_target``: the last placard is the pointed one, ``SMALL_SIZE_M`` wide (see the module doc).
    """
    for _ in range(tries):
        side = 1.0 if rng.random() < 0.5 else -1.0          # +1: placards on the right, diver on the left
        diver = (float(rng.uniform(1.8, 3.5)), float(-side * rng.uniform(8.0, 24.0)))
        count = int(rng.integers(2, 5) if small_target else rng.integers(3, 6))
        placards = [(float(rng.uniform(1.0, 4.0)), float(side * rng.uniform(4.0, MAX_BEARING_DEG)),
                     float(rng.uniform(0.7, 1.4)), float(rng.uniform(0.25, 0.35))) for _ in range(count)]
        if small_target:
            placards.append((float(rng.uniform(*SMALL_RANGE_M)), float(side * rng.uniform(4.0, MAX_BEARING_DEG)),
                             float(rng.uniform(0.7, 1.4)), SMALL_SIZE_M))
        points = [_xyz(r, b, d) for r, b, d, _ in placards]
        chest = _xyz(diver[0], diver[1], DIVER_DEPTH_M)
        half_diagonals = [size / math.sqrt(2.0) for *_, size in placards]
        if _apart(points, chest, min_apart_deg) and _apart(points, np.array([0.0, 0.0, CAMERA_DEPTH_M]), CAMERA_GAP_DEG, half_diagonals):
            return Layout(placards=placards, diver=diver, arm="right" if side > 0 else "left", water=water,
                          target=len(placards) if small_target else None)
    raise RuntimeError(f"no layout met the rules in {tries} draws (min apart {min_apart_deg} deg)")


def layout_yaml(layout: Layout, name: str) -> str:
    """Return the scenario file's text for a layout."""
    r, b = layout.diver
    small = "" if layout.target is None else f", the pointed placard {SMALL_SIZE_M * 100:.0f} cm (nothing there)"
    lines = [f"# {name}: drawn by sitl.variants (a layout nobody tuned on)",
             f"base: {BASES[layout.water]}",
             f'description: "{name}: {len(layout.placards)} placards, diver at {r:.1f} m, '
             f'{layout.arm} arm, {layout.water} water{small}"',
             "placards:"]
    for i, (pr, pb, pd, size) in enumerate(layout.placards, start=1):
        lines.append(f"  - {{id: {i}, range_m: {pr:.2f}, bearing_deg: {pb:.1f}, depth_m: {pd:.2f}, size_m: {size:.2f}}}")
    lines += ["diver:", "  positions:", f'    - {{name: "v", range_m: {r:.2f}, bearing_deg: {b:.1f}, '
              f"depth_m: {DIVER_DEPTH_M}}}", f"  arm: {layout.arm}",
              f"  target: {'random' if layout.target is None else layout.target}", ""]
    return "\n".join(lines)


def write_variants(out: Path, count: int, seed: int, waters: list[str], min_apart_deg: float,
                   small_share: float = 0.0) -> list[Path]:
    """Write ``count`` scenario files into ``out``; return their paths.

    ``small_share``: the share of layouts whose pointed placard is too small to detect (module doc).
    """
    rng = np.random.default_rng(seed)
    small = np.random.default_rng([seed, 1]).random(count) < small_share
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(count):
        name = f"variant_{seed}_{k:02d}"
        layout = draw_layout(rng, waters[k % len(waters)], min_apart_deg, small_target=bool(small[k]))
        path = out / f"{name}.yaml"
        path.write_text(layout_yaml(layout, name))
        paths.append(path)
    return paths


def main(argv: list[str] | None = None) -> int:
    """Write the scenario files and print their paths."""
    ap = argparse.ArgumentParser(prog="python -m sitl.variants", description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=20, help="files to write (default 20)")
    ap.add_argument("--seed", type=int, default=0, help="the layouts' random seed (default 0)")
    ap.add_argument("--out", required=True, metavar="DIR", help="folder to write them into")
    ap.add_argument("--water", default="clear,murky", help="water kinds, used in turn (clear, murky)")
    ap.add_argument("--min-apart-deg", type=float, default=15.0,
                    help="smallest angle between two placards seen from the diver (default 15)")
    ap.add_argument("--small-share", type=float, default=0.0, metavar="F",
                    help="share of layouts whose pointed placard is 4 cm, too small to detect: the right "
                         "answer is 'nothing there' (default 0)")
    args = ap.parse_args(argv)
    waters = [w.strip() for w in args.water.split(",") if w.strip()]
    bad = [w for w in waters if w not in BASES]
    if bad or not waters:
        ap.error(f"--water {args.water!r}: expected a list of {', '.join(BASES)}")
    if args.count < 1 or args.seed < 0 or not 0.0 <= args.min_apart_deg < 90.0 or not 0.0 <= args.small_share <= 1.0:
        ap.error("--count must be >= 1, --seed >= 0, --min-apart-deg in [0, 90) and --small-share in [0, 1]")
    for path in write_variants(Path(args.out), args.count, args.seed, waters, args.min_apart_deg, args.small_share):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The paper's metrics on an annotated dataset: hit rate, pixel error when correct, Table I.

For each annotated pair the perception core's chosen target (its left-image point, original px)
is assigned to an annotated object: the object whose polygon contains it, else the object whose
annotated point is nearest. The frame is *correct* when that object is the intended one; its
*pixel error* is the distance between the chosen point and the intended object's annotated point
(the paper's 119.95 +- 43.05 px is the mean +- std of this over the correct frames; std here is
the population std, numpy's default). A frame without a selection is a miss, counted by its
status (``no_pose``, ``pose_rejected``, ``no_candidates``, ``nothing_on_ray``, ...); a selection
on the wrong object is a miss counted as ``wrong_object``, or ``wrong_object_ambiguous`` when the
selector flagged it ambiguous (the mission does not act on such a frame).

``format_table`` prints the paper's Table I layout: one row per diver position, one column per
intended target, each cell ``mean +- std px (correct/frames)``, with totals.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Iterable, Mapping, Sequence

import cv2
import numpy as np

from .dataset import Dataset, FrameAnnotation

__all__ = [
    "decision_class", "CONFIDENT", "FrameOutcome", "Report", "assign_object", "frame_outcome", "evaluate_dataset", "format_table",
    "format_summary", "mean_std", "Progress", "pose_backend_for",
]

NO_POSITION = "-"
CONFIDENT = 0.8
"""Confidence at or above which a wrong pick that is not flagged ambiguous is confidently wrong."""


def decision_class(result: Mapping[str, Any], correct: bool) -> str:
    """Return how a frame's decision went: correct, nothing_on_ray, abstained, wrong_confident, wrong_unsure.

    ``result`` is the contract JSON; ``correct``: the chosen point lies on the intended object.
    Abstentions (no pose, rejected pose, no candidates, flagged ambiguous) are kept apart from
    wrong picks, and "nothing detected along the ray" apart from both.
    """
    if correct:
        return "correct"
    status = result.get("status")
    if status == "nothing_on_ray":
        return "nothing_on_ray"
    sel = result.get("selection") or {}
    if status != "ok" or result.get("target") is None or sel.get("ambiguous"):
        return "abstained"
    confidence = sel.get("confidence")
    return "wrong_confident" if confidence is not None and confidence >= CONFIDENT else "wrong_unsure"



@dataclass(frozen=True)
class FrameOutcome:
    """How one annotated pair went.

    Attributes:
        index: the pair's annotation index.
        target: intended object id.
        diver_position: label ("-" when the annotation has none).
        status: the perception status ("ok", "no_pose", ...).
        chosen: object id the selection was assigned to, or None without a selection.
        correct: chosen == target.
        selected_px: the chosen target's left-image point (original px) or None.
        error_px: distance from selected_px to the intended object's point, or None.
        target_range_m, diver_range_m: from the annotation when given.
    """

    index: int
    target: str
    diver_position: str
    status: str
    chosen: str | None
    correct: bool
    selected_px: tuple[float, float] | None
    error_px: float | None
    target_range_m: float | None = None
    diver_range_m: float | None = None
    ambiguous: bool = False

    @property
    def miss_reason(self) -> str | None:
        """None for a correct frame, else "wrong_object" (or "wrong_object_ambiguous") or the status."""
        if self.correct:
            return None
        if self.chosen is None:
            return self.status
        return "wrong_object_ambiguous" if self.ambiguous else "wrong_object"


def assign_object(point_px: Sequence[float], ann: FrameAnnotation) -> str:
    """Return the annotated object a chosen point belongs to (polygon first, else nearest point)."""
    x, y = float(point_px[0]), float(point_px[1])
    inside = [oid for oid, poly in ann.polygons.items()
              if cv2.pointPolygonTest(poly.astype(np.float32).reshape(-1, 1, 2), (x, y), False) >= 0]
    pool = inside or list(ann.objects)
    return min(pool, key=lambda oid: math.hypot(ann.objects[oid][0] - x, ann.objects[oid][1] - y))


def frame_outcome(ann: FrameAnnotation, result: Mapping[str, Any]) -> FrameOutcome:
    """Score one perception result (the contract JSON of ``PerceptionResult.to_json``)."""
    target = result.get("target")
    px = None if not target else target.get("left_px")
    if px is None or any(v is None for v in px):
        chosen, selected, error = None, None, None
    else:
        selected = (float(px[0]), float(px[1]))
        chosen = assign_object(selected, ann)
        tx, ty = ann.target_px
        error = math.hypot(selected[0] - tx, selected[1] - ty)
    sel = result.get("selection") or {}
    return FrameOutcome(ann.index, ann.target, ann.diver_position or NO_POSITION, str(result.get("status")),
                        chosen, chosen == ann.target, selected, error, ann.range_m.get(ann.target),
                        ann.diver_range_m, bool(sel.get("ambiguous", False)))


def mean_std(values: Iterable[float]) -> tuple[float, float, int]:
    """Return (mean, population std, n); NaNs when empty."""
    arr = np.asarray(list(values), dtype=float)
    if arr.size == 0:
        return math.nan, math.nan, 0
    return float(arr.mean()), float(arr.std()), int(arr.size)


@dataclass
class Report:
    """All frame outcomes of one parameter profile on one dataset."""

    profile: str
    outcomes: list[FrameOutcome] = field(default_factory=list)
    labels: dict[str, str] = field(default_factory=dict)

    # -- aggregates ------------------------------------------------------------------------
    def positions(self) -> list[str]:
        return sorted({o.diver_position for o in self.outcomes}, key=_natural)

    def targets(self) -> list[str]:
        return sorted({o.target for o in self.outcomes}, key=_natural)

    def cell(self, position: str | None = None, target: str | None = None) -> dict[str, Any]:
        """Return the metrics of the frames of one diver position and target (None = all)."""
        sel = [o for o in self.outcomes if (position is None or o.diver_position == position)
               and (target is None or o.target == target)]
        mean, std, n_ok = mean_std(o.error_px for o in sel if o.correct)
        return {"frames": len(sel), "correct": n_ok, "hit_rate": n_ok / len(sel) if sel else math.nan,
                "error_px_mean": mean, "error_px_std": std}

    def summary(self) -> dict[str, Any]:
        """Return overall metrics: hit rate, error mean/std when correct, misses by reason."""
        out = self.cell()
        out["misses"] = dict(sorted(Counter(o.miss_reason for o in self.outcomes if not o.correct).items()))
        chosen = [o for o in self.outcomes if o.chosen is not None]
        out["selected"] = len(chosen)
        out["precision"] = out["correct"] / len(chosen) if chosen else math.nan
        return out

    def chosen_frequency(self) -> dict[tuple[str, str], dict[str, float]]:
        """Return {(position, target): {chosen id or "none": relative frequency}} (Fig. 6)."""
        out: dict[tuple[str, str], dict[str, float]] = {}
        for p in self.positions():
            for t in self.targets():
                sel = [o for o in self.outcomes if o.diver_position == p and o.target == t]
                if sel:
                    counts = Counter(o.chosen if o.chosen is not None else "none" for o in sel)
                    out[(p, t)] = {k: v / len(sel) for k, v in counts.items()}
        return out

    def to_json(self) -> dict[str, Any]:
        """Return the report as plain JSON (NaN -> None)."""
        table = {p: {t: _clean(self.cell(p, t)) for t in self.targets()} for p in self.positions()}
        return {"profile": self.profile, "summary": _clean(self.summary()), "table": table,
                "frames": [_clean(asdict(o)) for o in self.outcomes]}


def _clean(value: Any) -> Any:
    if isinstance(value, float):
        return round(value, 4) if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def _natural(text: str) -> tuple:
    """Sort key: numbers numerically, then text."""
    try:
        return (0, float(text), text)
    except ValueError:
        return (1, 0.0, text)


# -- text tables -----------------------------------------------------------------------------
def _cell_text(cell: Mapping[str, Any]) -> str:
    if cell["frames"] == 0:
        return ""
    if cell["correct"] == 0:
        return f"- ({cell['correct']}/{cell['frames']})"
    return f"{cell['error_px_mean']:.1f} +- {cell['error_px_std']:.1f} ({cell['correct']}/{cell['frames']})"


def format_table(report: Report) -> str:
    """Return the Table I layout: rows diver position, columns target, cells error px (hits/frames)."""
    targets = report.targets()
    head = ["position"] + [f"target {report.labels.get(t, t)}" for t in targets] + ["all targets"]
    rows = [[p] + [_cell_text(report.cell(p, t)) for t in targets] + [_cell_text(report.cell(p))]
            for p in report.positions()]
    rows.append(["all"] + [_cell_text(report.cell(None, t)) for t in targets] + [_cell_text(report.cell())])
    widths = [max(len(r[i]) for r in [head] + rows) for i in range(len(head))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in [head] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def format_summary(report: Report) -> str:
    """Return the one-paragraph summary printed above the table."""
    s = report.summary()
    misses = ", ".join(f"{k} {v}" for k, v in s["misses"].items()) or "none"
    err = ("-" if s["correct"] == 0 else f"{s['error_px_mean']:.2f} +- {s['error_px_std']:.2f} px")
    return (f"profile {report.profile}: {s['frames']} frames, hit rate {s['hit_rate']:.3f} "
            f"({s['correct']}/{s['frames']}), pixel error when correct {err}\n"
            f"  misses: {misses}")


# -- running ---------------------------------------------------------------------------------
class Progress:
    """A dependency-free progress bar on a text stream (e.g. stderr); no-op when disabled."""

    def __init__(self, total: int, stream: Any, enabled: bool, label: str = "evaluate") -> None:
        self.total, self.stream, self.enabled, self.label = max(int(total), 1), stream, enabled, label
        self.done = 0

    def step(self, n: int = 1) -> None:
        self.done += n
        if self.enabled:
            frac = min(self.done / self.total, 1.0)
            bar = "#" * int(frac * 30)
            self.stream.write(f"\r{self.label} [{bar:<30}] {self.done}/{self.total}")
            self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


def pose_backend_for(dataset: Dataset, choice: str = "auto") -> str | None:
    """Return the pose backend to force for a dataset, or None to keep each profile's ``pose.backend``.

    ``auto``: ``keypoints`` when the annotations carry arm keypoints (a pair without them is then
    a ``no_pose`` frame, as with the simulator's pose-source dropouts), else the profile's.
    """
    if choice == "auto":
        return "keypoints" if any(f.keypoints is not None for f in dataset.frames) else None
    return None if choice == "params" else choice


def evaluate_dataset(dataset: Dataset, profiles: Mapping[str, Mapping[str, Any]],
                     progress: Progress | None = None,
                     on_result: Callable[[str, FrameAnnotation, Mapping[str, Any]], None] | None = None,
                     pose: str = "auto") -> dict[str, Report]:
    """Run the perception core with each parameter set on every annotated pair and score it.

    Args:
        dataset: the dataset.
        profiles: {name: effective parameters (config.Params)}; every set sees the same frames.
        progress: advanced once per pair.
        on_result: called with (profile name, annotation, contract JSON) for every result.
        pose: ``auto`` (the annotations' keypoints when they have them, see ``pose_backend_for``),
            ``keypoints``, ``blazepose``, or ``params`` (each profile's ``pose.backend``).

    Returns:
        {name: Report} in the order of ``profiles``.
    """
    from .perception.pipeline import Perception, make_pose_estimator

    backend = pose_backend_for(dataset, pose)
    if backend is not None:
        profiles = {n: p.with_overrides({"pose.backend": backend}, "evaluate --pose") for n, p in profiles.items()}
    reports = {name: Report(name, labels={k: dataset.label(k) for k in dataset.objects}) for name in profiles}
    engines: dict[str, Any] = {}
    rigs: dict[tuple, Any] = {}
    first_params = next(iter(profiles.values()))
    for ann, frame in dataset.pairs(first_params):
        size = (frame.left.shape[1], frame.left.shape[0])
        for name, params in profiles.items():
            if name not in engines:
                key = (float(params["calib.alpha"]), bool(params["calib.already_rectified"]), size)
                if key not in rigs:
                    rigs[key] = dataset.rig(size, params)
                engines[name] = Perception(rigs[key], params, make_pose_estimator(params, None))
            engine = engines[name]
            if params["pose.backend"] == "keypoints":
                engine.pose.provide(ann.keypoints, f"{dataset.root}: frame {ann.index} keypoints")
            result = engine.process(frame.left, frame.right).to_json(engine.rig)
            reports[name].outcomes.append(frame_outcome(ann, result))
            if on_result is not None:
                on_result(name, ann, result)
        if progress is not None:
            progress.step()
    return reports

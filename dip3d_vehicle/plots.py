"""The evaluation's figures (PNG): the paper's Fig. 6 and accuracy against range.

- ``plot_chosen_objects``: one panel per (diver position, intended target); bars give the
  relative frequency with which each object (or no object) was chosen, one bar per parameter
  profile; the ground-truth object's bars are drawn solid with a black edge on a shaded band,
  the others pale.
- ``plot_accuracy_vs_range``: hit rate against the intended object's range and against the
  diver's range (when the annotations give them), one line per profile, frame counts as labels.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .evaluation import Report, _natural  # noqa: E402

__all__ = ["plot_chosen_objects", "plot_accuracy_vs_range", "FIG6_FILE", "RANGE_FILE"]

FIG6_FILE = "chosen_objects.png"
RANGE_FILE = "accuracy_vs_range.png"
_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")


def plot_chosen_objects(reports: Mapping[str, Report], path: str | Path) -> Path:
    """Draw Fig. 6 (relative frequency of each chosen object, ground truth highlighted)."""
    reps = list(reports.values())
    positions = sorted({p for r in reps for p in r.positions()}, key=_natural)
    targets = sorted({t for r in reps for t in r.targets()}, key=_natural)
    labels = reps[0].labels if reps else {}
    objects = sorted({t for r in reps for o in r.outcomes for t in (o.target, o.chosen) if t is not None}
                     | set(labels), key=_natural) + ["none"]
    fig, axes = plt.subplots(len(positions), len(targets), squeeze=False, sharey=True,
                             figsize=(3.2 * len(targets) + 0.8, 2.6 * len(positions) + 0.9))
    width = 0.8 / max(len(reps), 1)
    x = np.arange(len(objects))
    for i, pos in enumerate(positions):
        for j, tgt in enumerate(targets):
            ax = axes[i][j]
            gt = objects.index(tgt)
            ax.axvspan(gt - 0.45, gt + 0.45, color="gold", alpha=0.25, lw=0)
            for k, rep in enumerate(reps):
                freq = rep.chosen_frequency().get((pos, tgt), {})
                n = sum(1 for o in rep.outcomes if o.diver_position == pos and o.target == tgt)
                heights = [freq.get(obj, 0.0) for obj in objects]
                colour = _COLOURS[k % len(_COLOURS)]
                offs = x - 0.4 + width * (k + 0.5)
                alphas = [1.0 if m == gt else 0.45 for m in range(len(objects))]
                for m in range(len(objects)):
                    ax.bar(offs[m], heights[m], width, color=colour, alpha=alphas[m],
                           edgecolor="black" if m == gt else "none", linewidth=1.2)
                ax.bar(0, 0, 0, color=colour, label=f"{rep.profile} (n={n})")  # legend entry
            ax.set_xticks(x, [labels.get(o, o) if o != "none" else "none" for o in objects], fontsize=8)
            ax.set_ylim(0, 1.12)
            ax.set_title(f"position {pos}, target {labels.get(tgt, tgt)}", fontsize=9)
            if j == 0:
                ax.set_ylabel("relative frequency")
            if i == len(positions) - 1:
                ax.set_xlabel("chosen object")
            ax.legend(fontsize=7, loc="upper right")
    fig.suptitle("Chosen object per diver position / intended target\n(ground truth shaded and outlined)",
                 fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def _binned(values: Sequence[float], hits: Sequence[bool], edges: np.ndarray) -> tuple[list, list, list]:
    """Return (bin centre, hit rate, count) for bins holding at least one frame."""
    xs, ys, ns = [], [], []
    v, h = np.asarray(values, float), np.asarray(hits, bool)
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (v >= lo) & (v < hi)
        if sel.any():
            xs.append(float(v[sel].mean()))
            ys.append(float(h[sel].mean()))
            ns.append(int(sel.sum()))
    return xs, ys, ns


def _edges(values: Sequence[float], width_m: float) -> np.ndarray:
    lo = math.floor(min(values) / width_m - 0.5) * width_m + width_m / 2
    hi = max(values) + width_m
    return np.arange(lo, hi + 1e-9, width_m)


def plot_accuracy_vs_range(reports: Mapping[str, Report], path: str | Path, bin_m: float = 0.5) -> Path:
    """Draw hit rate against the intended object's range and the diver's range."""
    kinds = [("target_range_m", "intended object's range from the camera (m)"),
             ("diver_range_m", "diver's range from the camera (m)")]
    kinds = [k for k in kinds if any(getattr(o, k[0]) is not None for r in reports.values() for o in r.outcomes)]
    fig, axes = plt.subplots(1, max(len(kinds), 1), squeeze=False, figsize=(5.2 * max(len(kinds), 1), 3.8))
    if not kinds:
        axes[0][0].text(0.5, 0.5, "the annotations give no ranges", ha="center", va="center")
        axes[0][0].set_axis_off()
    for ax, (attr, xlabel) in zip(axes[0], kinds):
        all_values = [getattr(o, attr) for r in reports.values() for o in r.outcomes if getattr(o, attr) is not None]
        edges = _edges(all_values, bin_m)
        for k, rep in enumerate(reports.values()):
            pts = [(getattr(o, attr), o.correct) for o in rep.outcomes if getattr(o, attr) is not None]
            xs, ys, ns = _binned([p[0] for p in pts], [p[1] for p in pts], edges)
            colour = _COLOURS[k % len(_COLOURS)]
            ax.plot(xs, ys, "o-", color=colour, label=rep.profile)
            for xv, yv, nv in zip(xs, ys, ns):
                ax.annotate(f"n={nv}", (xv, yv), textcoords="offset points", xytext=(4, 5 + 9 * k),
                            fontsize=7, color=colour)
        ax.set_ylim(-0.05, 1.2)
        ax.margins(x=0.1)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("hit rate (chosen = intended)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Accuracy against range (bins of {bin_m:g} m)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def _save(fig: "plt.Figure", path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

"""The evaluation's figures (PNG): the paper's Fig. 6 and accuracy against range.

- ``plot_chosen_objects``: one panel per (diver position, intended target); bars give the
  relative frequency with which each object (or no object) was chosen, one bar per parameter
  profile; the ground-truth object's bars are drawn solid with a black edge on a shaded band,
  the others pale.
- ``plot_accuracy_vs_range``: hit rate against the intended object's range and against the
  diver's range (when the annotations give them), one line per profile, frame counts as labels.
- ``plot_mission``: one simulated mission (``sitl``'s ``trajectory.png``): the top view with the
  track, headings, placards (pointed / chosen / others), diver and start; depth over time with the
  placards' depths; a state lane with a colour key; the outcome word in the title.
"""

from __future__ import annotations

import math
from pathlib import Path
from dataclasses import dataclass
from typing import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .evaluation import Report, _natural  # noqa: E402

__all__ = ["plot_chosen_objects", "plot_accuracy_vs_range", "plot_mission", "MissionPlacard", "MissionPlot",
           "FIG6_FILE", "RANGE_FILE"]

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


# ----------------------------------------------------------------------------------------- mission
@dataclass(frozen=True)
class MissionPlacard:
    """A placard on the mission plot: id, centre (north, east, depth in metres) and role (object|distractor)."""

    id: int
    north_m: float
    east_m: float
    depth_m: float
    role: str = "object"


@dataclass(frozen=True)
class MissionPlot:
    """What the mission plot shows.

    Attributes:
        track: (t_s, north_m, east_m, depth_m, yaw_rad) of the vehicle, in time order.
        placards: every placard.
        diver_north_east_m: the diver's chest (north, east).
        states: (t_s, state) of every mission state entered.
        sim_time_s: end of the run.
        scenario, seed, diver_position: the run.
        target_id: the placard the diver pointed at; chosen_id: the one the vehicle chose (or None).
        outcome, outcome_reason: the run's outcome word and its reason.
    """

    track: Sequence[tuple[float, float, float, float, float]]
    placards: Sequence[MissionPlacard]
    diver_north_east_m: tuple[float, float]
    states: Sequence[tuple[float, str]]
    sim_time_s: float
    scenario: str
    seed: int
    diver_position: str
    target_id: int
    chosen_id: int | None
    outcome: str
    outcome_reason: str


_STATE_COLOURS = {"idle": "#bdbdbd", "wait_for_diver": "#9ecae1", "confirm_point": "#6baed6",
                  "select_target": "#3182bd", "acknowledge": "#fdae6b", "servo": "#74c476", "arrive": "#31a354",
                  "done": "#006d2c", "lost_target": "#fb6a4a", "abort": "#a50f15", "suspended": "#756bb1"}


def plot_mission(m: MissionPlot, path: str | Path) -> Path:
    """Draw one simulated mission (top view, depth over time, state lane) to ``path``; return it."""
    fig = plt.figure(figsize=(13, 6.2))
    grid = fig.add_gridspec(2, 2, width_ratios=[1.1, 1], height_ratios=[4, 1.25], hspace=0.08, wspace=0.18)
    ax_map = fig.add_subplot(grid[:, 0])
    ax_depth = fig.add_subplot(grid[0, 1])
    ax_lane = fig.add_subplot(grid[1, 1], sharex=ax_depth)
    _draw_map(ax_map, m)
    _draw_depth(ax_depth, m)
    _draw_state_lane(ax_lane, m)
    ok = m.outcome == "reached"
    fig.suptitle(f"{m.scenario} seed {m.seed}: {m.outcome.upper()}\n{m.outcome_reason}", fontsize=11,
                 color="black" if ok else "tab:red", fontweight="bold")
    fig.subplots_adjust(left=0.06, right=0.98, top=0.86, bottom=0.2)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def _draw_map(ax, m: MissionPlot) -> None:
    """Top view (north up, east right): track, headings, placards, diver, start and end."""
    north = [r[1] for r in m.track]
    east = [r[2] for r in m.track]
    ax.plot(east, north, "-", color="tab:blue", lw=1.5, label="vehicle track")
    step = max(1, len(m.track) // 25)
    arrows = m.track[::step]
    ax.quiver([r[2] for r in arrows], [r[1] for r in arrows], [math.sin(r[4]) for r in arrows],
              [math.cos(r[4]) for r in arrows], color="tab:blue", alpha=0.45, width=0.004, scale=25,
              label=f"vehicle heading (every {arrows[1][0] - arrows[0][0]:.1f} s)" if len(arrows) > 1 else "heading")
    wrong = m.chosen_id is not None and m.chosen_id != m.target_id
    labelled: set[str] = set()
    for p in m.placards:
        if p.id == m.target_id:
            style, label = dict(marker="s", color="tab:green", ms=12), f"pointed placard ({p.id})"
        elif wrong and p.id == m.chosen_id:
            style, label = dict(marker="s", color="tab:red", ms=12), f"chosen placard ({p.id}): WRONG"
        elif p.role == "distractor":
            style, label = dict(marker="s", color="tab:gray", ms=9), "distractor"
        else:
            style, label = dict(marker="s", color="tab:orange", ms=10), "other placard"
        ax.plot(p.east_m, p.north_m, ls="none", label=None if label in labelled else label, **style)
        labelled.add(label)
        ax.annotate(str(p.id), (p.east_m, p.north_m), xytext=(8, 6), textcoords="offset points", fontsize=9,
                    fontweight="bold")
        if wrong and p.id == m.chosen_id:
            ax.plot(p.east_m, p.north_m, marker="x", color="white", ms=9, mew=2.5, ls="none")
    ax.plot(m.diver_north_east_m[1], m.diver_north_east_m[0], "o", color="k", ms=9,
            label=f"diver (position {m.diver_position})")
    if m.track:
        ax.plot(east[0], north[0], "^", color="tab:blue", ms=9, ls="none", label="start")
        ax.plot(east[-1], north[-1], "*", color="tab:purple", ms=13, ls="none", label="end")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=3, fontsize=8, frameon=False)
    ax.set_title("top view", fontsize=10)


def _draw_depth(ax, m: MissionPlot) -> None:
    """Vehicle depth over time with the placards' depths as dashed lines."""
    t = [r[0] for r in m.track]
    depth = [r[3] for r in m.track]
    ax.plot(t, depth, color="tab:blue", label="vehicle depth")
    labelled: set[str] = set()
    for p in m.placards:
        if p.id == m.target_id:
            colour, label = "tab:green", f"pointed placard {p.id} depth"
        elif p.id == m.chosen_id:
            colour, label = "tab:red", f"chosen placard {p.id} depth"
        else:
            colour, label = "tab:orange", "other placards' depth"
        ax.axhline(p.depth_m, color=colour, lw=0.9, ls="--", label=None if label in labelled else label)
        labelled.add(label)
    values = depth + [p.depth_m for p in m.placards]
    ax.set_ylim(max(values) + 0.2, min(values) - 0.2)
    ax.set_ylabel("depth (m)")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.tick_params(labelbottom=False)
    ax.set_title("depth and mission state over time", fontsize=10)


def _draw_state_lane(ax, m: MissionPlot) -> None:
    """One lane of coloured spans, one per state entered, with a colour key (no text inside the spans)."""
    seen: list[str] = []
    for i, (t0, state) in enumerate(m.states):
        t1 = m.states[i + 1][0] if i + 1 < len(m.states) else m.sim_time_s
        colour = _STATE_COLOURS.get(state, "#000000")
        ax.broken_barh([(t0, max(t1 - t0, 1e-3))], (0, 1), facecolors=colour, edgecolor="white", lw=0.3,
                       label=None if state in seen else state)
        if state not in seen:
            seen.append(state)
    ax.set_ylim(0, 1)
    ax.set_yticks([])
    ax.set_ylabel("state", rotation=0, ha="right", va="center")
    ax.set_xlabel("time (s)")
    ax.set_xlim(0, max(m.sim_time_s, 1e-3))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.55), ncol=min(len(seen), 4), fontsize=8,
              frameon=False, title="state colour key", title_fontsize=8)

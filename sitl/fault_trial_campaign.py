"""The fast tier's campaign: seeded trials of every fault, summarised per fault, and the README table.

    python -m sitl.fault_campaign trials [--trials 20] [--fault NAME] [--jobs N | --ray ADDRESS] [--json FILE]
"""

from __future__ import annotations

from typing import Any, Mapping

from dip3d_vehicle.config import load_params

from .fault_bounds import BOUNDS_S, EXPECTED
from .fault_trial import run_trial

__all__ = ["trial_campaign", "markdown_table"]


def trial_campaign(trials: int = 20, faults: list[str] | None = None, params: Mapping[str, Any] | None = None,
                   verbose: bool = True, jobs: int = 1, ray: str | None = None) -> dict:
    """Run ``trials`` seeded trials of every fault; return per-fault summaries and the raw trials.

    Runs here (``jobs`` 1), in ``jobs`` processes, or on Ray (``ray``: see sitl/parallel.py).
    """
    from .parallel import map_runs

    params = params if params is not None else load_params()
    out: dict[str, Any] = {"trials": {}, "summary": {}}
    names = faults or list(BOUNDS_S)
    items = [(fault, seed, params) for fault in names for seed in range(trials)]
    for (fault, seed, _), row in zip(items, map_runs(_trial_row, items, jobs, ray)):
        out["trials"].setdefault(fault, []).append(row)
        if verbose:
            print(f"{fault:22s} seed {seed:2d} sent {row['last_motion_sent_s']} recv {row['last_motion_received_s']} "
                  f"bound {row['bound_s']} ok {row['within_bound']} why '{row['disengage_reason']}' recovered "
                  f"{row['recovered']} ({row['reengaged_after_s']}) log {row['log_written']}/{row['log_read']} "
                  f"crash '{row['crashed'][:80]}'", flush=True)
    for fault in names:
        out["summary"][fault] = _summarise(fault, out["trials"].get(fault, []))
    return out


def _trial_row(args: tuple) -> dict:
    """One trial (in whatever process runs it) as a plain dict: (fault, seed, params)."""
    fault, seed, params = args
    return dict(run_trial(fault, seed, params).__dict__)


def _summarise(fault: str, rows: list[dict]) -> dict:
    sent = [r["last_motion_sent_s"] for r in rows if r["last_motion_sent_s"] is not None]
    recv = [r["last_motion_received_s"] for r in rows if r["last_motion_received_s"] is not None]
    reasons: dict[str, int] = {}
    for r in rows:
        key = r["disengage_reason"].split(" ->")[0] if r["disengage_reason"] else "(none)"
        reasons[key] = reasons.get(key, 0) + 1
    return {"trials": len(rows), "bound_s": BOUNDS_S.get(fault), "expected": EXPECTED.get(fault, ""),
            "max_last_motion_sent_s": max(sent, default=None), "max_last_motion_received_s": max(recv, default=None),
            "within_bound": sum(r["within_bound"] for r in rows),
            "crashes": sum(bool(r["crashed"]) for r in rows),
            "lost_log_records": sum(max(r["log_written"] - r["log_read"], 0) for r in rows),
            "log_records": sum(r["log_written"] for r in rows),
            "recovered": sum(bool(r["recovered"]) for r in rows),
            "reengaged_after_s_max": max((r["reengaged_after_s"] for r in rows if r["reengaged_after_s"] is not None),
                                         default=None),
            "disengage_reasons": reasons,
            "rechecked_state": sum(bool(r["counters"].get("rechecked_state")) for r in rows),
            "engaged_fraction_min": min((r["engaged_fraction"] for r in rows), default=None)}



def markdown_table(summary: Mapping[str, dict]) -> str:
    """The README table of a ``trials`` summary: fault, expected safe outcome, bound, measured numbers."""
    rows = ["| fault | expected safe outcome | bound on last motion command after onset | measured "
            "(max sent / max received by the autopilot) | within bound | recovered | crashes | log records "
            "lost / written | controller's reason |", "|---|---|---|---|---|---|---|---|---|"]
    for fault, s in summary.items():
        bound = "n/a (keeps working)" if s["bound_s"] is None else f"{s['bound_s']:.2f} s"
        meas = ("engaged fraction min {:.2f}".format(s["engaged_fraction_min"]) if s["max_last_motion_sent_s"] is None
                else f"{s['max_last_motion_sent_s']:.2f} s / {s['max_last_motion_received_s']:.2f} s")
        rec = "n/a" if s["max_last_motion_sent_s"] is None else (
            f"{s['recovered']}/{s['trials']} (moving again <= {s['reengaged_after_s_max']:.2f} s after the "
            f"clear / re-enable)")
        reasons = ", ".join(f"{k} x{v}" for k, v in s["disengage_reasons"].items())
        rows.append(f"| {fault} | {s['expected']} | {bound} | {meas} | {s['within_bound']}/{s['trials']} | {rec} | "
                    f"{s['crashes']} | {s['lost_log_records']} / {s['log_records']} | {reasons} |")
    return "\n".join(rows)

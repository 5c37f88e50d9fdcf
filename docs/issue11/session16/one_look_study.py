"""Every acted-on decision's one-look posterior (best, best other object, "none") over truth-pose mission runs.

Runs ``sitl.point_campaign``'s mission trials (same scenarios, seeds and defaults) and prints one JSON
line per run: scenario, seed, outcome, chosen and pointed placard, and the record of EVERY decision
the mission acted on (``FusedDecision.record``: kind, frames, fused posterior, one-look posterior of
the best hypothesis, the best other object and "nothing detected"). ``point_campaign`` itself gives
only the first decision.

Usage (from the repository root):
    PYTHONPATH=. python docs/issue11/session16/one_look_study.py SEEDS SCENARIO [SCENARIO ...] > out.jsonl
e.g. ``0-9 paper_pool near_miss``; then ``guard_table.py out.jsonl``.
"""
from __future__ import annotations

import json
import multiprocessing
import sys

from sitl import point_campaign

LAST: dict = {}
_make = point_campaign._simulation


def _simulation_keeping_decisions(scenario, seed, overrides, stop_at_s=None):
    """point_campaign's simulation, whose run leaves the mission's decision records in ``LAST``."""
    sim = _make(scenario, seed, overrides, stop_at_s)
    run = sim.run

    def run_and_keep():
        result = run()
        LAST[(scenario, seed)] = list(sim.mission.bb.decided)
        return result

    sim.run = run_and_keep
    return sim


def trial(args: tuple) -> dict:
    """One mission run (``point_campaign.mission_trial``) with every acted-on decision's record."""
    scenario, seed, _ = args
    row = point_campaign.mission_trial(args)
    return {"scenario": scenario, **{k: row[k] for k in ("seed", "position", "target_id", "chosen_id", "outcome",
                                                          "decision", "decision_posterior", "decision_one_look")},
            "decisions": LAST.get((scenario, seed), [])}


def main(argv: list[str]) -> None:
    point_campaign._simulation = _simulation_keeping_decisions
    lo, _, hi = argv[0].partition("-")
    jobs = [(sc, s, {}) for sc in argv[1:] for s in range(int(lo), int(hi or lo) + 1)]
    with multiprocessing.get_context("fork").Pool(2) as pool:
        for row in pool.imap(trial, jobs):
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])

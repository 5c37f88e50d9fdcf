"""Issue 12's closed-loop figures: "nothing there" (the shake, no motion toward a placard) and the stop gesture.

    python -m sitl.point_campaign nothing [--scenario nothing_there] [--seeds 0-9] [--jobs 1] [--json FILE]
                                          (every campaign: [--ray auto|local[:N]|ADDRESS], sitl/parallel.py)
    python -m sitl.point_campaign stop    [--scenario paper_pool] [--trials 20] [--jobs 1] [--json FILE]
    python -m sitl.point_campaign mission --scenario FILE [--seeds 0-9] [--jobs 1] [--json FILE]
    (every campaign: [--set KEY=VALUE ...] parameter overrides, e.g. --set selection.evidence=sampled)

``nothing``: per seed, counted on the AUTOPILOT's side: translation commands received (MANUAL_CONTROL
with x, y or z off neutral: any motion toward anything), the vehicle's largest distance from its start
(true pose), whether the mission entered ``nothing_there``, and whether the yaw commands the
autopilot received form the shake (first swing left, three reversals).

``stop``: per trial the diver performs the stop gesture at a seeded random time in [2, 16] s (so the
mission is in a random state); the gesture counts as visible from the first frame whose TRUE keypoints
show both wrists above the head, continuously. Trials whose gesture the camera never sees (the vehicle
has turned toward a placard and the diver is out of view) are counted apart; with ``--visible N`` trials
are drawn until N of them had the gesture in view (at most 3 x N trials). Measured: the time from "visible for
``behaviour.stop_gesture_hold_s``" to the last motion command the autopilot received (<= 0.5 s; 0 when
it was not moving), and motion commands received after that (must be 0).

``mission``: a scenario over seeds (arrived at the pointed placard / at a wrong one / abstained), with
the time from the point (the arm fully raised) to the decision and whether ``nothing_there`` or a
second try (``ambiguous``) happened, and how many fresh looks followed a "nothing there" the diver
kept pointing through (``relooks``; ``nothing_there`` counts the runs that said it at least once).
Each run also gives the first decision's fused posterior and
its posterior with the point's frames counted as one look (``behaviours/fusion.py``): the frames
share the diver's pointing error, so the one-look figure is what the point said once. ``decisions``
holds the record of every decision the mission acted on (``FusedDecision.record``: also the one-look
posterior of the best other object and of "nothing detected", where the rest of the doubt lay). The
summary gives the one-look range over the arrived and over the wrong runs (issue 11: where they
overlap, no threshold on it separates the two).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import sys

import numpy as np

__all__ = ["nothing_trial", "stop_trial", "mission_trial", "main"]

SHORT = {"sitl.max_sim_time_s": 16.0}
"""A nothing-there run: the decision and the shake are over by ~10 s."""


def _simulation(scenario, seed: int, overrides: dict, stop_at_s: float | None = None):
    """Return a Simulation for a scenario and seed (optionally with the stop gesture at ``stop_at_s``)."""
    from dip3d_vehicle.config import load_params
    from sitl.scenario import load_scenario
    from sitl.simulation import Simulation, sim_params

    sc = load_scenario(scenario, seed)
    if stop_at_s is not None:
        sc = dataclasses.replace(sc, diver=dataclasses.replace(sc.diver, stop_gesture_at_s=stop_at_s))
    return Simulation(sc, sim_params(load_params(), sc, **overrides))


def _shake_seen(received: list) -> bool:
    """Return True when the yaw commands received (MANUAL_CONTROL r) start left and reverse three times."""
    signs = []
    for r in received:
        if r.kind != "MANUAL_CONTROL" or not r.motion or r.values[:3] != (0, 0, 500):
            continue
        s = int(np.sign(r.values[3]))
        if s and (not signs or signs[-1] != s):
            signs.append(s)
    return len(signs) >= 4 and signs[0] < 0


def nothing_trial(args: tuple) -> dict:
    """One "nothing there" run; see the module doc."""
    scenario, seed, overrides = args
    sim = _simulation(scenario, seed, dict(SHORT, **overrides))
    try:
        result = sim.run()
    finally:
        sim.close()
    start = np.array(sim.trajectory[0][1:4])
    moved = max(float(np.linalg.norm(np.array(row[1:4]) - start)) for row in sim.trajectory)
    translation = sum(1 for r in sim.received if r.kind == "MANUAL_CONTROL" and r.values[:3] != (0, 0, 500))
    states = [s["state"] for s in result.states]
    return {"seed": seed, "target_id": result.target_id, "chosen_id": result.chosen_id,
            "nothing_there": "nothing_there" in states, "shake": _shake_seen(sim.received),
            "translation_commands": translation, "max_displacement_m": round(moved, 3),
            "arrived": result.arrived, "states": states,
            "story": [line for line in result.story if "fused" in line or "nothing" in line][:4]}


def stop_trial(args: tuple) -> dict:
    """One stop-gesture trial; see the module doc."""
    from dip3d_vehicle.perception.keypoints_file import GivenKeypoints

    scenario, trial, overrides = args
    at_s = float(np.random.default_rng([trial, 12]).uniform(2.0, 16.0))
    sim = _simulation(scenario, trial, dict({"sitl.max_sim_time_s": at_s + 4.0}, **overrides), stop_at_s=at_s)
    seen: list[tuple[float, bool]] = []
    in_view: list[bool] = []
    before, rig = sim.processor.before, sim.rig

    def record(frame):
        truth = frame.meta.get("keypoints_truth")
        arm = None
        if truth is not None:
            arm = GivenKeypoints(sim.params["pose.arm"], truth).estimate(None, None, rig)
        seen.append((float(frame.stamp_s), sim.mission.stop_watch.shows(arm)))
        in_view.append(truth is not None)
        before(frame)

    sim.processor.before = record
    try:
        result = sim.run()
    finally:
        sim.close()
    hold = float(sim.mission.bb.config.stop_gesture_hold_s)
    visible = _first_hold(seen, hold)
    state_at = next((s for t, s in reversed(sim.mission.history) if t <= at_s), "idle")
    stopped = next((t for t, s in sim.mission.history if s == "stopped"), None)
    out = {"trial": trial, "gesture_at_s": round(at_s, 2), "state_at_gesture": state_at,
           "visible_from_s": visible, "stopped_at_s": stopped}
    if visible is None:
        after = [v for (t, _), v in zip(seen, in_view) if t >= at_s]
        out["note"] = (f"gesture never visible: the diver's arm in view in {sum(after)} of the {len(after)} frames "
                       "after the gesture")
        return out
    due = visible + hold
    motion_after = [r.t_s for r in sim.received if r.t_s > due and r.motion]
    last_motion = max((r.t_s for r in sim.received if r.motion), default=None)
    out["last_motion_after_due_s"] = round(max(0.0, (last_motion or 0.0) - due), 3)
    out["motion_after_due_plus_0_5_s"] = sum(1 for t in motion_after if t > due + 0.5)
    out["motion_after_stopped"] = sum(1 for r in sim.received if stopped is not None and r.t_s > stopped + 0.05
                                      and r.motion)
    out["neutral_after_due"] = any(not r.motion for r in sim.received if r.t_s > due)
    out["states"] = [s["state"] for s in result.states]
    return out


def _first_hold(seen: list[tuple[float, bool]], hold_s: float) -> float | None:
    """Return the start of the first unbroken run of showing frames that lasts ``hold_s``, or None.

    Examples:
        >>> _first_hold([(0.0, True), (0.2, False), (0.4, True), (0.6, True), (1.4, True), (1.6, False)], 1.0)
        0.4
    """
    start = None
    for t, ok in seen:
        start = (start if start is not None else t) if ok else None
        if start is not None and t - start >= hold_s - 1e-9:
            return start
    return None


def mission_trial(args: tuple) -> dict:
    """One mission run with the point-to-decision time; see the module doc."""
    scenario, seed, overrides = args
    sim = _simulation(scenario, seed, overrides)
    try:
        result = sim.run()
    finally:
        sim.close()
    raised = sim.scenario.diver.start_s
    decided = next((t for t, s in sim.mission.history if s in ("acknowledge", "nothing_there")), None)
    states = [s["state"] for s in result.states]
    outcome = ("wrong" if result.chosen_id is not None and result.chosen_id != result.target_id and
               "acknowledge" in states else "arrived" if result.reached else "abstained")
    first = sim.mission.bb.decided[0] if sim.mission.bb.decided else None
    relooks = _relooks(states)
    doc = result.to_json()
    return {"seed": seed, "position": result.diver_position, "target_id": result.target_id,
            "chosen_id": result.chosen_id, "outcome": outcome, "arrived": result.arrived,
            "time_to_decision_s": None if decided is None else round(decided - raised, 2),
            "decision": None if first is None else first["kind"],
            "decision_posterior": None if first is None else first["posterior"],
            "decision_one_look": None if first is None else first["one_look"],
            "ambiguous_round_trips": states.count("confirm_point") - 1 - relooks,
            "nothing_there": "nothing_there" in states, "relooks": relooks,
            "second_looks": states.count("second_look"), "second_look_displacement_m": _look_displacement(sim),
            "second_look_resolved": _resolved_after_look(states), "time_to_arrive_s": result.time_to_arrive_s,
            "states": states, "decisions": list(sim.mission.bb.decided),
            "closest_other_m": doc["closest_other_m"], "closest_m": doc["closest_m"],
            "closest_diver_m": doc["closest_diver_m"], "held_short_m": doc["held_short_m"]}


def _relooks(states: list[str]) -> int:
    """Return how many fresh looks followed a "nothing there" the diver kept pointing through."""
    return sum(a == "nothing_there" and b == "confirm_point" for a, b in zip(states, states[1:]))


def _look_displacement(sim) -> float:
    """Return the vehicle's largest true distance from where its first second look began (0 if none), metres."""
    rows = [r for r in sim.trajectory if r[6] == "second_look"]
    if not rows:
        return 0.0
    start = np.array(rows[0][1:4])
    later = [r for r in sim.trajectory if r[0] >= rows[0][0] and r[6] in ("second_look", "select_target")]
    return round(max(float(np.linalg.norm(np.array(r[1:4]) - start)) for r in later), 3)


def _resolved_after_look(states: list[str]) -> bool | None:
    """Return whether a decision (acknowledge / nothing_there) directly followed a second look (None: no look)."""
    if "second_look" not in states:
        return None
    i = states.index("second_look")
    return any(s in ("acknowledge", "nothing_there") for s in states[i:i + 3])


def _seeds(text: str) -> list[int]:
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def _map(fn, items: list, jobs: int, ray: str | None = None):
    """Yield ``fn`` of every item, in order: here, in ``jobs`` processes or on Ray (sitl/parallel.py)."""
    from .parallel import map_runs

    yield from map_runs(fn, items, jobs, ray)


def main(argv: list[str] | None = None) -> int:
    """Run one campaign; print one line per run and a summary."""
    from .parallel import add_executor_arguments

    ap = argparse.ArgumentParser(prog="python -m sitl.point_campaign")
    ap.add_argument("which", choices=["nothing", "stop", "mission"])
    ap.add_argument("--scenario")
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--visible", type=int, default=0, metavar="N",
                    help="stop: draw trials until N had the gesture in view (at most 3 x N; runs here, one by one)")
    add_executor_arguments(ap)
    ap.add_argument("--json", metavar="FILE")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override a parameter for every run (repeatable; validated against the schema)")
    a = ap.parse_args(argv)
    from .campaign import _sets

    sets = _sets(a.set)
    if a.which == "stop" and a.visible:
        fn, items = stop_trial, _until_visible(a.scenario or "paper_pool", a.visible, sets)
    elif a.which == "stop":
        fn, items = stop_trial, [(a.scenario or "paper_pool", k, sets) for k in range(a.trials)]
    else:
        fn = nothing_trial if a.which == "nothing" else mission_trial
        items = [(a.scenario or "nothing_there", s, sets) for s in _seeds(a.seeds)]
    rows = []
    runs = (fn(item) for item in items) if isinstance(items, _until_visible) else _map(fn, items, a.jobs, a.ray)
    for row in runs:
        rows.append(row)
        if isinstance(items, _until_visible):
            items.count(row)
        print(json.dumps(row), flush=True)
    summary = _summary(a.which, rows)
    print(json.dumps(summary), flush=True)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({"rows": rows, "summary": summary}, fh, indent=1)
    return 0


class _until_visible:
    """Trial arguments for ``stop_trial`` until ``wanted`` trials saw the gesture (the caller reports each row)."""

    def __init__(self, scenario: str, wanted: int, overrides: dict | None = None) -> None:
        self.scenario, self.wanted, self.seen, self.k = scenario, wanted, 0, 0
        self.overrides = overrides or {}

    def __iter__(self):
        while self.seen < self.wanted and self.k < 3 * self.wanted:
            yield (self.scenario, self.k, self.overrides)
            self.k += 1

    def count(self, row: dict) -> None:
        """Count a finished trial."""
        self.seen += row.get("visible_from_s") is not None


def _summary(which: str, rows: list[dict]) -> dict:
    """Return the campaign's figures."""
    if which == "nothing":
        return {"runs": len(rows), "nothing_there": sum(r["nothing_there"] for r in rows),
                "shake": sum(r["shake"] for r in rows),
                "runs_with_translation": sum(r["translation_commands"] > 0 for r in rows),
                "max_displacement_m": max((r["max_displacement_m"] for r in rows), default=None)}
    if which == "stop":
        vis = [r for r in rows if r.get("visible_from_s") is not None]
        return {"trials": len(rows), "gesture_visible": len(vis), "stopped": sum(r["stopped_at_s"] is not None for r in vis),
                "max_last_motion_after_due_s": max((r["last_motion_after_due_s"] for r in vis), default=None),
                "motion_after_due_plus_0_5_s": sum(r["motion_after_due_plus_0_5_s"] for r in vis),
                "motion_after_stopped": sum(r["motion_after_stopped"] for r in vis),
                "states_at_gesture": sorted({r["state_at_gesture"] for r in rows})}
    times = [r["time_to_decision_s"] for r in rows if r["time_to_decision_s"] is not None]
    return {"runs": len(rows), "arrived": sum(r["outcome"] == "arrived" for r in rows),
            "wrong": sum(r["outcome"] == "wrong" for r in rows),
            "abstained": sum(r["outcome"] == "abstained" for r in rows),
            "nothing_there": sum(r["nothing_there"] for r in rows),
            "relook_runs": sum(r.get("relooks", 0) > 0 for r in rows),
            "decision_median_s": statistics.median(times) if times else None,
            "decision_max_s": max(times) if times else None,
            "ambiguous_round_trips": sum(max(0, r["ambiguous_round_trips"]) for r in rows),
            "second_look_runs": sum(r.get("second_looks", 0) > 0 for r in rows),
            "second_look_resolved": sum(bool(r.get("second_look_resolved")) for r in rows),
            "second_look_max_displacement_m": max((r.get("second_look_displacement_m", 0.0) for r in rows), default=0.0),
            "one_look_arrived": _span(r.get("decision_one_look") for r in rows if r["outcome"] == "arrived"),
            "one_look_wrong": _span(r.get("decision_one_look") for r in rows if r["outcome"] == "wrong")}


def _span(values) -> list[float] | None:
    """Return [min, max] of the values that are not None, or None.

    Examples:
        >>> _span([0.8, None, 0.95, 0.7]), _span([None])
        ([0.7, 0.95], None)
    """
    got = [v for v in values if v is not None]
    return [min(got), max(got)] if got else None


if __name__ == "__main__":
    sys.exit(main())

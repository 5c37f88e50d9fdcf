"""Test helper for the behaviour tests (a uniquely named module): drive a built mission by hand."""

from __future__ import annotations

from behaviours.blackboard import Observation

FRAME_S = 0.2
"""The frame interval the behaviour tests feed results at, seconds."""


def feed(m, results, t0: float = 0.0) -> list:
    """Tick the mission once per perception result at ``FRAME_S``; return the triggers fired."""
    fired = []
    for i, r in enumerate(results):
        m.bb.now_s = t0 + (i + 1) * FRAME_S
        m.bb.observation = Observation(m.bb.now_s, i, result=r)
        fired.append(m.tick())
        m.bb.observation = None
    return fired


def move_until_trigger(m, result, max_ticks: int, tick_s: float = 0.02, every: int = 10) -> tuple:
    """Tick the mission every ``tick_s`` (a result every ``every`` ticks) until a trigger fires.

    Returns (trigger or None, the command of every tick): how a moving state ends and what it sent.
    """
    cmds, t0, trig = [], m.bb.now_s, None
    for k in range(1, max_ticks):
        m.bb.now_s = t0 + tick_s * k
        m.bb.observation = Observation(m.bb.now_s, k, result=result) if k % every == 0 else None
        trig = m.tick()
        m.bb.observation = None
        cmds.append(m.bb.command)
        if trig:
            break
    return trig, cmds


def enter(m, state: str) -> None:
    """Put the mission in ``state`` and run that state's enter hook (skipping the way there)."""
    m.machine.set_state(state)
    m.behaviours[state].enter(m.bb)


def engaged_mission(rig, **over):
    """Return the mission built from the default parameters plus ``over`` (key=value), engaged."""
    from behaviours.loop import build_mission
    from dip3d_vehicle.config import load_params

    params = load_params(overrides={k: str(v) for k, v in over.items()})
    m = build_mission(params, rig, (1600, 1200))
    m.bb.engaged = True
    return m

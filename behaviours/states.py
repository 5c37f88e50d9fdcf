"""Every mission state's behaviour class, gathered for the machine (``machine.py``).

Each state is a small class with enter / tick / exit (``mission_state.MissionState``), kept in the
module of its part of the mission: ``pointing_states`` (wait for the diver, confirm the point,
select the target, second look, close in), ``approach_states`` (acknowledge, servo, lost target,
arrive) and ``holding_states`` (idle, done, abort, suspended, nothing there, stopped). The names are
re-exported here, so ``from behaviours.states import Servo`` keeps working.
"""

from __future__ import annotations

from .approach_states import Acknowledge, Arrive, LostTarget, Servo, within
from .holding_states import Abort, Done, Idle, NothingThere, Stopped, Suspended
from .mission_state import MissionState
from .pointing_states import CloseIn, ConfirmPoint, SecondLook, SelectTarget, WaitForDiver

__all__ = ["MissionState", "Idle", "WaitForDiver", "ConfirmPoint", "SelectTarget", "Acknowledge",
           "Servo", "LostTarget", "Arrive", "Done", "Abort", "Suspended", "NothingThere", "Stopped", "SecondLook",
           "CloseIn", "STATE_CLASSES", "within"]

STATE_CLASSES: tuple[type[MissionState], ...] = (Idle, WaitForDiver, ConfirmPoint, SelectTarget, Acknowledge,
                                                 Servo, LostTarget, Arrive, Done, Abort, Suspended, NothingThere,
                                                 Stopped, SecondLook, CloseIn)
"""Every state's behaviour class, by ``name``."""

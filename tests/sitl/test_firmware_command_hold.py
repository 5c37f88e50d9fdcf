"""On the real ArduSub SITL firmware: a MANUAL_CONTROL stays in force after the stream stops until the pilot-input
failsafe (FS_PILOT_TIMEOUT, 3 s by default; "Lost manual control", sticks centred, disarmed), and for the shorter time
the controller sets (``link.max_command_hold_s``, PARAM_SET from its own 1/191 identity) - the row sitl.autopilot is
held to in tests/link/test_command_hold.py. RC_OVERRIDE_TIME does not end it (2.97 s with it at 1 s:
docs/issue11/session61/scripts/override_probe.py).

Driven in wall-clock time as the ground station (255/190: heartbeat 1 Hz, the sticks) after the pre-dive; the forward
channel is read from RC_CHANNELS (channel 5) at 20 Hz. Skipped with the reason when the binary is absent.
"""

from __future__ import annotations

import time

import pytest
from pymavlink.dialects.v20 import ardupilotmega as m2

from sitl.ardusub_sitl import ArdusubSitl, SitlOptions
from sitl.firmware_mav import MavSocket
from sitl.firmware_world import pre_dive

from test_conformance import firmware_binary

INSTANCE = 36


def _run(m: MavSocket, seconds: float, sticks_x: int | None, state: dict) -> float | None:
    """Heartbeat 1 Hz and (unless None) MANUAL_CONTROL x at 10 Hz for ``seconds``; return the wall time the forward
    channel last read above neutral, and keep the last HEARTBEAT / PARAM_VALUE in ``state``."""
    end, next_hb, next_mc, last_forward = time.monotonic() + seconds, 0.0, 0.0, None
    while time.monotonic() < end:
        now = time.monotonic()
        if now >= next_hb:
            m.heartbeat()
            next_hb = now + 1.0
        if sticks_x is not None and now >= next_mc:
            m.send(m2.MAVLink_manual_control_message(1, sticks_x, 0, 500, 0, 0))
            state["last_sent"] = now
            next_mc = now + 0.1
        for msg in m.pump():
            kind = msg.get_type()
            if kind == "RC_CHANNELS" and msg.chan5_raw > 1510:
                last_forward = time.monotonic()
            elif kind == "HEARTBEAT" and msg.get_srcSystem() == 1 and msg.type == m2.MAV_TYPE_SUBMARINE:
                state["armed"], state["mode"] = bool(msg.base_mode & 128), msg.custom_mode
            elif kind == "PARAM_VALUE":
                state[msg.param_id] = msg.param_value
            elif kind == "STATUSTEXT":
                state.setdefault("texts", []).append(msg.text)
        time.sleep(0.005)
    return last_forward


def _arm(m: MavSocket, state: dict) -> None:
    """As the pilot: ALT_HOLD and arm, with neutral sticks."""
    m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 2.0)
    m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
    _run(m, 1.5, 0, state)
    assert state.get("armed") and state.get("mode") == 2, state


def _held_s(m: MavSocket, state: dict) -> float:
    """Sticks forward for 2 s, then none for 4 s: how long the forward channel stayed above neutral, s."""
    _arm(m, state)
    _run(m, 2.0, 300, state)
    last_forward = _run(m, 4.0, None, state)
    assert last_forward is not None
    return last_forward - state["last_sent"]


def _set_timeout(m: MavSocket, value_s: float, state: dict) -> None:
    """PARAM_SET FS_PILOT_TIMEOUT as the controller (1/191) and wait for the firmware's PARAM_VALUE."""
    state.pop("FS_PILOT_TIMEOUT", None)
    m.send(m2.MAVLink_param_set_message(1, 1, b"FS_PILOT_TIMEOUT", value_s, m2.MAV_PARAM_TYPE_REAL32), 1, 191)
    _run(m, 1.0, 0, state)
    assert state.get("FS_PILOT_TIMEOUT") == pytest.approx(value_s)


def test_a_stale_command_is_dropped_after_the_override_time_on_the_firmware() -> None:
    binary = firmware_binary()
    if binary is None:
        pytest.skip("no ArduSub SITL binary ($DIP3D_ARDUSUB or ../shared/ardusub-sitl/ardusub)")
    sitl = ArdusubSitl(SitlOptions(binary, instance=INSTANCE))
    sock = sitl.start()
    try:
        pre_dive(sock, 1.0, timeout_s=60.0)
        m, state = MavSocket(sock), {}
        m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(m2.MAVLINK_MSG_ID_RC_CHANNELS), 1e6 / 20)
        _set_timeout(m, 3.0, state)
        default_s = _held_s(m, state)
        disarmed_after_default = not state.get("armed")
        _set_timeout(m, 1.0, state)
        lowered_s = _held_s(m, state)
        disarmed_after_lowered = not state.get("armed")
        lost = state.get("texts", []).count("Lost manual control")
    finally:
        status = sitl.stop()
    assert status == 0
    assert 2.7 <= default_s <= 3.4, default_s
    assert 0.7 <= lowered_s <= 1.4, lowered_s
    assert disarmed_after_default and disarmed_after_lowered and lost == 2  # FS_PILOT_INPUT 2: centred, disarmed

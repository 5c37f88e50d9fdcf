"""Protocol conformance: the same checks against the built-in autopilot (4.5 and 4.7 settings) and the
real ArduSub SITL firmware, with every difference named (issue 13).

Each target is driven in wall-clock time by the same script, as the ground station (255/190) on a
loopback TCP socket: first HEARTBEAT (type, autopilot, boot mode, system_status), GCS-id parameter
reads under both names, GUIDED refused without a position (ack + STATUSTEXT), the SET_MODE message's
ack, arming right after boot, ALT_HOLD + arm once ready, MANUAL_CONTROL from another system ignored
and from the GCS id obeyed, message intervals (ATTITUDE accepted, an unknown id denied, SIMSTATE), the
RC-override hold after the stick stream stops, and the pilot-input failsafe.

Found on the 4.7 SITL with this test: its pilot-input failsafe is NOT compiled out once MANUAL_CONTROL
has been received ("Lost manual control", "Disarming motors" 3 s after the stream stopped), so it is
no longer an expected difference; the built-in autopilot agrees.

The firmware target needs the binary: ``$DIP3D_ARDUSUB`` or ``$DIP3D_SHARED/ardusub-sitl/ardusub``
(``../shared``); absent -> skipped with the reason. It runs with its own ``-I`` instance, loopback only.
Not covered here: the GUIDED velocity timeout and the never-timing-out yaw rate (GUIDED needs a
position source; with its simulated GPS the firmware accepts it only ~41 s after boot). They are
checked on the firmware, with the SITL's simulated external navigation as its position source, by
tests/sitl/test_firmware_guided.py, and on the built-in autopilot by tests/sitl/test_autopilot_protocol.py.
"""

from __future__ import annotations

import math
import os
import socket
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from pymavlink.dialects.v20 import ardupilotmega as m2

from dip3d_vehicle.clock import WallClock
from dip3d_vehicle.config import load_params
from sitl.autopilot import Autopilot
from sitl.firmware_mav import MavSocket

SHARED = Path(os.environ.get("DIP3D_SHARED", Path(__file__).resolve().parents[2].parent / "shared"))
FIRMWARE_INSTANCE = 31

# check -> expected value per behaviour ("4.5", "4.7"); the firmware is expected to behave as 4.7
# except where FIRMWARE_DIFFERENCES names it.
EXPECTED: dict[str, dict[str, Any]] = {
    "heartbeat type/autopilot": {"4.5": (12, 3), "4.7": (12, 3)},
    "boot mode": {"4.5": "MANUAL", "4.7": "MANUAL"},
    "boot system_status": {"4.5": 3, "4.7": 5},
    "GCS-id params answered": {"4.5": ("SYSID_MYGCS",), "4.7": ("MAV_GCS_SYSID",)},
    "GCS-id value": {"4.5": 255, "4.7": 255},
    "GUIDED without position: ack result": {"4.5": 4, "4.7": 4},
    "GUIDED without position: STATUSTEXT": {"4.5": True, "4.7": True},
    "SET_MODE message acked": {"4.5": True, "4.7": False},
    "arm right after boot": {"4.5": 0, "4.7": 4},
    "ALT_HOLD + arm when ready": {"4.5": True, "4.7": True},
    "MANUAL_CONTROL from sysid 1 turns": {"4.5": False, "4.7": False},
    "MANUAL_CONTROL from GCS id turns": {"4.5": True, "4.7": True},
    "RC override holds the last sticks ~3 s": {"4.5": True, "4.7": True},
    "interval ATTITUDE": {"4.5": 0, "4.7": 0},
    "interval unknown id 12345": {"4.5": 2, "4.7": 2},
    "interval SIMSTATE": {"4.5": 2, "4.7": 2},
    "pilot-input failsafe disarms": {"4.5": True, "4.7": True},
}
FIRMWARE_DIFFERENCES: dict[str, tuple[Any, str]] = {
    "interval SIMSTATE": (0, "the firmware is a simulator and has its truth message; the built-in autopilot "
                             "imitates a vehicle and denies it"),
}
"""Expected firmware-vs-4.7 differences: check -> (the firmware's value, why)."""


def firmware_binary() -> Path | None:
    """The ArduSub SITL binary, or None when neither $DIP3D_ARDUSUB nor ../shared has one."""
    env = os.environ.get("DIP3D_ARDUSUB")
    path = Path(env) if env else SHARED / "ardusub-sitl" / "ardusub"
    return path if path.is_file() and os.access(path, os.X_OK) else None


class _Builtin:
    """The built-in autopilot on a wall clock, stepped by a thread; ``sock`` is a client socket."""

    def __init__(self, firmware: str) -> None:
        self.ap = Autopilot(load_params(), WallClock(), listen=["tcp:127.0.0.1:0"], firmware=firmware)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        host, port = self.ap.addresses[0].split(":")[-2:]
        self.sock = socket.create_connection((host, int(port)))

    def _run(self) -> None:
        while not self._stop.is_set():
            self.ap.step()
            time.sleep(0.002)

    def close(self) -> None:
        self.sock.close()
        self._stop.set()
        self._thread.join(2.0)
        self.ap.close()


class _Firmware:
    """The ArduSub SITL binary on loopback (sitl/ardusub_sitl.py)."""

    def __init__(self, binary: Path) -> None:
        from sitl.ardusub_sitl import ArdusubSitl, SitlOptions
        self.sitl = ArdusubSitl(SitlOptions(binary, instance=FIRMWARE_INSTANCE))
        self.sock = self.sitl.start()

    def close(self) -> None:
        assert self.sitl.stop() == 0  # SIGTERM ends a booted firmware with status 0


class _Script:
    """The ground station's side: heartbeat 1 Hz, neutral sticks 10 Hz (unless told otherwise), checks."""

    def __init__(self, m: MavSocket) -> None:
        self.m = m
        self.sticks: tuple[int, int, int, int] | None = (0, 0, 500, 0)
        self.other_sticks: tuple[int, int, int, int] | None = None
        self._next_hb = self._next_mc = 0.0

    def pump(self, seconds: float) -> list[Any]:
        end, out = time.monotonic() + seconds, []
        while time.monotonic() < end:
            now = time.monotonic()
            if now >= self._next_hb:
                self.m.heartbeat()
                self._next_hb = now + 1.0
            if now >= self._next_mc:
                if self.sticks is not None:
                    self.m.send(m2.MAVLink_manual_control_message(1, *self.sticks, 0))
                if self.other_sticks is not None:
                    self.m.send(m2.MAVLink_manual_control_message(1, *self.other_sticks, 0), sysid=1, compid=190)
                self._next_mc = now + 0.1
            out += self.m.pump()
            time.sleep(0.005)
        return out

    def until(self, pred, timeout_s: float) -> Any:
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            for msg in self.pump(0.02):
                if pred(msg):
                    return msg
        return None

    def ack(self, command: int, timeout_s: float = 1.5) -> int | None:
        msg = self.until(lambda x: x.get_type() == "COMMAND_ACK" and x.command == command, timeout_s)
        return None if msg is None else int(msg.result)

    def heartbeat(self) -> Any:
        return self.until(lambda x: x.get_type() == "HEARTBEAT" and x.get_srcSystem() == 1
                          and x.get_srcComponent() == 1, 3.0)

    def yaw_change(self, seconds: float) -> float:
        """|yaw turned| over ``seconds``: the mean ATTITUDE yawspeed times the time (the gyro, so the EKF's
        yaw alignment ~5 s after the firmware boots does not count as a turn)."""
        rates = [x.yawspeed for x in self.pump(seconds) if x.get_type() == "ATTITUDE"]
        return abs(sum(rates) / len(rates)) * seconds if rates else 0.0


def observe(m: MavSocket) -> dict[str, Any]:
    """Run the script; return check -> observed value."""
    s, out = _Script(m), {}
    hb = s.heartbeat()
    out["heartbeat type/autopilot"] = (hb.type, hb.autopilot)
    out["boot mode"] = {19: "MANUAL"}.get(hb.custom_mode, hb.custom_mode)
    out["boot system_status"] = hb.system_status
    m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
    out["arm right after boot"] = s.ack(m2.MAV_CMD_COMPONENT_ARM_DISARM)
    m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 0.0)
    s.ack(m2.MAV_CMD_COMPONENT_ARM_DISARM)
    answered = []
    for name in ("SYSID_MYGCS", "MAV_GCS_SYSID"):
        m.send(m2.MAVLink_param_request_read_message(1, 1, name.encode(), -1))
        pv = s.until(lambda x, n=name: x.get_type() == "PARAM_VALUE" and x.param_id == n, 1.5)
        if pv is not None:
            answered.append(name)
            out["GCS-id value"] = int(pv.param_value)
    out["GCS-id params answered"] = tuple(answered)
    m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 4.0)
    before = len(m.received)
    out["GUIDED without position: ack result"] = s.ack(m2.MAV_CMD_DO_SET_MODE)
    s.pump(0.3)
    texts = [x.text for _, x in m.received[before:] if x.get_type() == "STATUSTEXT"]
    out["GUIDED without position: STATUSTEXT"] = any("GUIDED" in t and "position" in t for t in texts)
    m.send(m2.MAVLink_set_mode_message(1, 1, 19))  # MANUAL again, by the SET_MODE message
    out["SET_MODE message acked"] = s.ack(m2.MAVLINK_MSG_ID_SET_MODE) is not None
    for name, mid in (("ATTITUDE", 30), ("unknown id 12345", 12345), ("SIMSTATE", 164)):
        m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(mid), 1e5)
        out[f"interval {name}"] = s.ack(m2.MAV_CMD_SET_MESSAGE_INTERVAL)
    armed = None
    end = time.monotonic() + 15.0
    while time.monotonic() < end and armed is None:
        m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 2.0)
        m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
        armed = s.until(lambda x: x.get_type() == "HEARTBEAT" and x.get_srcSystem() == 1
                        and x.base_mode & 128 and x.custom_mode == 2, 1.0)
    out["ALT_HOLD + arm when ready"] = armed is not None
    s.pump(1.0)
    s.other_sticks = (0, 0, 500, 800)
    out["MANUAL_CONTROL from sysid 1 turns"] = s.yaw_change(2.0) > 0.3
    s.other_sticks, s.sticks = None, (0, 0, 500, 800)
    s.pump(0.5)
    out["MANUAL_CONTROL from GCS id turns"] = s.yaw_change(1.5) > 0.3
    s.sticks = None  # the stream stops: ArduSub keeps the last sticks for RC_OVERRIDE_TIME (3 s)
    held = s.yaw_change(2.0)
    s.pump(2.0)
    after = s.yaw_change(1.0)
    out["RC override holds the last sticks ~3 s"] = held > 0.5 and after < 0.25
    before = len(m.received)
    s.pump(2.0)  # with no MANUAL_CONTROL for > FS_PILOT_TIMEOUT (3 s) in all
    hbs = [x for _, x in m.received[before:] if x.get_type() == "HEARTBEAT" and x.get_srcSystem() == 1]
    out["pilot-input failsafe disarms"] = bool(hbs) and not hbs[-1].base_mode & 128
    return out


def expected_for(target: str) -> dict[str, Any]:
    """The expected values of ``target`` ("builtin-4.5", "builtin-4.7", "firmware")."""
    version = "4.5" if target == "builtin-4.5" else "4.7"
    exp = {k: v[version] for k, v in EXPECTED.items()}
    if target == "firmware":
        exp.update({k: v for k, (v, _) in FIRMWARE_DIFFERENCES.items()})
    return exp


def _target(name: str):
    if name == "firmware":
        binary = firmware_binary()
        if binary is None:
            pytest.skip("no ArduSub SITL binary ($DIP3D_ARDUSUB or ../shared/ardusub-sitl/ardusub): "
                        "a user's clone has no ../shared; build one with tools/build_ardusub_sitl.sh")
        return _Firmware(binary)
    return _Builtin(name.split("-")[1])


OBSERVED: dict[str, dict[str, Any]] = {}


@pytest.mark.parametrize("target", ["builtin-4.5", "builtin-4.7", "firmware"])
def test_conformance(target: str) -> None:
    t = _target(target)
    try:
        got = observe(MavSocket(t.sock))
    finally:
        t.close()
    OBSERVED[target] = got
    exp = expected_for(target)
    wrong = {k: (got.get(k), v) for k, v in exp.items() if got.get(k) != v}
    print(conformance_table())
    assert not wrong, f"{target}: (observed, expected) {wrong}"


def conformance_table() -> str:
    """Markdown table of what each target showed so far, with the differences marked."""
    targets = [t for t in ("builtin-4.5", "builtin-4.7", "firmware") if t in OBSERVED]
    rows = ["| check | " + " | ".join(targets) + " |", "|---" * (len(targets) + 1) + "|"]
    for k in EXPECTED:
        vals = [OBSERVED[t].get(k) for t in targets]
        mark = " (differs)" if len({repr(v) for v in vals}) > 1 else ""
        rows.append(f"| {k}{mark} | " + " | ".join(str(v) for v in vals) + " |")
    return "\n".join(rows)

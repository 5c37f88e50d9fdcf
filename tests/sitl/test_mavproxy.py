"""A real third-party ground station (MAVProxy) against the simulated autopilot over TCP.

MAVProxy must identify an ArduSub vehicle (it names ArduSub's modes), change mode, arm, and show
the refusal of GUIDED without a position estimate as ArduSub words it. With MAVProxy's default
modules (as a user starts it) it must fetch the parameters by MAVLink FTP as from ArduSub, and
never report a fence breach or an FTP time-out.
"""

from __future__ import annotations

import queue
import shutil
import subprocess
import threading
import time

import pytest

from dip3d_vehicle.clock import WallClock
from dip3d_vehicle.config import load_params
from sitl.autopilot import Autopilot

MAVPROXY = shutil.which("mavproxy.py")
pytestmark = pytest.mark.skipif(MAVPROXY is None, reason="mavproxy.py not on PATH")


class _Running:
    """The autopilot stepping on the wall clock in a background thread."""

    def __init__(self) -> None:
        params = load_params(overrides={"sim.pilot_input_failsafe": False})  # MAVProxy sends no joystick
        self.ap = Autopilot(params, WallClock(), listen=["tcp:127.0.0.1:0"])
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def _loop(self) -> None:
        while not self._stop.is_set():
            self.ap.step()
            time.sleep(0.002)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(5)
        self.ap.close()


class _Proc:
    """MAVProxy with its stdout read by a thread, so waiting on text is bounded."""

    def __init__(self, url: str, modules: str | None = "cmdlong,mode,arm") -> None:
        self.p = subprocess.Popen(
            [MAVPROXY, f"--master={url}", "--no-state"] + ([f"--default-modules={modules}"] if modules else []),
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.text = ""
        self._q: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.p.stdout:
            self._q.put(line)

    def send(self, line: str) -> None:
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()

    def wait_for(self, *needles: str, timeout_s: float = 10.0) -> bool:
        end = time.monotonic() + timeout_s
        while not all(n in self.text for n in needles):
            try:
                self.text += self._q.get(timeout=max(0.01, end - time.monotonic()))
            except queue.Empty:
                return False
        return True

    def close(self) -> None:
        try:
            self.send("exit")
            self.p.wait(5)
        except (OSError, subprocess.TimeoutExpired):
            self.p.kill()
            self.p.wait(5)


def test_mavproxy_sees_ardusub_changes_mode_arms_and_gets_refusal():
    sim = _Running()
    mp = _Proc(sim.ap.addresses[0])
    try:
        assert mp.wait_for("Detected vehicle 1:1", "Mode MANUAL", timeout_s=20), mp.text
        mp.send("mode ALT_HOLD")
        assert mp.wait_for("Mode ALT_HOLD"), mp.text        # ArduSub's mode table (type 12)
        assert sim.ap.mode == 2
        mp.send("arm throttle")
        assert mp.wait_for("AP: Arming motors", "ARMED"), mp.text
        assert sim.ap.armed
        mp.send("mode GUIDED")
        assert mp.wait_for("AP: Mode change failed: GUIDED requires position",
                           "DO_SET_MODE: FAILED"), mp.text
        assert sim.ap.mode == 2
        mp.send("disarm")
        assert mp.wait_for("AP: Disarming motors"), mp.text
    finally:
        mp.close()
        sim.close()


def test_mavproxy_default_modules_fetch_params_by_ftp_without_fence_breach_or_timeout():
    from sitl.autopilot import ARDUSUB_PARAMS

    sim = _Running()
    mp = _Proc(sim.ap.addresses[0], modules=None)  # every default module, as a user runs it: ftp, param, fence
    try:
        assert mp.wait_for("Detected vehicle 1:1", f"Received {len(ARDUSUB_PARAMS)} parameters (ftp)",
                           timeout_s=30), mp.text
        mp.send("mode ALT_HOLD")  # depth / XY control bits become enabled in SYS_STATUS
        assert mp.wait_for("Mode ALT_HOLD"), mp.text
        mp.send("param show SYSID_MYGCS")
        assert mp.wait_for("SYSID_MYGCS      255"), mp.text
        time.sleep(3.0)  # SYS_STATUS at 2 Hz: several more after the mode change
        mp.wait_for("never printed", timeout_s=0.5)  # collect what arrived meanwhile
        assert "fence breach" not in mp.text, mp.text
        assert "timed out" not in mp.text, mp.text
        print(mp.text)  # the transcript (pytest -s shows it)
    finally:
        mp.close()
        sim.close()

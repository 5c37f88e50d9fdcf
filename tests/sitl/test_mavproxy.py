"""A real third-party ground station (MAVProxy) against the simulated autopilot over TCP.

MAVProxy must identify an ArduSub vehicle (it names ArduSub's modes), change mode, arm, and show
the refusal of GUIDED without a position estimate as ArduSub words it.
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

    def __init__(self, url: str) -> None:
        self.p = subprocess.Popen(
            [MAVPROXY, f"--master={url}", "--no-state", "--default-modules=cmdlong,mode,arm"],
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

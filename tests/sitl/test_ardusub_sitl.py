"""The ArduSub SITL runner: one clear error for a bad binary, loopback only, stopped cleanly."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time

import pytest

from dip3d_vehicle.errors import FirmwareError
from sitl.ardusub_sitl import ArdusubSitl, SitlOptions, resolve_binary

from test_conformance import firmware_binary


def test_missing_or_not_executable_binary_is_one_clear_error(tmp_path, monkeypatch) -> None:
    monkeypatch.delenv("DIP3D_ARDUSUB", raising=False)
    with pytest.raises(FirmwareError, match="no such file"):
        resolve_binary(tmp_path / "ardusub")
    f = tmp_path / "ardusub"
    f.write_text("not a program")
    with pytest.raises(FirmwareError, match="not executable"):
        resolve_binary(f)
    with pytest.raises(FirmwareError, match="DIP3D_ARDUSUB"):
        resolve_binary(None)
    monkeypatch.setenv("DIP3D_ARDUSUB", str(f))
    with pytest.raises(FirmwareError, match="not executable"):
        resolve_binary(None)


def test_sitl_command_with_a_missing_binary_exits_2_with_one_line(tmp_path) -> None:
    proc = subprocess.run([sys.executable, "-m", "dip3d_vehicle.cli", "sitl", "--ardusub", str(tmp_path / "nope"),
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "nope: no such file" in proc.stderr


def test_firmware_opens_no_listening_socket_and_stops_with_status_0() -> None:
    binary = firmware_binary()
    if binary is None:
        pytest.skip("no ArduSub SITL binary ($DIP3D_ARDUSUB or ../shared/ardusub-sitl/ardusub)")
    if shutil.which("ss") is None:
        pytest.skip("no `ss` to list sockets")
    sitl = ArdusubSitl(SitlOptions(binary, instance=32))
    sock = sitl.start()
    try:
        sock.settimeout(5.0)
        assert sock.recv(1)  # it talks MAVLink to us
        time.sleep(1.0)
        listing = subprocess.run(["ss", "-lntupH"], capture_output=True, text=True).stdout
        mine = [line for line in listing.splitlines() if f"pid={sitl.proc.pid}," in line]
        assert mine == [], mine
    finally:
        status = sitl.stop()
    assert status in (0, -15) and not sitl.running  # 0 once booted (its SIGTERM handler), else the signal

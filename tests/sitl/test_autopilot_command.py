"""``dip3d-vehicle autopilot`` standalone, and the speed benchmark's harness (not timed here)."""

from __future__ import annotations

from dip3d_vehicle.cli import main
from sitl.bench import measure_speed


def test_autopilot_command_runs_and_stops(capsys):
    assert main(["autopilot", "--listen", "tcp:127.0.0.1:0", "--listen", "udpin:127.0.0.1:0",
                 "--duration", "0.3", "--speed", "3", "--with-dvl"]) == 0
    out = capsys.readouterr().out
    assert "position estimate yes" in out and "tcp:127.0.0.1:" in out and "udpin:127.0.0.1:" in out


def test_autopilot_command_bad_inputs(tmp_path, capsys):
    key = tmp_path / "key"
    key.write_bytes(b"short")
    assert main(["autopilot", "--listen", "tcp:127.0.0.1:0", "--signing-key", str(key), "--duration", "0.1"]) == 2
    assert f"{key}: signing key must be 32 raw bytes or 64 hex digits" in capsys.readouterr().err
    assert main(["autopilot", "--listen", "serial:/dev/x", "--duration", "0.1"]) == 2
    assert "expected tcp:HOST:PORT or udpin:HOST:PORT" in capsys.readouterr().err


def test_autopilot_command_reads_hex_key(tmp_path):
    key = tmp_path / "key"
    key.write_text(bytes(range(32)).hex() + "\n")
    assert main(["autopilot", "--listen", "tcp:127.0.0.1:0", "--signing-key", str(key), "--duration", "0.1",
                 "--speed", "5"]) == 0


def test_bench_harness_runs():
    r = measure_speed(2.0)
    assert r["armed_at_end"] and r["messages_received"] > 30 and r["ratio"] > 0

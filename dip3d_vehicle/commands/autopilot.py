"""``dip3d-vehicle autopilot``: the simulator's ArduSub-like autopilot alone, for a ground station."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..errors import LinkError, ScenarioError
from ._common import add_params_arguments, params_from_args

NAME = "autopilot"
HELP = "run the simulated ArduSub-like autopilot (MAVLink 2 on loopback) until Ctrl-C"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --listen, --scenario, --with-dvl, --speed, --signing-key, --duration."""
    parser.add_argument("--listen", action="append", default=[], metavar="URL",
                        help="tcp:HOST:PORT or udpin:HOST:PORT (repeatable; default tcp:127.0.0.1:5760)")
    parser.add_argument("--scenario", metavar="NAME|FILE",
                        help="scenario name or file (only its DVL switch and start pose are used for now)")
    parser.add_argument("--with-dvl", action="store_true",
                        help="the vehicle has a position estimate (GUIDED allowed, LOCAL_POSITION_NED sent)")
    parser.add_argument("--speed", type=float, default=1.0, help="simulated seconds per wall second (default 1)")
    parser.add_argument("--signing-key", metavar="FILE",
                        help="file holding the MAVLink 2 signing key (32 bytes raw, or 64 hex digits)")
    parser.add_argument("--duration", type=float, default=None, metavar="S",
                        help="stop after this many simulated seconds (default: run until Ctrl-C)")
    add_params_arguments(parser)


def read_signing_key(path: str) -> bytes:
    """Read a 32-byte signing key (raw, or 64 hex digits); raise LinkError naming the file."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise LinkError(f"{path}: cannot read signing key ({exc.strerror or exc})") from None
    text = data.strip()
    if len(text) == 64:
        try:
            return bytes.fromhex(text.decode("ascii"))
        except (ValueError, UnicodeDecodeError):
            pass
    if len(data) == 32:
        return data
    raise LinkError(f"{path}: signing key must be 32 raw bytes or 64 hex digits (got {len(data)} bytes)")


def _scenario_overrides(arg: str | None) -> dict:
    """Take the DVL switch / initial pose from a scenario file (keys has_position/with_dvl, initial_*)."""
    if not arg:
        return {}
    path = Path(arg)
    if not path.is_file():
        return {}  # a built-in scenario name: sitl/scenario.py owns those; nothing to take yet
    import yaml
    try:
        data = yaml.safe_load(path.read_text()) or {}
    except (OSError, yaml.YAMLError) as exc:
        raise ScenarioError(f"{path}: cannot read scenario ({exc})") from None
    if not isinstance(data, dict):
        raise ScenarioError(f"{path}: expected a mapping")
    out = {}
    vehicle = data.get("vehicle", data)
    for key in ("has_position", "with_dvl"):
        if isinstance(vehicle, dict) and key in vehicle:
            out["sim.has_position"] = bool(vehicle[key])
    for key in ("initial_depth_m", "initial_yaw_deg"):
        if isinstance(vehicle, dict) and key in vehicle:
            out[f"sim.{key}"] = vehicle[key]
    return out


class _ScaledClock:
    """The wall clock scaled by ``speed`` (simulated seconds per wall second)."""

    def __init__(self, speed: float) -> None:
        self.speed = speed
        self._t0 = time.monotonic()

    def now(self) -> float:
        return (time.monotonic() - self._t0) * self.speed


def run(args: argparse.Namespace) -> int:
    """Run the autopilot until Ctrl-C (or --duration)."""
    from sitl.autopilot import Autopilot

    if not args.speed > 0:
        raise LinkError(f"--speed {args.speed}: must be > 0")
    params = params_from_args(args)
    over = _scenario_overrides(args.scenario)
    if args.with_dvl:
        over["sim.has_position"] = True
    if over:
        params = params.with_overrides(over, "--scenario/--with-dvl")
    key = read_signing_key(args.signing_key) if args.signing_key else None
    clock = _ScaledClock(args.speed)
    ap = Autopilot(params, clock, listen=args.listen or ["tcp:127.0.0.1:5760"], signing_key=key)
    print(f"autopilot: ArduSub-like vehicle sysid {ap.sysid}, position estimate "
          f"{'yes' if ap.has_position else 'no'}, listening on {' '.join(ap.addresses)}", flush=True)
    try:
        while args.duration is None or clock.now() < args.duration:
            ap.step()
            time.sleep(0.002)
    except KeyboardInterrupt:
        print("autopilot: stopped", file=sys.stderr)
    finally:
        ap.close()
    return 0

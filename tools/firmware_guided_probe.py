"""Is the ArduSub SITL's EKF good enough for GUIDED? Its estimate against the simulator's truth.

usage: .venv/bin/python tools/firmware_guided_probe.py [BINARY] [--position gps|external_nav] [--seconds 40]
       [--speedup 1] [--instance 83] [--out probe.jsonl]

Boots the binary on loopback, dives to 1 m and waits for GUIDED as the mission harness does
(sitl/firmware_world.py pre_dive), then for ``--seconds`` streams zero body velocity (and 0.2 m/s
forward between 10 and 20 s) as the controller does, with neutral sticks and heartbeats as the
ground station, and every 2 s prints one JSON line: the truth (SIM_STATE north/east speed and yaw)
beside the EKF's (LOCAL_POSITION_NED vx/vy, ATTITUDE yaw) and EKF_STATUS_REPORT (flags, variances).
``--position gps`` is the SITL's default (its simulated GPS), ``external_nav`` the SITL's simulated
external navigation (sitl/ardusub_sitl.py EXTERNAL_NAV_PARAMS).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from pymavlink.dialects.v20 import ardupilotmega as m2

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from sitl.ardusub_sitl import (DEFAULT_HOME, EXTERNAL_NAV_ARGS, EXTERNAL_NAV_PARAMS, ArdusubSitl,  # noqa: E402
                               SitlOptions, resolve_binary)
from sitl.firmware_mav import MavSocket  # noqa: E402
from sitl.firmware_world import pre_dive  # noqa: E402

STREAMS = ((m2.MAVLINK_MSG_ID_LOCAL_POSITION_NED, 5), (m2.MAVLINK_MSG_ID_EKF_STATUS_REPORT, 2),
           (m2.MAVLINK_MSG_ID_SIM_STATE, 5), (m2.MAVLINK_MSG_ID_ATTITUDE, 5))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary", nargs="?", default=None)
    ap.add_argument("--position", choices=["gps", "external_nav"], default="external_nav")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--speedup", type=float, default=1.0)
    ap.add_argument("--instance", type=int, default=83)
    ap.add_argument("--out", default=None)
    ap.add_argument("--pos-z", choices=["baro", "external_nav"], default="baro", help="EKF depth source with external_nav")
    a = ap.parse_args()
    nav = a.position == "external_nav"
    sitl = ArdusubSitl(SitlOptions(resolve_binary(a.binary), instance=a.instance, speedup=a.speedup,
                                   home=(DEFAULT_HOME[0], DEFAULT_HOME[1], 0.0, 0.0),
                                   extra_params=_nav_params(a.pos_z) if nav else (),
                                   extra_args=EXTERNAL_NAV_ARGS if nav else ()))
    sock = sitl.start()
    try:
        dive_s = pre_dive(sock, 1.0, timeout_s=150.0, guided=True)
        _emit(a, {"position": a.position, "guided_accepted_after_wall_s": round(dive_s, 1), "speedup": a.speedup})
        _watch(MavSocket(sock), a)
    finally:
        sitl.stop()
    return 0


def _nav_params(pos_z: str) -> tuple:
    """EXTERNAL_NAV_PARAMS, with the EKF's depth from external navigation when ``pos_z`` says so."""
    if pos_z == "baro":
        return EXTERNAL_NAV_PARAMS
    return tuple((k, 6 if k in ("EK3_SRC1_POSZ", "EK3_SRC1_VELZ") else v) for k, v in EXTERNAL_NAV_PARAMS)


def _watch(m: MavSocket, a: argparse.Namespace) -> None:
    """Stream the setpoints and print truth vs estimate every 2 s for ``a.seconds``."""
    for mid, hz in STREAMS:
        m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(mid), 1e6 / hz)
    sp, t0, last = a.speedup, time.monotonic(), {}
    next_hb = next_sp = next_mc = next_row = 0.0
    while (time.monotonic() - t0) * sp < a.seconds:
        now = time.monotonic()
        t = (now - t0) * sp
        for msg in m.pump():
            last[msg.get_type()] = msg
        if now >= next_hb:
            m.heartbeat()
            next_hb = now + 1.0 / sp
        if now >= next_mc:  # the joystick's neutral sticks (the pilot-input failsafe)
            m.send(m2.MAVLink_manual_control_message(1, 0, 0, 500, 0, 0))
            next_mc = now + 0.1 / sp
        if now >= next_sp:  # as the controller: BODY_NED velocity + yaw rate, from 1/191
            vx = 0.2 if 10.0 <= t < 20.0 else 0.0
            m.send(m2.MAVLink_set_position_target_local_ned_message(0, 1, 1, 8, 1479, 0, 0, 0, vx, 0, 0,
                                                                    0, 0, 0, 0, 0), 1, 191)
            next_sp = now + 0.05 / sp
        if now >= next_row and "SIM_STATE" in last:
            _emit(a, _row(t, last))
            next_row = now + 2.0 / sp
        time.sleep(0.005)


def _row(t: float, last: dict) -> dict:
    """One line: truth beside the EKF's estimate."""
    s, lp, e, att = (last.get(k) for k in ("SIM_STATE", "LOCAL_POSITION_NED", "EKF_STATUS_REPORT", "ATTITUDE"))
    return {"t_s": round(t, 1), "true_vn_m_s": round(s.vn, 3), "true_ve_m_s": round(s.ve, 3),
            "true_yaw_rad": round(s.yaw, 3), "true_depth_m": round(-s.alt, 3),
            "ekf_z_m": None if lp is None else round(lp.z, 3),
            "ekf_vn_m_s": None if lp is None else round(lp.vx, 3), "ekf_ve_m_s": None if lp is None else round(lp.vy, 3),
            "ekf_yaw_rad": None if att is None else round(att.yaw, 3),
            "ekf_flags": None if e is None else e.flags,
            "velocity_variance": None if e is None else round(e.velocity_variance, 3),
            "compass_variance": None if e is None else round(e.compass_variance, 3)}


def _emit(a: argparse.Namespace, row: dict) -> None:
    print(json.dumps(row), flush=True)
    if a.out:
        with open(a.out, "a") as f:
            f.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    raise SystemExit(main())

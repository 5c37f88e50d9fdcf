"""Probe the real ArduSub SITL in GUIDED: how far the vehicle keeps turning after the setpoint stream stops.

Two ways to ask for a turn at RATE rad/s, each streamed at 10 Hz for 5 s and then cut (the pilot's heartbeat and
neutral joystick go on, as over a link cut between the controller and the autopilot):
  rate     type_mask 1479: velocity 0 + yaw_rate RATE (what the link sent before session 62)
  heading  type_mask 455, frame BODY_NED: velocity 0 + absolute yaw = ATTITUDE.yaw + RATE x LEAD (at least FLOOR rad),
           yaw_rate |RATE| (ArduSub turns at it while the heading is more than 5 deg away, then holds the heading)
Prints the turn rate while streaming and the heading change from the cut to 8 s after it:
    PYTHONPATH=TREE python docs/issue11/session62/scripts/guided_yaw_probe.py rate|heading [RATE] [LEAD] [FLOOR]"""
import math
import sys
from pathlib import Path
import time

from pymavlink.dialects.v20 import ardupilotmega as m2

from sitl.ardusub_sitl import EXTERNAL_NAV_ARGS, EXTERNAL_NAV_PARAMS, ArdusubSitl, SitlOptions
from sitl.firmware_mav import MavSocket
from sitl.firmware_world import pre_dive

way = sys.argv[1]
rate = float(sys.argv[2]) if len(sys.argv) > 2 else 0.3
lead = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
floor = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
sitl = ArdusubSitl(SitlOptions(Path("/work/shared/ardusub-sitl/ardusub"), instance=38,
                               extra_params=EXTERNAL_NAV_PARAMS, extra_args=EXTERNAL_NAV_ARGS))
sock = sitl.start()
try:
    pre_dive(sock, 1.0, guided=True)
    m = MavSocket(sock)
    m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(m2.MAVLINK_MSG_ID_ATTITUDE), 1e6 / 20)
    t0 = time.monotonic()
    nhb = nmc = nsp = 0.0
    yaw = None
    rows = []
    cut = 6.0
    while time.monotonic() - t0 < cut + 8.0:
        now = time.monotonic() - t0
        if now >= nhb:
            m.heartbeat()
            nhb = now + 1.0
        if now >= nmc:
            m.send(m2.MAVLink_manual_control_message(1, 0, 0, 500, 0, 0))
            nmc = now + 0.1
        if 1.0 <= now < cut and now >= nsp and yaw is not None:
            if way == "rate":
                msg = m2.MAVLink_set_position_target_local_ned_message(
                    0, 1, 1, m2.MAV_FRAME_BODY_NED, 1479, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, rate)
            else:
                ahead = math.copysign(max(abs(rate) * lead, floor), rate)
                target = math.atan2(math.sin(yaw + ahead), math.cos(yaw + ahead))
                msg = m2.MAVLink_set_position_target_local_ned_message(
                    0, 1, 1, m2.MAV_FRAME_BODY_NED, 455, 0, 0, 0, 0, 0, 0, 0, 0, 0, target, abs(rate))
            m.send(msg, 1, 191)
            nsp = now + 0.1
        for msg in m.pump():
            k = msg.get_type()
            if k == "ATTITUDE":
                yaw = msg.yaw
                rows.append((now, msg.yaw, msg.yawspeed))
            elif k == "STATUSTEXT":
                print(f"{now:.2f} STATUSTEXT {msg.text}")
            elif k == "HEARTBEAT" and msg.get_srcSystem() == 1 and msg.type == m2.MAV_TYPE_SUBMARINE:
                if int(now * 10) % 20 == 0:
                    print(f"{now:.2f} HEARTBEAT armed {bool(msg.base_mode & 128)} mode {msg.custom_mode}")
        time.sleep(0.005)
    unwrap = []
    for t, y, r in rows:
        if unwrap:
            y = unwrap[-1][1] + math.atan2(math.sin(y - unwrap[-1][1]), math.cos(y - unwrap[-1][1]))
        unwrap.append((t, y, r))
    at = lambda s: min(unwrap, key=lambda row: abs(row[0] - s))  # noqa: E731
    streaming = [r for t, y, r in unwrap if cut - 2.0 <= t < cut]
    print(f"way {way} rate {rate} lead {lead} floor {floor}: turn rate over the last 2 s of the stream "
          f"{sum(streaming) / len(streaming):.3f} rad/s")
    for s in (0.0, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0):
        t, y, r = at(cut + s)
        print(f"  cut +{s:.0f} s: heading change {y - at(cut)[1]:+.3f} rad, yaw speed {r:+.3f} rad/s")
finally:
    sitl.stop()

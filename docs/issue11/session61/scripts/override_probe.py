"""Probe the real ArduSub SITL: how long a stale MANUAL_CONTROL stays in force after the stream stops, for given
RC_OVERRIDE_TIME / FS_PILOT_TIMEOUT values; prints the forward channel's hold, armed state and STATUSTEXTs:
    python docs/issue11/session61/scripts/override_probe.py [PARAM=VALUE ...]   (PYTHONPATH=TREE)"""
import sys
from pathlib import Path
import time

from pymavlink.dialects.v20 import ardupilotmega as m2

from sitl.ardusub_sitl import ArdusubSitl, SitlOptions
from sitl.firmware_mav import MavSocket
from sitl.firmware_world import pre_dive

sets = [(a.split("=")[0], float(a.split("=")[1])) for a in sys.argv[1:]]
sitl = ArdusubSitl(SitlOptions(Path("/work/shared/ardusub-sitl/ardusub"), instance=37))
sock = sitl.start()
try:
    pre_dive(sock, 1.0)
    m = MavSocket(sock)
    m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(m2.MAVLINK_MSG_ID_RC_CHANNELS), 1e6 / 20)
    m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 2.0)
    m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
    for name, value in sets:
        m.send(m2.MAVLink_param_set_message(1, 1, name.encode(), value, m2.MAV_PARAM_TYPE_REAL32), 1, 191)
    t0 = time.monotonic()
    nhb = nmc = 0.0
    last_sent = None
    rows = []
    while time.monotonic() - t0 < 9.0:
        now = time.monotonic() - t0
        if now >= nhb:
            m.heartbeat()
            nhb = now + 1.0
        if now < 4.0 and now >= nmc:
            m.send(m2.MAVLink_manual_control_message(1, 0 if now < 2.0 else 300, 0, 500, 0, 0))
            last_sent, nmc = now, now + 0.1
        for msg in m.pump():
            k = msg.get_type()
            if k == "RC_CHANNELS":
                rows.append((now, msg.chan5_raw))
            elif k == "STATUSTEXT":
                print(f"{now:.2f} STATUSTEXT {msg.text}")
            elif k == "PARAM_VALUE":
                print(f"{now:.2f} PARAM_VALUE {msg.param_id} = {msg.param_value:g}")
            elif k == "HEARTBEAT" and msg.get_srcSystem() == 1 and msg.type == m2.MAV_TYPE_SUBMARINE:
                print(f"{now:.2f} HEARTBEAT armed {bool(msg.base_mode & 128)} mode {msg.custom_mode}")
        time.sleep(0.005)
    fwd = [t for t, c in rows if c > 1510]
    print("last MANUAL_CONTROL", f"{last_sent:.2f}", "forward above neutral until", f"{max(fwd):.2f}" if fwd else None,
          "held", f"{max(fwd) - last_sent:.2f} s" if fwd else None)
    print("channel 5 after:", [(round(t, 2), c) for t, c in rows if t > last_sent][::5])
finally:
    sitl.stop()

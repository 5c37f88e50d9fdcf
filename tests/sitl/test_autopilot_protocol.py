"""Protocol conformance: one test per row of ardusub_mavlink.md / ardusub_sitl_response.md that the
controller relies on, over a real loopback socket with pymavlink as the client, in SimClock lockstep."""

from __future__ import annotations


import pytest

from dip3d_vehicle.link.setpoints import guided_from_velocity
from dip3d_vehicle.servo.command import VelocityCommand
from sitl.dynamics import wrap_pi

from mav_client import M, command_long, send_manual

FAILED, ACCEPTED, DENIED = M.MAV_RESULT_FAILED, M.MAV_RESULT_ACCEPTED, M.MAV_RESULT_DENIED
BODY_VEL_YAWRATE = 1479  # X/Y/Z, AX/AY/AZ, YAW ignored: vx, vy, vz and yaw_rate used (as measured)


def _last(ls, conn, kind):
    msgs = ls.messages(conn, kind)
    assert msgs, f"no {kind} received"
    return msgs[-1]


def _arm(ls, conn, mode=2):
    command_long(conn, M.MAV_CMD_DO_SET_MODE, 1, mode)
    command_long(conn, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    ls.run(0.05)
    assert ls.ap.armed and ls.ap.mode == mode


def _statustexts(ls, conn):
    return [(m.severity, m.text) for m in ls.messages(conn, "STATUSTEXT")]


def test_heartbeat_at_boot_disarmed_manual(sim):
    c = sim.connect()
    sim.run(1.1)
    hb = _last(sim, c, "HEARTBEAT")
    assert (hb.type, hb.autopilot, hb.base_mode, hb.custom_mode, hb.system_status, hb.mavlink_version) == (12, 3, 81, 19, 3, 3)
    assert (hb.get_srcSystem(), hb.get_srcComponent()) == (1, 1)
    assert c.mavlink20()


def test_heartbeat_armed_alt_hold(sim):
    c = sim.connect()
    _arm(sim, c)
    sim.clear(c)
    sim.run(1.1, every=lambda t: send_manual(c))
    hb = _last(sim, c, "HEARTBEAT")
    assert (hb.base_mode, hb.custom_mode, hb.system_status) == (209, 2, 4)


def test_heartbeat_guided_with_position(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False}, has_position=True)
    c = ls.connect()
    command_long(c, M.MAV_CMD_DO_SET_MODE, 1, 4)
    ls.run(1.1)
    assert _last(ls, c, "HEARTBEAT").base_mode == 89
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    ls.run(1.1, every=lambda t: send_manual(c))
    hb = _last(ls, c, "HEARTBEAT")
    assert (hb.base_mode, hb.custom_mode, hb.system_status) == (217, 4, 4)


@pytest.mark.parametrize("mode", [0, 1, 2, 19, 21])
def test_do_set_mode_accepted_without_position(sim, mode):
    c = sim.connect()
    command_long(c, M.MAV_CMD_DO_SET_MODE, 1, mode)
    sim.run(1.1)
    ack = _last(sim, c, "COMMAND_ACK")
    assert (ack.command, ack.result, ack.progress, ack.result_param2, ack.target_system, ack.target_component) == (176, 0, 0, 0, 255, 190)
    assert _last(sim, c, "HEARTBEAT").custom_mode == mode


@pytest.mark.parametrize("mode,name", [(4, "GUIDED"), (3, "AUTO"), (7, "CIRCLE"), (16, "POSHOLD"), (9, "SURFACE")])
def test_position_modes_refused_without_dvl(sim, mode, name):
    c = sim.connect()
    command_long(c, M.MAV_CMD_DO_SET_MODE, 1, mode)
    sim.run(0.1)
    ack = _last(sim, c, "COMMAND_ACK")
    assert (ack.command, ack.result, ack.target_system, ack.target_component) == (176, FAILED, 255, 190)
    assert (4, f"Mode change failed: {name} requires position") in _statustexts(sim, c)
    assert sim.ap.mode == 19


def test_set_mode_message_acked_as_command_11(sim):
    c = sim.connect()
    c.mav.set_mode_send(1, M.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 4)
    sim.run(0.1)
    ack = _last(sim, c, "COMMAND_ACK")
    assert (ack.command, ack.result, ack.target_system, ack.target_component) == (11, FAILED, 255, 190)
    c.mav.set_mode_send(1, M.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 0)
    sim.run(0.1)
    assert (_last(sim, c, "COMMAND_ACK").command, _last(sim, c, "COMMAND_ACK").result) == (11, ACCEPTED)
    assert sim.ap.mode == 0


def test_guided_accepted_with_dvl(lockstep_factory):
    ls = lockstep_factory(has_position=True)
    c = ls.connect()
    command_long(c, M.MAV_CMD_DO_SET_MODE, 1, 4)
    ls.run(0.1)
    assert (_last(ls, c, "COMMAND_ACK").result, ls.ap.mode) == (ACCEPTED, 4)


def test_arm_disarm_ack_and_statustext(sim):
    c = sim.connect()
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    sim.run(0.1)
    ack = _last(sim, c, "COMMAND_ACK")
    assert (ack.command, ack.result, ack.progress, ack.result_param2, ack.target_system, ack.target_component) == (400, 0, 0, 0, 255, 190)
    assert (6, "Arming motors") in _statustexts(sim, c) and sim.ap.armed
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    sim.run(1.1)
    assert (_last(sim, c, "COMMAND_ACK").result, sim.ap.armed) == (0, False)
    assert (6, "Disarming motors") in _statustexts(sim, c)
    assert _last(sim, c, "HEARTBEAT").base_mode == 81


def test_manual_control_scaling_and_sysid_rule(sim):
    c = sim.connect()
    other = sim.connect(sysid=1, compid=191)
    _arm(sim, c)
    c.mav.request_data_stream_send(1, 1, M.MAV_DATA_STREAM_RC_CHANNELS, 10, 1)
    sim.run(1.0, every=lambda t: send_manual(c, x=500, r=1000))
    rc = _last(sim, c, "RC_CHANNELS")
    assert (rc.chan3_raw, rc.chan4_raw, rc.chan5_raw, rc.chan6_raw) == (1500, 1700, 1600, 1500)
    assert sim.ap.state.u_m_s > 0.3
    # from sysid 1 (not SYSID_MYGCS): silently ignored
    sim.run(3.0, every=lambda t: send_manual(c))
    ignored = sim.ap.counters["manual_control_ignored"]
    sim.run(2.0, every=lambda t: send_manual(other, r=800))
    assert sim.ap.counters["manual_control_ignored"] > ignored
    assert abs(sim.ap.state.r_rad_s) < 0.01 and not ls_statustexts_after(sim, c, "Lost")


def ls_statustexts_after(ls, conn, prefix):
    return [t for _, t in _statustexts(ls, conn) if t.startswith(prefix)]


def test_manual_control_wrong_target_ignored(sim):
    c = sim.connect()
    _arm(sim, c)
    sim.run(2.0, every=lambda t: send_manual(c, x=1000, target=2))
    assert abs(sim.ap.state.u_m_s) < 1e-6


def test_stopped_manual_control_holds_last_input_3s_then_neutral(sim):
    """Failsafe not compiled (as in SITL): last input stays 3 s (RC_OVERRIDE_TIME), then coast."""
    c = sim.connect()
    _arm(sim, c)
    sim.run(3.0, every=lambda t: (send_manual(c, x=500), c.mav.heartbeat_send(6, 8, 0, 0, 0)))
    sim.clear(c)
    u_stop = sim.ap.state.u_m_s
    sim.run(2.9, every=lambda t: c.mav.heartbeat_send(6, 8, 0, 0, 0))
    assert sim.ap.pilot.forward == 1600 and sim.ap.state.u_m_s == pytest.approx(u_stop, rel=0.05)
    sim.run(9.0, every=lambda t: c.mav.heartbeat_send(6, 8, 0, 0, 0))
    assert sim.ap.pilot.forward == 1500 and sim.ap.state.u_m_s < 0.1 * u_stop
    assert sim.ap.armed and not _statustexts(sim, c)


@pytest.mark.parametrize("fs_input,disarms", [(2, True), (1, False)])
def test_pilot_input_failsafe(lockstep_factory, fs_input, disarms):
    ls = lockstep_factory({"sim.initial_depth_m": 3.0})
    c = ls.connect()
    c.mav.param_set_send(1, 1, b"FS_PILOT_INPUT", fs_input, M.MAV_PARAM_TYPE_REAL32)
    _arm(ls, c)
    hb = lambda t: c.mav.heartbeat_send(6, 8, 0, 0, 0)   # GCS still there: no GCS failsafe
    ls.run(1.0, every=lambda t: (send_manual(c, x=500), hb(t)))
    t_stop = ls.clock.now()
    ls.run(2.9, every=hb)
    assert ls.ap.armed and not ls_statustexts_after(ls, c, "Lost")
    ls.run(0.3, every=hb)
    assert (2, "Lost manual control") in _statustexts(ls, c)
    assert ls.ap.pilot.forward == 1500
    assert ls.ap.armed is (not disarms)
    lost = [e.time_s for e in ls.ap.events if e.detail == "Lost manual control"][0]
    assert lost - t_stop == pytest.approx(3.0, abs=0.05)


def test_gcs_failsafe_disarms_after_heartbeats_stop(sim):
    c = sim.connect()
    _arm(sim, c)
    sim.run(5.0)  # no GCS seen yet: no failsafe
    assert sim.ap.armed
    sim.run(1.0, every=lambda t: c.mav.heartbeat_send(6, 8, 0, 0, 0))
    t_last = sim.clock.now()
    sim.run(2.4)
    assert sim.ap.armed
    sim.run(0.3)
    assert not sim.ap.armed
    assert (4, "MYGCS: 255, heartbeat lost") in _statustexts(sim, c)
    fs = [e.time_s for e in sim.ap.events if e.detail == "gcs"][0]
    assert fs - t_last == pytest.approx(2.5, abs=0.05)


def test_companion_heartbeat_does_not_count_as_gcs(sim):
    c = sim.connect()
    comp = sim.connect(sysid=1, compid=191)
    _arm(sim, c)
    sim.run(0.5, every=lambda t: c.mav.heartbeat_send(6, 8, 0, 0, 0))
    sim.run(3.0, every=lambda t: comp.mav.heartbeat_send(18, 8, 0, 0, 0))
    assert not sim.ap.armed


def _guided(ls):
    c = ls.connect()
    _arm(ls, c, mode=4)
    return c


def _vel(c, vx=0.0, vy=0.0, vz=0.0, yaw_rate=0.0, frame=M.MAV_FRAME_BODY_NED, mask=BODY_VEL_YAWRATE):
    c.mav.set_position_target_local_ned_send(0, 1, 1, frame, mask, 0, 0, 0, vx, vy, vz, 0, 0, 0, 0, yaw_rate)


def test_guided_velocity_times_out_after_3s(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0}, has_position=True)
    c = _guided(ls)
    ls.run(8.0, every=lambda t: _vel(c, vx=0.5) if round(t * 100) % 10 == 0 else None)
    assert ls.ap.state.u_m_s == pytest.approx(0.35, abs=0.05)
    ls.run(2.8)
    assert ls.ap.state.u_m_s == pytest.approx(0.35, abs=0.05)
    ls.run(1.5)
    assert ls.ap.state.u_m_s < 0.1


def test_guided_yaw_rate_does_not_time_out(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0}, has_position=True)
    c = _guided(ls)
    ls.run(4.0, every=lambda t: _vel(c, yaw_rate=0.3) if round(t * 100) % 10 == 0 else None)
    assert ls.ap.state.r_rad_s == pytest.approx(0.305, abs=0.02)
    ls.run(8.0)
    assert ls.ap.state.r_rad_s == pytest.approx(0.3, abs=0.02)   # still turning
    ls.run(2.0, every=lambda t: _vel(c) if round(t * 100) % 10 == 0 else None)
    assert abs(ls.ap.state.r_rad_s) < 0.03                         # explicit zero stops it


def _heading_turn(ls, c, rate):
    """The link's GUIDED turn: a heading ahead of the vehicle's with the turn speed (setpoints.guided_from_velocity)."""
    sp = guided_from_velocity(VelocityCommand(yaw_rate_rad_s=rate), ls.ap.state.yaw_rad, 1.0)
    c.mav.set_position_target_local_ned_send(0, 1, 1, sp.frame, sp.type_mask, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                             sp.yaw_rad, sp.yaw_rate_rad_s)


def _turned(ls, seconds, every=None):
    """Run ``seconds`` in 0.1 s steps; return the heading change, rad."""
    turned, last = 0.0, ls.ap.state.yaw_rad
    for _ in range(int(round(seconds * 10))):
        ls.run(0.1, every=every)
        turned += wrap_pi(ls.ap.state.yaw_rad - last)
        last = ls.ap.state.yaw_rad
    return turned


def test_guided_heading_turn_is_turned_at_its_speed_and_ends_by_itself(lockstep_factory):
    """As the real firmware (tests/sitl/test_firmware_guided.py): a heading more than 5 deg away is turned toward at
    the given speed, then held; so a turn sent as a heading ahead stops within that lead once the stream stops."""
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0}, has_position=True)
    c = _guided(ls)
    every = lambda rate: (lambda t: _heading_turn(ls, c, rate) if round(t * 100) % 10 == 0 else None)  # noqa: E731
    ls.run(2.0, every=every(0.3))
    assert _turned(ls, 2.0, every(0.3)) / 2.0 == pytest.approx(0.3, abs=0.02)
    ls.run(2.0, every=every(-0.05))
    assert _turned(ls, 2.0, every(-0.05)) / 2.0 == pytest.approx(-0.05, abs=0.01)
    ls.run(2.0, every=every(0.3))
    assert 0.2 < _turned(ls, 6.0) < 0.4              # the stream stops: at most the lead (0.3 rad) further
    assert abs(ls.ap.state.r_rad_s) < 0.02


def test_guided_heading_is_absolute_in_body_ned_and_relative_in_body_offset_ned(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0,
                           "sim.initial_yaw_deg": 90.0}, has_position=True)
    c = _guided(ls)
    send = lambda frame: (lambda t: c.mav.set_position_target_local_ned_send(  # noqa: E731
        0, 1, 1, frame, 455, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, 0.0) if round(t * 100) % 10 == 0 else None)
    ls.run(8.0, every=send(M.MAV_FRAME_BODY_NED))
    assert ls.ap.state.yaw_rad == pytest.approx(0.5, abs=0.03)
    ls.run(0.1, every=send(M.MAV_FRAME_BODY_OFFSET_NED))
    ls.run(8.0)
    assert ls.ap.state.yaw_rad == pytest.approx(1.0, abs=0.03)


def test_guided_body_frame_rotates_by_yaw_and_local_ned_does_not(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0,
                           "sim.initial_yaw_deg": 90.0}, has_position=True)
    c = _guided(ls)
    ls.run(3.0, every=lambda t: _vel(c, vx=0.5, frame=M.MAV_FRAME_BODY_NED))
    s = ls.ap.state
    assert s.ve_m_s > 0.3 and abs(s.vn_m_s) < 0.05   # heading east: body forward = east
    ls.run(4.0, every=lambda t: _vel(c, vx=0.5, frame=M.MAV_FRAME_LOCAL_NED))
    s = ls.ap.state
    assert s.vn_m_s > 0.3 and abs(s.ve_m_s) < 0.05


@pytest.mark.parametrize("mask,frame", [
    (0b0000_0000_0000, M.MAV_FRAME_BODY_NED),           # acceleration not ignored
    (0b0000_0011_1111, M.MAV_FRAME_BODY_NED),           # nothing but acceleration
    (BODY_VEL_YAWRATE, M.MAV_FRAME_GLOBAL_RELATIVE_ALT),  # frame not accepted here
])
def test_guided_invalid_setpoints_ignored(lockstep_factory, mask, frame):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0}, has_position=True)
    c = _guided(ls)
    ls.run(2.0, every=lambda t: _vel(c, vx=0.5, frame=frame, mask=mask))
    assert abs(ls.ap.state.u_m_s) < 0.02 and ls.ap.counters["setpoints_ignored"] > 0
    assert len(ls.messages(c, "COMMAND_ACK")) == 2   # mode + arm; setpoints are never acked


def test_setpoints_ignored_outside_guided(sim):
    c = sim.connect()
    _arm(sim, c)
    acks = len(sim.messages(c, "COMMAND_ACK"))
    sim.run(2.0, every=lambda t: (_vel(c, vx=0.5), send_manual(c)))
    assert abs(sim.ap.state.u_m_s) < 0.02
    assert len(sim.messages(c, "COMMAND_ACK")) == acks


def test_guided_position_target(lockstep_factory):
    ls = lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0}, has_position=True)
    c = _guided(ls)
    c.mav.set_position_target_local_ned_send(0, 1, 1, M.MAV_FRAME_LOCAL_NED, 0b0000_1111_1111_1000,
                                             2.0, 1.0, 4.0, 0, 0, 0, 0, 0, 0, 0, 0)
    ls.run(25.0)
    s = ls.ap.state
    assert (s.north_m, s.east_m, s.depth_m) == pytest.approx((2.0, 1.0, 4.0), abs=0.15)


def test_set_message_interval(sim):
    c = sim.connect()
    command_long(c, M.MAV_CMD_SET_MESSAGE_INTERVAL, M.MAVLINK_MSG_ID_ATTITUDE, 50_000)
    sim.run(0.05)
    ack = _last(sim, c, "COMMAND_ACK")
    assert (ack.command, ack.result, ack.target_system, ack.target_component) == (511, 0, 255, 190)
    sim.clear(c)
    sim.run(2.0)
    assert len(sim.messages(c, "ATTITUDE")) == pytest.approx(40, abs=2)
    command_long(c, M.MAV_CMD_SET_MESSAGE_INTERVAL, M.MAVLINK_MSG_ID_ATTITUDE, -1)
    sim.run(0.1)
    sim.clear(c)
    sim.run(1.0)
    assert not sim.messages(c, "ATTITUDE")
    command_long(c, M.MAV_CMD_SET_MESSAGE_INTERVAL, 9999, 100_000)   # unknown message
    sim.run(0.05)
    assert _last(sim, c, "COMMAND_ACK").result == DENIED


def test_local_position_ned_only_with_position(lockstep_factory):
    for has_position in (False, True):
        ls = lockstep_factory({"sim.initial_depth_m": 2.5}, has_position=has_position)
        c = ls.connect()
        command_long(c, M.MAV_CMD_SET_MESSAGE_INTERVAL, M.MAVLINK_MSG_ID_LOCAL_POSITION_NED, 50_000)
        ls.run(1.0)
        assert _last(ls, c, "COMMAND_ACK").result == ACCEPTED
        lpn = ls.messages(c, "LOCAL_POSITION_NED")
        assert bool(lpn) is has_position
        if lpn:
            assert lpn[-1].z == pytest.approx(2.5, abs=0.01)


def test_telemetry_depth_attitude_hud_sys_status(sim):
    c = sim.connect()
    sim.run(1.2)
    gpi = _last(sim, c, "GLOBAL_POSITION_INT")
    assert gpi.relative_alt == pytest.approx(-3000, abs=10) and gpi.alt == pytest.approx(-3000, abs=10)
    assert _last(sim, c, "VFR_HUD").alt == pytest.approx(-3.0, abs=0.01)
    att = _last(sim, c, "ATTITUDE")
    assert att.yaw == pytest.approx(0.0, abs=1e-3)
    assert ls_count(sim, c, "ATTITUDE") >= 10 and ls_count(sim, c, "SYS_STATUS") >= 2


def ls_count(ls, c, kind):
    return len(ls.messages(c, kind))


@pytest.mark.parametrize("name,value", [("SYSID_MYGCS", 255), ("FS_PILOT_INPUT", 2), ("FS_PILOT_TIMEOUT", 3.0),
                                        ("FS_GCS_ENABLE", 2), ("JS_GAIN_DEFAULT", 0.5), ("RC_OVERRIDE_TIME", 3.0)])
def test_param_request_read(sim, name, value):
    c = sim.connect()
    c.mav.param_request_read_send(1, 1, name.encode(), -1)
    sim.run(0.05)
    pv = _last(sim, c, "PARAM_VALUE")
    assert (pv.param_id, pv.param_value, pv.param_type) == (name, pytest.approx(value), M.MAV_PARAM_TYPE_REAL32)


def test_param_unknown_no_reply_and_param_set(sim):
    c = sim.connect()
    c.mav.param_request_read_send(1, 1, b"FS_GCS_TIMEOUT", -1)
    sim.run(0.1)
    assert not sim.messages(c, "PARAM_VALUE")
    c.mav.param_set_send(1, 1, b"FS_PILOT_TIMEOUT", 1.5, M.MAV_PARAM_TYPE_REAL32)
    sim.run(0.05)
    pv = _last(sim, c, "PARAM_VALUE")
    assert (pv.param_id, pv.param_value) == ("FS_PILOT_TIMEOUT", 1.5)
    assert sim.ap.ap_params["FS_PILOT_TIMEOUT"] == 1.5


def test_depth_cannot_go_above_surface(sim):
    c = sim.connect()
    _arm(sim, c)
    sim.run(12.0, every=lambda t: send_manual(c, z=1000))
    assert sim.ap.state.depth_m == 0.0
    assert _last(sim, c, "GLOBAL_POSITION_INT").relative_alt == 0


def test_udp_link(sim):
    c = sim.connect(sim.ap.addresses[1])
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    sim.run(1.1)
    assert _last(sim, c, "COMMAND_ACK").result == ACCEPTED and _last(sim, c, "HEARTBEAT").base_mode == 209


def test_rc_channels_override_same_sysid_rule(sim):
    c = sim.connect()
    other = sim.connect(sysid=1, compid=191)
    _arm(sim, c)
    sim.run(1.0, every=lambda t: other.mav.rc_channels_override_send(1, 1, 0, 0, 1500, 1500, 1700, 1500, 0, 0))
    assert sim.ap.pilot.forward == 1500
    sim.run(1.0, every=lambda t: c.mav.rc_channels_override_send(1, 1, 0, 0, 1500, 1500, 1700, 1500, 0, 0))
    assert sim.ap.pilot.forward == 1700 and sim.ap.state.u_m_s > 0.5


def test_lockstep_is_deterministic(lockstep_factory):
    def run():
        ls = lockstep_factory({"sim.initial_depth_m": 3.0})
        c = ls.connect()
        _arm(ls, c)
        ls.run(6.0, every=lambda t: (send_manual(c, x=400, y=-200, z=700, r=300), c.mav.heartbeat_send(6, 8, 0, 0, 0)))
        ls.run(5.0)   # silence: pilot-input and GCS failsafes
        return ls.ap.state, [(round(e.time_s - ls.ap._t0, 6), e.kind, e.detail) for e in ls.ap.events]
    assert run() == run()

"""VehicleLink over real loopback sockets against the fake ArduSub, in simulated time."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import pytest
from pymavlink import mavutil

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.errors import LinkError
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.connection import mavlink2, use_mavlink2
from dip3d_vehicle.servo.command import VelocityCommand

from fake_ardusub import MOVE, FakeAutopilot, Harness, link_params


def _moving(r) -> bool:
    m = r.msg
    if r.kind == "MANUAL_CONTROL":
        return not (m.x == 0 and m.y == 0 and m.r == 0 and m.z == 500)
    if r.kind == "SET_POSITION_TARGET_LOCAL_NED":
        return any(abs(v) > 0 for v in (m.vx, m.vy, m.vz, m.yaw_rate))
    return False


def _motion(fake: FakeAutopilot, since: float = -1e9):
    return [r for r in fake.received if _moving(r) and r.t >= since]


# ---------------------------------------------------------------- identity, params, intervals

def test_identity_heartbeat_and_manual_control_as_sysid_mygcs(make_udp, caplog) -> None:
    with caplog.at_level(logging.WARNING, logger="dip3d_vehicle.link"):
        h = make_udp(fake_kw={"sysid_mygcs": 250})
    assert "MANUAL_CONTROL will be sent with the ground station's system id" in caplog.text
    h.fake._gcs = None  # the fake GCS speaks as 250 too
    h.run(1.5)
    hbs = h.fake.of("HEARTBEAT")
    assert hbs and all(r.src == (1, 191) for r in hbs)
    assert all(r.msg.type == 18 and r.msg.autopilot == 8 for r in hbs)
    assert h.link.gcs.sysid == 250 and h.link.gcs.sysid_from_autopilot
    h.engage(command=MOVE)
    h.run(1.0, MOVE)
    mc = h.fake.of("MANUAL_CONTROL")
    assert mc and all(r.src[0] == 250 for r in mc) and all(r.msg.target == 1 for r in mc)
    assert all(r.msg.buttons == 0 for r in mc)
    # nothing but MANUAL_CONTROL ever carries the ground station's id
    assert {r.kind for r in h.fake.received if r.src[0] == 250} == {"MANUAL_CONTROL"}
    # streaming rate: about 20 Hz, independent of how often tick() is called
    last_s = [r for r in mc if r.t > h.clock.now() - 1.0]
    assert 18 <= len(last_s) <= 22


def test_message_intervals_requested_at_connect_and_after_reboot(make_udp) -> None:
    h = make_udp()
    h.run(1.0)
    reqs = h.fake.of("COMMAND_LONG")
    ids = sorted(int(r.msg.param1) for r in reqs if r.msg.command == 511)
    assert ids == sorted([30, 33, 74, 1])  # ATTITUDE, GLOBAL_POSITION_INT, VFR_HUD, SYS_STATUS
    att = [r for r in reqs if r.msg.command == 511 and int(r.msg.param1) == 30][0]
    assert att.msg.param2 == pytest.approx(1e5)
    t_reboot = h.clock.now() + 5.0
    h.run(5.0)
    assert not [r for r in h.fake.of("COMMAND_LONG", since=h.clock.now() - 3.0) if r.msg.command == 511]
    h.fake.reboot()
    h.run(0.5)
    again = [r for r in h.fake.of("COMMAND_LONG", since=t_reboot) if r.msg.command == 511]
    assert len(again) == 4
    assert h.fake.of("PARAM_REQUEST_READ", since=t_reboot)
    assert any("rebooted" in e for e in h.link.events)


def test_intervals_rerequested_after_heartbeat_gap(make_udp) -> None:
    h = make_udp()
    h.run(1.0)
    h.fake.alive = False
    h.run(3.0)
    t = h.clock.now()
    h.fake.alive = True
    h.run(0.5)
    assert len([r for r in h.fake.of("COMMAND_LONG", since=t) if r.msg.command == 511]) == 4
    assert h.link.autopilot.boots == 2


def test_sysid_mygcs_unreadable_refuses_to_engage_with_reason(make_udp, caplog) -> None:
    h = make_udp(fake_kw={"answer_params": False}, auto_enable=True)
    h.fake.armed, h.fake.mode = True, "ALT_HOLD"
    with caplog.at_level(logging.WARNING, logger="dip3d_vehicle.link"):
        h.run(6.0, MOVE)
    assert not h.link.engaged
    assert "SYSID_MYGCS could not be read" in h.link.not_engaged_reason
    assert "SYSID_MYGCS could not be read" in caplog.text
    assert not h.fake.of("MANUAL_CONTROL")
    assert len(h.fake.of("PARAM_REQUEST_READ")) >= 8  # retried (both names, every second)


def test_sysid_mygcs_equal_to_own_sysid_refused(make_udp) -> None:
    h = make_udp(fake_kw={"sysid_mygcs": 1}, auto_enable=True, require_gcs=False)
    h.fake.armed, h.fake.mode = True, "ALT_HOLD"
    h.run(2.0, MOVE)
    assert not h.link.engaged and "own system id" in h.link.not_engaged_reason
    assert not h.fake.of("MANUAL_CONTROL")


def test_guided_velocity_never_uses_gcs_identity(make_udp) -> None:
    h = make_udp(output_mode="guided_velocity")
    h.engage("GUIDED", MOVE)
    h.run(1.0, MOVE)
    assert not h.fake.of("MANUAL_CONTROL")
    assert all(r.src == (1, 191) for r in h.fake.received)
    sp = h.fake.of("SET_POSITION_TARGET_LOCAL_NED")[-1].msg
    assert (sp.coordinate_frame, sp.type_mask) == (8, 455)  # a turn is a heading ahead: it ends by itself
    assert (sp.vx, sp.yaw, sp.yaw_rate) == (pytest.approx(0.3), pytest.approx(0.2), pytest.approx(0.2))
    lpn = [r for r in h.fake.of("COMMAND_LONG") if r.msg.command == 511 and int(r.msg.param1) == 32]
    assert lpn  # LOCAL_POSITION_NED asked for in guided


def test_a_guided_turn_is_withheld_without_a_heading_and_said_once(make_udp, caplog) -> None:
    """An ATTITUDE without a usable yaw (NaN: a broken estimate) gives no heading: the velocity goes out, the turn
    does not (a plain yaw rate would never end on a link loss); counted, warned about once."""
    h = make_udp(output_mode="guided_velocity", fake_kw={"attitude_yaw_rad": math.nan})
    with caplog.at_level(logging.WARNING, logger="dip3d_vehicle.link"):
        h.engage("GUIDED", MOVE)
        h.run(1.0, MOVE)
    sp = h.fake.of("SET_POSITION_TARGET_LOCAL_NED")[-1].msg
    assert (sp.type_mask, sp.vx, sp.yaw_rate) == (1479, pytest.approx(0.3), 0.0)
    assert h.link.stats.turns_withheld >= 10
    assert caplog.text.count("GUIDED turns withheld for 0.6 s") == 1


def test_a_link_loss_mid_turn_is_not_called_a_missing_heading(make_udp, caplog) -> None:
    """The heading goes stale with everything else when the autopilot falls silent: the link disengages
    ("autopilot lost") before a missing heading is worth a warning (seen once in a GUIDED link-cut mission)."""
    h = make_udp(output_mode="guided_velocity")
    h.engage("GUIDED", MOVE)
    h.run(1.0, MOVE)
    h.fake.alive = False
    with caplog.at_level(logging.WARNING, logger="dip3d_vehicle.link"):
        h.run(2.0, MOVE)
    assert not h.link.engaged and "autopilot lost" in h.link.disengage_reason
    assert "GUIDED turns withheld" not in caplog.text


# ---------------------------------------------------------------- engage gating

def test_engage_only_when_armed_right_mode_and_enabled(make_udp) -> None:
    h = make_udp()
    h.run(2.0, MOVE)
    assert not h.link.engaged and not _motion(h.fake)
    h.fake.armed = True
    h.fake.heartbeat()
    h.run(1.0, MOVE)
    assert not h.link.engaged  # MANUAL mode, not enabled
    h.fake.mode = "ALT_HOLD"
    h.fake.heartbeat()
    h.run(1.0, MOVE)
    assert not h.link.engaged and h.link.not_engaged_reason == "not enabled by the operator"
    assert not _motion(h.fake)
    h.fake.operator(True)
    h.run(0.2, MOVE)
    assert h.link.engaged and _motion(h.fake)
    ack = h.fake.of("COMMAND_ACK")[-1]
    assert ack.src == (1, 191) and ack.msg.command == 31010 and ack.msg.result == 0


def test_operator_command_from_non_gcs_is_denied(make_udp) -> None:
    h = make_udp()
    h.fake.armed, h.fake.mode = True, "ALT_HOLD"
    h.run(1.0)
    h.fake.operator(True, as_gcs=False)  # from the autopilot's own id (1, 1)
    h.run(1.0, MOVE)
    assert not h.link.engaged and h.link.stats.operator_commands_denied == 1
    assert h.fake.of("COMMAND_ACK")[-1].msg.result == 2  # DENIED


@pytest.mark.parametrize("action", ["mode", "disarm"])
def test_pilot_mode_change_or_disarm_stops_motion_and_does_not_reengage(make_udp, action: str) -> None:
    h = make_udp()
    h.engage(command=MOVE)
    h.run(1.0, MOVE)
    if action == "mode":
        h.fake.mode = "MANUAL"
    else:
        h.fake.armed = False
    h.fake.heartbeat()
    t_change = h.clock.now()
    h.run(2.0, MOVE)
    # the heartbeat reached the link during the first step after t_change: no motion after it
    assert not _motion(h.fake, since=t_change + 0.011)
    neutral = [r for r in h.fake.of("MANUAL_CONTROL", since=t_change) if not _moving(r)]
    assert neutral and neutral[0].t <= t_change + 0.02
    assert not h.fake.of("MANUAL_CONTROL", since=t_change + 1.1)  # silent after the stop window
    expected = "mode changed ALT_HOLD -> MANUAL" if action == "mode" else "disarmed"
    assert h.link.disengage_reason == expected
    assert any(e.endswith("disengaged: " + expected) for e in h.link.events)
    # the pilot hands back: no automatic re-engage
    h.fake.mode, h.fake.armed = "ALT_HOLD", True
    h.fake.heartbeat()
    h.run(2.0, MOVE)
    assert not h.link.engaged and not _motion(h.fake, since=t_change + 0.011)


def test_many_trials_mode_change_never_followed_by_motion(make_udp) -> None:
    for trial in range(20):
        h = make_udp()
        h.engage(command=MOVE)
        h.run(0.3 + 0.037 * trial, MOVE)
        h.fake.mode = "STABILIZE" if trial % 2 else "MANUAL"
        h.fake.armed = trial % 3 != 0
        h.fake.heartbeat()
        t_change = h.clock.now()
        h.run(1.5, MOVE)
        assert not _motion(h.fake, since=t_change + 0.011), trial
        h.link.close()
        h.fake.close()


def test_heartbeat_loss_stops_motion_within_one_second(make_udp) -> None:
    for trial in range(20):
        h = make_udp()
        h.engage(command=MOVE)
        h.run(0.5 + 0.013 * trial, MOVE)
        h.fake.alive = False
        t_last = h.fake.last_sent_s
        h.run(2.0, MOVE)
        moving = _motion(h.fake)
        assert moving[-1].t <= t_last + 1.0, (trial, moving[-1].t - t_last)
        assert not h.link.engaged and h.link.disengage_reason == "autopilot lost"
        # the autopilot comes back (e.g. after a reboot): no automatic re-engage
        h.fake.alive = True
        h.run(1.0, MOVE)
        assert not h.link.engaged
        h.link.close()
        h.fake.close()


def test_gcs_loss_stops_manual_control_so_autopilot_failsafe_can_act(make_udp) -> None:
    h = make_udp()
    h.engage(command=MOVE)
    h.run(1.0, MOVE)
    h.fake.gcs_alive = False
    t_lost = h.clock.now()
    h.run(6.0, MOVE)
    assert h.link.disengage_reason == "ground station lost"
    last_mc = h.fake.of("MANUAL_CONTROL")[-1]
    cfg = h.link.config
    assert last_mc.t <= t_lost + cfg.gcs_timeout_s + cfg.stop_zero_s + 0.1
    assert not _motion(h.fake, since=t_lost + cfg.gcs_timeout_s + 0.05)


def test_stale_perception_sends_neutral_then_resumes(make_udp) -> None:
    h = make_udp()
    h.engage(command=MOVE)
    h.run(0.5, MOVE)
    t_stale = h.clock.now()
    h.run(2.0, MOVE, fresh=False)
    assert not _motion(h.fake, since=t_stale + 0.001)
    assert h.link.disengage_reason == "perception stale"
    assert [r for r in h.fake.of("MANUAL_CONTROL", since=t_stale) if not _moving(r)]
    h.run(0.5, MOVE)
    assert h.link.engaged and _motion(h.fake, since=t_stale + 2.0)


def test_perception_stamp_too_old_is_stale(make_udp) -> None:
    h = make_udp()
    h.engage(command=MOVE)
    stamp = h.clock.now()
    for _ in range(100):
        h.clock.advance(0.01)
        h.fake.update()
        h.link.poll()
        h.link.tick(MOVE, True, perception_stamp_s=stamp)
        h.fake.poll()
    assert not h.link.engaged and h.link.disengage_reason == "perception stale"
    assert not _motion(h.fake, since=stamp + h.link.config.perception_timeout_s + 0.02)


def test_guided_zero_yaw_rate_within_one_second_of_disengaging(make_udp) -> None:
    for trial, action in enumerate(["mode", "disarm", "lost", "stale", "operator"] * 4):
        h = make_udp(output_mode="guided_velocity")
        h.engage("GUIDED", MOVE)
        h.run(0.4 + 0.021 * trial, MOVE)
        fresh = True
        if action == "mode":
            h.fake.mode = "ALT_HOLD"
            h.fake.heartbeat()
        elif action == "disarm":
            h.fake.armed = False
            h.fake.heartbeat()
        elif action == "lost":
            h.fake.alive = False
        elif action == "stale":
            fresh = False
        else:
            h.fake.operator(False)
        t0 = h.clock.now()
        for _ in range(150):
            h.step(MOVE, fresh)
            if not h.link.engaged:
                break
        t_dis = h.clock.now()
        h.run(2.0, MOVE, fresh=fresh)
        sps = h.fake.of("SET_POSITION_TARGET_LOCAL_NED", since=t0)
        zeros = [r for r in sps if r.msg.yaw_rate == 0.0 and not _moving(r)]
        assert zeros and zeros[0].t <= t_dis + 1.0, (trial, action)
        assert not [r for r in sps if _moving(r) and r.t > t_dis], (trial, action)
        assert sps[-1].msg.yaw_rate == 0.0
        assert len(zeros) >= 15  # stop window: ~1 s at 20 Hz
        h.link.close()
        h.fake.close()


def test_close_sends_neutral(make_udp) -> None:
    h = make_udp()
    h.engage(command=MOVE)
    h.run(0.5, MOVE)
    before = len(h.fake.of("MANUAL_CONTROL"))
    h.link.close()
    h.fake.poll()
    mc = h.fake.of("MANUAL_CONTROL")[before:]
    assert len(mc) >= 3 and not any(_moving(r) for r in mc)


def test_other_systems_heartbeats_are_ignored(make_udp) -> None:
    h = make_udp()
    h.run(1.0)
    rogue = mavlink2.MAVLink(h.fake.conn, srcSystem=1, srcComponent=2)
    other = mavlink2.MAVLink(h.fake.conn, srcSystem=7, srcComponent=1)
    for enc in (rogue, other):
        enc.send(mavlink2.MAVLink_heartbeat_message(12, 3, 209, 2, 4, 3))
    h.run(0.05)
    assert not h.link.autopilot.armed and h.link.autopilot.mode == "MANUAL"
    assert h.link.stats.ignored_heartbeats == 2


# ---------------------------------------------------------------- signing

def test_signing_both_ways_commands_signed(make_udp, tmp_path: Path) -> None:
    key = bytes(range(32))
    (tmp_path / "key").write_bytes(key)
    h = make_udp(fake_key=key, signing_key_file=str(tmp_path / "key"))
    h.engage(command=MOVE)
    h.run(0.5, MOVE)
    mc = h.fake.of("MANUAL_CONTROL")
    assert mc and all(r.msg._signed for r in mc)
    assert all(r.msg._signed for r in h.fake.of("HEARTBEAT"))
    assert h.fake.conn.mav.signing.goodsig_count > 10 and h.fake.conn.mav.signing.badsig_count == 0
    assert h.link.stats.rejected_bad_signature == 0 and h.link.stats.rejected_unsigned == 0


def test_wrong_key_and_unsigned_peers_ignored_and_counted(make_udp, tmp_path: Path) -> None:
    (tmp_path / "key").write_text("the right passphrase\n")
    h = make_udp(fake_key=b"\x01" * 32, signing_key_file=str(tmp_path / "key"), auto_enable=True)
    h.fake.armed, h.fake.mode = True, "ALT_HOLD"
    h.run(2.0, MOVE)
    assert h.link.autopilot.last_message_s is None and not h.link.engaged
    assert h.link.stats.rejected_bad_signature > 10
    assert not _motion(h.fake)
    # an unsigned peer on a second socket
    unsigned = FakeAutopilot.udp(h.clock, h.link._conn.port.getsockname()[1], armed=True, mode="ALT_HOLD")
    try:
        for _ in range(5):
            unsigned.heartbeat()
        h.run(0.1, MOVE)
        assert h.link.stats.rejected_unsigned >= 5
        assert h.link.autopilot.last_message_s is None and not h.link.engaged
    finally:
        unsigned.close()


# ---------------------------------------------------------------- tcp, config errors

def test_tcp_link_engages_and_stops_on_mode_change() -> None:
    clock = SimClock(10.0)
    fake, port = FakeAutopilot.tcp_server(clock)
    link = VehicleLink(link_params(url=f"tcp:127.0.0.1:{port}"), clock)
    link.open()
    try:
        h = Harness(link, fake, clock)
        fake.poll()  # accept the connection
        h.engage(command=MOVE)
        h.run(0.5, MOVE)
        assert _motion(fake) and all(r.src[0] == 255 for r in fake.of("MANUAL_CONTROL"))
        fake.mode = "MANUAL"
        fake.heartbeat()
        t = clock.now()
        h.run(1.5, MOVE)
        assert not _motion(fake, since=t + 0.011) and not link.engaged
    finally:
        link.close()
        fake.close()


@pytest.mark.parametrize("over, words", [
    ({"url": "bogus"}, "expected udpin"),
    ({"url": "udpin:127.0.0.1:notaport"}, "HOST:PORT"),
    ({"url": "tcp:127.0.0.1:1"}, "cannot open"),
    ({"output_mode": "guided_velocity", "engage_mode": "ALT_HOLD"}, "needs GUIDED"),
])
def test_bad_configuration_explained(over: dict, words: str) -> None:
    with pytest.raises(LinkError, match=words):
        VehicleLink(link_params(**over), SimClock()).open()


def test_command_none_is_neutral(make_udp) -> None:
    h = make_udp()
    h.engage()
    h.run(0.5, None)
    assert h.fake.of("MANUAL_CONTROL") and not _motion(h.fake)
    h.run(0.2, VelocityCommand())
    assert not _motion(h.fake)


def test_tcp_reconnects_after_peer_restart_and_rerequests_intervals() -> None:
    clock = SimClock(10.0)
    fake, port = FakeAutopilot.tcp_server(clock)
    link = VehicleLink(link_params(url=f"tcp:127.0.0.1:{port}", reconnect_s=0.5), clock)
    link.open()
    fake.poll()
    h = Harness(link, fake, clock)
    try:
        h.run(1.0)
        assert link.autopilot.boots == 1
        fake.close()
        h.run(0.1)  # the link sees EOF
        assert any("closed by the peer" in e for e in link.events)
        conn = mavutil.mavlink_connection(f"tcpin:127.0.0.1:{port}", source_system=1, source_component=1)
        use_mavlink2(conn)
        h.fake = fake = FakeAutopilot(conn=conn, clock=clock)
        h.run(2.0)
        assert any("tcp reconnected" in e for e in link.events)
        assert link.autopilot.boots == 2 and link.autopilot.alive(clock.now(), 0.6)
        assert len([r for r in fake.of("COMMAND_LONG") if r.msg.command == 511]) == 4
    finally:
        link.close()
        fake.close()


def test_heartbeat_only_autopilot_never_engaged(make_udp) -> None:
    h = make_udp(fake_kw={"attitude_hz": 0.5}, auto_enable=True)
    h.fake.poll = lambda: FakeAutopilot.poll(h.fake) or setattr(h.fake, "attitude_hz", 0.5)  # refuses intervals
    h.fake.armed, h.fake.mode = True, "ALT_HOLD"
    h.run(5.0, MOVE)
    assert not h.link.engaged and not _motion(h.fake)
    assert "slower than the liveness timeout" in h.link.not_engaged_reason or \
        h.link.not_engaged_reason == "autopilot not heard"

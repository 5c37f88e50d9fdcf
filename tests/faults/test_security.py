"""Security end to end: MAVLink 2 signing with key files on both sides, identity filtering, own identity.

Set-up (all loopback, lockstep on one SimClock): the simulated autopilot (sitl.Autopilot) signs with
the key; it listens on serial 0 (tcp, unused here) and three UDP links (not serial 0, so unsigned
traffic is dropped): one for the controller (VehicleLink with ``link.signing_key_file``), one for a
signed ground station, one for an attacker. The attacker (pymavlink, no key or a wrong key) sends
every motion-capable command to the autopilot and every operator/telemetry message to the
controller; none may have any effect, and each is counted.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import pytest
from pymavlink import mavutil

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link import MAV_CMD_USER_1, VehicleLink
from dip3d_vehicle.link.connection import mavlink2 as m2, use_mavlink2
from dip3d_vehicle.servo.command import VelocityCommand
from sitl.autopilot import Autopilot

PASSPHRASE = "dip3d test key"
KEY = hashlib.sha256(PASSPHRASE.encode()).digest()
WRONG_KEY = hashlib.sha256(b"not the key").digest()
GCS = (255, 190)
FORWARD = VelocityCommand(surge_m_s=0.3)


def _client(port: int, sysid: int, compid: int, key: bytes | None):
    conn = mavutil.mavlink_connection(f"udpout:127.0.0.1:{port}", source_system=sysid, source_component=compid)
    use_mavlink2(conn)
    if key is not None:
        conn.setup_signing(key, sign_outgoing=True)
    return conn


@dataclass
class Rig:
    clock: SimClock
    ap: Autopilot
    link: VehicleLink
    gcs: object
    gcs_to_ctrl: object
    ctrl_port: int
    gcs_port: int
    attacker_port: int
    seen_by_ap: list = field(default_factory=list)   # (link name, type, src) of accepted messages
    _next_gcs_hb: float = 0.0

    def step(self, seconds: float, command: VelocityCommand | None = FORWARD, gcs_heartbeat: bool = True) -> None:
        end = self.clock.now() + seconds
        while self.clock.now() < end - 1e-9:
            now = self.clock.advance(0.02)
            self.ap.step()
            if gcs_heartbeat and now >= self._next_gcs_hb:
                for g in (self.gcs, self.gcs_to_ctrl):  # the autopilot routes nothing: tell both
                    g.mav.heartbeat_send(m2.MAV_TYPE_GCS, m2.MAV_AUTOPILOT_INVALID, 0, 0, 0)
                self._next_gcs_hb = now + 1.0
            for g in (self.gcs, self.gcs_to_ctrl):
                while g.recv_msg() is not None:
                    pass
            self.link.poll()
            self.link.tick(command, perception_fresh=True, perception_stamp_s=now)

    def gcs_command(self, target: tuple[int, int], command: int, *params: float) -> None:
        p = list(params) + [0.0] * (7 - len(params))
        conn = self.gcs_to_ctrl if target == (1, 191) else self.gcs
        conn.mav.command_long_send(target[0], target[1], command, 0, *p)

    def close(self) -> None:
        self.link.close()
        self.gcs.close()
        self.gcs_to_ctrl.close()
        self.ap.close()


def _rig(tmp_path, output_mode: str = "manual_control", signing: bool = True) -> Rig:
    key_file = tmp_path / "signing.key"
    key_file.write_text(PASSPHRASE + "\n")
    clock = SimClock()
    guided = output_mode == "guided_velocity"
    params = load_params()
    if guided:  # no joystick in these tests: ArduSub's pilot-input failsafe would disarm in GUIDED
        params = params.with_overrides({"sim.pilot_input_failsafe": False}, "test")
    ap = Autopilot(params, clock, listen=["tcp:127.0.0.1:0", "udpin:127.0.0.1:0", "udpin:127.0.0.1:0",
                                          "udpin:127.0.0.1:0"], signing_key=KEY if signing else None,
                   has_position=guided)
    ports = [int(a.rsplit(":", 1)[1]) for a in ap.addresses[1:]]
    seen: list = []
    orig = ap._handle

    def handle(link, msg, now):
        seen.append((link.name, msg.get_type(), (msg.get_srcSystem(), msg.get_srcComponent())))
        orig(link, msg, now)
    ap._handle = handle
    link = VehicleLink({"link.url": f"udpout:127.0.0.1:{ports[0]}", "link.output_mode": output_mode,
                        "link.signing_key_file": str(key_file) if signing else ""}, clock)
    link.open()
    gcs = _client(ports[1], *GCS, KEY if signing else None)
    link.poll()
    gcs_to_ctrl = _client(link._conn.port.getsockname()[1], *GCS, KEY if signing else None)
    rig = Rig(clock, ap, link, gcs, gcs_to_ctrl, ports[0], ports[1], ports[2], seen)
    rig.step(0.5)
    return rig


def _hand_over(rig: Rig, mode: str) -> None:
    """The signed ground station arms, selects the engage mode and enables the controller."""
    rig.gcs_command((1, 1), m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
    rig.gcs_command((1, 1), m2.MAV_CMD_DO_SET_MODE, 1.0, {"ALT_HOLD": 2.0, "GUIDED": 4.0}[mode])
    rig.step(1.5)
    rig.gcs_command((1, 191), MAV_CMD_USER_1, 1.0)
    rig.step(1.0)


@pytest.mark.parametrize("output_mode", ["manual_control", "guided_velocity"])
def test_signed_control_works(tmp_path, output_mode):
    rig = _rig(tmp_path, output_mode)
    try:
        _hand_over(rig, rig.link.config.engage_mode)
        assert rig.ap.armed and rig.ap.mode_name == rig.link.config.engage_mode
        assert rig.link.engaged, rig.link.not_engaged_reason
        north0 = rig.ap.state.north_m
        rig.step(3.0)
        assert rig.ap.state.north_m - north0 > 0.3  # the vehicle moved forward on signed commands
        assert rig.ap.dropped_unsigned == 0
        assert rig.link.stats.rejected_unsigned == 0 and rig.link.stats.rejected_bad_signature == 0
        assert "signing on" in rig.link.events[0]
    finally:
        rig.close()


# Every message an attacker would use, to the autopilot (1, 1) and to the controller (1, 191).
def _attacks(mav) -> dict[str, list]:
    return {
        "arm": [mav.command_long_encode(1, 1, m2.MAV_CMD_COMPONENT_ARM_DISARM, 0, 1, 0, 0, 0, 0, 0, 0)],
        "disarm": [mav.command_long_encode(1, 1, m2.MAV_CMD_COMPONENT_ARM_DISARM, 0, 0, 21196, 0, 0, 0, 0, 0)],
        "mode": [mav.command_long_encode(1, 1, m2.MAV_CMD_DO_SET_MODE, 0, 1, 19, 0, 0, 0, 0, 0),
                 mav.set_mode_encode(1, 1, 0)],
        "MANUAL_CONTROL": [mav.manual_control_encode(1, 1000, 0, 500, 1000, 0)],
        "SET_POSITION_TARGET_LOCAL_NED": [mav.set_position_target_local_ned_encode(
            0, 1, 1, m2.MAV_FRAME_BODY_NED, 0b110111000111, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 1.0)],
        "SETUP_SIGNING": [mav.setup_signing_encode(1, 1, bytes(32), 0)],
        "PARAM_SET": [mav.param_set_encode(1, 1, b"SYSID_MYGCS", 42.0, m2.MAV_PARAM_TYPE_REAL32)],
        "controller_enable": [mav.command_long_encode(1, 191, MAV_CMD_USER_1, 0, 1, 0, 0, 0, 0, 0, 0)],
        "controller_disable": [mav.command_long_encode(1, 191, MAV_CMD_USER_1, 0, 0, 0, 0, 0, 0, 0, 0)],
        "spoofed_autopilot_heartbeat": [mav.heartbeat_encode(m2.MAV_TYPE_SUBMARINE, m2.MAV_AUTOPILOT_ARDUPILOTMEGA,
                                                            81, 19, m2.MAV_STATE_STANDBY)],
    }


@pytest.mark.parametrize("attacker_key", [None, WRONG_KEY], ids=["unsigned", "wrong_key"])
@pytest.mark.parametrize("output_mode", ["manual_control", "guided_velocity"])
def test_unsigned_and_wrong_key_traffic_is_ignored(tmp_path, attacker_key, output_mode, summary):
    rig = _rig(tmp_path, output_mode)
    try:
        _hand_over(rig, rig.link.config.engage_mode)
        assert rig.link.engaged
        # the attacker speaks as the ground station (255) and as the autopilot (1, 1): identities are
        # worthless without the key.
        attackers = {
            "to_autopilot": _client(rig.attacker_port, 255, 190, attacker_key),
            "to_controller": None,
        }
        ctrl_port = rig.link._conn.port.getsockname()[1]
        as_gcs = _client(ctrl_port, 255, 190, attacker_key)
        as_ap = _client(ctrl_port, 1, 1, attacker_key)
        sent: dict[str, int] = {}
        ap_dropped0, ap_in0 = rig.ap.dropped_unsigned, rig.ap.counters["messages_in"]
        rej0 = rig.link.stats.rejected_unsigned + rig.link.stats.rejected_bad_signature
        events0 = list(rig.ap.events)
        rounds = 25
        for _ in range(rounds):
            for name, msgs in _attacks(attackers["to_autopilot"].mav).items():
                if name.startswith("controller_") or name.startswith("spoofed"):
                    continue
                for msg in msgs:
                    attackers["to_autopilot"].mav.send(msg)
                    sent[f"autopilot:{name}"] = sent.get(f"autopilot:{name}", 0) + 1
            for name in ("controller_enable", "controller_disable", "MANUAL_CONTROL", "mode"):
                for msg in _attacks(as_gcs.mav)[name]:
                    as_gcs.mav.send(msg)
                    sent[f"controller:{name}"] = sent.get(f"controller:{name}", 0) + 1
            for msg in _attacks(as_ap.mav)["spoofed_autopilot_heartbeat"]:
                as_ap.mav.send(msg)
                sent["controller:spoofed_autopilot_heartbeat"] = sent.get("controller:spoofed_autopilot_heartbeat", 0) + 1
            rig.step(0.1)
        rig.step(0.5)
        to_ap = sum(v for k, v in sent.items() if k.startswith("autopilot:"))
        to_ctrl = sum(v for k, v in sent.items() if k.startswith("controller:"))
        dropped_ap = rig.ap.dropped_unsigned - ap_dropped0
        rejected_ctrl = rig.link.stats.rejected_unsigned + rig.link.stats.rejected_bad_signature - rej0
        attacker_links = {n for n, _, _ in rig.seen_by_ap[-2000:] if n.endswith(str(rig.attacker_port))}
        summary(f"[security {output_mode} {'unsigned' if attacker_key is None else 'wrong key'}] sent "
                f"{to_ap} to the autopilot, dropped {dropped_ap}; sent {to_ctrl} to the controller, "
                f"rejected {rejected_ctrl}; per type: {sent}")
        # 100 % ignored, counted
        assert dropped_ap == to_ap
        assert rejected_ctrl == to_ctrl
        assert not attacker_links
        assert [e for e in rig.ap.events if e not in events0 and e.kind in ("armed", "mode", "param", "signing")] == []
        assert rig.ap.armed and rig.ap.mode_name == rig.link.config.engage_mode
        assert rig.link.engaged and rig.link.operator_enabled
        assert rig.link.autopilot.mode == rig.link.config.engage_mode and rig.link.autopilot.armed
        assert rig.ap.ap_params["SYSID_MYGCS"] == 255
        for c in (attackers["to_autopilot"], as_gcs, as_ap):
            c.close()
    finally:
        rig.close()


def test_wrong_system_or_component_never_changes_the_autopilot_state(tmp_path):
    """Without signing: only (target_system, target_component) is the autopilot; others are ignored."""
    rig = _rig(tmp_path, signing=False)
    try:
        _hand_over(rig, "ALT_HOLD")
        assert rig.link.engaged
        ctrl_port = rig.link._conn.port.getsockname()[1]
        impostors = [_client(ctrl_port, s, c, None) for s, c in ((1, 2), (2, 1), (1, 191), (255, 1), (42, 1))]
        before = rig.link.stats.ignored_heartbeats
        n = 0
        for _ in range(20):
            for imp in impostors:
                # disarmed, MANUAL: would disengage the controller if believed
                imp.mav.heartbeat_send(m2.MAV_TYPE_SUBMARINE, m2.MAV_AUTOPILOT_ARDUPILOTMEGA, 81, 19, m2.MAV_STATE_STANDBY)
                n += 1
            rig.step(0.1)
        assert rig.link.stats.ignored_heartbeats - before == n
        assert rig.link.autopilot.armed and rig.link.autopilot.mode == "ALT_HOLD"
        assert rig.link.engaged
        # operator commands (disable) from anyone but the ground station's system id are denied
        denied0 = rig.link.stats.operator_commands_denied
        for imp in impostors:
            if imp.mav.srcSystem != 255:
                imp.mav.command_long_send(1, 191, MAV_CMD_USER_1, 0, 0, 0, 0, 0, 0, 0, 0)
        rig.step(0.5)
        assert rig.link.stats.operator_commands_denied - denied0 == 4
        assert rig.link.engaged and rig.link.operator_enabled
        assert not any("disengaged" in e for e in rig.link.events)
        for imp in impostors:
            imp.close()
    finally:
        rig.close()


@pytest.mark.parametrize("output_mode", ["manual_control", "guided_velocity"])
def test_controller_identity(tmp_path, output_mode):
    """Own HEARTBEAT always 1/191; the GCS id 255 only on MANUAL_CONTROL and only in manual_control,
    which is announced with a warning at start."""
    rig = _rig(tmp_path, output_mode)
    try:
        _hand_over(rig, rig.link.config.engage_mode)
        rig.step(3.0)
        from_ctrl = [(kind, src) for name, kind, src in rig.seen_by_ap if name.endswith(f":{rig.ctrl_port}")]
        heartbeats = {src for kind, src in from_ctrl if kind == "HEARTBEAT"}
        assert heartbeats == {(1, 191)}
        with_gcs_id = {kind for kind, src in from_ctrl if src[0] == 255}
        warned = [e for e in rig.link.events if "WARNING manual_control" in e]
        if output_mode == "manual_control":
            assert with_gcs_id == {"MANUAL_CONTROL"}
            assert warned and warned[0].startswith("t=0.00")  # said at start
        else:
            assert with_gcs_id == set()
            assert not warned
    finally:
        rig.close()

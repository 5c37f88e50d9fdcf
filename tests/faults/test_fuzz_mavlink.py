"""Fuzzing the MAVLink input path (hypothesis, derandomized, bounded).

Random bytes and mutated valid MAVLink 2 frames (unsigned, signed with the right key, signed with a
wrong key; every message type either side handles) are sent over real loopback sockets into
``VehicleLink`` (controller side, with and without signing) and into the simulated autopilot's
endpoint (a UDP link, and serial 0 over TCP as a byte stream). Nothing may escape ``poll()`` /
``tick()`` / ``step()``, and the state must stay sane. The counts of inputs are printed.
"""

from __future__ import annotations

import hashlib
import math
import random
import socket

from hypothesis import HealthCheck, given, settings, strategies as st

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link import MAV_CMD_USER_1, VehicleLink
from dip3d_vehicle.link.connection import mavlink2 as m2
from dip3d_vehicle.link.state import SUB_MODES
from dip3d_vehicle.servo.command import VelocityCommand
from sitl.autopilot import Autopilot

KEY = hashlib.sha256(b"fuzz key").digest()
WRONG = hashlib.sha256(b"other key").digest()
FUZZ = dict(deadline=None, derandomize=True, database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
COUNTS: dict[str, int] = {}


def _encoder(sysid: int, compid: int, key: bytes | None) -> m2.MAVLink:
    mav = m2.MAVLink(None, srcSystem=sysid, srcComponent=compid)
    if key is not None:
        mav.signing.secret_key = key
        mav.signing.sign_outgoing = True
        mav.signing.timestamp = 1
    return mav


def _templates(mav: m2.MAVLink) -> list:
    m = m2
    return [
        mav.heartbeat_encode(m.MAV_TYPE_SUBMARINE, m.MAV_AUTOPILOT_ARDUPILOTMEGA, 209, 2, 4),
        mav.heartbeat_encode(m.MAV_TYPE_GCS, m.MAV_AUTOPILOT_INVALID, 0, 0, 0),
        mav.attitude_encode(123456, 0.1, -0.2, 3.0, 0.0, 0.0, 0.5),
        mav.param_value_encode(b"SYSID_MYGCS", 255.0, m.MAV_PARAM_TYPE_REAL32, 30, 5),
        mav.command_long_encode(1, 191, MAV_CMD_USER_1, 0, 1, 0, 0, 0, 0, 0, 0),
        mav.command_ack_encode(m.MAV_CMD_SET_MESSAGE_INTERVAL, 0, 0, 0, 1, 191),
        mav.statustext_encode(4, b"Lost manual control", 0, 0),
        mav.global_position_int_encode(1000, 0, 0, -2000, -2000, 0, 0, 0, 9000),
        mav.manual_control_encode(1, 500, -500, 700, 300, 0),
        mav.set_position_target_local_ned_encode(0, 1, 1, 8, 0b110111000111, 0, 0, 0, 0.5, 0, 0, 0, 0, 0, 0, 0.3),
        mav.command_long_encode(1, 1, m.MAV_CMD_COMPONENT_ARM_DISARM, 0, 1, 0, 0, 0, 0, 0, 0),
        mav.command_long_encode(1, 1, m.MAV_CMD_DO_SET_MODE, 0, 1, 4, 0, 0, 0, 0, 0),
        mav.command_long_encode(1, 1, m.MAV_CMD_SET_MESSAGE_INTERVAL, 0, 30, 1e5, 0, 0, 0, 0, 0),
        mav.command_int_encode(1, 1, 0, m.MAV_CMD_REQUEST_MESSAGE, 0, 0, 148, 0, 0, 0, 0, 0, 0),
        mav.param_request_read_encode(1, 1, b"SYSID_MYGCS", -1),
        mav.param_request_read_encode(1, 1, b"", 32000),
        mav.param_set_encode(1, 1, b"FS_PILOT_TIMEOUT", float("nan"), 9),
        mav.request_data_stream_encode(1, 1, 0, 50, 1),
        mav.rc_channels_override_encode(1, 1, *([1600] * 8)),
        mav.set_mode_encode(1, 1, 2),
        mav.setup_signing_encode(1, 1, bytes(32), 0),
    ]


_ENCODERS = {"unsigned": lambda s, c: _encoder(s, c, None), "signed": lambda s, c: _encoder(s, c, KEY),
             "wrong_key": lambda s, c: _encoder(s, c, WRONG)}


def _mutate(buf: bytes, seed: int, n: int) -> bytes:
    rng = random.Random(seed)
    b = bytearray(buf)
    for _ in range(n):
        if not b:
            break
        op = rng.randrange(5)
        i = rng.randrange(len(b))
        if op == 0:
            b[i] ^= 1 << rng.randrange(8)
        elif op == 1:
            b[i] = rng.choice([0, 0xFF, 0xFD, 0xFE, 0x01, 0x7F, 0x80, rng.randrange(256)])
        elif op == 2:
            del b[i:]
        elif op == 3:
            b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 8)))
        else:
            j = rng.randrange(len(b))
            b[i], b[j] = b[j], b[i]
    return bytes(b)


def _packet(kind: str, sysid: int, compid: int, idx: int, seed: int, n: int) -> bytes:
    mav = _ENCODERS[kind](sysid, compid)
    msgs = _templates(mav)
    raw = msgs[idx % len(msgs)].pack(mav)
    return _mutate(raw, seed, n) if n else raw


_INPUT = st.one_of(
    st.binary(min_size=1, max_size=300),
    st.tuples(st.sampled_from(sorted(_ENCODERS)), st.sampled_from([1, 255, 42]), st.sampled_from([1, 190, 191]),
              st.integers(0, 40), st.integers(0, 10**6), st.integers(0, 4)).map(lambda t: _packet(*t)),
    st.lists(st.tuples(st.sampled_from(sorted(_ENCODERS)), st.just(1), st.just(1), st.integers(0, 40),
                       st.integers(0, 10**6), st.integers(0, 2)).map(lambda t: _packet(*t)),
             min_size=2, max_size=4).map(b"".join),
)


class _Controller:
    """A VehicleLink on udpin with a sender socket; ``feed`` sends one datagram and polls."""

    def __init__(self, signing: bool, tmp_path) -> None:
        self.clock = SimClock()
        probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
        probe.close()
        params = {"link.url": f"udpin:127.0.0.1:{port}"}
        if signing:
            key_file = tmp_path / "key.bin"
            key_file.write_bytes(KEY)
            params["link.signing_key_file"] = str(key_file)
        self.link = VehicleLink(params, self.clock)
        self.link.open()
        self.port = port
        self.tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

    def feed(self, data: bytes) -> None:
        self.tx.sendto(data, ("127.0.0.1", self.port))
        self.clock.advance(0.01)
        self.link.poll()
        self.link.tick(VelocityCommand(surge_m_s=0.2), perception_fresh=True, perception_stamp_s=self.clock.now())
        ap = self.link.autopilot
        assert isinstance(ap.armed, bool) and (ap.mode == "" or ap.mode in SUB_MODES.values()
                                               or ap.mode.startswith("MODE"))
        assert 1 <= self.link.gcs.sysid <= 255 or not self.link.gcs.sysid_from_autopilot
        assert not self.link.engaged or self.link.operator_enabled

    def close(self) -> None:
        self.tx.close()
        self.link.close()


def _run_controller(signing: bool, tmp_path, summary, examples: int) -> None:
    ctl = _Controller(signing, tmp_path)
    name = f"VehicleLink ({'signing' if signing else 'no signing'})"

    @settings(max_examples=examples, **FUZZ)
    @given(data=_INPUT)
    def case(data):
        COUNTS[name] = COUNTS.get(name, 0) + 1
        ctl.feed(data)

    try:
        case()
        if signing:  # nothing unsigned or wrongly signed got through to the state
            assert ctl.link.stats.rejected_unsigned + ctl.link.stats.rejected_bad_signature > 0
    finally:
        ctl.close()
    summary(f"[fuzz] {name}: {COUNTS[name]} inputs, 0 unhandled exceptions; stats {ctl.link.stats}")


def test_fuzz_vehicle_link_input(tmp_path, summary):
    _run_controller(False, tmp_path, summary, 1500)


def test_fuzz_vehicle_link_input_signed(tmp_path, summary):
    _run_controller(True, tmp_path, summary, 1000)


def test_fuzz_autopilot_endpoint(summary):
    clock = SimClock()
    ap = Autopilot(load_params(), clock, listen=["tcp:127.0.0.1:0", "udpin:127.0.0.1:0", "udpin:127.0.0.1:0"],
                   signing_key=None)
    signed = Autopilot(load_params(), clock, listen=["udpin:127.0.0.1:0"], signing_key=KEY)
    udp_port = int(ap.addresses[1].rsplit(":", 1)[1])
    signed_port = int(signed.addresses[0].rsplit(":", 1)[1])
    tcp = socket.create_connection(("127.0.0.1", int(ap.addresses[0].rsplit(":", 1)[1])))
    tcp.setblocking(False)
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.setblocking(False)
    name = "Autopilot endpoint (udp, tcp serial 0, signed udp)"

    def drain(sock):
        while True:
            try:
                if not sock.recv(65536):
                    break
            except (BlockingIOError, InterruptedError):
                break

    @settings(max_examples=1500, **FUZZ)
    @given(data=_INPUT, where=st.sampled_from(["udp", "tcp", "signed"]))
    def case(data, where):
        COUNTS[name] = COUNTS.get(name, 0) + 1
        if where == "tcp":
            tcp.sendall(data)
        else:
            udp.sendto(data, ("127.0.0.1", udp_port if where == "udp" else signed_port))
        clock.advance(0.01)
        ap.step()
        signed.step()
        drain(tcp)
        drain(udp)
        for a in (ap, signed):
            s = a.state
            assert all(math.isfinite(v) for v in (s.north_m, s.east_m, s.depth_m, s.yaw_rad))
            assert a.mode_name in ("MANUAL", "STABILIZE", "ALT_HOLD", "ACRO", "SURFACE", "GUIDED", "POSHOLD",
                                   "AUTO", "CIRCLE", "MOTOR_DETECT", "SURFTRAK") or isinstance(a.mode, int)
            assert all(math.isfinite(v) for v in a.ap_params.values())

    try:
        case()
        assert signed.armed is False  # the signed link never obeyed an unsigned / wrong-key arm
        # pymavlink passes unknown message ids without a CRC or signature check, but with source 0/0:
        # nothing the autopilot acts on
        counts = (ap.counters["messages_in"], signed.counters["messages_in"], signed.dropped_unsigned)
    finally:
        tcp.close()
        udp.close()
        ap.close()
        signed.close()
    summary(f"[fuzz] {name}: {COUNTS[name]} inputs, 0 unhandled exceptions; autopilot messages accepted "
            f"{counts[0]}, signed autopilot accepted {counts[1]} (unknown ids only), dropped unsigned/wrong key "
            f"{counts[2]}")

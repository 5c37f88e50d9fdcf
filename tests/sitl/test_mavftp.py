"""The simulated autopilot's MAVLink FTP server and SYS_STATUS bits (as ArduSub's)."""

from __future__ import annotations

import struct

import pytest
from pymavlink.dialects.v20 import ardupilotmega as M

from sitl.autopilot import ARDUSUB_PARAMS
from sitl.mavftp import ERR, OP, FtpServer, param_pck
from sitl.sys_status import sys_status_bits

_HDR = struct.Struct("<HBBBBBBI")


def _req(seq: int, session: int, opcode: int, data: bytes = b"", offset: int = 0, size: int | None = None) -> bytes:
    return _HDR.pack(seq, session, opcode, len(data) if size is None else size, 0, 0, 0, offset) + data


def _parse(payload: bytes) -> tuple:
    seq, session, opcode, size, req, complete, _, offset = _HDR.unpack_from(payload)
    return seq, session, opcode, req, complete, offset, payload[12:12 + size]


def _decode_pck(data: bytes) -> dict[str, tuple[float, float]]:
    """An independent decoder of ArduPilot's param.pck (name -> (value, default))."""
    magic, count, total = struct.unpack_from("<HHH", data)
    assert magic in (0x671B, 0x671C) and count == total
    pos, last, out = 6, b"", {}
    while pos < len(data):
        if data[pos] == 0:
            pos += 1
            continue
        ptype, plen = data[pos], data[pos + 1]
        assert ptype & 0x0F == 4
        n, common = (plen >> 4) + 1, plen & 0x0F
        name = last[:common] + data[pos + 2:pos + 2 + n]
        pos += 2 + n
        value = struct.unpack_from("<f", data, pos)[0]
        pos += 4
        default = value
        if magic == 0x671C and ptype & 0x10:
            default = struct.unpack_from("<f", data, pos)[0]
            pos += 4
        out[name.decode()] = (value, default)
        last = name
    assert len(out) == count
    return out


def test_param_pck_round_trips_with_and_without_defaults():
    values = dict(ARDUSUB_PARAMS, SYSID_MYGCS=200)
    decoded = _decode_pck(param_pck(values, ARDUSUB_PARAMS))
    assert {k: v for k, (v, _) in decoded.items()} == pytest.approx(values)
    assert decoded["SYSID_MYGCS"] == (200.0, 255.0) and decoded["FS_PILOT_TIMEOUT"] == pytest.approx((3.0, 3.0))
    assert struct.unpack_from("<H", param_pck(values))[0] == 0x671B


def test_param_pck_decodes_with_mavproxys_own_decoder():
    param_ftp = pytest.importorskip("MAVProxy.modules.lib.param_ftp")
    pdata = param_ftp.ftp_param_decode(param_pck(ARDUSUB_PARAMS, ARDUSUB_PARAMS))
    assert pdata is not None and len(pdata.params) == len(ARDUSUB_PARAMS)
    assert {n.decode(): v for n, v, _ in pdata.params} == pytest.approx(ARDUSUB_PARAMS)


def test_open_burst_read_terminate_as_mavproxy_asks_at_connect():
    server = FtpServer(lambda: ARDUSUB_PARAMS, ARDUSUB_PARAMS)
    gcs = (255, 190)
    seq, session, opcode, req, _, _, data = _parse(server.handle(gcs, _req(0, 7, OP.OPEN_FILE_RO,
                                                                           b"@PARAM/param.pck?withdefaults=1"))[0])
    assert (seq, session, opcode, req) == (1, 7, OP.ACK, OP.OPEN_FILE_RO)
    size = struct.unpack("<I", data)[0]
    replies = [_parse(p) for p in server.handle(gcs, _req(1, 7, OP.BURST_READ_FILE, offset=0, size=80))]
    assert all(r[2] == OP.ACK and r[3] == OP.BURST_READ_FILE for r in replies)
    assert [r[4] for r in replies] == [0] * (len(replies) - 1) + [1]  # last one completes the burst
    body = b"".join(r[6] for r in replies)
    assert len(body) == size and _decode_pck(body).keys() == ARDUSUB_PARAMS.keys()
    past_end = _parse(server.handle(gcs, _req(2, 7, OP.BURST_READ_FILE, offset=size, size=80))[0])
    assert past_end[2] == OP.NACK and past_end[6] == bytes([ERR.EOF])
    assert _parse(server.handle(gcs, _req(3, 7, OP.TERMINATE_SESSION))[0])[2] == OP.ACK
    stale = _parse(server.handle(gcs, _req(4, 7, OP.READ_FILE, offset=0, size=10))[0])
    assert stale[2] == OP.NACK and stale[6] == bytes([ERR.INVALID_SESSION])


def test_unknown_file_and_unknown_opcode_are_refused_at_once():
    server = FtpServer(lambda: ARDUSUB_PARAMS, ARDUSUB_PARAMS)
    missing = _parse(server.handle((255, 190), _req(0, 1, OP.OPEN_FILE_RO, b"@SYS/uarts.txt"))[0])
    assert missing[2] == OP.NACK and missing[6][0] == ERR.FAIL_ERRNO
    write = _parse(server.handle((255, 190), _req(1, 1, 7, b"x"))[0])  # WriteFile
    assert write[2] == OP.NACK and write[6] == bytes([ERR.UNKNOWN_COMMAND])


def test_a_repeated_request_gets_the_same_reply():
    server = FtpServer(lambda: ARDUSUB_PARAMS, ARDUSUB_PARAMS)
    first = server.handle((255, 190), _req(5, 2, OP.OPEN_FILE_RO, b"@PARAM/param.pck"))
    assert server.handle((255, 190), _req(5, 2, OP.OPEN_FILE_RO, b"@PARAM/param.pck")) == first


@pytest.mark.parametrize("mode, control", [(19, False), (0, False), (2, True), (4, True)])
def test_sys_status_bits_are_ardusubs_and_report_a_healthy_fence(mode, control):
    present, enabled, health = sys_status_bits(mode, has_position=False)
    fence = M.MAV_SYS_STATUS_GEOFENCE
    assert health & fence and not present & fence and not enabled & fence  # FENCE_ENABLE 0, not failed
    assert present & M.MAV_SYS_STATUS_AHRS and health & M.MAV_SYS_STATUS_AHRS
    z = M.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL
    assert bool(enabled & z) == control and bool(health & z) == control and present & z
    assert not present & M.MAV_SYS_STATUS_SENSOR_GPS
    assert enabled & ~present == 0  # nothing enabled that is not present

"""MAVLink 2 signing: unsigned / wrongly signed commands dropped on signed links, serial 0 exempt."""

from __future__ import annotations

import pytest


from mav_client import M, command_long, send_manual

KEY = bytes(range(32))
WRONG = bytes(32 - i for i in range(32))


def _sign(conn, key):
    conn.setup_signing(key, sign_outgoing=True)


@pytest.fixture
def signed(lockstep_factory):
    return lockstep_factory({"sim.pilot_input_failsafe": False}, signing_key=KEY)


def test_unsigned_dropped_on_udp_link(signed):
    c = signed.connect(signed.ap.addresses[1])
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.2)
    assert not signed.ap.armed and not signed.messages(c, "COMMAND_ACK")
    assert signed.ap.dropped_unsigned >= 2   # the hello heartbeat and the command


def test_wrong_key_dropped(signed):
    c = signed.connect(signed.ap.addresses[1])
    _sign(c, WRONG)
    before = signed.ap.dropped_unsigned
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.2)
    assert not signed.ap.armed and not signed.messages(c, "COMMAND_ACK")
    assert signed.ap.dropped_unsigned > before


def test_signed_command_gets_signed_reply(signed):
    c = signed.connect(signed.ap.addresses[1])
    _sign(c, KEY)
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.2)
    assert signed.ap.armed
    ack = signed.messages(c, "COMMAND_ACK")[-1]
    assert ack.result == M.MAV_RESULT_ACCEPTED and ack.get_signed()
    assert c.mav.signing.goodsig_count > 0


def test_serial0_tcp_accepts_unsigned(signed):
    c = signed.connect(signed.ap.addresses[0])
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.2)
    assert signed.ap.armed and signed.messages(c, "COMMAND_ACK")[-1].result == M.MAV_RESULT_ACCEPTED


def test_serial0_unsigned_can_be_switched_off(lockstep_factory):
    ls = lockstep_factory({"sim.serial0_accepts_unsigned": False}, signing_key=KEY)
    c = ls.connect()
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    ls.run(0.2)
    assert not ls.ap.armed and ls.ap.dropped_unsigned >= 1


def test_setup_signing_refused_while_armed_and_zero_key_turns_off(signed):
    c = signed.connect()
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.1)
    c.mav.setup_signing_send(1, 1, [0] * 32, 0)
    signed.run(0.1)
    assert signed.ap.endpoint.signing_key == KEY   # refused while armed
    command_long(c, M.MAV_CMD_COMPONENT_ARM_DISARM, 0)
    c.mav.setup_signing_send(1, 1, [0] * 32, 0)
    signed.run(0.1)
    assert signed.ap.endpoint.signing_key is None
    u = signed.connect(signed.ap.addresses[1])
    command_long(u, M.MAV_CMD_COMPONENT_ARM_DISARM, 1)
    signed.run(0.1)
    assert signed.ap.armed

"""STATUSTEXT beyond 50 characters: chunks with id / chunk_seq, put back together whole."""

from __future__ import annotations

import pytest
from hypothesis import given, strategies as st
from pymavlink.dialects.v20 import ardupilotmega as m2

from dip3d_vehicle.link.statustext import STATUSTEXT_LEN, StatusTextAssembler, split_statustext, statustext_messages


def _over_the_wire(msgs):
    """Pack and parse each message as a receiver would see it."""
    mav = m2.MAVLink(None, srcSystem=1, srcComponent=191)
    parser = m2.MAVLink(None)
    return [parser.parse_char(bytes(m.pack(mav))) for m in msgs]


def test_short_text_is_one_message_with_id_0():
    (msg,) = statustext_messages(6, "DIP3D: arrived", 9)
    assert msg.id == 0 and msg.chunk_seq == 0


@given(st.text(alphabet=st.characters(min_codepoint=32, max_codepoint=126), min_size=0, max_size=400),
       st.integers(1, 65535))
def test_any_text_survives_the_wire_whole(text, text_id):
    received = _over_the_wire(statustext_messages(6, text, text_id))
    assert all(len(m.text.encode()) <= STATUSTEXT_LEN for m in received)
    assembler = StatusTextAssembler()
    out = [assembler.add(m) for m in received]
    assert out[:-1] == [None] * (len(out) - 1) and out[-1] == text


def test_a_text_of_exactly_100_characters_ends_with_an_empty_chunk():
    assert [len(c) for c in split_statustext("x" * 100)] == [50, 50, 0]


def test_a_lost_chunk_is_marked_not_hidden():
    msgs = _over_the_wire(statustext_messages(6, "a" * 50 + "b" * 50 + "c" * 10, 3))
    assembler = StatusTextAssembler()
    assert assembler.add(msgs[0]) is None
    assert assembler.add(msgs[2]) == "a" * 50 + " ... " + "c" * 10


def test_chunked_text_needs_a_nonzero_id():
    with pytest.raises(ValueError, match="id 0"):
        statustext_messages(6, "y" * 60, 0)

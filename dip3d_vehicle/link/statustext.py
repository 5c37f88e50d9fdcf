"""STATUSTEXT longer than MAVLink's 50 characters: split into chunks, and put back together.

MAVLink 2's STATUSTEXT has ``id`` and ``chunk_seq`` for exactly this (as ArduPilot sends its own long
messages): every chunk of one text carries the same non-zero ``id`` and ``chunk_seq`` 0, 1, 2, ...;
each chunk but the last holds exactly 50 characters, so a chunk shorter than 50 (empty if need be)
ends the text. A text of at most 50 characters goes out as one message with ``id`` 0. MAVProxy and
QGroundControl reassemble the chunks; ``StatusTextAssembler`` does the same for the simulator's
ground station.
"""

from __future__ import annotations

from typing import Any

from pymavlink.dialects.v20 import ardupilotmega as m2

__all__ = ["STATUSTEXT_LEN", "split_statustext", "statustext_messages", "StatusTextAssembler"]

STATUSTEXT_LEN = 50
"""Characters in one STATUSTEXT's text field."""


def split_statustext(text: str) -> list[bytes]:
    """Return the chunks (UTF-8 bytes) of a text: one if it fits, else 50-byte chunks ending with a short one."""
    data = text.encode()
    if len(data) <= STATUSTEXT_LEN:
        return [data]
    chunks = [data[i:i + STATUSTEXT_LEN] for i in range(0, len(data), STATUSTEXT_LEN)]
    if len(chunks[-1]) == STATUSTEXT_LEN:
        chunks.append(b"")  # a short chunk marks the end
    return chunks


def statustext_messages(severity: int, text: str, text_id: int) -> list[Any]:
    """Return the STATUSTEXT messages of one text; ``text_id`` (1..65535) is used only when it needs chunks."""
    chunks = split_statustext(text)
    if len(chunks) == 1:
        return [m2.MAVLink_statustext_message(severity, chunks[0], 0, 0)]
    if not 1 <= text_id <= 65535:
        raise ValueError(f"STATUSTEXT id {text_id}: must be 1..65535 for a chunked text")
    return [m2.MAVLink_statustext_message(severity, c, text_id, seq) for seq, c in enumerate(chunks)]


class StatusTextAssembler:
    """Put chunked STATUSTEXTs back together, per sender and text id."""

    def __init__(self) -> None:
        self._pending: dict[tuple[int, int, int], list[str]] = {}

    def add(self, msg: Any) -> str | None:
        """Take one STATUSTEXT; return the whole text once it is complete, else None."""
        text = msg.text if isinstance(msg.text, str) else msg.text.decode(errors="replace")
        text = text.rstrip("\0")
        text_id = int(getattr(msg, "id", 0) or 0)
        if text_id == 0:
            return text
        key = (msg.get_srcSystem(), msg.get_srcComponent(), text_id)
        parts = self._pending.setdefault(key, [])
        if int(getattr(msg, "chunk_seq", 0)) != len(parts):  # a lost chunk: say so instead of guessing
            parts.append(" ... ")
        parts.append(text)
        if len(text.encode()) < STATUSTEXT_LEN:
            return "".join(self._pending.pop(key))
        return None

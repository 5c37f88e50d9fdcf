"""MAVLink 2 signing: read a key file in one of three forms; sign and check a link's connection.

A key file holds one of:
- exactly 32 raw bytes (binary, used as is);
- 64 hexadecimal characters (surrounding whitespace ignored), decoded to 32 bytes;
- anything else non-empty: a passphrase; the key is SHA-256 of its UTF-8 text with surrounding
  whitespace stripped (MAVProxy's ``signing setup PASSPHRASE`` and QGroundControl derive the key
  the same way, so the same passphrase gives the same key).
An all-zero key is refused: ArduSub treats it as "signing off".

``LinkSigning`` sets a connection up to sign everything it sends and to drop (and count) unsigned
and wrong-key messages, keeping the counts across a reconnect.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path
from typing import Any

from ..errors import LinkError

__all__ = ["load_key", "key_from_text", "LinkSigning"]

_HEX64 = re.compile(r"^[0-9a-fA-F]{64}$")


def key_from_text(text: str) -> bytes:
    """Return the 32-byte key of a hex string or passphrase (see the module doc)."""
    stripped = text.strip()
    if _HEX64.match(stripped):
        return bytes.fromhex(stripped)
    return hashlib.sha256(stripped.encode("utf-8")).digest()


def load_key(path: str | Path) -> bytes:
    """Read a signing key file.

    Args:
        path: the key file.

    Returns:
        The 32-byte secret key.

    Raises:
        LinkError: the file is missing, empty, or gives the all-zero key.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise LinkError(f"{path}: cannot read signing key file ({exc.__class__.__name__}); "
                        f"expected 32 raw bytes, 64 hex characters or a passphrase") from None
    if len(raw) == 32 and not _is_text(raw):
        key = raw
    else:
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise LinkError(f"{path}: signing key file is {len(raw)} bytes of binary; expected 32 raw bytes, "
                            f"64 hex characters or a passphrase") from None
        if not text.strip():
            raise LinkError(f"{path}: signing key file is empty; expected 32 raw bytes, 64 hex characters or a passphrase")
        key = key_from_text(text)
    if key == bytes(32):
        raise LinkError(f"{path}: signing key is all zeros, which ArduSub treats as 'signing off'")
    return key


def _is_text(raw: bytes) -> bool:
    """Return True when ``raw`` looks like printable text (a 32-character passphrase, not a raw key)."""
    try:
        text = raw.decode("ascii")
    except UnicodeDecodeError:
        return False
    return text.isprintable() or text.strip().isprintable()


class LinkSigning:
    """One link's signing: sign all it sends, drop unsigned / wrong-key messages and count them.

    Args:
        key: the 32-byte secret key, or None (signing off: nothing set up, nothing counted).
    """

    def __init__(self, key: bytes | None = None) -> None:
        self.key = key
        self._unsigned_calls = 0
        self._bad_sig_base = 0

    def setup(self, conn: Any) -> None:
        """Sign everything sent on ``conn`` and drop (and count) unsigned / wrong-key messages."""
        if self.key is None:
            return

        def reject_unsigned(_mav: Any, _msg_id: int) -> bool:
            self._unsigned_calls += 1
            return False

        conn.setup_signing(self.key, sign_outgoing=True, allow_unsigned_callback=reject_unsigned)

    def retire(self, conn: Any) -> None:
        """Keep the bad-signature count of a connection being replaced (a tcp reconnect)."""
        self._bad_sig_base += conn.mav.signing.badsig_count

    def count(self, conn: Any, stats: Any) -> None:
        """Copy pymavlink's signing counters into ``stats`` (a LinkStats; the callback also sees bad signatures)."""
        if self.key is None or conn is None:
            return
        bad = conn.mav.signing.badsig_count
        stats.rejected_bad_signature = self._bad_sig_base + bad
        stats.rejected_unsigned = self._unsigned_calls - stats.rejected_bad_signature

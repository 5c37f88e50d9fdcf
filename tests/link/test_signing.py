"""Signing key files: raw, hex, passphrase; bad files explained."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from dip3d_vehicle.errors import LinkError
from dip3d_vehicle.link.signing import load_key


def test_raw_hex_and_passphrase(tmp_path: Path) -> None:
    raw = bytes(range(1, 33))
    (tmp_path / "raw").write_bytes(raw)
    (tmp_path / "hex").write_text(raw.hex() + "\n")
    (tmp_path / "pass").write_text("correct horse battery staple\n")
    assert load_key(tmp_path / "raw") == raw
    assert load_key(tmp_path / "hex") == raw
    assert load_key(tmp_path / "pass") == hashlib.sha256(b"correct horse battery staple").digest()


def test_32_character_passphrase_is_not_a_raw_key(tmp_path: Path) -> None:
    (tmp_path / "k").write_text("a" * 32)
    assert load_key(tmp_path / "k") == hashlib.sha256(b"a" * 32).digest()


@pytest.mark.parametrize("content, words", [(b"", "empty"), (bytes(32).hex().encode(), "all zeros"),
                                            (b"\xff\xfe" * 20, "binary")])
def test_bad_key_files_explained(tmp_path: Path, content: bytes, words: str) -> None:
    (tmp_path / "k").write_bytes(content)
    with pytest.raises(LinkError, match=words):
        load_key(tmp_path / "k")


def test_missing_key_file(tmp_path: Path) -> None:
    with pytest.raises(LinkError, match="cannot read"):
        load_key(tmp_path / "nope")

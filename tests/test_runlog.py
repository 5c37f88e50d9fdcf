"""The run log survives a crash: a file cut at any byte loads every record that ended before it."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dip3d_vehicle.errors import LogError
from dip3d_vehicle.runlog import SYNC, RunLogReader, RunLogWriter, to_jsonable

N_FRAMES = 8


def _images(i: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(i)
    left = rng.integers(0, 256, (12, 16, 3), dtype=np.uint8)
    return left, 255 - left


def write_log(path: Path, fmt: str = "png", every: int = 1) -> None:
    """A small run: header, per frame a record and an image pair, telemetry and events."""
    with RunLogWriter(path, params={"selection.method": "default"}, meta={"camera": "test"},
                      keep_images_every=every, image_format=fmt, fsync_every_records=3) as log:
        log.event("start", mode="ALT_HOLD")
        for i in range(N_FRAMES):
            log.frame({"index": i, "stamp_s": 0.1 * i, "arm": {"wrist": {"xyz_m": np.array([0.1, np.nan, 2.0])}},
                       "candidates": [{"left_px": np.float32(i)}], "state": "SEARCH", "setpoint": None})
            log.images(i, *_images(i))
            log.telemetry({"depth_m": np.float64(-1.5 - i), "armed": np.bool_(True)})
        log.event("stop")


@pytest.fixture(scope="module")
def full_log():
    """(bytes of a complete log, [(kind, end offset, payload)] of its records)."""
    folder = Path(tempfile.mkdtemp())
    write_log(folder / "run.dlog")
    data = (folder / "run.dlog").read_bytes()
    reader = RunLogReader(folder / "run.dlog")
    records = [(r.kind, r.end, r.payload) for r in reader.records()]
    reader.close()
    return data, records


def test_round_trip(tmp_path):
    write_log(tmp_path / "run.dlog")
    with RunLogReader(tmp_path / "run.dlog") as log:
        assert log.header["format"] == "dip3d-vehicle-runlog" and log.header["version"] == 1
        assert log.params == {"selection.method": "default"}
        assert log.header["runlog"]["image_format"] == "png" and log.header["meta"] == {"camera": "test"}
        frames = list(log.frames())
        assert [f["index"] for f in frames] == list(range(N_FRAMES))
        assert frames[0]["arm"]["wrist"]["xyz_m"] == [0.1, None, 2.0]  # NaN -> null
        assert frames[3]["candidates"] == [{"left_px": 3.0}] and "wall_s" in frames[0]
        assert [e["text"] for e in log.events()] == ["start", "stop"]
        assert list(log.events())[0]["mode"] == "ALT_HOLD"
        assert [t["armed"] for t in log.telemetry()] == [True] * N_FRAMES
        pairs = list(log.image_pairs())
        assert [p[0] for p in pairs] == list(range(N_FRAMES))
        for i, left, right in pairs:  # PNG is exact
            assert np.array_equal(left, _images(i)[0]) and np.array_equal(right, _images(i)[1])
        assert log.stats == {"records": 1 + 2 + 3 * N_FRAMES, "bytes_skipped": 0, "corrupt_regions": 0,
                             "truncated_tail_bytes": 0}


def test_keep_every_nth_jpeg(tmp_path):
    write_log(tmp_path / "run.dlog", fmt="jpg", every=3)
    with RunLogReader(tmp_path / "run.dlog") as log:
        pairs = list(log.image_pairs())
    assert [p[0] for p in pairs] == [0, 3, 6]
    assert all(p[1].shape == (12, 16, 3) and p[1].dtype == np.uint8 for p in pairs)


CUTS_TRIED: list[int] = []


@settings(max_examples=300, derandomize=True, deadline=None)
@given(fraction=st.floats(0.0, 1.0))
def test_cut_at_any_byte_loads_every_complete_record(full_log, fraction):
    data, records = full_log
    cut = int(fraction * len(data))
    CUTS_TRIED.append(cut)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "cut.dlog"
        path.write_bytes(data[:cut])
        with RunLogReader(path) as log:
            got = [(r.kind, r.end, r.payload) for r in log.records()]
            want = [r for r in records if r[1] <= cut]
            assert got == want
            assert log.stats["bytes_skipped"] == 0
            assert log.stats["truncated_tail_bytes"] == cut - (want[-1][1] if want else 0)
            frames_before = sum(1 for r in want if r[0] == "frame")
            assert len(list(log.frames())) == frames_before
            assert len(list(log.image_pairs())) == sum(1 for r in want if r[0] == "images")


def test_every_cut_point_near_record_ends(full_log, tmp_path):
    """Exhaustive around each record boundary (end-1, end, end+1) and every byte of the header."""
    data, records = full_log
    cuts = set(range(0, records[0][1] + 2))
    for _, end, _ in records:
        cuts |= {end - 1, end, end + 1}
    for cut in sorted(c for c in cuts if 0 <= c <= len(data)):
        path = tmp_path / f"c{cut}.dlog"
        path.write_bytes(data[:cut])
        with RunLogReader(path) as log:
            assert [r.end for r in log.records()] == [r[1] for r in records if r[1] <= cut]
            assert (log.header is None) == (cut < records[0][1])


def test_corrupt_record_in_the_middle_is_skipped(full_log, tmp_path):
    data, records = full_log
    victim = 7  # some record in the middle
    start = records[victim - 1][1]
    for offset in (0, 4, 6, 10, 20):  # sync, type, length, crc, payload
        damaged = bytearray(data)
        damaged[start + offset] ^= 0x5A
        path = tmp_path / f"d{offset}.dlog"
        path.write_bytes(bytes(damaged))
        with RunLogReader(path) as log:
            got = [r.end for r in log.records()]
            assert got == [r[1] for i, r in enumerate(records) if i != victim]
            assert log.stats["corrupt_regions"] == 1
            assert log.stats["bytes_skipped"] == records[victim][1] - start
            assert log.stats["truncated_tail_bytes"] == 0


def test_garbage_inserted_in_the_middle_resyncs(full_log, tmp_path):
    data, records = full_log
    at = records[4][1]
    path = tmp_path / "g.dlog"
    path.write_bytes(data[:at] + SYNC + b"garbage" + SYNC[:2] + data[at:])
    with RunLogReader(path) as log:
        assert len(list(log.records())) == len(records)
        assert log.stats["bytes_skipped"] == 4 + 7 + 2


def test_header_check(tmp_path):
    with pytest.raises(LogError, match="missing.dlog: run log not found"):
        RunLogReader(tmp_path / "missing.dlog")
    (tmp_path / "x.dlog").write_bytes(b"hello world, not a log at all")
    with pytest.raises(LogError, match="x.dlog: not a dip3d-vehicle run log"):
        RunLogReader(tmp_path / "x.dlog")
    write_log(tmp_path / "run.dlog")
    data = bytearray((tmp_path / "run.dlog").read_bytes())
    data[20] ^= 1
    (tmp_path / "bad.dlog").write_bytes(bytes(data))
    with pytest.raises(LogError, match="corrupt header record"):
        RunLogReader(tmp_path / "bad.dlog")
    with pytest.raises(LogError, match="already exists"):
        RunLogWriter(tmp_path / "run.dlog")
    with pytest.raises(LogError, match="image_format"):
        RunLogWriter(tmp_path / "other.dlog", image_format="bmp")


def test_writer_after_close(tmp_path):
    log = RunLogWriter(tmp_path / "a.dlog")
    log.close()
    log.close()
    with pytest.raises(LogError, match="closed"):
        log.event("late")


def test_to_jsonable():
    value = {"a": np.array([[1, 2]], dtype=np.int16), "b": (np.float32(0.5), float("inf")), 3: np.bool_(False)}
    assert to_jsonable(value) == {"a": [[1, 2]], "b": [0.5, None], "3": False}
    json.dumps(to_jsonable(value), allow_nan=False)


CHILD = r"""
import sys, numpy as np
from dip3d_vehicle.runlog import RunLogWriter
log = RunLogWriter(sys.argv[1], keep_images_every=1, image_format="png", fsync_every_s=3600,
                   fsync_every_records=1000000)
i = 0
while True:
    log.frame({"index": i})
    log.images(i, np.full((8, 8, 3), i % 256, np.uint8), np.zeros((8, 8, 3), np.uint8))
    print(i, flush=True)
    i += 1
"""


def test_killed_writer_loses_nothing_it_logged(tmp_path):
    """A writer killed with SIGKILL mid-run: every frame it had logged is in the file."""
    path = tmp_path / "killed.dlog"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE, text=True)
    try:
        logged = [int(child.stdout.readline()) for _ in range(200)]
    finally:
        os.kill(child.pid, signal.SIGKILL)
        child.wait()
        child.stdout.close()
    with RunLogReader(path) as log:
        indices = [f["index"] for f in log.frames()]
        pairs = sum(1 for _ in log.image_pairs())
    assert indices[: len(logged)] == logged
    assert indices == list(range(len(indices))) and pairs >= len(logged)

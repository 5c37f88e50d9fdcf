"""The MCAP run record survives a crash: a file cut at any byte yields every message flushed before the
cut; a writer killed with SIGKILL loses at most ``runlog.flush_every_s`` of messages."""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dip3d_vehicle.errors import LogError
from dip3d_vehicle.record.jsonable import to_jsonable
from dip3d_vehicle.record.mcap_log import McapRunReader, McapRunWriter

N_FRAMES = 12


def _images(i: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(i)
    left = rng.integers(0, 256, (12, 16, 3), dtype=np.uint8)
    return left, 255 - left


def write_record(path: Path, fmt: str = "png", every: int = 1) -> list[tuple[int, int]]:
    """A small run, flushed after every frame; return [(file size after the flush, messages so far)]."""
    flushes = []
    with McapRunWriter(path, params={"selection.method": "default"}, meta={"camera": "test"},
                       keep_images_every=every, image_format=fmt, flush_every_s=1.0) as log:
        log.event("start", mode="ALT_HOLD")
        for i in range(N_FRAMES):
            log.frame({"index": i, "stamp_s": 0.1 * i, "arm": {"wrist": {"xyz_m": np.array([0.1, np.nan, 2.0])}},
                       "candidates": [{"left_px": np.float32(i)}], "state": "SEARCH", "setpoint": None})
            log.images(i, *_images(i))
            log.telemetry({"depth_m": np.float64(-1.5 - i), "armed": np.bool_(True)})
            log.flush()
            flushes.append((path.stat().st_size, log.records_written))
        log.event("stop")
    return flushes


@pytest.fixture(scope="module")
def full_record():
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "run.mcap"
        flushes = write_record(path)
        with McapRunReader(path) as log:
            messages = list(log.messages())
            assert log.stats["truncated"] is False and log.stats["error"] == ""
        yield path.read_bytes(), flushes, messages


def test_round_trip(tmp_path):
    write_record(tmp_path / "run.mcap")
    with McapRunReader(tmp_path / "run.mcap") as log:
        assert log.header["format"] == "dip3d-vehicle-run" and log.header["version"] == 2
        assert log.params == {"selection.method": "default"} and log.header["meta"] == {"camera": "test"}
        frames = list(log.frames())
        assert [f["index"] for f in frames] == list(range(N_FRAMES))
        assert frames[0]["arm"]["wrist"]["xyz_m"] == [0.1, None, 2.0]
        assert [t["depth_m"] for t in log.telemetry()] == [-1.5 - i for i in range(N_FRAMES)]
        assert [e["text"] for e in log.events()] == ["start", "stop"]
        pairs = list(log.image_pairs())
    assert [p[0] for p in pairs] == list(range(N_FRAMES))
    for i, left, right in pairs:  # PNG: exact
        assert np.array_equal(left, _images(i)[0]) and np.array_equal(right, _images(i)[1])


def test_the_mcap_package_reads_it_indexed(tmp_path):
    """The official reader (seeking, through the summary written on close) sees every message."""
    from mcap.reader import make_reader

    write_record(tmp_path / "run.mcap")
    with open(tmp_path / "run.mcap", "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        counts = {summary.channels[k].topic: v for k, v in summary.statistics.channel_message_counts.items()}
        assert counts["/dip3d/frame"] == N_FRAMES and counts["/camera/left/image"] == N_FRAMES
        schemas = {s.name for s in summary.schemas.values()}
        assert {"foxglove.CompressedImage", "foxglove.Log", "dip3d.FrameRecord"} <= schemas
        assert {m.name for m in reader.iter_metadata()} == {"record", "run", "params", "calibration"}


CUTS_TRIED: list[int] = []


def _check_cut(data: bytes, flushes, messages, cut: int) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "cut.mcap"
        path.write_bytes(data[:cut])
        if cut < 8:  # inside the magic bytes: an empty record, no error
            with McapRunReader(path) as log:
                assert list(log.messages()) == [] and log.header is None
            return
        with McapRunReader(path) as log:
            got = list(log.messages())
            flushed = max((n for size, n in flushes if size <= cut), default=0)
            assert got == messages[:len(got)], "not a prefix of what was written"
            assert len(got) >= flushed, f"cut at {cut}: {len(got)} messages, {flushed} flushed before it"
            if cut < len(data) - 8:  # the footer is 8 bytes before the closing magic at least
                assert log.stats["truncated"]
            pairs = list(log.image_pairs())
            assert [p[0] for p in pairs] == list(range(len(pairs)))


@settings(max_examples=300, derandomize=True, deadline=None)
@given(fraction=st.floats(0.0, 1.0))
def test_cut_at_any_byte_yields_everything_flushed_before_it(full_record, fraction):
    data, flushes, messages = full_record
    cut = int(fraction * len(data))
    CUTS_TRIED.append(cut)
    _check_cut(data, flushes, messages, cut)


def test_every_cut_point_near_flush_ends_and_in_the_header(full_record):
    """Exhaustive: every byte of the first flush (magic, header, metadata) and +-2 around each flush end."""
    data, flushes, messages = full_record
    cuts = set(range(0, flushes[0][0] + 3))
    for size, _ in flushes:
        cuts |= set(range(size - 2, size + 3))
    cuts = sorted(c for c in cuts if 0 <= c <= len(data))
    for cut in cuts:
        _check_cut(data, flushes, messages, cut)
    CUTS_TRIED.extend(cuts)


def test_cut_points_tried():
    """How many cut points the two tests above tried (printed for the closing note)."""
    print(f"\ncut points tried: {len(CUTS_TRIED)} ({len(set(CUTS_TRIED))} distinct)")
    assert len(set(CUTS_TRIED)) > 250


def test_corrupt_chunk_stops_reading_there(full_record, tmp_path):
    """A flipped byte inside a chunk fails its CRC: the messages before it are still read."""
    data, flushes, messages = full_record
    start = flushes[4][0]
    damaged = bytearray(data)
    damaged[start + 40] ^= 0x5A
    (tmp_path / "d.mcap").write_bytes(bytes(damaged))
    with McapRunReader(tmp_path / "d.mcap") as log:
        got = list(log.messages())
        assert got == messages[:len(got)] and len(got) >= flushes[4][1] and len(got) < len(messages)
        assert log.stats["error"]


def test_errors(tmp_path):
    with pytest.raises(LogError, match="missing.mcap: run record not found"):
        McapRunReader(tmp_path / "missing.mcap")
    (tmp_path / "x.mcap").write_bytes(b"hello world, not a record at all")
    with pytest.raises(LogError, match="x.mcap: not an MCAP file"):
        McapRunReader(tmp_path / "x.mcap")
    write_record(tmp_path / "run.mcap")
    with pytest.raises(LogError, match="already exists"):
        McapRunWriter(tmp_path / "run.mcap")
    with pytest.raises(LogError, match="image_format"):
        McapRunWriter(tmp_path / "other.mcap", image_format="bmp")
    with pytest.raises(LogError, match="flush_every_s"):
        McapRunWriter(tmp_path / "other2.mcap", flush_every_s=5.0)
    log = McapRunWriter(tmp_path / "a.mcap")
    log.close()
    log.close()
    with pytest.raises(LogError, match="closed"):
        log.event("late")


def test_to_jsonable():
    value = {"a": np.array([[1, 2]], dtype=np.int16), "b": (np.float32(0.5), float("inf")), 3: np.bool_(False)}
    assert to_jsonable(value) == {"a": [[1, 2]], "b": [0.5, None], "3": False}
    json.dumps(to_jsonable(value), allow_nan=False)


CHILD = r"""
import sys, time, numpy as np
from dip3d_vehicle.record.mcap_log import McapRunWriter
log = McapRunWriter(sys.argv[1], keep_images_every=10, image_format="jpg", fsync_every_s=3600)
i = 0
img = np.random.default_rng(0).integers(0, 256, (120, 160, 3), dtype=np.uint8)
while True:
    log.frame({"index": i})
    log.images(i, img, img)
    print(i, time.monotonic(), flush=True)
    i += 1
    time.sleep(0.005)
"""

KILLS = 6
LOSSES: list[tuple[int, float]] = []


@pytest.mark.parametrize("trial", range(KILLS))
def test_killed_writer_loses_at_most_flush_every_s(tmp_path, trial):
    """SIGKILL after a random 0.5-2.5 s of logging (~200 frames/s): frames logged more than
    ``flush_every_s`` (0.5 s) before the kill are all in the file."""
    path = tmp_path / "killed.mcap"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE, text=True)
    logged: list[tuple[int, float]] = []
    try:
        first = child.stdout.readline().split()
        logged.append((int(first[0]), float(first[1])))
        run_for = random.Random(trial).uniform(0.5, 2.5)
        while time.monotonic() - logged[0][1] < run_for:
            i, t = child.stdout.readline().split()
            logged.append((int(i), float(t)))
    finally:
        killed_at = time.monotonic()
        os.kill(child.pid, signal.SIGKILL)
        child.wait()
        child.stdout.close()
    with McapRunReader(path) as log:
        indices = [f["index"] for f in log.frames()]
    assert indices == list(range(len(indices)))
    lost = [(i, t) for i, t in logged if i >= len(indices)]
    lost_age = killed_at - min((t for _, t in lost), default=killed_at)
    LOSSES.append((len(lost), lost_age))
    print(f"\nkill {trial}: {len(logged)} frames logged, {len(indices)} in the file, {len(lost)} lost, "
          f"oldest lost {lost_age:.3f} s before the kill")
    assert lost_age <= 1.0


def test_a_run_record_is_a_stereo_source(tmp_path):
    """``record:RUN.mcap`` (or the bare path) yields the kept pairs, e.g. as a dataset's ``source``."""
    from dip3d_vehicle.errors import SourceError
    from dip3d_vehicle.sources import open_source, parse_spec

    write_record(tmp_path / "run.mcap", every=3)
    assert parse_spec(str(tmp_path / "run.mcap"))[0] == "record"
    (tmp_path / "other.mcap").write_bytes(b"\x89MCAP0\r\n")  # an MCAP that is not ours: a ROS 2 bag
    assert parse_spec(str(tmp_path / "other.mcap"))[0] == "bag"
    for spec in (f"record:{tmp_path / 'run.mcap'}", str(tmp_path / "run.mcap")):
        with open_source(spec) as source:
            frames = list(source)
        assert [f.meta["frame_index"] for f in frames] == [0, 3, 6, 9]
        assert np.array_equal(frames[1].left, _images(3)[0]) and frames[1].index == 1
    with pytest.raises(SourceError, match="not found"):
        open_source(f"record:{tmp_path / 'missing.mcap'}")

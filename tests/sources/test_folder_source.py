"""Folder sources: both namings, stamps.csv, the writer round trip, and every error."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from dip3d_vehicle.errors import SourceError
from dip3d_vehicle.sources import FolderSource, FolderWriter, open_source, write_folder


def _same(got, want) -> None:
    assert len(got) == len(want)
    for g, w in zip(got, want):
        assert np.array_equal(g.left, w.left) and np.array_equal(g.right, w.right)
        assert g.stamp_s == w.stamp_s
        assert g.left.dtype == np.uint8 and g.left.shape == w.left.shape


@pytest.mark.parametrize("layout", ["prefixed", "subfolders"])
def test_writer_round_trip_is_exact(tmp_path, frames, layout):
    assert write_folder(tmp_path / "d", frames, layout=layout) == len(frames)
    with open_source(str(tmp_path / "d")) as source:
        assert len(source) == len(frames)
        got = list(source)
    _same(got, frames)
    assert [f.index for f in got] == list(range(len(frames)))


def test_prefixed_pairs_order_by_number_and_mix_extensions(tmp_path, frames):
    for number, frame in zip((3, 10, 7), frames):
        cv2.imwrite(str(tmp_path / f"left_{number}.png"), frame.left)
        cv2.imwrite(str(tmp_path / f"right_{number:06d}.png"), frame.right)
    with open_source(f"folder:{tmp_path}?folder_fps=2") as source:
        got = list(source)
    assert [f.meta["name"] for f in got] == ["000003", "000007", "000010"]
    assert [f.stamp_s for f in got] == [0.0, 0.5, 1.0]
    assert np.array_equal(got[1].left, frames[2].left)


def test_stamps_csv_and_jpg(tmp_path, make_frames):
    frames = make_frames(3)
    write_folder(tmp_path, frames, fmt="jpg", jpeg_quality=100)
    got = list(FolderSource(tmp_path))
    assert [f.stamp_s for f in got] == [f.stamp_s for f in frames]
    for g, w in zip(got, frames):
        ok, data = cv2.imencode(".jpg", w.left, [cv2.IMWRITE_JPEG_QUALITY, 100])
        assert np.array_equal(g.left, cv2.imdecode(data, cv2.IMREAD_COLOR))


def test_gray_and_bgra_images_become_bgr(tmp_path, frames):
    cv2.imwrite(str(tmp_path / "left_000000.png"), frames[0].left[:, :, 0])
    cv2.imwrite(str(tmp_path / "right_000000.png"), cv2.cvtColor(frames[0].right, cv2.COLOR_BGR2BGRA))
    (got,) = list(open_source(str(tmp_path)))
    assert got.left.shape == got.right.shape == frames[0].left.shape
    assert np.array_equal(got.right, frames[0].right)
    assert np.array_equal(got.left[:, :, 2], frames[0].left[:, :, 0])


def test_max_frames(tmp_path, frames):
    write_folder(tmp_path, frames)
    source = open_source(str(tmp_path), max_frames=2)
    assert len(source) == 2 and len(list(source)) == 2


@pytest.mark.parametrize("case, message", [
    ("missing", "image folder not found"),
    ("empty", "no stereo pairs found"),
    ("unmatched", "mismatched pairs: 2 left images, 1 right images (left_000001.png has no right image)"),
    ("unreadable", "not a readable image"),
    ("stamps_missing", "no stamp for 1 pair(s), first frame 000001"),
    ("stamps_header", "expected a header line 'frame,stamp_s'"),
    ("stamps_bad", "stamps.csv:2: bad row"),
    ("size", "differ in size"),
    ("sub_unmatched", "right/b.png has no left image"),
])
def test_errors_name_the_file_and_problem(tmp_path, frames, case, message):
    folder = tmp_path / "d"
    if case != "missing":
        folder.mkdir()
    img = frames[0].left
    if case in ("unmatched", "unreadable", "stamps_missing", "stamps_header", "stamps_bad", "size"):
        for i in range(2):
            cv2.imwrite(str(folder / f"left_{i:06d}.png"), img)
            if case != "unmatched" or i == 0:
                cv2.imwrite(str(folder / f"right_{i:06d}.png"), img if case != "size" else img[:, :20])
    if case == "unreadable":
        (folder / "right_000001.png").write_bytes(b"not a png")
    if case == "stamps_missing":
        (folder / "stamps.csv").write_text("frame,stamp_s\n0,1.5\n")
    if case == "stamps_header":
        (folder / "stamps.csv").write_text("a,b\n0,1.5\n")
    if case == "stamps_bad":
        (folder / "stamps.csv").write_text("frame,stamp_s\n0,abc\n")
    if case == "sub_unmatched":
        (folder / "left").mkdir()
        (folder / "right").mkdir()
        cv2.imwrite(str(folder / "left" / "a.png"), img)
        cv2.imwrite(str(folder / "right" / "a.png"), img)
        cv2.imwrite(str(folder / "right" / "b.png"), img)
    with pytest.raises(SourceError) as info:
        list(open_source(str(folder)))
    assert message in str(info.value)
    assert str(folder) in str(info.value)


def test_writer_refuses_to_overwrite_and_duplicate_index(tmp_path, frames):
    with FolderWriter(tmp_path) as writer:
        writer.write(frames[0])
        with pytest.raises(SourceError, match="frame index 0 written twice"):
            writer.write(frames[0])
    with pytest.raises(SourceError, match="already holds stamps.csv"):
        FolderWriter(tmp_path)


def test_bad_option_is_a_source_error(tmp_path, frames):
    write_folder(tmp_path, frames)
    with pytest.raises(SourceError, match="folder_fps"):
        open_source(f"{tmp_path}?folder_fps=-1")

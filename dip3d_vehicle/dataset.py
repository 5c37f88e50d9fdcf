"""Evaluation datasets: recorded stereo pairs with a calibration and per-pair annotations.

A dataset is a folder::

    DATASET/
      calib.yaml            stereo calibration (OpenCV FileStorage as written by
                            ``write_opencv_calibration``, or any format ``load_rig`` reads; another
                            file or list of files can be named by the ``calib`` field below)
      left_000000.png       the pairs, named as the folder source reads them
      right_000000.png      (left_NNNNNN.png|jpg + right_NNNNNN.png|jpg, or left/ + right/) ...
      annotations.json

``annotations.json``::

    {
      "source": "bag:dive.bag?left=/l&right=/r",   # optional: where the pairs are (any source
                                                    # spec; relative paths are relative to DATASET);
                                                    # default: the folder DATASET itself
      "calib": "calib.yaml",                        # optional: file or list of files (default calib.yaml)
      "objects": {"1": {"label": "placard 1"}, ...},
      "frames": [
        {"index": 0,                                # the pair: NNNNNN of a folder, else the
                                                    # 0-based position in the source
         "target": "2",                             # the intended object (an id of "objects")
         "objects": {"1": [x, y], "2": [x, y], ...},  # every visible object's centre, ORIGINAL
                                                    # (unrectified) left-image pixels
         "polygons": {"1": [[x, y], x4], ...},      # optional outlines, original left px
         "keypoints": {"left": {...}, "right": {...}},  # optional: the keypoints-file dict
         "diver_position": "2",                     # optional label (rows of the table)
         "range_m": {"1": 1.02, ...},               # optional: object ranges from the camera
         "diver_range_m": 2.1}                      # optional: the diver's range
      ]
    }

Object ids are strings (JSON keys); an integer ``target`` is read as its string. Every problem
raises :class:`DatasetError` naming the file and the field.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np

from .errors import DatasetError, Dip3dError
from .frames import StereoFrame

__all__ = ["Dataset", "FrameAnnotation", "load_dataset", "ANNOTATIONS_FILE", "CALIB_FILE"]

ANNOTATIONS_FILE = "annotations.json"
CALIB_FILE = "calib.yaml"


@dataclass(frozen=True)
class FrameAnnotation:
    """The annotation of one stereo pair (pixels are original left-image pixels)."""

    index: int
    target: str
    objects: dict[str, tuple[float, float]]
    polygons: dict[str, np.ndarray] = field(default_factory=dict)
    keypoints: dict | None = None
    diver_position: str | None = None
    range_m: dict[str, float] = field(default_factory=dict)
    diver_range_m: float | None = None

    @property
    def target_px(self) -> tuple[float, float]:
        """The intended object's annotated point."""
        return self.objects[self.target]


@dataclass(frozen=True)
class Dataset:
    """A read and validated dataset (see the module doc for the format)."""

    root: Path
    source_spec: str
    calib_paths: tuple[Path, ...]
    objects: dict[str, dict]
    frames: tuple[FrameAnnotation, ...]

    def label(self, object_id: str) -> str:
        """Return the object's label (its id when it has none)."""
        return str(self.objects.get(object_id, {}).get("label", object_id))

    def rig(self, image_size: tuple[int, int], params: Mapping[str, Any] | None = None):
        """Return the dataset's StereoRig for frames of ``image_size`` (w, h).

        ``calib.alpha`` and ``calib.already_rectified`` come from ``params`` when given.
        """
        from .perception.calibration_io import load_rig

        alpha = float(params["calib.alpha"]) if params is not None else 0.0
        rectified = bool(params["calib.already_rectified"]) if params is not None else False
        paths = [str(p) for p in self.calib_paths]
        return load_rig(paths if len(paths) > 1 else paths[0], image_size, alpha, rectified)

    def pairs(self, params: Mapping[str, Any] | None = None) -> Iterator[tuple[FrameAnnotation, StereoFrame]]:
        """Yield (annotation, frame) for every annotated pair, in source order.

        Raises:
            DatasetError: an annotated index has no pair in the source.
        """
        from .sources import open_source

        wanted = {f.index: f for f in self.frames}
        seen: set[int] = set()
        try:
            with open_source(self.source_spec, params) as source:
                for frame in source:
                    key = _frame_key(frame)
                    ann = wanted.get(key)
                    if ann is not None and key not in seen:
                        seen.add(key)
                        yield ann, frame
                    if len(seen) == len(wanted):
                        break
        except DatasetError:
            raise
        except Dip3dError as exc:
            raise DatasetError(f"{self.root / ANNOTATIONS_FILE}: source {self.source_spec}: {exc}") from None
        missing = sorted(set(wanted) - seen)
        if missing:
            raise DatasetError(f"{self.root / ANNOTATIONS_FILE}: frames[index={missing[0]}]: no image pair "
                               f"with this index in {self.source_spec} ({len(missing)} annotated pairs missing)")


def _frame_key(frame: StereoFrame) -> int:
    """The annotation index of a frame: its folder number NNNNNN, else its position."""
    name = (frame.meta or {}).get("name")
    if isinstance(name, str) and name.isdigit():
        return int(name)
    return int(frame.index)


# -- reading ------------------------------------------------------------------------------------
def load_dataset(path: str | Path) -> Dataset:
    """Read and validate a dataset folder.

    Raises:
        DatasetError: the folder, the annotations or the calibration is missing or malformed;
            the message names the file and the field.
    """
    root = Path(path)
    if not root.is_dir():
        raise DatasetError(f"{root}: dataset folder not found")
    ann_path = root / ANNOTATIONS_FILE
    if not ann_path.is_file():
        raise DatasetError(f"{ann_path}: annotations file not found (every dataset needs {ANNOTATIONS_FILE})")
    try:
        data = json.loads(ann_path.read_text())
    except (OSError, UnicodeDecodeError) as exc:
        raise DatasetError(f"{ann_path}: cannot read ({exc.__class__.__name__})") from None
    except json.JSONDecodeError as exc:
        raise DatasetError(f"{ann_path}:{exc.lineno}: not valid JSON ({exc.msg})") from None
    if not isinstance(data, dict):
        raise DatasetError(f"{ann_path}: expected a JSON object with 'objects' and 'frames'")
    where = str(ann_path)
    objects = _objects(data.get("objects"), where)
    frames_raw = data.get("frames")
    if not isinstance(frames_raw, list) or not frames_raw:
        raise DatasetError(f"{where}: frames: expected a non-empty list of frame annotations")
    frames = tuple(_frame(f, objects, f"{where}: frames[{i}]") for i, f in enumerate(frames_raw))
    indices = [f.index for f in frames]
    if len(set(indices)) != len(indices):
        dup = next(i for i in indices if indices.count(i) > 1)
        raise DatasetError(f"{where}: frames: index {dup} is annotated twice")
    return Dataset(root, _source(data.get("source"), root, where), _calib(data.get("calib"), root, where),
                   objects, frames)


def _objects(value: Any, where: str) -> dict[str, dict]:
    if not isinstance(value, dict) or not value:
        raise DatasetError(f"{where}: objects: expected a non-empty object {{id: {{\"label\": ...}}}}")
    out = {}
    for key, spec in value.items():
        if spec is None:
            spec = {}
        if not isinstance(spec, dict):
            raise DatasetError(f"{where}: objects.{key}: expected an object like {{\"label\": \"...\"}}")
        out[str(key)] = dict(spec)
    return out


def _source(value: Any, root: Path, where: str) -> str:
    if value is None:
        return str(root)
    if not isinstance(value, str) or not value.strip():
        raise DatasetError(f"{where}: source: expected a source spec string, got {value!r}")
    from .sources import parse_spec

    scheme, target, _ = parse_spec(value)
    if scheme in ("folder", "bag", "record", "") and target and not Path(target).is_absolute():
        resolved = str(root / target)
        return value.replace(target, resolved, 1)
    return value


def _calib(value: Any, root: Path, where: str) -> tuple[Path, ...]:
    names = [CALIB_FILE] if value is None else ([value] if isinstance(value, str) else value)
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise DatasetError(f"{where}: calib: expected a file name or a list of file names, got {value!r}")
    paths = tuple(p if p.is_absolute() else root / p for p in map(Path, names))
    for p in paths:
        if not p.exists():
            raise DatasetError(f"{p}: calibration file not found (named by {where}: calib"
                               f"{'' if value is not None else ', default ' + CALIB_FILE})")
    return paths


def _point(value: Any, where: str) -> tuple[float, float]:
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            or not all(math.isfinite(v) for v in value)):
        raise DatasetError(f"{where}: expected [x, y] in pixels, got {value!r}")
    return float(value[0]), float(value[1])


def _frame(raw: Any, objects: Mapping[str, dict], where: str) -> FrameAnnotation:
    if not isinstance(raw, dict):
        raise DatasetError(f"{where}: expected an object with index, target and objects")
    index = raw.get("index")
    if isinstance(index, bool) or not isinstance(index, int) or index < 0:
        raise DatasetError(f"{where}.index: expected an integer >= 0, got {index!r}")
    pts_raw = raw.get("objects")
    if not isinstance(pts_raw, dict) or not pts_raw:
        raise DatasetError(f"{where}.objects: expected {{id: [x, y], ...}} with at least the target")
    points = {}
    for key, value in pts_raw.items():
        if str(key) not in objects:
            raise DatasetError(f"{where}.objects.{key}: unknown object id (not in the top-level objects)")
        points[str(key)] = _point(value, f"{where}.objects.{key}")
    target = raw.get("target")
    if target is None or isinstance(target, bool) or str(target) not in points:
        raise DatasetError(f"{where}.target: {target!r} is not one of this frame's objects "
                           f"({', '.join(points)})")
    polygons = {}
    for key, poly in (raw.get("polygons") or {}).items():
        arr = np.asarray(poly, dtype=float) if isinstance(poly, list) else None
        if arr is None or arr.ndim != 2 or arr.shape[1] != 2 or len(arr) < 3 or not np.isfinite(arr).all():
            raise DatasetError(f"{where}.polygons.{key}: expected a list of at least 3 [x, y] points")
        if str(key) not in points:
            raise DatasetError(f"{where}.polygons.{key}: no point for this object in {where}.objects")
        polygons[str(key)] = arr
    keypoints = raw.get("keypoints")
    if keypoints is not None:
        from .errors import KeypointsError
        from .perception.keypoints_file import parse_keypoints
        try:
            parse_keypoints(keypoints, f"{where}.keypoints")
        except KeypointsError as exc:
            raise DatasetError(str(exc)) from None
    position = raw.get("diver_position")
    ranges = raw.get("range_m") or {}
    if not isinstance(ranges, dict) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in ranges.values()):
        raise DatasetError(f"{where}.range_m: expected {{id: metres, ...}}")
    diver_range = raw.get("diver_range_m")
    if diver_range is not None and (isinstance(diver_range, bool) or not isinstance(diver_range, (int, float))):
        raise DatasetError(f"{where}.diver_range_m: expected metres, got {diver_range!r}")
    return FrameAnnotation(index, str(target), points, polygons, keypoints,
                           None if position is None else str(position),
                           {str(k): float(v) for k, v in ranges.items()},
                           None if diver_range is None else float(diver_range))

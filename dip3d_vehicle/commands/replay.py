"""``dip3d-vehicle replay RUN.mcap``: re-run perception on the image pairs a run record kept.

Parameters: the log header's ``params`` (the run's effective values), then ``--params`` files and
``--set`` overrides; with an explicit ``--profile`` the run's values are replaced by that profile.

What replay reads from the run record (``run.mcap``, written by ``run`` and ``sitl``; the "header"
is its ``run``, ``params`` and ``calibration`` metadata):

- header ``meta["calib"]``: calibration file path, or list of paths, as ``load_rig`` takes them
  (relative paths are tried from the working directory, then from the log's folder); or
  header ``meta["calib_opencv_yaml"]``: the calibration embedded as the text of an OpenCV
  FileStorage YAML (what ``write_opencv_calibration`` writes); one of the two is required.
- header ``meta["image_size"]`` (optional): [width, height] of the frames.
- image messages (``/camera/left/image``, ``/camera/right/image`` and ``/dip3d/kept``): the kept pairs, ``frame_index`` = the frame's index.
- frame records (``/dip3d/frame``): ``index`` (matches the image record's ``frame_index``), ``status`` and
  ``target`` (``{"left_px": [x, y], ...}`` original px, or null) as in the contract JSON: the
  run's decision; and ``keypoints`` (keypoints-file dict, original px, or null) when the run's
  ``pose.backend`` is ``keypoints`` (the simulator's pose source): replay feeds them back.

A decision *changed* when the status differs or the target moved more than ``--tolerance-px``.
Each kept pair is decided alone (``candidates.reuse_frames`` 0: the frames between kept pairs are
not in the record). A run's frame decided on candidates followed from earlier frames
(``candidates_followed`` in its record, ``perception/reuse.py``) can therefore only be compared on
its status: its target, a centre of features found on an earlier frame and followed, may lie a few
pixels from the one computed on this frame alone.
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from pathlib import Path
from typing import Any, Iterator, Mapping

from ..config import Params, load_params, schema
from ..errors import LogError
from ..record.mcap_log import McapRunReader
from ._common import add_params_arguments

NAME = "replay"
HELP = "re-run perception (optionally with other parameters) on the image pairs a run record (run.mcap) kept"

__all__ = ["replay_log", "replay_params", "log_rig", "changed"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the command's arguments."""
    parser.add_argument("log", metavar="RUN.mcap", help="run record (run.mcap) written by run or sitl")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--tolerance-px", type=float, default=2.0,
                        help="a target that moved more than this counts as changed (default 2 px)")
    add_params_arguments(parser)
    parser.set_defaults(profile=None)
    for action in parser._actions:
        if action.dest == "profile":
            action.help = "start from this profile instead of the parameters recorded in the log"


def replay_params(header: Mapping[str, Any], profile: str | None = None, files: list[str] | tuple = (),
                  sets: list[str] | tuple = ()) -> tuple[Params, list[str]]:
    """Return (parameters for the replay, header keys ignored as unknown to this version)."""
    if profile is not None:
        return load_params(profile, files, sets), []
    known = schema()
    logged = dict(header.get("params") or {})
    unknown = sorted(k for k in logged if k not in known)
    base = load_params("default").with_overrides({k: v for k, v in logged.items() if k in known}, "run log")
    given, plain = load_params("default", files, sets), load_params("default")
    over = {k: given[k] for k in given if given.source(k) != plain.source(k)}
    return (base.with_overrides(over, "command line") if over else base), unknown


def log_rig(reader: McapRunReader, params: Mapping[str, Any], image_size: tuple[int, int]):
    """Return the StereoRig named or embedded in the log header (see the module doc)."""
    from ..perception.calibration_io import load_rig

    meta = (reader.header or {}).get("meta") or {}
    alpha, rect = float(params["calib.alpha"]), bool(params["calib.already_rectified"])
    size = tuple(meta.get("image_size") or image_size)
    if meta.get("calib_opencv_yaml"):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "calibration.yaml"
            path.write_text(str(meta["calib_opencv_yaml"]))
            return load_rig(str(path), size, alpha, rect)
    calib = meta.get("calib")
    if not calib:
        raise LogError(f"{reader.path}: header meta has no 'calib' (file) or 'calib_opencv_yaml' "
                       "(embedded calibration): replay needs one")
    paths = [calib] if isinstance(calib, str) else list(calib)
    resolved = [p if Path(p).exists() or Path(p).is_absolute() else str(reader.path.parent / p) for p in paths]
    return load_rig(resolved if len(resolved) > 1 else resolved[0], size, alpha, rect)


def changed(old: Mapping[str, Any] | None, new: Mapping[str, Any], tolerance_px: float) -> bool:
    """Return True when the decision differs (status, or target moved more than the tolerance).

    A run's frame decided on followed candidates (``old["candidates_followed"]``) is compared on its status only.
    """
    if old is None:
        return True
    if old.get("status") != new.get("status"):
        return True
    if old.get("candidates_followed"):
        return False
    a, b = _px(old.get("target")), _px(new.get("target"))
    if a is None or b is None:
        return (a is None) != (b is None)
    return math.hypot(a[0] - b[0], a[1] - b[1]) > tolerance_px


def _px(target: Mapping[str, Any] | None) -> tuple[float, float] | None:
    if not target or target.get("left_px") is None or None in target["left_px"]:
        return None
    return float(target["left_px"][0]), float(target["left_px"][1])


def replay_log(path: str | Path, params: Params, tolerance_px: float = 2.0) -> Iterator[dict]:
    """Yield, for each kept image pair, {index, old, new, changed} (old/new: status + target)."""
    from ..perception.pipeline import Perception, make_pose_estimator

    with McapRunReader(path) as reader:
        if reader.header is None:
            raise LogError(f"{reader.path}: run record is cut before its metadata (nothing to replay)")
        records = {int(f["index"]): f for f in reader.frames() if isinstance(f.get("index"), int)}
        engine = None
        for index, left, right in reader.image_pairs():
            if engine is None:
                rig = log_rig(reader, params, (left.shape[1], left.shape[0]))
                alone = params.with_overrides({"candidates.reuse_frames": 0}, "replay: each kept pair decided alone")
                engine = Perception(rig, alone, make_pose_estimator(alone, None))
            old = records.get(index)
            if params["pose.backend"] == "keypoints":
                engine.pose.provide((old or {}).get("keypoints"), f"{reader.path}: frame {index} keypoints")
            new = engine.process(left, right).to_json(engine.rig)
            old_short = None if old is None else {"status": old.get("status"), "target": old.get("target"),
                                                  "candidates_followed": bool(old.get("candidates_followed"))}
            yield {"index": index, "old": old_short, "new": new,
                   "changed": changed(old_short, new, tolerance_px)}


def _fmt(decision: Mapping[str, Any] | None) -> str:
    if decision is None:
        return "(no frame record)"
    px = _px(decision.get("target"))
    where = "" if px is None else f" ({px[0]:.1f}, {px[1]:.1f})"
    return f"{decision.get('status')}{where}"


def run(args: argparse.Namespace) -> int:
    """Replay the log and print per-frame old -> new decisions and a summary."""
    with McapRunReader(args.log) as reader:
        header = reader.header or {}
    params, unknown = replay_params(header, args.profile, args.params, args.set_)
    rows = []
    for row in replay_log(args.log, params, args.tolerance_px):
        rows.append(row)
        if not args.json:
            mark = "  CHANGED" if row["changed"] else ""
            print(f"frame {row['index']:6d}: {_fmt(row['old']):<32} -> {_fmt(row['new'])}{mark}")
    n_changed = sum(r["changed"] for r in rows)
    if args.json:
        print(json.dumps({"log": str(args.log), "frames": len(rows), "changed": n_changed,
                          "ignored_params": unknown,
                          "replayed": [{"index": r["index"], "old": r["old"], "changed": r["changed"],
                                        "new": {k: r["new"][k] for k in ("status", "reason", "target",
                                                                          "selection")}}
                                       for r in rows]}))
        return 0
    if unknown:
        print(f"note: ignored {len(unknown)} logged parameters unknown to this version: {', '.join(unknown)}")
    print(f"{args.log}: replayed {len(rows)} kept pairs, {n_changed} decisions changed "
          f"(tolerance {args.tolerance_px:g} px)")
    return 0

"""Fuzzing the file parsers (hypothesis, derandomized, bounded): only the documented error may escape.

- parameter files -> ``check_file`` / ``load_params(files=...)``: ParamsError only;
- calibration files (random bytes, mutated OpenCV / Kalibr / ROS files) -> ``load_rig``: CalibrationError only;
- keypoints files (random bytes, mutated JSON, random JSON structures) -> ``load_keypoints_file``:
  KeypointsError only.

Each test counts the inputs it tried and prints the count (``pytest -s`` shows it).
"""

from __future__ import annotations

import json
import random
from pathlib import Path

import yaml
from hypothesis import HealthCheck, given, settings, strategies as st

from dip3d_vehicle.config import check_file, load_params, schema
from dip3d_vehicle.errors import CalibrationError, KeypointsError, ParamsError
from dip3d_vehicle.perception.calibration_io import load_rig
from dip3d_vehicle.perception.keypoints_file import load_keypoints_file

ROOT = Path(__file__).resolve().parents[2]
CALIB = ROOT / "tests" / "data" / "calib"
SAMPLES = ROOT / "dip3d_vehicle" / "samples"
FUZZ = dict(deadline=None, derandomize=True, database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                   HealthCheck.data_too_large, HealthCheck.filter_too_much])
COUNTS: dict[str, int] = {}


def _report(name: str, summary) -> None:
    summary(f"[fuzz] {name}: {COUNTS.get(name, 0)} inputs, 0 unhandled exceptions")


def _mutate(data: bytes, seed: int, n: int) -> bytes:
    """Byte-level mutations: flips, deletions, insertions of interesting bytes, chunk duplication."""
    rng = random.Random(seed)
    b = bytearray(data)
    for _ in range(n):
        if not b:
            b.extend(b"\x00")
        op = rng.randrange(6)
        i = rng.randrange(len(b))
        if op == 0:
            b[i] ^= 1 << rng.randrange(8)
        elif op == 1:
            del b[i:i + rng.randrange(1, 16)]
        elif op == 2:
            b[i:i] = rng.choice([b"-", b"nan", b"1e309", b"\n", b":", b"[", b"]", b"{", b"\x00", b"\xff",
                                 b"0", b"-1", b"  ", b"!!opencv-matrix", b"'", b'"', b"inf", b"99999999999"])
        elif op == 3:
            j = rng.randrange(len(b))
            b[i:i] = b[min(i, j):max(i, j)][:64]
        elif op == 4:
            b[i] = rng.randrange(256)
        else:
            del b[i:]
    return bytes(b)


# -------------------------------------------------------------------------------- parameters
_KEYS = sorted(schema())
_VALUES = st.one_of(st.none(), st.booleans(), st.integers(-10**12, 10**12), st.floats(allow_nan=True),
                    st.text(max_size=20), st.lists(st.integers(-5, 5), max_size=4),
                    st.sampled_from(["inf", "-.inf", ".nan", "1e999", "manual_control", "GUIDED", "yes"]))


@settings(max_examples=1500, **FUZZ)
@given(text=st.one_of(st.text(max_size=300),
                      st.binary(max_size=300).map(lambda b: b.decode("latin-1")),
                      st.lists(st.tuples(st.sampled_from(_KEYS + ["bogus", "link", "link.rate", ""]), _VALUES),
                               max_size=6).map(lambda kv: "\n".join(f"{k}: {json.dumps(v)}" for k, v in kv)),
                      st.dictionaries(st.sampled_from(_KEYS), _VALUES, max_size=6).map(
                          lambda d: yaml.safe_dump(d, default_flow_style=False)),
                      st.tuples(st.sampled_from(["default", "paper", "fast"]), st.integers(0, 10**6),
                                st.integers(1, 8)).map(
                          lambda t: _mutate((ROOT / "params" / f"{t[0]}.yaml").read_bytes(), t[1], t[2]).decode(
                              "utf-8", "replace"))))
def _params_case(tmp_path_factory, text):
    COUNTS["params"] = COUNTS.get("params", 0) + 1
    path = tmp_path_factory.getbasetemp() / "fuzz_params.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogateescape")
    for call in (lambda: check_file(path), lambda: load_params(files=[path])):
        try:
            call()
        except ParamsError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc).strip()


def test_fuzz_parameter_files(tmp_path_factory, summary):
    _params_case(tmp_path_factory)
    _report("params", summary)


# -------------------------------------------------------------------------------- calibration
_CALIB_SETS = [[CALIB / "opencv_stereo.yml"], [CALIB / "kalibr_camchain.yaml"],
               [CALIB / "ros_left.yaml", CALIB / "ros_right.yaml"], [SAMPLES / "calib.yaml"]]


@settings(max_examples=600, **FUZZ)
@given(case=st.one_of(
    st.tuples(st.just(-1), st.binary(max_size=400), st.integers(0, 0), st.integers(0, 0)),
    st.tuples(st.integers(0, len(_CALIB_SETS) - 1), st.just(b""), st.integers(0, 10**6), st.integers(1, 6))),
    size=st.sampled_from([None, (1600, 1200), (800, 600), (0, 0)]))
def _calib_case(tmp_path_factory, case, size):
    COUNTS["calibration"] = COUNTS.get("calibration", 0) + 1
    which, raw, seed, n = case
    base = tmp_path_factory.getbasetemp()
    if which < 0:
        paths = [base / "fuzz_calib.yaml"]
        paths[0].write_bytes(raw)
    else:
        paths = []
        for i, src in enumerate(_CALIB_SETS[which]):
            p = base / f"fuzz_calib_{i}{src.suffix}"
            p.write_bytes(_mutate(src.read_bytes(), seed + i, n))
            paths.append(p)
    try:
        load_rig(paths if len(paths) > 1 else paths[0], image_size=size)
    except CalibrationError as exc:
        assert "\n" not in str(exc).strip()


def test_fuzz_calibration_files(tmp_path_factory, summary):
    _calib_case(tmp_path_factory)
    _report("calibration", summary)


# -------------------------------------------------------------------------------- keypoints
_JSON = st.recursive(st.one_of(st.none(), st.booleans(), st.integers(-10**20, 10**20), st.floats(allow_nan=False),
                               st.text(max_size=8)),
                     lambda kids: st.lists(kids, max_size=4) | st.dictionaries(
                         st.sampled_from(["left", "right", "shoulder", "elbow", "wrist", "rectified", "x"]), kids,
                         max_size=4), max_leaves=20)
_POINT = st.lists(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30),
                            st.text(max_size=3), st.none()), min_size=0, max_size=4)
_NEAR = st.fixed_dictionaries({side: st.dictionaries(st.sampled_from(["shoulder", "elbow", "wrist"]), _POINT,
                                                     min_size=2, max_size=3) for side in ("left", "right")},
                              optional={"rectified": st.one_of(st.booleans(), st.integers(), st.text(max_size=3))})


@settings(max_examples=2000, **FUZZ)
@given(raw=st.one_of(st.binary(max_size=200),
                     _JSON.map(lambda v: json.dumps(v).encode()),
                     _NEAR.map(lambda v: json.dumps(v, allow_nan=True).encode()),
                     st.tuples(st.integers(0, 10**6), st.integers(1, 6)).map(
                         lambda t: _mutate((SAMPLES / "keypoints.json").read_bytes(), t[0], t[1]))))
def _keypoints_case(tmp_path_factory, raw):
    COUNTS["keypoints"] = COUNTS.get("keypoints", 0) + 1
    path = tmp_path_factory.getbasetemp() / "fuzz_keypoints.json"
    path.write_bytes(raw)
    try:
        load_keypoints_file(path)
    except KeypointsError as exc:
        assert str(path) in str(exc)


def test_fuzz_keypoints_files(tmp_path_factory, summary):
    _keypoints_case(tmp_path_factory)
    _report("keypoints", summary)

"""The parameter system: one schema, profiles, files with file:line errors, --set, show/check."""

from __future__ import annotations

import json

import pytest

from dip3d_vehicle.cli import main
from dip3d_vehicle.config import check_file, load_params, profile_names, schema
from dip3d_vehicle.errors import ParamsError


def test_every_parameter_has_doc_unit_and_valid_default():
    """Every schema entry has a one-line doc, and its default passes its own range check."""
    for key, p in schema().items():
        assert p.doc and "\n" not in p.doc, key
        assert p.coerce(p.default, "schema") == p.default, key


def test_profiles_are_valid_and_paper_holds_the_paper_constants():
    """Each profile loads; paper holds ratio 0.3, |dz| 0.5 m, s_f 3, brute force, right of the wrist."""
    for name in profile_names():
        load_params(name)
    p = load_params("paper")
    assert p["candidates.lowe_ratio"] == 0.3
    assert p["filters.max_joint_dz_m"] == 0.5
    assert p["selection.extension_factor"] == 3.0
    assert p["candidates.matcher"] == "bruteforce"
    assert p["candidates.mask_side"] == "right"
    assert p["selection.method"] == "paper"
    assert p.source("candidates.lowe_ratio").startswith("params/paper.yaml:")


def test_layering_file_then_set(tmp_path):
    """A --params file overrides the profile and --set overrides the file; sources say so."""
    f = tmp_path / "mine.yaml"
    f.write_text("candidates:\n  lowe_ratio: 0.5\nselection.method: paper\n")
    p = load_params("default", [f], ["selection.method=default"])
    assert p["candidates.lowe_ratio"] == 0.5 and p.source("candidates.lowe_ratio") == f"{f}:2"
    assert p["selection.method"] == "default" and p.source("selection.method") == "--set"


@pytest.mark.parametrize("text,needle", [
    ("candidates.lowe_ratio: 1.7\n", ":1: candidates.lowe_ratio = 1.7 is out of range"),
    ("x: 1\nnot_a_key: 2\n", ":1: unknown parameter 'x'"),
    ("selection.method: best\n", "not allowed (expected one of paper, default)"),
    ("candidates.max_features: 1.5\n", "is not valid"),
    ("a: [1, 2\n", "not valid YAML"),
    ("- 1\n- 2\n", "expected a mapping"),
])
def test_check_reports_file_line_key_value_and_range(tmp_path, text, needle):
    """`params check` fails with file:line, key, value and the allowed range."""
    f = tmp_path / "bad.yaml"
    f.write_text(text)
    with pytest.raises(ParamsError) as exc:
        check_file(f)
    assert str(f) in str(exc.value) and needle in str(exc.value)


def test_params_cli_show_and_check(tmp_path, capsys):
    """`params show --json` prints values with sources; `params check` exits 0 / 2."""
    assert main(["params", "show", "--json", "--profile", "paper"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["candidates.lowe_ratio"] == {"value": 0.3, "unit": "", "source": "params/paper.yaml:6"}
    good, bad = tmp_path / "good.yaml", tmp_path / "bad.yaml"
    good.write_text("candidates.lowe_ratio: 0.4\n")
    bad.write_text("candidates.lowe_ratio: 0.4\nfilters.max_joint_dz_m: -1\n")
    assert main(["params", "check", str(good)]) == 0
    assert main(["params", "check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:2: filters.max_joint_dz_m = -1 is out of range" in err

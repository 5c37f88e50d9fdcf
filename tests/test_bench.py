"""``dip3d-vehicle bench``: structure of the report on a tiny run (2 small frames; not a timing test)."""

from __future__ import annotations

import json

import pytest

from dip3d_vehicle.bench import STAGES, format_table, run_bench, simulated_frames
from dip3d_vehicle.cli import main


@pytest.fixture(scope="module")
def tiny_report():
    data = simulated_frames("paper_pool", seeds=(1,), frames_per_seed=2, size=(640, 480))
    return run_bench(data, ("paper", "fast", "fast+follow2bg"), latency_profile="fast", latency_s=0.6)


def test_report_has_every_profile_metric(tiny_report):
    assert tiny_report["n_frames"] == 2
    for name in ("paper", "fast", "fast+follow2bg"):
        r = tiny_report["profiles"][name]
        assert r["frames"] == 2 and r["fps"] > 0
        assert set(r["stages_ms"]) == set(STAGES)
        assert {"p50", "p99"} <= set(r["latency_ms"])
        assert r["peak_rss_mib"] > 0 and r["cpu_ms_per_frame"] >= 0
        assert r["scored_frames"] == 2 and 0.0 <= r["accuracy"] <= 1.0
        assert 1 <= sum(r["pose_source"].values()) <= 2   # followed frames run no pose
        assert r["scored_blazepose_frames"] <= r["scored_frames"]
        if not r["follow"]:  # followed frames inherit their keyframe's pose source
            assert r["scored_blazepose_frames"] <= r["pose_source"]["blazepose"]
        assert r["correct_blazepose"] <= r["scored_blazepose_frames"]
    assert tiny_report["profiles"]["paper"]["fps_ratio_to_paper"] == 1.0
    assert tiny_report["profiles"]["paper"]["pose_settings"]["tracking"] is False
    assert tiny_report["profiles"]["fast"]["pose_settings"]["tracking"] is True
    follow = tiny_report["profiles"]["fast+follow2bg"]["follow"]
    assert follow["keyframe_interval"] == 2 and follow["keyframes"] >= 1
    assert follow["paced_hz"] == 10.0, "background keyframes get the frames at their camera rate"
    assert tiny_report["profiles"]["fast"]["follow"]["paced_hz"] == 10.0  # fast: follow.background true
    assert follow["keyframes"] + follow["followed"] + follow["lost"] >= 2


def test_latency_run_counts_frames(tiny_report):
    lat = tiny_report["latency"]
    assert lat["profile"] == "fast" and lat["frames_submitted"] >= 1 and lat["camera_hz"] == 15.0
    assert lat["frames_submitted"] >= lat["frames_processed"] + lat["frames_dropped"] - 1
    assert {"p50", "p99"} <= set(lat["frame_to_setpoint_ms"])


def test_table_names_every_profile(tiny_report):
    text = format_table(tiny_report)
    assert "paper" in text and "fast" in text and "frame-to-setpoint" in text


def test_command_json(capsys):
    assert main(["bench", "--json", "--profiles", "fast", "--seeds", "2", "--frames", "1", "--size", "480x360",
                 "--latency-profile", ""]) == 0
    out = json.loads(capsys.readouterr().out)
    assert list(out["profiles"]) == ["fast"] and "latency" not in out


def test_command_bad_size(capsys):
    assert main(["bench", "--size", "big", "--latency-profile", ""]) == 2
    assert "--size" in capsys.readouterr().err

"""``sitl`` streams its story as it happens: whole words, a progress line only on a terminal."""

from __future__ import annotations

import io
import json
import subprocess
import sys
import time
from types import SimpleNamespace

from sitl.live import LiveStory, wrap_story_line

WARNING = ("t=0.00 WARNING manual_control: MANUAL_CONTROL will be sent with the ground station's system id "
           "(the autopilot's SYSID_MYGCS; 255 until it has been read), because ArduSub drops pilot input from "
           "any other system.")


def _fake_sim():
    bb = SimpleNamespace(story=[], target=None)
    return SimpleNamespace(link=SimpleNamespace(events=[]), mission=SimpleNamespace(bb=bb, state="idle"),
                           pilot=SimpleNamespace(statustexts=[]), chosen_placard=lambda: None, last_meta={})


def test_long_lines_wrap_between_words_and_keep_every_word():
    parts = wrap_story_line(WARNING, 60)
    assert len(parts) > 2 and all(len(p) <= 60 for p in parts)
    assert " ".join(p.strip() for p in parts) == WARNING  # nothing cut, nothing lost


def test_new_lines_print_in_time_order_and_only_once():
    sim, out = _fake_sim(), io.StringIO()
    live = LiveStory(sim, out, progress=False, width=100)
    sim.link.events.append("t=0.02 autopilot first heard")
    sim.mission.bb.story.append("t=0.01 state idle -> wait_for_diver (engage)")
    sim.pilot.statustexts.append((0.03, "1/191: DIP3D: " + "x" * 70))
    live(0.04)
    live(0.06)
    lines = out.getvalue().splitlines()
    assert lines[0].strip().startswith("t=0.01") and lines[1].strip().startswith("t=0.02")
    assert "x" * 70 in out.getvalue() and "\r" not in out.getvalue()  # a long word moves whole to the next line
    assert sum(line.strip().startswith("t=") for line in lines) == 3  # each story line once


def test_progress_line_on_a_terminal_is_erased_before_story_lines():
    sim, out = _fake_sim(), io.StringIO()
    live = LiveStory(sim, out, progress=True, width=100)
    live(1.0)
    sim.mission.bb.story.append("t=1.02 diver's arm raised")
    live(1.02)
    live.finish()
    text = out.getvalue()
    assert "[sim    1.0 s] idle" in text and "no object chosen" in text
    assert "\r\033[K  t=1.02 diver's arm raised\n" in text and text.endswith("\r\033[K")


def test_sitl_streams_while_running_and_exits_with_its_outcome(tmp_path):
    cmd = [sys.executable, "-m", "dip3d_vehicle.cli", "sitl", "--no-plots", "--speed", "1",
           "--set", "sitl.max_sim_time_s=2.5", "--set", f"sitl.out_dir={tmp_path / 'runs'}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    arrivals = [(time.monotonic(), line) for line in proc.stdout]
    end = time.monotonic()
    assert proc.wait(120) == 6, proc.stderr.read()  # no_decision after 2.5 s
    story = [(t, line) for t, line in arrivals if line.startswith("  t=")]
    assert story and end - story[0][0] >= 1.0  # the first story line came out while the run went on (>= 2 s)
    assert any(line.startswith("sitl: outcome NO_DECISION (exit code 6): no object chosen") for _, line in arrivals)
    (run_dir,) = (tmp_path / "runs").iterdir()
    assert (run_dir / "run.mcap").is_file() and "_paper_pool_s0" in run_dir.name


def test_sitl_json_prints_one_object_and_nothing_else(tmp_path):
    cmd = [sys.executable, "-m", "dip3d_vehicle.cli", "sitl", "--no-plots", "--json",
           "--set", "sitl.max_sim_time_s=2.5", "--out", str(tmp_path / "one")]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 6, proc.stderr
    (line,) = proc.stdout.splitlines()
    doc = json.loads(line)
    assert doc["outcome"] == "no_decision" and doc["exit_code"] == 6 and doc["outcome_reason"]
    assert doc["arrived"] is False and doc["reached"] is False
    again = subprocess.run(cmd, capture_output=True, text=True, timeout=120)  # same --out: refused, not overwritten
    assert again.returncode == 2 and "already holds files" in again.stderr and again.stderr.count("\n") == 1

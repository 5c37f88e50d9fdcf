"""A whole simulated mission recorded as ``sitl`` records it: run.mcap read back with the ``mcap``
package (every channel, expected counts, schema names), replayed with the same decisions, and
mav.tlog read back with pymavlink, counted both ways against the two ends of the link."""

from __future__ import annotations

import math
from collections import Counter

import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.record.mcap_log import McapRunReader
from dip3d_vehicle.record.recorder import RunRecorder
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

pytestmark = pytest.mark.slow

KEEP = 10

SCHEMAS = {
    "/camera/left/image": "foxglove.CompressedImage", "/camera/right/image": "foxglove.CompressedImage",
    "/camera/left/annotations": "foxglove.ImageAnnotations", "/scene": "foxglove.SceneUpdate",
    "/mission/log": "foxglove.Log", "/story": "foxglove.Log", "/mavlink/statustext": "foxglove.Log",
    "/mission/state": "dip3d.MissionState", "/servo": "dip3d.Servo", "/autopilot/attitude": "dip3d.Attitude",
    "/autopilot/depth": "dip3d.Depth", "/autopilot/status": "dip3d.AutopilotStatus",
    "/link/status": "dip3d.LinkStatus", "/dip3d/frame": "dip3d.FrameRecord", "/dip3d/telemetry": "dip3d.Telemetry",
    "/dip3d/kept": "dip3d.KeptFrame",
}


@pytest.fixture(scope="module")
def mission(tmp_path_factory):
    out = tmp_path_factory.mktemp("sitl_record")
    scenario = load_scenario("paper_pool", 0)
    params = sim_params(load_params(), scenario)
    recorder = RunRecorder(out / "run.mcap", params, {"command": "sitl", "scenario": "paper_pool", "seed": 0,
                                                       "image_size": list(scenario.camera.image_size),
                                                       "calib_opencv_yaml": _calib_text(scenario, params, out)},
                           tlog_path=out / "mav.tlog", keep_images_every=KEEP, image_format="png")
    sim = Simulation(scenario, params, log=recorder)
    recorder.rig = sim.rig
    recorder.attach_link(sim.link)
    try:
        result = sim.run()
        recorder.story(sim.link.events + sim.mission.bb.story)  # the lines of the link's close
    finally:
        sim.close()
        recorder.close()
    return out, result, sim, recorder


def _calib_text(scenario, params, out) -> str:
    from dip3d_vehicle.perception.calibration_io import write_opencv_calibration

    return write_opencv_calibration(scenario.rig(params["calib.alpha"]), out / "calib.yaml").read_text()


def test_the_mcap_package_reads_every_channel_with_the_expected_counts(mission):
    from mcap.reader import make_reader

    out, result, sim, recorder = mission
    with open(out / "run.mcap", "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        schemas = {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}
        counts = Counter(ch.topic for _, ch, _ in reader.iter_messages())
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
    print("\nchannels (topic: schema, messages):")
    for name in sorted(counts):
        print(f"  {name}: {schemas[name]}, {counts[name]}")
    for name, schema in SCHEMAS.items():
        assert schemas[name] == schema, name
        assert counts[name] > 0, name
    frames = sim.controller.observations  # processed and delivered before the run ended
    captured = math.floor(result.sim_time_s * float(sim.params["sitl.camera_rate_hz"]) + 1e-6)
    assert counts["/camera/left/image"] == counts["/camera/right/image"] == counts["/dip3d/kept"]
    assert counts["/dip3d/kept"] == math.ceil(captured / KEEP), captured
    assert counts["/dip3d/frame"] == counts["/camera/left/annotations"] == counts["/scene"] == frames
    assert counts["/mission/state"] == counts["/mission/log"] == len(result.states)
    assert abs(counts["/servo"] - result.sim_time_s * 10) <= 2  # 10 Hz
    assert abs(counts["/link/status"] - result.sim_time_s) <= 2  # 1 Hz
    assert abs(counts["/dip3d/telemetry"] - result.sim_time_s * 10) <= 2
    assert counts["/story"] >= len([s for s in result.story if "pilot heard" not in s])
    assert {"record", "run", "params", "calibration"} <= set(metadata)
    assert metadata["calibration"]["calib_opencv_yaml"].startswith("%YAML")
    assert int(metadata["record"]["version"]) == 2 and metadata["run"]["command"] == "sitl"


def test_plottable_autopilot_channels_match_the_tlog(mission):
    from pymavlink import mavutil

    out, result, sim, recorder = mission
    with McapRunReader(out / "run.mcap") as record:
        topics = Counter(m.topic for m in record.messages())
        depth = [record.decode(m)["depth_m"] for m in record.messages(("/autopilot/depth",))]
    tlog = _read_tlog(out / "mav.tlog", mavutil)
    ap = (sim.link.config.target_system, sim.link.config.target_component)
    assert topics["/autopilot/attitude"] == tlog[("in", ap, "ATTITUDE")]
    assert topics["/autopilot/depth"] == tlog[("in", ap, "VFR_HUD")]
    assert topics["/autopilot/status"] == tlog[("in", ap, "HEARTBEAT")]
    statustext = sum(v for (d, _, kind), v in tlog.items() if kind == "STATUSTEXT")
    assert topics["/mavlink/statustext"] == statustext
    assert max(depth) > 0.5  # the scenario's vehicle is under water


def _read_tlog(path, mavutil) -> Counter:
    """Count (direction, (sys, comp), type) of every message in a tlog; ours are 1/191 or the GCS id."""
    conn = mavutil.mavlink_connection(str(path))
    out = Counter()
    last_usec = 0
    while True:
        msg = conn.recv_match()
        if msg is None:
            break
        assert msg._timestamp * 1e6 >= last_usec - 1  # time never goes back
        last_usec = msg._timestamp * 1e6
        src = (msg.get_srcSystem(), msg.get_srcComponent())
        out[("out" if src[1] in (191,) else "in", src, msg.get_type())] += 1
    return out


def test_tlog_counts_both_ways(mission):
    """Sent: the tlog (read by pymavlink) equals the link's own counters and what the autopilot got;
    received: equals the recorder's count and the link's received counter."""
    from pymavlink import mavutil

    out, result, sim, recorder = mission
    conn = mavutil.mavlink_connection(str(out / "mav.tlog"))
    read = Counter()
    while (msg := conn.recv_match()) is not None:
        read[msg.get_type()] += 1
    written_sent, written_in = recorder.tlog.counts["sent"], recorder.tlog.counts["received"]
    total = Counter(written_sent) + Counter(written_in)
    print(f"\ntlog read back by pymavlink: {dict(sorted(read.items()))}")
    print(f"controller sent (tlog writer): {dict(sorted(written_sent.items()))}")
    print(f"controller received (tlog writer): {dict(sorted(written_in.items()))}")
    assert read == total
    assert dict(written_sent) == {k: v for k, v in sim.link.stats.sent.items() if v}
    assert sum(written_in.values()) == sim.link.stats.received  # no BAD_DATA on a clean link
    got_by_autopilot = sum(1 for r in sim.received if r.kind == "MANUAL_CONTROL")
    assert written_sent.get("MANUAL_CONTROL", 0) == got_by_autopilot
    assert recorder.tlog.write_errors == 0


def test_replay_reproduces_the_runs_decisions(mission):
    """PNG pairs: replaying each kept full-perception frame gives the run's own decision."""
    from dip3d_vehicle.commands.replay import replay_log, replay_params

    out, result, sim, recorder = mission
    with McapRunReader(out / "run.mcap") as record:
        params, unknown = replay_params(record.header)
    assert unknown == []
    rows = list(replay_log(out / "run.mcap", params))
    full = [r for r in rows if r["old"] is not None and r["old"]["status"] != "tracking"]
    print(f"\nreplayed {len(rows)} kept pairs, {len(full)} full-perception frames, "
          f"{sum(r['changed'] for r in full)} changed")
    assert len(full) >= 2
    assert not any(r["changed"] for r in full)

"""Units of sitl/faults.py (plan files, relay, camera faults, frame guard) and Autopilot.reboot()."""

from __future__ import annotations

import socket
from pathlib import Path

import numpy as np
import pytest

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.errors import ScenarioError
from dip3d_vehicle.frames import StereoFrame
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.connection import mavlink2 as m2
from sitl.autopilot import Autopilot
from sitl.faults import (CameraFaults, FaultEvent, FrameGuard, LinkFaults, LossyRelay, load_fault_plan,
                         parse_fault_plan, split_frames)

FAULT_DIR = Path(__file__).resolve().parents[2] / "sitl" / "faults"


def test_every_bundled_plan_loads():
    files = sorted(FAULT_DIR.glob("*.yaml"))
    assert files
    for f in files:
        plan = load_fault_plan(f, seed=3)
        assert plan.seed == 3


def test_random_ranges_are_seeded():
    data = {"events": [{"kind": "link_cut", "at_s": [10, 20], "duration_s": [1, 5]}]}
    a, b, c = (parse_fault_plan(data, "x", s) for s in (1, 1, 2))
    assert a == b and a != c
    assert 10 <= a.events[0].at_s <= 20 and 1 <= a.events[0].duration_s <= 5


@pytest.mark.parametrize("data, needle", [
    ([1], "top level"), ({"bogus": 1}, "unknown key"), ({"link": {"drop": 2}}, "link.drop"),
    ({"link": {"lag": 1}}, "link: unknown"), ({"events": [{"kind": "meteor", "at_s": 1}]}, "events[0].kind"),
    ({"events": [{"kind": "link_cut", "at_s": 1}]}, "duration_s"),
    ({"events": [{"kind": "pilot_disarm"}]}, "exactly one of at_s"),
    ({"events": [{"kind": "pilot_disarm", "at_s": [3, 1]}]}, "high < low"),
    ({"events": [{"kind": "camera_one_eye", "at_s": 1, "duration_s": 1, "eye": "middle"}]}, "eye"),
    ({"seed": -1}, "seed"),
])
def test_bad_plans_name_the_field(data, needle):
    with pytest.raises(ScenarioError, match=None) as exc:
        parse_fault_plan(data, "plan.yaml")
    assert needle in str(exc.value) and "plan.yaml" in str(exc.value)


def test_bad_plan_file(tmp_path):
    p = tmp_path / "f.yaml"
    p.write_text("link: [\n")
    with pytest.raises(ScenarioError, match="f.yaml"):
        load_fault_plan(p)
    with pytest.raises(ScenarioError, match="cannot read"):
        load_fault_plan(tmp_path / "missing.yaml")


def test_split_frames_resyncs_and_keeps_partial():
    mav = m2.MAVLink(None, 1, 1)
    a = mav.heartbeat_encode(12, 3, 0, 0, 0).pack(mav)
    b = mav.attitude_encode(1, 0, 0, 0, 0, 0, 0).pack(mav)
    buf = bytearray(b"junk" + a + b[:5])
    assert split_frames(buf) == [a]
    buf.extend(b[5:])
    assert split_frames(buf) == [b] and not buf


def _relay_pair(faults: LinkFaults, seed: int = 0):
    clock = SimClock()
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    relay = LossyRelay(f"tcp:127.0.0.1:{server.getsockname()[1]}", faults, clock, seed)
    up, _ = server.accept()
    up.setblocking(False)
    ctrl = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    ctrl.setblocking(False)
    return clock, server, relay, up, ctrl


def test_relay_delay_drop_cut_deterministic():
    mav = m2.MAVLink(None, 1, 191)
    results = []
    for _ in range(2):
        clock, server, relay, up, ctrl = _relay_pair(LinkFaults(drop=0.2, delay_s=0.1, jitter_s=0.05), seed=7)
        port = relay.down.getsockname()[1]
        relay.cut(2.0, 3.0)
        got, sent_at = [], {}
        for i in range(200):
            now = clock.advance(0.02)
            pkt = mav.heartbeat_encode(18, 8, 0, i, 0).pack(mav)
            ctrl.sendto(pkt, ("127.0.0.1", port))
            sent_at[i] = now
            relay.step()
            try:
                data = up.recv(65536)
            except BlockingIOError:
                data = b""
            for f in split_frames(bytearray(data)):
                got.append((round(now, 2), f[-2 - 4 - 1 - 1 - 1:]))
        c = relay.counts()["to_autopilot"]
        results.append((c, len(got)))
        assert c["in"] == 200 and c["cut"] >= 45  # 50 packets in the cut, minus those released before it
        assert 0.1 < c["dropped"] / (c["in"] - c["cut"]) < 0.3
        relay.close()
        up.close()
        server.close()
        ctrl.close()
    assert results[0] == results[1]


def test_camera_faults_and_guard():
    clock_frames = []

    def provider(t):
        i = len(clock_frames)
        clock_frames.append(t)
        img = np.full((40, 60, 3), 100, np.uint8)
        return StereoFrame(img, img.copy(), t, i, {"keypoints": {"x": 1}})

    cam = CameraFaults(provider)
    for kind, extra in (("camera_stall", {}), ("camera_black", {}), ("camera_one_eye", {"eye": "right"}),
                        ("camera_wrong_size", {"scale": 0.5}), ("camera_time_backwards", {"step_s": 0.5}),
                        ("camera_out_of_order", {})):
        cam.add(len(cam.events) * 2.0 + 1.0, FaultEvent(kind, at_s=0, duration_s=1.0, **extra))
    guard = FrameGuard((60, 40))
    verdicts = {}
    t = 0.0
    while t < 14.0:
        t = round(t + 0.2, 3)
        frame = cam(t)
        active = [e.kind for e in cam.active(t)]
        verdicts.setdefault(active[0] if active else "none", []).append(guard.check(frame))
    assert set(verdicts["none"]) == {""}
    assert set(verdicts["camera_stall"]) == {"no frame"}
    assert set(verdicts["camera_black"]) == {"black frame"}
    assert set(verdicts["camera_one_eye"]) == {"right eye missing"}
    assert set(verdicts["camera_wrong_size"]) == {"wrong image size"}
    assert set(verdicts["camera_time_backwards"]) == {"stamp not increasing"}
    ooo = verdicts["camera_out_of_order"]  # (none), f1 ok, f0 late: rejected, f3 ok, f2 rejected
    assert ooo[0] == "no frame" and ooo[2::2] == ["stamp not increasing"] * len(ooo[2::2]) and set(ooo[1::2]) == {""}


def test_autopilot_reboot_gap_and_link_recheck():
    clock = SimClock()
    ap = Autopilot(load_params(), clock, listen=["tcp:127.0.0.1:0"])
    link = VehicleLink({"link.url": ap.addresses[0], "link.output_mode": "guided_velocity"}, clock)
    link.open()
    heard = []
    try:
        def run(seconds):
            end = clock.now() + seconds
            while clock.now() < end - 1e-9:
                clock.advance(0.02)
                ap.step()
                link.poll()
                link.tick(None, perception_fresh=False)
                heard.append((clock.now(), link.autopilot.last_message_s))
        run(3.0)
        ap.ap_params["SYSID_MYGCS"] = 200
        ap.arm(True)
        run(0.5)
        assert link.autopilot.armed and link.gcs.sysid == 255
        boots0 = link.autopilot.boots
        ap.reboot(gap_s=2.0)
        run(1.5)
        assert not link.autopilot.alive(clock.now(), link.config.autopilot_timeout_s)
        run(2.5)
        assert not ap.armed and ap.mode_name == "MANUAL" and ap.time_boot_s < 2.5
        assert ap.ap_params["SYSID_MYGCS"] == 200  # parameters survive a reboot
        assert link.autopilot.boots >= boots0 + 1
        assert not link.autopilot.armed and link.autopilot.mode == "MANUAL"
        assert any("requesting message intervals and SYSID_MYGCS" in e for e in link.events[-5:])
        assert link.gcs.sysid == 200  # re-read after the reboot
        assert [e.detail for e in ap.events if e.kind in ("reboot", "booted")] == [2.0, 1]
    finally:
        link.close()
        ap.close()


def test_sitl_command_rejects_a_bad_fault_plan(tmp_path, capsys):
    from dip3d_vehicle.cli import main

    plan = tmp_path / "plan.yaml"
    plan.write_text("events:\n  - {kind: meteor, at_s: 1}\n")
    assert main(["sitl", "--faults", str(plan), "--no-plots", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "plan.yaml" in err and "events[0].kind" in err and len(err.splitlines()) == 1

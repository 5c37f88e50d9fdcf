"""``dip3d-vehicle run`` wiring: folder camera, calibration, perception worker, link to a (simulated) autopilot."""

from __future__ import annotations

import argparse
import threading
import time
from pathlib import Path

import cv2
import numpy as np

from dip3d_vehicle.clock import WallClock
from dip3d_vehicle.commands import run as run_command
from dip3d_vehicle.config import load_params
from sitl.autopilot import Autopilot

CALIB = Path(__file__).resolve().parents[1] / "data" / "calib" / "opencv_stereo.yml"


def test_run_loop_processes_a_folder_and_talks_to_the_autopilot(tmp_path, capsys):
    rng = np.random.default_rng(0)
    for i in range(4):
        img = (rng.random((480, 752, 3)) * 255).astype(np.uint8)
        cv2.imwrite(str(tmp_path / f"left_{i:06d}.png"), img)
        cv2.imwrite(str(tmp_path / f"right_{i:06d}.png"), np.roll(img, -8, axis=1))
    stop = threading.Event()
    ap = Autopilot(load_params(), WallClock(), listen=["tcp:127.0.0.1:0"])

    def serve() -> None:
        while not stop.is_set():
            ap.step()
            time.sleep(0.002)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        parser = argparse.ArgumentParser()
        run_command.add_arguments(parser)
        args = parser.parse_args(["--connect", ap.addresses[0], "--camera", str(tmp_path), "--calib", str(CALIB),
                                  "--duration", "3", "--set", "pose.backend=keypoints",
                                  "--out", str(tmp_path / "out")])
        assert run_command.run(args) == 0
    finally:
        stop.set()
        thread.join(2.0)
        ap.close()
    out = capsys.readouterr().out
    assert "autopilot first heard" in out and "frames in 4" in out
    start = next(line for line in out.splitlines() if line.startswith("run: "))
    assert f"camera {tmp_path}," in start and f"calibration {CALIB}" in start, start  # not the calib as the camera
    from collections import Counter

    from pymavlink import mavutil

    from dip3d_vehicle.record.mcap_log import McapRunReader

    with McapRunReader(tmp_path / "out" / "run.mcap") as record:
        topics = Counter(m.topic for m in record.messages())
        assert record.stats["truncated"] is False and record.header["meta"]["command"] == "run"
        assert len(list(record.image_pairs())) >= 1
    assert topics["/dip3d/frame"] >= 1 and topics["/autopilot/status"] >= 1 and topics["/story"] >= 1
    tlog = mavutil.mavlink_connection(str(tmp_path / "out" / "mav.tlog"))
    kinds = Counter(iter(lambda: (m := tlog.recv_match()) and m.get_type(), None))
    assert kinds["HEARTBEAT"] >= 2 and kinds["ATTITUDE"] >= 1  # ours and the autopilot's

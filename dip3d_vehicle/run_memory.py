"""Peak memory of the onboard loop: ``dip3d-vehicle run`` on a folder of stereo pairs, per profile.

A companion computer has little memory; this measures what the whole ``run`` process needs (models,
remap tables, frame buffers, threads) the way it runs onboard: the folder's pairs arrive at the
camera's pace (``sources.folder_realtime``), the perception worker takes the newest, the tick
loop streams to a MAVLink URL nobody answers (the link stays disengaged; no autopilot needed). The
peak resident set size is the kernel's high-water mark of that child process after it started
(``VmHWM`` of ``/proc/self/status``, read by the child as ``run`` returns: ``ru_maxrss`` would also
count the pages the child shared with this parent between fork and exec).

``write_folder`` writes bench frames as such a folder (pairs + ``stamps.csv`` at the camera rate +
the rig's OpenCV calibration), so the figure is reproducible from a scenario and seed::

    dip3d-vehicle bench --json                    # "run_memory": default and fast on the bench's first sequence
"""

from __future__ import annotations

import socket
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Sequence

__all__ = ["write_folder", "run_peak_rss_mib", "run_memory"]


def write_folder(frames: Sequence, rig, path: str | Path, rate_hz: float = 15.0) -> Path:
    """Write stereo frames as a folder source (JPEG pairs, stamps at ``rate_hz``, calib.yaml); return it."""
    import dataclasses

    from .perception.calibration_io import write_opencv_calibration
    from .sources.writer import FolderWriter

    path = Path(path)
    writer = FolderWriter(path, fmt="jpg", overwrite=True)
    try:
        for k, frame in enumerate(frames):
            writer.write(dataclasses.replace(frame, index=k, stamp_s=k / rate_hz))
    finally:
        writer.close()
    write_opencv_calibration(rig, path / "calib.yaml")
    return path


def _free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def run_peak_rss_mib(folder: str | Path, profile: str, extra_args: Sequence[str] = (),
                     timeout_s: float = 300.0) -> dict:
    """Run ``dip3d-vehicle run`` on ``folder`` (paced) with ``profile``; return its peak RSS and frame counts."""
    folder = Path(folder)
    args = ["run", "--camera", f"{folder}?folder_realtime=true", "--calib", str(folder / "calib.yaml"),
            "--connect", f"udpin:127.0.0.1:{_free_udp_port()}", "--profile", profile, *extra_args]
    cmd = [sys.executable, "-c", "import sys; from dip3d_vehicle.run_memory import child_main; "
           "sys.exit(child_main(sys.argv[1:]))", *args]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s)
    text = proc.stdout + proc.stderr
    if proc.returncode != 0:
        raise RuntimeError(f"dip3d-vehicle {' '.join(args)}: exit {proc.returncode}: {text[-400:]}")
    summary = next((line for line in text.splitlines() if line.startswith("run: frames in")), "")
    peak = next((float(line.split()[1]) for line in text.splitlines() if line.startswith("peak_rss_mib ")), None)
    return {"profile": profile, "peak_rss_mib": peak, "summary": summary, "command": "dip3d-vehicle " + " ".join(args)}


def child_main(argv: Sequence[str]) -> int:
    """Run the CLI with ``argv`` in this (fresh) process, then print ``peak_rss_mib N`` (VmHWM)."""
    from .cli import main

    code = main(list(argv))
    print(f"peak_rss_mib {_status_mib('VmHWM'):.1f}", flush=True)
    return code


def proc_status_mib(key: str) -> float | None:
    """Return a ``/proc/self/status`` memory field (VmRSS, VmHWM, ...) in MiB, or None where there is none."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None


def _status_mib(key: str) -> float:
    """Return a ``/proc/self/status`` memory field in MiB (NaN where there is none)."""
    value = proc_status_mib(key)
    return float("nan") if value is None else value


def run_memory(frames: Sequence, rig, profiles: Sequence[str] = ("default", "fast"), rate_hz: float = 15.0) -> dict:
    """Write ``frames`` to a temporary folder and measure ``run``'s peak RSS for each profile."""
    with tempfile.TemporaryDirectory(prefix="dip3d-run-rss-") as tmp:
        folder = write_folder(frames, rig, Path(tmp) / "pairs", rate_hz)
        runs = {p: run_peak_rss_mib(folder, p) for p in profiles}
    return {"frames": len(frames), "rate_hz": rate_hz, "method": "ru_maxrss of the run process (os.wait4)",
            "profiles": runs}

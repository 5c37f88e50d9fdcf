"""Start and stop a real ArduSub SITL binary, on loopback only.

The binary (``../shared/ardusub-sitl/ardusub``, ArduSub 4.7.0-dev; or one built with
``tools/build_ardusub_sitl.sh``) is a test tool beside the project (GPLv3), never part of the package.

How it is kept on loopback: by default ArduPilot SITL *listens* on TCP 5760/5762/5763 (+10*I) and
UDP 5501 (+10*I, the simulator's RC input), all bound to 0.0.0.0. Here

- SERIAL0 is ``tcpclient:127.0.0.1:PORT``: the firmware connects OUT to our loopback listener
  (which is also what makes it boot: it waits for SERIAL0's first client);
- SERIAL1 and SERIAL2 are ``none`` (no listening MAVLink ports);
- the RC-input UDP port (``--rc-in-port``) is one we hold ourselves on 127.0.0.1, so the firmware's
  bind to 0.0.0.0 on it fails and it opens no RC socket at all (it needs none: the pilot input is
  MAVLink). Checked with ``ss -lnptu``: the process then has no listening socket.

Process: it exits by itself when its parent dies (so it never outlives us); ``stop()`` sends SIGTERM
(status 0) and SIGKILL after 3 s. A temporary working directory receives ``eeprom.bin``, ``logs/``
and ``sitl.log``; ``-w`` wipes the stored parameters, so every start is fresh defaults + ``sub.parm``.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from dip3d_vehicle.errors import FirmwareError

__all__ = ["ArdusubSitl", "SitlOptions", "resolve_binary", "ENV_VAR", "DEFAULT_HOME", "EXTERNAL_NAV_PARAMS",
           "EXTERNAL_NAV_ARGS"]

ENV_VAR = "DIP3D_ARDUSUB"
"""Environment variable naming the ArduSub SITL binary (tests and ``sitl --ardusub``)."""
DEFAULT_HOME = (-27.563, -48.459, 0.0, 270.0)
"""lat, lng, alt m, heading deg: the home ArduSub's autotest and the shared README use."""
EXTERNAL_NAV_ARGS = ("--serial5", "sim:vicon:")
"""SERIAL5 is the SITL's simulated external navigation (an in-process device: no socket), which sends
the simulator's pose and velocity as VISION_POSITION_ESTIMATE / VISION_SPEED_ESTIMATE."""
EXTERNAL_NAV_PARAMS = (("GPS1_TYPE", 0), ("VISO_TYPE", 1), ("SERIAL5_PROTOCOL", 2), ("EK3_SRC1_POSXY", 6),
                       ("EK3_SRC1_VELXY", 6), ("EK3_SRC1_POSZ", 1), ("EK3_SRC1_VELZ", 0), ("EK3_SRC1_YAW", 6))
"""The EKF's horizontal position, velocity and yaw from external navigation, depth from the barometer,
no GPS: how a BlueROV2 flies GUIDED (a DVL or an acoustic positioning system; GPS does not reach under
water). With the SITL's simulated GPS instead, its EKF at 1 m depth is not usable for GUIDED
(tools/firmware_guided_probe.py, docs/issue13/guided_probe.jsonl): GUIDED accepted only ~45 s after boot,
then the EKF's heading up to 1.26 rad and its velocity up to 0.50 m/s off the simulator's truth, and zero
GUIDED velocity setpoints moved the vehicle at up to 0.32 m/s. With these the EKF tracked the truth
within 0.006 m/s and 0.003 rad, the vehicle stayed still, and GUIDED was accepted right after the dive."""


def resolve_binary(path: str | os.PathLike | None) -> Path:
    """Return the binary's path (``path``, else ``$DIP3D_ARDUSUB``) after checking it can run.

    Raises:
        FirmwareError: no path given, the file is missing, or it is not executable.
    """
    raw = str(path) if path else os.environ.get(ENV_VAR, "")
    if not raw:
        raise FirmwareError(f"no ArduSub SITL binary: give --ardusub PATH, sitl.ardusub_path or ${ENV_VAR}")
    p = Path(raw).expanduser()
    if not p.is_file():
        raise FirmwareError(f"ArduSub SITL binary {p}: no such file")
    if not os.access(p, os.X_OK):
        raise FirmwareError(f"ArduSub SITL binary {p}: not executable (chmod +x?)")
    return p


@dataclass(frozen=True)
class SitlOptions:
    """How to start the binary.

    Attributes:
        binary: the ardusub executable.
        instance: ``-I`` (distinct per concurrent run; only its default ports change, which are unused here).
        speedup: ``--speedup`` (1 = real time).
        home: lat, lng, alt m, heading deg.
        defaults: the parameter defaults file (default: ``sub.parm`` next to the binary).
        model: the SITL frame model.
        extra_params: parameters set at boot on top of the defaults file (written to an extra defaults file).
        extra_args: more command-line arguments (e.g. ``EXTERNAL_NAV_ARGS``).
    """

    binary: Path
    instance: int = 0
    speedup: float = 1.0
    home: tuple[float, float, float, float] = DEFAULT_HOME
    defaults: Path | None = None
    model: str = "vectored"
    extra_params: tuple[tuple[str, float], ...] = ()
    extra_args: tuple[str, ...] = ()


class ArdusubSitl:
    """One ArduSub SITL process whose SERIAL0 is a connected loopback TCP socket.

    Use as a context manager or call ``start()`` / ``stop()``; ``sock`` is the MAVLink stream.
    """

    def __init__(self, options: SitlOptions, workdir: str | os.PathLike | None = None) -> None:
        self.options = options
        self._own_workdir = workdir is None
        self.workdir = Path(workdir) if workdir is not None else Path(tempfile.mkdtemp(prefix="dip3d-ardusub-"))
        self.proc: subprocess.Popen | None = None
        self.sock: socket.socket | None = None
        self._rc_hold: socket.socket | None = None
        self.started_wall_s: float | None = None

    @property
    def defaults(self) -> Path:
        """The defaults file passed with ``--defaults``."""
        return self.options.defaults or self.options.binary.parent / "sub.parm"

    def command(self, port: int, rc_port: int) -> list[str]:
        """The command line for SERIAL0 connecting to ``port`` and the RC input on ``rc_port``."""
        o = self.options
        lat, lng, alt, hdg = o.home
        defaults = str(self.defaults)
        if o.extra_params:
            extra = self.workdir / "extra.parm"
            extra.write_text("".join(f"{k} {v:g}\n" for k, v in o.extra_params))
            defaults += f",{extra}"
        return [str(o.binary), "--model", o.model, "--speedup", f"{o.speedup:g}", "--defaults", defaults,
                "-I", str(o.instance), "--home", f"{lat},{lng},{alt:g},{hdg:g}", "-w",
                "--serial0", f"tcpclient:127.0.0.1:{port}", "--serial1", "none", "--serial2", "none",
                "--rc-in-port", str(rc_port), *o.extra_args]

    def start(self, connect_timeout_s: float = 10.0) -> socket.socket:
        """Start the process and wait for it to connect; return the MAVLink socket.

        Raises:
            FirmwareError: the defaults file is missing, the process exits, or it does not connect in time.
        """
        if not self.defaults.is_file():
            raise FirmwareError(f"ArduSub SITL defaults file {self.defaults}: no such file")
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.bind(("127.0.0.1", 0))
        listener.listen(1)
        self._rc_hold = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._rc_hold.bind(("127.0.0.1", 0))
        cmd = self.command(listener.getsockname()[1], self._rc_hold.getsockname()[1])
        log = open(self.workdir / "sitl.log", "wb")
        try:
            self.proc = subprocess.Popen(cmd, cwd=self.workdir, stdin=subprocess.DEVNULL, stdout=log,
                                         stderr=subprocess.STDOUT)
        except OSError as exc:
            listener.close()
            raise FirmwareError(f"ArduSub SITL binary {self.options.binary}: cannot start ({exc})") from None
        finally:
            log.close()
        listener.settimeout(0.2)
        deadline = time.monotonic() + connect_timeout_s
        try:
            while True:
                try:
                    sock, _ = listener.accept()
                    break
                except socket.timeout:
                    if self.proc.poll() is not None:
                        raise FirmwareError(f"ArduSub SITL exited with status {self.proc.returncode} before "
                                            f"connecting; see {self.workdir / 'sitl.log'}") from None
                    if time.monotonic() > deadline:
                        raise FirmwareError(f"ArduSub SITL did not connect within {connect_timeout_s:g} s; "
                                            f"see {self.workdir / 'sitl.log'}") from None
        except BaseException:
            listener.close()
            self.stop()
            raise
        listener.close()
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.sock, self.started_wall_s = sock, time.monotonic()
        return sock

    def stop(self) -> int | None:
        """Close the socket, SIGTERM the process (SIGKILL after 3 s); return its exit status."""
        if self.sock is not None:
            try:
                self.sock.close()
            except OSError:
                pass
            self.sock = None
        status = None
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.send_signal(signal.SIGTERM)
                try:
                    self.proc.wait(3.0)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait(3.0)
            status = self.proc.returncode
        if self._rc_hold is not None:
            self._rc_hold.close()
            self._rc_hold = None
        if self._own_workdir and os.environ.get("DIP3D_KEEP_SITL_DIR", "") == "":
            shutil.rmtree(self.workdir, ignore_errors=True)
        return status

    @property
    def running(self) -> bool:
        """True while the process is alive."""
        return self.proc is not None and self.proc.poll() is None

    def __enter__(self) -> "ArdusubSitl":
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

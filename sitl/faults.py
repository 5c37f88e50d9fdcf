"""Fault injection for the closed-loop simulator: a lossy MAVLink relay, camera faults, timed events.

A fault plan is a YAML file (``sitl/faults/*.yaml``)::

    seed: 0                    # optional; the campaign overrides it per trial
    params: {link.gcs_timeout_s: 5.0}   # optional parameter overrides the plan is meant to run with
    link:                      # the relay between the controller and the autopilot's router
      drop: 0.2                # probability a packet is lost (each direction, independently)
      delay_s: 0.1             # one-way delay ...
      jitter_s: 0.05           # ... +- uniform jitter
      duplicate: 0.0           # probability a packet is delivered twice
      reorder: 0.0             # probability a packet may overtake earlier ones (else FIFO)
      corrupt: 0.0             # probability one byte of a packet is flipped
    events:                    # each: kind, when, and for some a duration
      - {kind: link_cut, at_s: [20, 40], duration_s: 5}
      - {kind: autopilot_reboot, after_state: servo, after_s: 2, gap_s: 3}

When: ``at_s`` (simulated seconds from the start) or ``after_state`` + ``after_s`` (seconds
after the mission first enters that state); a two-element list ``[lo, hi]`` anywhere a number is
expected draws uniformly from the plan's seeded RNG. Kinds (``EVENT_KINDS``): ``link_cut``
(both directions, ``duration_s``), ``autopilot_reboot`` (``gap_s``), ``pilot_mode_change``
(``mode``, default MANUAL), ``pilot_disarm``, ``gcs_loss`` (``duration_s``), and the camera
faults ``camera_stall``, ``camera_black``, ``camera_one_eye`` (``eye``: right|left),
``camera_wrong_size`` (``scale``), ``camera_out_of_order``, ``camera_time_backwards``
(``step_s``), each for ``duration_s``. Pilot actions and a reboot are followed, ``reenable_s``
(default 3 s) after they clear, by the pilot handing the vehicle over again (arm, mode, enable), as
an operator would; a link cut and a ground-station loss likewise.

The relay is driven by the simulation's SimClock (``LossyRelay.step()`` forwards packets whose
release time has come) and is deterministic for a given seed and packet sequence.

A missing camera eye is a ``StereoFrame`` with ``right`` (or ``left``) set to None. ``FrameGuard``
is the check at the perception boundary: a frame with a missing eye, a black eye, a wrong size, a
stamp or index not after the previous accepted frame is rejected (counted by reason), so no 3D
decision is ever made from it; the mission then sees stale perception and holds.
"""

from __future__ import annotations

import math
import random
import socket
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

import numpy as np
import yaml

from dip3d_vehicle.errors import ScenarioError
from dip3d_vehicle.frames import FrameGuard, StereoFrame

__all__ = ["EVENT_KINDS", "CAMERA_KINDS", "LinkFaults", "FaultEvent", "FaultPlan", "load_fault_plan",
           "parse_fault_plan", "LossyRelay", "CameraFaults", "FrameGuard", "split_frames"]

CAMERA_KINDS = ("camera_stall", "camera_black", "camera_one_eye", "camera_wrong_size",
                "camera_out_of_order", "camera_time_backwards")
EVENT_KINDS = ("link_cut", "autopilot_reboot", "pilot_mode_change", "pilot_disarm", "gcs_loss") + CAMERA_KINDS
_EVENT_KEYS = {"kind", "at_s", "after_state", "after_s", "duration_s", "gap_s", "mode", "eye", "scale",
               "step_s", "reenable_s"}
_LINK_KEYS = ("drop", "delay_s", "jitter_s", "duplicate", "reorder", "corrupt")
_MAX_DATAGRAM = 65536


# ------------------------------------------------------------------------------------ the plan
@dataclass(frozen=True)
class LinkFaults:
    """Per-packet faults of the relay (each direction independently); all zero = a perfect wire."""

    drop: float = 0.0
    delay_s: float = 0.0
    jitter_s: float = 0.0
    duplicate: float = 0.0
    reorder: float = 0.0
    corrupt: float = 0.0

    @property
    def perfect(self) -> bool:
        """True when the relay changes nothing but adds no delay either."""
        return not any(getattr(self, k) for k in _LINK_KEYS)


@dataclass(frozen=True)
class FaultEvent:
    """One timed fault, resolved (random draws done).

    Attributes:
        kind: one of EVENT_KINDS.
        at_s: absolute simulated time, or None when relative to ``after_state``.
        after_state: the mission state whose first entry starts the countdown ("" = none).
        after_s: seconds after entering ``after_state``.
        duration_s: how long it lasts (cuts, GCS loss, camera faults; 0 = instantaneous).
        gap_s: autopilot reboot: seconds without any message.
        mode: pilot_mode_change: the mode the pilot selects.
        eye: camera_one_eye: which eye is missing.
        scale: camera_wrong_size: image size factor.
        step_s: camera_time_backwards: how far each stamp goes back.
        reenable_s: the pilot hands over again this long after the fault cleared (< 0 = never).
    """

    kind: str
    at_s: float | None = None
    after_state: str = ""
    after_s: float = 0.0
    duration_s: float = 0.0
    gap_s: float = 3.0
    mode: str = "MANUAL"
    eye: str = "right"
    scale: float = 0.5
    step_s: float = 0.5
    reenable_s: float = 3.0

    @property
    def lasting_s(self) -> float:
        """How long the fault itself lasts after its onset."""
        return self.gap_s if self.kind == "autopilot_reboot" else self.duration_s


@dataclass(frozen=True)
class FaultPlan:
    """A whole fault plan: link faults for the relay plus timed events."""

    link: LinkFaults = LinkFaults()
    events: tuple[FaultEvent, ...] = ()
    seed: int = 0
    source: str = "<plan>"
    params: tuple[tuple[str, Any], ...] = ()

    @property
    def needs_relay(self) -> bool:
        """True when the controller must talk through a LossyRelay."""
        return not self.link.perfect or any(e.kind == "link_cut" for e in self.events)


def load_fault_plan(path: str | Path, seed: int | None = None) -> FaultPlan:
    """Read a fault plan file.

    Args:
        path: the YAML file.
        seed: overrides the file's ``seed`` (random draws of ``[lo, hi]`` values use it).

    Raises:
        ScenarioError: the file is missing, not YAML, or a field is unknown or invalid (the
            message names the file and the field).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{path}: cannot read fault plan ({exc.__class__.__name__})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f":{mark.line + 1}" if mark is not None else ""
        raise ScenarioError(f"{path}{line}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    return parse_fault_plan(data, str(path), seed)


def parse_fault_plan(data: Any, where: str = "<plan>", seed: int | None = None) -> FaultPlan:
    """Validate a fault plan mapping (see the module doc) and draw its random values.

    Raises:
        ScenarioError: naming ``where`` and the field at fault.
    """
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: top level: expected a mapping, got {type(data).__name__}")
    unknown = set(data) - {"seed", "link", "events", "description", "params"}
    if unknown:
        raise ScenarioError(f"{where}: unknown key(s) {sorted(map(str, unknown))}; expected seed, link, events, "
                            f"params, description")
    file_seed = data.get("seed", 0)
    if isinstance(file_seed, bool) or not isinstance(file_seed, int) or file_seed < 0:
        raise ScenarioError(f"{where}: seed: expected an integer >= 0, got {file_seed!r}")
    seed = file_seed if seed is None else int(seed)
    rng = random.Random(seed)
    link_data = data.get("link") or {}
    if not isinstance(link_data, dict):
        raise ScenarioError(f"{where}: link: expected a mapping, got {type(link_data).__name__}")
    bad = set(link_data) - set(_LINK_KEYS)
    if bad:
        raise ScenarioError(f"{where}: link: unknown key(s) {sorted(map(str, bad))}; expected {', '.join(_LINK_KEYS)}")
    lk = {}
    for key in _LINK_KEYS:
        hi = 1.0 if key in ("drop", "duplicate", "reorder", "corrupt") else 60.0
        lk[key] = _number(link_data.get(key, 0.0), f"{where}: link.{key}", rng, 0.0, hi)
    events_data = data.get("events") or []
    if not isinstance(events_data, list):
        raise ScenarioError(f"{where}: events: expected a list, got {type(events_data).__name__}")
    events = tuple(_event(e, f"{where}: events[{i}]", rng) for i, e in enumerate(events_data))
    return FaultPlan(LinkFaults(**lk), events, seed, where, _params(data.get("params"), where))


def _params(data: Any, where: str) -> tuple[tuple[str, Any], ...]:
    """Validate the plan's parameter overrides against the schema."""
    from dip3d_vehicle.config import schema
    from dip3d_vehicle.errors import ParamsError

    if data is None:
        return ()
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: params: expected a mapping of parameter: value, got {type(data).__name__}")
    known = schema()
    out = []
    for key, value in data.items():
        if key not in known:
            raise ScenarioError(f"{where}: params.{key}: not a parameter (see dip3d-vehicle params show)")
        try:
            out.append((key, known[key].coerce(value, f"{where}: params.{key}")))
        except ParamsError as exc:
            raise ScenarioError(str(exc)) from None
    return tuple(out)


def _event(data: Any, where: str, rng: random.Random) -> FaultEvent:
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: expected a mapping with 'kind', got {type(data).__name__}")
    bad = set(data) - _EVENT_KEYS
    if bad:
        raise ScenarioError(f"{where}: unknown key(s) {sorted(map(str, bad))}; expected {', '.join(sorted(_EVENT_KEYS))}")
    kind = data.get("kind")
    if kind not in EVENT_KINDS:
        raise ScenarioError(f"{where}.kind: {kind!r} is not one of {', '.join(EVENT_KINDS)}")
    if ("at_s" in data) == ("after_state" in data):
        raise ScenarioError(f"{where}: give exactly one of at_s or after_state (+ after_s)")
    out: dict[str, Any] = {"kind": kind}
    if "at_s" in data:
        out["at_s"] = _number(data["at_s"], f"{where}.at_s", rng, 0.0, 1e6)
    else:
        state = data["after_state"]
        if not isinstance(state, str) or not state:
            raise ScenarioError(f"{where}.after_state: expected a mission state name, got {state!r}")
        out["after_state"] = state
        out["after_s"] = _number(data.get("after_s", 0.0), f"{where}.after_s", rng, 0.0, 1e6)
    for key, lo, hi in (("duration_s", 0.0, 1e5), ("gap_s", 0.0, 600.0), ("scale", 0.05, 4.0),
                        ("step_s", 0.0, 1e3), ("reenable_s", -1.0, 1e5)):
        if key in data:
            out[key] = _number(data[key], f"{where}.{key}", rng, lo, hi)
    if "mode" in data:
        if data["mode"] not in ("MANUAL", "STABILIZE", "ALT_HOLD", "GUIDED"):
            raise ScenarioError(f"{where}.mode: {data['mode']!r} is not one of MANUAL, STABILIZE, ALT_HOLD, GUIDED")
        out["mode"] = data["mode"]
    if "eye" in data:
        if data["eye"] not in ("left", "right"):
            raise ScenarioError(f"{where}.eye: {data['eye']!r} is not left or right")
        out["eye"] = data["eye"]
    needs_duration = kind in ("link_cut", "gcs_loss") + CAMERA_KINDS
    if needs_duration and out.get("duration_s", 0.0) <= 0:
        raise ScenarioError(f"{where}.duration_s: {kind} needs a duration > 0 s")
    return FaultEvent(**out)


def _number(value: Any, where: str, rng: random.Random, lo: float, hi: float) -> float:
    """A number in [lo, hi], or a ``[a, b]`` range drawn uniformly."""
    if isinstance(value, list):
        if len(value) != 2:
            raise ScenarioError(f"{where}: a range must be [low, high], got {value!r}")
        a, b = (_number(v, where, rng, lo, hi) for v in value)
        if b < a:
            raise ScenarioError(f"{where}: range [{a}, {b}] has high < low")
        return rng.uniform(a, b)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ScenarioError(f"{where}: expected a number or [low, high], got {value!r}")
    if not lo <= value <= hi:
        raise ScenarioError(f"{where}: {value} is outside [{lo:g}, {hi:g}]")
    return float(value)


# ------------------------------------------------------------------------------------ the relay
def split_frames(buf: bytearray) -> list[bytes]:
    """Cut whole MAVLink 1/2 packets off the front of a TCP byte buffer (in place).

    Bytes before a start marker are discarded; an incomplete packet stays in ``buf``.
    """
    out: list[bytes] = []
    while buf:
        if buf[0] not in (0xFD, 0xFE):
            nxt = [i for i in (buf.find(b"\xfd"), buf.find(b"\xfe")) if i >= 0]
            if not nxt:
                buf.clear()
                break
            del buf[:min(nxt)]
            continue
        if len(buf) < 3:
            break
        if buf[0] == 0xFD:
            n = 12 + buf[1] + (13 if buf[2] & 1 else 0)
        else:
            n = 8 + buf[1]
        if len(buf) < n:
            break
        out.append(bytes(buf[:n]))
        del buf[:n]
    return out


@dataclass
class _Queue:
    """One direction of the relay: packets waiting for their release time."""

    name: str
    items: list = field(default_factory=list)  # (release_s, seq, bytes)
    last_release_s: float = 0.0
    counts: dict = field(default_factory=lambda: {"in": 0, "out": 0, "dropped": 0, "cut": 0, "duplicated": 0,
                                                  "corrupted": 0, "reordered": 0})


class LossyRelay:
    """A MAVLink relay on loopback between the controller and the autopilot (or its router).

    Controller side: a UDP socket (the controller uses ``udpout:`` ``controller_url``), one packet
    per datagram. Autopilot side: a TCP client to ``upstream`` (``tcp:HOST:PORT``), split into
    packets. Each packet, each direction: dropped with ``drop``; else released after
    ``delay_s +- jitter_s`` (FIFO unless it is chosen to ``reorder``), maybe twice
    (``duplicate``), maybe with one byte flipped (``corrupt``); during a cut everything is dropped.

    Args:
        upstream: ``tcp:HOST:PORT`` of the autopilot / router.
        faults: the per-packet faults.
        clock: the simulation clock.
        seed: RNG seed (deterministic per seed and packet sequence).
    """

    def __init__(self, upstream: str, faults: LinkFaults, clock: Any, seed: int = 0) -> None:
        self.faults, self.clock = faults, clock
        self.rng = random.Random(seed)
        host, port = upstream.split(":")[-2:]
        self.up = socket.create_connection((host, int(port)))
        self.up.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.up.setblocking(False)
        self.down = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.down.bind(("127.0.0.1", 0))
        self.down.setblocking(False)
        self.peer: tuple[str, int] | None = None
        self._up_buf = bytearray()
        self.to_autopilot, self.to_controller = _Queue("to_autopilot"), _Queue("to_controller")
        self.cuts: list[tuple[float, float]] = []
        self._seq = 0
        self.upstream_closed = False

    @property
    def controller_url(self) -> str:
        """The URL the controller connects to (``udpout:127.0.0.1:PORT``)."""
        return f"udpout:127.0.0.1:{self.down.getsockname()[1]}"

    def cut(self, start_s: float, end_s: float) -> None:
        """Drop every packet, both ways, while ``start_s <= t < end_s``."""
        self.cuts.append((start_s, end_s))

    def is_cut(self, t_s: float) -> bool:
        """True during a cut."""
        return any(a <= t_s < b for a, b in self.cuts)

    def step(self) -> None:
        """Read both sides, queue what arrived with its fate, send what is due (never blocks)."""
        now = self.clock.now()
        while True:
            try:
                data, addr = self.down.recvfrom(_MAX_DATAGRAM)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                break
            self.peer = addr
            self._admit(self.to_autopilot, data, now)
        while not self.upstream_closed:
            try:
                data = self.up.recv(_MAX_DATAGRAM)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                self.upstream_closed = True
                break
            if not data:
                self.upstream_closed = True
                break
            self._up_buf.extend(data)
        for pkt in split_frames(self._up_buf):
            self._admit(self.to_controller, pkt, now)
        self._release(self.to_autopilot, now, self._send_up)
        self._release(self.to_controller, now, self._send_down)

    def _admit(self, q: _Queue, pkt: bytes, now: float) -> None:
        f, rng = self.faults, self.rng
        q.counts["in"] += 1
        if self.is_cut(now):
            q.counts["cut"] += 1
            return
        if f.drop and rng.random() < f.drop:
            q.counts["dropped"] += 1
            return
        copies = 2 if f.duplicate and rng.random() < f.duplicate else 1
        if copies == 2:
            q.counts["duplicated"] += 1
        for _ in range(copies):
            data = pkt
            if f.corrupt and rng.random() < f.corrupt:
                b = bytearray(pkt)
                i = rng.randrange(len(b))
                b[i] ^= 1 << rng.randrange(8)
                data = bytes(b)
                q.counts["corrupted"] += 1
            t = now + max(0.0, f.delay_s + (rng.uniform(-f.jitter_s, f.jitter_s) if f.jitter_s else 0.0))
            if f.reorder and rng.random() < f.reorder:
                q.counts["reordered"] += 1
                t += rng.uniform(0.0, max(0.05, 2 * f.jitter_s))
            else:
                t = max(t, q.last_release_s)  # FIFO: never overtakes an earlier packet
                q.last_release_s = t
            self._seq += 1
            q.items.append((t, self._seq, data))

    def _release(self, q: _Queue, now: float, send: Callable[[bytes], None]) -> None:
        if not q.items:
            return
        q.items.sort()
        while q.items and q.items[0][0] <= now + 1e-9:
            _, _, data = q.items.pop(0)
            if self.is_cut(now):
                q.counts["cut"] += 1
                continue
            send(data)
            q.counts["out"] += 1

    def _send_up(self, data: bytes) -> None:
        if self.upstream_closed:
            return
        try:
            self.up.sendall(data)
        except OSError:
            self.upstream_closed = True

    def _send_down(self, data: bytes) -> None:
        if self.peer is None:
            return
        try:
            self.down.sendto(data, self.peer)
        except OSError:
            pass

    def counts(self) -> dict:
        """Per-direction packet counters."""
        return {"to_autopilot": dict(self.to_autopilot.counts), "to_controller": dict(self.to_controller.counts)}

    def close(self) -> None:
        """Close both sockets."""
        for s in (self.up, self.down):
            try:
                s.close()
            except OSError:
                pass


# ------------------------------------------------------------------------------------ camera
class CameraFaults:
    """Wraps a frame provider (``t_s -> StereoFrame``) and applies the active camera faults.

    Args:
        provider: returns the true frame at a time.
        events: the plan's camera events with their absolute onset times: (onset_s, FaultEvent).
    """

    def __init__(self, provider: Callable[[float], StereoFrame],
                 events: list[tuple[float, FaultEvent]] | None = None) -> None:
        self.provider = provider
        self.events = list(events or [])
        self._last: StereoFrame | None = None
        self._held: StereoFrame | None = None
        self._late: StereoFrame | None = None
        self.applied: dict[str, int] = {}

    def add(self, onset_s: float, event: FaultEvent) -> None:
        """Activate ``event`` from ``onset_s`` for its duration."""
        self.events.append((onset_s, event))

    def active(self, t_s: float) -> list[FaultEvent]:
        """The camera faults in effect at ``t_s``."""
        return [e for on, e in self.events if on <= t_s < on + e.duration_s]

    def __call__(self, t_s: float) -> StereoFrame | None:
        """Return the frame the (faulty) camera delivers at ``t_s``; None = no new frame (stall)."""
        active = {e.kind: e for e in self.active(t_s)}
        if "camera_stall" in active:
            self._count("camera_stall")
            return None
        frame = self.provider(t_s)
        if "camera_out_of_order" in active:  # pairs swapped: (none), f1, f0, f3, f2, ...
            self._count("camera_out_of_order")
            if self._late is not None:
                frame, self._late, self._held = self._late, None, frame
            elif self._held is not None:
                self._late, self._held = self._held, None
            else:
                self._held = frame
                return None
        else:
            self._held = self._late = None
        if "camera_black" in active:
            self._count("camera_black")
            frame = replace(frame, left=np.zeros_like(frame.left), right=np.zeros_like(frame.right),
                            meta={**frame.meta, "keypoints": None})
        if "camera_one_eye" in active:
            self._count("camera_one_eye")
            eye = active["camera_one_eye"].eye
            frame = replace(frame, **{eye: None})
        if "camera_wrong_size" in active:
            self._count("camera_wrong_size")
            s = active["camera_wrong_size"].scale
            frame = replace(frame, left=_resize(frame.left, s), right=_resize(frame.right, s))
        if "camera_time_backwards" in active:
            self._count("camera_time_backwards")
            base = self._last.stamp_s if self._last is not None else frame.stamp_s
            frame = replace(frame, stamp_s=base - active["camera_time_backwards"].step_s)
        self._last = frame
        return frame

    def _count(self, kind: str) -> None:
        self.applied[kind] = self.applied.get(kind, 0) + 1


def _resize(image: np.ndarray | None, scale: float) -> np.ndarray | None:
    if image is None:
        return None
    h, w = image.shape[:2]
    ys = (np.arange(max(1, int(h * scale))) / scale).astype(int).clip(0, h - 1)
    xs = (np.arange(max(1, int(w * scale))) / scale).astype(int).clip(0, w - 1)
    return image[ys][:, xs]

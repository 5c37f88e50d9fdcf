"""Perception in its own thread: the newest frame wins, stale results are dropped and counted.

The one perception worker of the project: ``run`` (a camera feeding it), ``bench`` (frames paced
at the camera rate) and any loop that must never wait for perception. ``PerceptionWorker`` owns
one thread that runs a processing function (e.g. ``Perception.process`` on a frame) on the NEWEST
submitted frame only:

- ``submit(frame, stamp_s)`` never blocks; a frame still waiting when a newer one arrives is
  replaced (counted in ``dropped_frames``);
- a frame older than ``max_frame_age_s`` when the thread gets to it is skipped (``stale_frames``),
  and one the ``accept`` check rejects (e.g. ``FrameGuard.check``: an eye missing or black) is
  never processed (``rejected``);
- ``latest()`` never blocks; it returns the newest finished result with the capture stamp of its
  frame, or None when there is none or it is older than ``max_age_s`` (counted once per result in
  ``stale_results``);
- ``take_new()`` returns a result only the first time it is asked for (to tell a fresh result from
  a repeated one in a setpoint loop); a result replaced before anyone took it is counted in
  ``dropped_results``.

``CameraFeed`` is the grabber: a thread that reads a frame source as fast as it delivers and
submits every frame, stamped on arrival, to a worker (the worker keeps only the newest).

Stamps are in the clock the caller uses (``time.monotonic()`` unless a clock is given), so the
age of a result is ``clock() - stamp_s``. With ``stamped=True`` the processing function is called
as ``process(frame, stamp_s)`` (an onboard processor stamps its observation with the capture time).

Example::

    worker = PerceptionWorker(lambda f: perception.process(f.left, f.right))
    worker.start()
    worker.submit(frame, frame_stamp)          # camera callback
    found = worker.latest()                    # setpoint tick: (result, stamp_s) or None
    worker.stop()
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any, Callable, Iterable

__all__ = ["PerceptionWorker", "WorkerCounters", "Finished", "CameraFeed"]


@dataclass
class WorkerCounters:
    """Frame and result counts of a worker.

    Attributes:
        submitted: frames given to ``submit``.
        processed: frames the processing function finished.
        dropped_frames: frames replaced by a newer one before processing started.
        stale_frames: frames older than ``max_frame_age_s`` when processing could start (skipped).
        rejected: frames the ``accept`` check refused (never processed).
        stale_results: results that aged past ``max_age_s`` before being used.
        dropped_results: results replaced by a newer one before ``take_new`` took them.
        errors: frames whose processing raised (the exception is kept in ``last_error``).
    """

    submitted: int = 0
    processed: int = 0
    dropped_frames: int = 0
    stale_frames: int = 0
    rejected: int = 0
    stale_results: int = 0
    dropped_results: int = 0
    errors: int = 0


@dataclass(frozen=True)
class Finished:
    """One processed frame: the result, its frame's capture stamp and when processing ended."""

    result: Any
    stamp_s: float
    done_s: float
    seq: int


class PerceptionWorker:
    """Runs ``process(frame)`` in a thread on the newest submitted frame.

    Args:
        process: the function applied to each frame (its return value is the result).
        max_age_s: results older than this (clock() - frame stamp) are stale: not returned.
        clock: the time source for stamps and ages (``time.monotonic``).
        name: the thread's name.
        max_frame_age_s: frames older than this when processing could start are skipped (None: never).
        accept: called with each frame before processing; a non-empty return (a reason) rejects it.
        stamped: call ``process(frame, stamp_s)`` instead of ``process(frame)``.
    """

    def __init__(self, process: Callable[..., Any], max_age_s: float = 0.5,
                 clock: Callable[[], float] = time.monotonic, name: str = "perception",
                 max_frame_age_s: float | None = None, accept: Callable[[Any], Any] | None = None,
                 stamped: bool = False) -> None:
        self._process = process
        self.max_age_s = float(max_age_s)
        self.max_frame_age_s = None if max_frame_age_s is None else float(max_frame_age_s)
        self.accept = accept
        self.stamped = bool(stamped)
        self.clock = clock
        self.counters = WorkerCounters()
        self.last_error: BaseException | None = None
        self._cond = threading.Condition()
        self._pending: tuple[Any, float] | None = None
        self._latest: Finished | None = None
        self._taken_seq = -1
        self._stale_seq = -1
        self._running = False
        self._busy = False
        self._thread: threading.Thread | None = None
        self._name = name

    # -- lifecycle ------------------------------------------------------------------------------
    def start(self) -> "PerceptionWorker":
        """Start the thread (idempotent); return self."""
        with self._cond:
            if self._running:
                return self
            self._running = True
        self._thread = threading.Thread(target=self._run, name=self._name, daemon=True)
        self._thread.start()
        return self

    def stop(self, timeout_s: float = 5.0) -> None:
        """Stop the thread after the frame in progress (a pending frame is discarded)."""
        with self._cond:
            self._running = False
            self._cond.notify_all()
        if self._thread is not None:
            self._thread.join(timeout_s)
            self._thread = None

    def __enter__(self) -> "PerceptionWorker":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # -- producer / consumer --------------------------------------------------------------------
    def submit(self, frame: Any, stamp_s: float | None = None) -> None:
        """Hand over a frame captured at ``stamp_s`` (now if None); never blocks."""
        stamp = self.clock() if stamp_s is None else float(stamp_s)
        with self._cond:
            self.counters.submitted += 1
            if self._pending is not None:
                self.counters.dropped_frames += 1
            self._pending = (frame, stamp)
            self._cond.notify()

    def latest(self) -> tuple[Any, float] | None:
        """Return (result, frame stamp) of the newest finished frame, or None if none or stale."""
        found = self._fresh()
        return None if found is None else (found.result, found.stamp_s)

    def take_new(self) -> Finished | None:
        """Return the newest finished frame if it was not taken before and is not stale, else None."""
        with self._cond:
            found = self._fresh_locked()
            if found is None or found.seq == self._taken_seq:
                return None
            self._taken_seq = found.seq
            return found

    def peek(self) -> Finished | None:
        """Return the newest finished frame whatever its age (for statistics; not for control)."""
        with self._cond:
            return self._latest

    @property
    def busy(self) -> bool:
        """True while a frame is being processed."""
        return self._busy

    def has_new(self) -> bool:
        """True when a finished result has not been taken yet (whatever its age)."""
        with self._cond:
            return self._latest is not None and self._latest.seq != self._taken_seq

    @property
    def idle(self) -> bool:
        """True when no frame is pending or in progress."""
        with self._cond:
            return self._pending is None and not self._busy

    def wait_idle(self, timeout_s: float = 10.0) -> bool:
        """Block until no frame is pending or in progress (for tests and benchmarks); True if idle."""
        end = time.monotonic() + timeout_s
        with self._cond:
            while self._pending is not None or self._busy:
                left = end - time.monotonic()
                if left <= 0:
                    return False
                self._cond.wait(left)
        return True

    # -- internals ------------------------------------------------------------------------------
    def _fresh(self) -> Finished | None:
        with self._cond:
            return self._fresh_locked()

    def _fresh_locked(self) -> Finished | None:
        found = self._latest
        if found is None:
            return None
        if self.clock() - found.stamp_s > self.max_age_s:
            if self._stale_seq != found.seq and self._taken_seq != found.seq:
                self.counters.stale_results += 1
            self._stale_seq = found.seq
            return None
        return found

    def _next(self) -> tuple[Any, float] | None:
        """Wait for a frame to process (None: stopping); skipped frames are counted."""
        with self._cond:
            while True:
                while self._running and self._pending is None:
                    self._cond.wait()
                if not self._running:
                    return None
                frame, stamp = self._pending
                self._pending = None
                if self.max_frame_age_s is not None and self.clock() - stamp > self.max_frame_age_s:
                    self.counters.stale_frames += 1
                    self._cond.notify_all()
                    continue
                self._busy = True
                return frame, stamp

    def _run(self) -> None:
        seq = 0
        while True:
            item = self._next()
            if item is None:
                return
            frame, stamp = item
            try:
                if self.accept is not None and self.accept(frame):
                    with self._cond:
                        self.counters.rejected += 1
                        self._busy = False
                        self._cond.notify_all()
                    continue
                result = self._process(frame, stamp) if self.stamped else self._process(frame)
            except Exception as exc:  # a bad frame must not kill the worker
                with self._cond:
                    self.counters.errors += 1
                    self.last_error = exc
                    self._busy = False
                    self._cond.notify_all()
                continue
            with self._cond:
                if self._latest is not None and self._latest.seq != self._taken_seq:
                    self.counters.dropped_results += 1
                self._latest = Finished(result, stamp, self.clock(), seq)
                seq += 1
                self.counters.processed += 1
                self._busy = False
                self._cond.notify_all()


class CameraFeed:
    """A grabber thread: reads ``frames`` as fast as they come and submits each, stamped on arrival.

    Args:
        frames: an iterable of frames (a camera or folder source).
        worker: the PerceptionWorker to submit to (it keeps only the newest frame).
        clock: the stamp clock (the worker's by default).

    ``ended`` is set when the source is exhausted or failed (the exception in ``error``);
    ``frames_in`` counts frames read.
    """

    def __init__(self, frames: Iterable[Any], worker: PerceptionWorker,
                 clock: Callable[[], float] | None = None, name: str = "camera") -> None:
        self.frames, self.worker = frames, worker
        self.clock = clock or worker.clock
        self.ended = threading.Event()
        self.error: BaseException | None = None
        self.frames_in = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._grab, name=name, daemon=True)

    def start(self) -> "CameraFeed":
        """Start the grabber thread; return self."""
        self._thread.start()
        return self

    def stop(self, timeout_s: float = 2.0) -> None:
        """Ask the grabber to stop after the frame it is reading; wait briefly."""
        self._stop.set()
        self._thread.join(timeout_s)

    def _grab(self) -> None:
        try:
            for frame in self.frames:
                if self._stop.is_set():
                    break
                self.worker.submit(frame, self.clock())
                self.frames_in += 1
        except BaseException as exc:  # noqa: BLE001 - reported by the consumer
            self.error = exc
        finally:
            self.ended.set()

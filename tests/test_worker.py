"""PerceptionWorker: newest frame wins, dropped frames and stale results are counted, never blocks."""

from __future__ import annotations

import threading
import time

from dip3d_vehicle.worker import PerceptionWorker


class FakeClock:
    """A settable clock (seconds)."""

    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_newest_frame_wins_and_dropped_frames_are_counted():
    gate = threading.Event()
    seen = []

    def process(frame):
        gate.wait(5.0)
        seen.append(frame)
        return frame * 10

    clock = FakeClock()
    with PerceptionWorker(process, max_age_s=1.0, clock=clock) as worker:
        worker.submit(1, 100.0)
        deadline = time.monotonic() + 5.0
        while not worker.busy and time.monotonic() < deadline:   # frame 1 is being processed
            time.sleep(0.001)
        for k in (2, 3, 4):                                      # 2 and 3 are overwritten by 4
            worker.submit(k, 100.0)
        gate.set()
        assert worker.wait_idle(5.0)
        assert seen == [1, 4]
        assert worker.counters.dropped_frames == 2
        assert worker.counters.processed == 2
        assert worker.latest() == (40, 100.0)


def test_stale_result_is_not_returned_and_counted_once():
    clock = FakeClock()
    with PerceptionWorker(lambda f: f, max_age_s=0.5, clock=clock) as worker:
        worker.submit("a", 100.0)
        assert worker.wait_idle(5.0)
        assert worker.latest() == ("a", 100.0)
        clock.t = 100.6
        assert worker.latest() is None
        assert worker.take_new() is None
        assert worker.counters.stale_results == 1


def test_take_new_returns_each_result_once():
    clock = FakeClock()
    with PerceptionWorker(lambda f: f + 1, clock=clock) as worker:
        worker.submit(1, 100.0)
        assert worker.wait_idle(5.0)
        first = worker.take_new()
        assert first is not None and first.result == 2 and first.stamp_s == 100.0
        assert worker.take_new() is None
        assert worker.latest() == (2, 100.0)


def test_submit_and_latest_do_not_block_while_processing():
    gate = threading.Event()
    with PerceptionWorker(lambda f: gate.wait(5.0)) as worker:
        worker.submit(0)
        t0 = time.perf_counter()
        for k in range(100):
            worker.submit(k)
            worker.latest()
        assert time.perf_counter() - t0 < 0.5
        gate.set()
        assert worker.wait_idle(5.0)


def test_errors_are_counted_and_the_worker_keeps_going():
    def process(frame):
        if frame == "bad":
            raise ValueError("bad frame")
        return frame

    with PerceptionWorker(process) as worker:
        worker.submit("bad")
        assert worker.wait_idle(5.0)
        worker.submit("good")
        assert worker.wait_idle(5.0)
        assert worker.counters.errors == 1
        assert isinstance(worker.last_error, ValueError)
        assert worker.latest()[0] == "good"

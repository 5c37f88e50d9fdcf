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


def test_old_frames_are_skipped_and_rejected_frames_never_processed():
    clock = FakeClock()
    seen = []

    def process(frame, stamp_s):
        seen.append((frame, stamp_s))
        return frame

    with PerceptionWorker(process, clock=clock, max_frame_age_s=0.5, stamped=True,
                          accept=lambda f: "black" if f == "black" else "") as worker:
        worker.submit("old", 99.0)       # 1 s old when the thread gets to it: skipped
        assert worker.wait_idle(5.0)
        worker.submit("black", 100.0)    # refused by the check
        assert worker.wait_idle(5.0)
        worker.submit("good", 100.0)
        assert worker.wait_idle(5.0)
    assert seen == [("good", 100.0)]
    assert worker.counters.stale_frames == 1 and worker.counters.rejected == 1
    assert worker.counters.processed == 1


def test_a_result_replaced_before_it_was_taken_is_counted():
    clock = FakeClock()
    with PerceptionWorker(lambda f: f, clock=clock) as worker:
        for k in range(3):
            worker.submit(k, 100.0)
            assert worker.wait_idle(5.0)
        assert worker.has_new()
        assert worker.take_new().result == 2
        assert not worker.has_new()
        assert worker.counters.dropped_results == 2


def test_camera_feed_submits_every_frame_and_ends_with_the_source():
    from dip3d_vehicle.worker import CameraFeed

    got = []
    with PerceptionWorker(lambda f: got.append(f) or f) as worker:
        feed = CameraFeed(iter(range(5)), worker).start()
        assert feed.ended.wait(5.0)
        assert worker.wait_idle(5.0)
        feed.stop()
    assert feed.frames_in == 5 and feed.error is None
    assert got[-1] == 4 and worker.counters.submitted == 5
    assert worker.counters.processed + worker.counters.dropped_frames == 5


def test_camera_feed_reports_a_failing_source():
    from dip3d_vehicle.worker import CameraFeed

    def broken():
        yield 1
        raise OSError("camera unplugged")

    with PerceptionWorker(lambda f: f) as worker:
        feed = CameraFeed(broken(), worker).start()
        assert feed.ended.wait(5.0)
    assert isinstance(feed.error, OSError) and feed.frames_in == 1

"""Perception through the project's one ``PerceptionWorker`` for simulations that follow the wall clock.

In lockstep (``Simulation``) perception runs synchronously and its result is delivered
``sitl.perception_latency_s`` later, so a run is deterministic. A world that follows the wall clock
(the ArduSub firmware, ``FirmwareSimulation``) is a real-time system like ``run``: there the camera's
frame goes to a ``PerceptionWorker`` thread (``dip3d_vehicle/worker.py``, newest frame wins, the
``FrameGuard`` check, frames older than ``mission.max_frame_age_s`` skipped) and the controller
tick takes each result once, when it is finished: the latency is the real one.

``WorkerPerception`` is a mixin placed before ``Simulation`` in a subclass's bases; it overrides the
two hooks of ``Simulation.run`` (``_capture``, ``_deliver``) and stops the worker in ``close``.
"""

from __future__ import annotations

from typing import Any

from dip3d_vehicle.frames import FrameGuard
from dip3d_vehicle.worker import PerceptionWorker

__all__ = ["WorkerPerception"]


class WorkerPerception:
    """Mixin for a wall-clock Simulation: perception in the one PerceptionWorker (see the module doc)."""

    perception_worker: PerceptionWorker | None = None

    def _worker(self) -> PerceptionWorker:
        """Return (starting it on first use) the worker over this simulation's FrameProcessor."""
        if self.perception_worker is None:
            size = tuple(self.scenario.camera.image_size)

            def perceive(frame: Any, stamp_s: float) -> tuple[Any, dict]:
                need = self.mission.needs
                roi = self.mission.track_roi(self.rig, size) if need == "track" else None
                return self.processor.process(frame, need, stamp_s, roi), frame.meta

            self.frame_guard = FrameGuard(size)
            self.perception_worker = PerceptionWorker(
                perceive, max_age_s=float("inf"), clock=self.clock.now, name="sim-perceive",
                max_frame_age_s=float(self.params["mission.max_frame_age_s"]), accept=self.frame_guard.check,
                stamped=True).start()
        return self.perception_worker

    def _capture(self, now: float) -> None:
        """Render the frame the camera sees now and hand it to the worker (nothing is delivered here)."""
        frame = self._render_now(now)
        if frame is not None:
            self._worker().submit(frame, now)
        return None

    def _deliver(self, now: float, pending: list) -> tuple[Any, dict | None]:
        """Return the worker's newest result not taken yet as (observation, its frame's meta), else (None, None)."""
        worker = self.perception_worker
        if worker is not None and worker.last_error is not None:
            error, worker.last_error = worker.last_error, None
            raise RuntimeError(f"perception: {error.__class__.__name__}: {error}") from error
        done = worker.take_new() if worker is not None else None
        if done is None:
            return None, None
        return done.result

    def close(self) -> None:
        """Stop the worker, then close the simulation."""
        if self.perception_worker is not None:
            self.perception_worker.stop()
        super().close()

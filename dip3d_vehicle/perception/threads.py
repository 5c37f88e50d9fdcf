"""Shared worker threads for the perception core (OpenCV and onnxruntime release the GIL).

The core runs its own threads (the two images' remaps, the two eyes' landmark runs, the two
images' SIFT, the corridor), so OpenCV's internal thread pool is set to one thread
(``single_threaded_opencv``): with its default (one per core) its workers spin-wait beside ours,
which cost ~10 % more CPU per frame on 2 cores for no gain in wall time (issue 16).
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

__all__ = ["shared_pool", "single_threaded_opencv"]

_POOLS: dict[str, ThreadPoolExecutor] = {}
_LOCK = threading.Lock()


def shared_pool(name: str, workers: int) -> ThreadPoolExecutor:
    """Return the process-wide thread pool called ``name`` (created once with ``workers`` threads)."""
    with _LOCK:
        if name not in _POOLS:
            _POOLS[name] = ThreadPoolExecutor(workers, thread_name_prefix=name)
        return _POOLS[name]


def single_threaded_opencv() -> None:
    """Make OpenCV's own parallel loops single-threaded (the core parallelises by itself)."""
    import cv2

    if cv2.getNumThreads() != 1:
        cv2.setNumThreads(1)

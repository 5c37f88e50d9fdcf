"""Shared worker threads for the perception core (OpenCV and onnxruntime release the GIL).

The core runs its own threads (the two images' remaps, the two eyes' landmark runs, the two
images' SIFT, the corridor), so OpenCV's internal thread pool is set to one thread
(``single_threaded_opencv``): with its default (one per core) its workers spin-wait beside ours,
which cost ~10 % more CPU per frame on 2 cores for no gain in wall time (issue 16). numpy's BLAS
(OpenBLAS, the selector's and matcher's matrix products) is limited to one thread for the same
reason (``single_threaded_blas``): its idle workers spin as well, ~60 ms CPU per ``default`` frame.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

__all__ = ["shared_pool", "single_threaded_opencv", "single_threaded_blas"]

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


_BLAS_LIMITED: list = []


def single_threaded_blas() -> None:
    """Limit numpy's BLAS to one thread for the rest of the process (threadpoolctl, once)."""
    from threadpoolctl import threadpool_limits

    with _LOCK:
        if not _BLAS_LIMITED:
            _BLAS_LIMITED.append(threadpool_limits(1, user_api="blas"))

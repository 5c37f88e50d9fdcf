"""Where a campaign's runs execute: in this process, in local worker processes, or on a Ray cluster.

Every campaign (``sitl.campaign``, ``sitl.fault_campaign``, ``sitl.point_campaign``, ``sitl.sweep``,
``sitl.pose_eval``) hands its list of independent runs to ``map_runs``; results come back in the
order of the runs whichever executor ran them, so a campaign prints and sums the same way
everywhere, and a run's result depends only on its arguments (scenario, seed, parameters): the
same seeds give the same outcomes locally and on Ray.

- ``ray=None``: ``jobs`` <= 1 runs in this process, one after another; more uses a
  ``ProcessPoolExecutor`` of ``jobs`` processes (as the campaigns always did).
- ``ray="auto"`` joins the running Ray cluster (``ray start --head`` on this or another machine);
  ``ray="ADDRESS"`` (``HOST:PORT`` or ``ray://HOST:PORT``) joins that one; ``ray="local"`` or
  ``"local:N"`` starts a private Ray instance on this machine with N CPUs (default ``jobs``).
  When Ray is already initialised in this process (a test's ``ray.init(num_cpus=2)``), that
  instance is used. Each run is one Ray task with one CPU. Ray is an optional extra
  (``pip install .[ray]``); every machine of the cluster needs the project installed.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from typing import Any, Callable, Iterator, Sequence

__all__ = ["map_runs", "RayUnavailable", "add_executor_arguments"]


class RayUnavailable(RuntimeError):
    """``--ray`` was asked for but Ray is not installed or the cluster cannot be reached."""


def map_runs(fn: Callable[[Any], Any], items: Sequence[Any], jobs: int = 1, ray: str | None = None
             ) -> Iterator[Any]:
    """Yield ``fn(item)`` for every item, in order, run where ``jobs`` / ``ray`` say (module doc)."""
    items = list(items)
    if ray:
        yield from _ray_map(fn, items, ray, jobs)
    elif jobs <= 1:
        for item in items:
            yield fn(item)
    else:
        with ProcessPoolExecutor(jobs) as pool:
            yield from pool.map(fn, items)


def _ray_module():
    """Return the ``ray`` module or raise RayUnavailable naming the extra to install."""
    try:
        import ray
    except ImportError:
        raise RayUnavailable("--ray: Ray is not installed (pip install 'dip3d-vehicle[ray]')") from None
    return ray


def connect(address: str, jobs: int = 1) -> Any:
    """Initialise Ray for ``address`` ("auto", "local[:N]", "HOST:PORT", "ray://HOST:PORT"); return the module."""
    ray = _ray_module()
    if ray.is_initialized():
        return ray
    kind, _, cpus = address.partition(":")
    try:
        if kind == "local":
            ray.init(num_cpus=int(cpus) if cpus else max(int(jobs), 1), include_dashboard=False,
                     log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    except ValueError:
        raise RayUnavailable(f"--ray {address}: expected auto, local[:N], HOST:PORT or ray://HOST:PORT") from None
    except ConnectionError as exc:
        raise RayUnavailable(f"--ray {address}: cannot reach the Ray cluster ({exc})") from None
    return ray


def _ray_map(fn: Callable[[Any], Any], items: list, address: str, jobs: int) -> Iterator[Any]:
    """Run every item as one Ray task (1 CPU each) and yield the results in order."""
    ray = connect(address, jobs)
    task = ray.remote(num_cpus=1)(fn)
    refs = [task.remote(item) for item in items]
    for ref in refs:
        yield ray.get(ref)


def add_executor_arguments(parser: Any, jobs_default: int = 1) -> None:
    """Add ``--jobs N`` and ``--ray auto|local[:N]|ADDRESS`` to a campaign's argument parser."""
    parser.add_argument("--jobs", type=int, default=jobs_default,
                        help=f"local worker processes (default {jobs_default}; 1 = in this process)")
    parser.add_argument("--ray", metavar="auto|local[:N]|ADDRESS", default=None,
                        help="run the campaign's runs as Ray tasks: 'auto' joins the running cluster, ADDRESS a "
                             "given one, 'local[:N]' starts one here with N CPUs (pip install .[ray])")

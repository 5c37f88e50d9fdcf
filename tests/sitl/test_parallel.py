"""Campaign runs on local processes and on Ray give the same outcome per seed (sitl/parallel.py)."""

from __future__ import annotations

import pytest

from sitl.parallel import RayUnavailable, map_runs

WALL_CLOCK_FIELDS = {"wall_s", "wall_time_s"}


def _square(x: int) -> int:
    return x * x


def _comparable(row: dict) -> dict:
    """A trial's row without its wall-clock measurements."""
    return {k: v for k, v in row.items() if k not in WALL_CLOCK_FIELDS}


def test_local_processes_keep_the_order_of_the_runs():
    assert list(map_runs(_square, range(7), jobs=2)) == [x * x for x in range(7)]
    assert list(map_runs(_square, range(7), jobs=1)) == [x * x for x in range(7)]


def test_ray_address_errors_are_one_clear_exception(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_ray(name, *args, **kwargs):
        if name == "ray":
            raise ImportError("no ray here")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_ray)
    with pytest.raises(RayUnavailable, match=r"pip install 'dip3d-vehicle\[ray\]'"):
        list(map_runs(_square, [1], ray="auto"))


def test_fault_trials_on_local_ray_match_local_processes():
    ray = pytest.importorskip("ray", reason="Ray is not installed (pip install '.[ray]'): the Ray campaign test needs it")
    from sitl.fault_campaign import trial_campaign

    faults = ["link_cut"]  # the fast tier's trials: real autopilot, router, link; ~3 s each
    local = trial_campaign(2, faults, verbose=False, jobs=2)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        on_ray = trial_campaign(2, faults, verbose=False, ray="auto")
    finally:
        ray.shutdown()
    for fault in faults:
        rows_local = [_comparable(r) for r in local["trials"][fault]]
        rows_ray = [_comparable(r) for r in on_ray["trials"][fault]]
        assert [r["seed"] for r in rows_ray] == [0, 1]
        assert rows_ray == rows_local, fault
        assert not any(r["crashed"] for r in rows_ray)
    assert on_ray["summary"] == local["summary"]

"""Fixtures for the link tests (helpers in fake_ardusub.py, a uniquely named module)."""

from __future__ import annotations

from typing import Any

import pytest

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.link import VehicleLink

from fake_ardusub import FakeAutopilot, Harness, link_params


@pytest.fixture
def make_udp():
    """Factory: (params overrides, fake kwargs) -> Harness over real UDP loopback; closed after the test."""
    made: list[Harness] = []

    def make(fake_kw: dict | None = None, fake_key: bytes | None = None, **over: Any) -> Harness:
        clock = SimClock(100.0)
        link = VehicleLink(link_params(**over), clock)
        link.open()
        port = link._conn.port.getsockname()[1]
        fake = FakeAutopilot.udp(clock, port, **(fake_kw or {}))
        if fake_key is not None:
            fake.sign(fake_key)
        h = Harness(link, fake, clock)
        made.append(h)
        return h

    yield make
    for h in made:
        h.link.close()
        h.fake.close()

"""The ground station's identity rule as a property of VehicleLink (issue 13, defect 1).

After "ground station lost" (no GCS HEARTBEAT for ``link.gcs_timeout_s``) not one message may carry
the ground station's system id until a GCS HEARTBEAT is heard again: not the stop stream, not
close(), not after a TCP reconnect. Otherwise ArduSub takes the controller's neutral sticks for
ground-station contact and clears its own GCS failsafe (seen on the 4.7 SITL: "GCS Failsafe
Cleared" 23 s after the loss, at the controller's shutdown).

Checked over random event sequences (hypothesis) against the fake ArduSub on a real TCP socket.
"""

from __future__ import annotations

from bisect import bisect_right

from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from pymavlink import mavutil

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.connection import use_mavlink2

from fake_ardusub import MOVE, FakeAutopilot, Harness, Received, link_params

GCS_SYSID = 255
DT_S = 0.02

ACTIONS = st.one_of(
    st.tuples(st.just("run"), st.sampled_from([0.3, 1.0, 2.0, 4.0]), st.booleans()),
    st.tuples(st.just("gcs"), st.booleans()),
    st.tuples(st.just("mode"), st.sampled_from(["ALT_HOLD", "MANUAL"])),
    st.tuples(st.just("armed"), st.booleans()),
    st.just(("enable",)),
    st.just(("reconnect",)),
    st.just(("close_open",)),
)


def gcs_id_violations(received: list[Received], gcs_heartbeats_s: list[float], timeout_s: float) -> list[Received]:
    """Messages with the GCS system id sent while the GCS was lost (or never heard)."""
    bad = []
    for r in received:
        if r.src[0] != GCS_SYSID:
            continue
        i = bisect_right(gcs_heartbeats_s, r.t + 1e-9)
        if i == 0 or r.t - gcs_heartbeats_s[i - 1] > timeout_s + 1e-9:
            bad.append(r)
    return bad


class _TcpWorld:
    """The link on tcp to a fake ArduSub server whose connection can be dropped and re-accepted."""

    def __init__(self) -> None:
        self.clock = SimClock(100.0)
        self.fake, self.port = FakeAutopilot.tcp_server(self.clock, armed=True, mode="ALT_HOLD")
        self.link = VehicleLink(link_params(url=f"tcp:127.0.0.1:{self.port}", reconnect_s=0.3,
                                            auto_enable=True), self.clock)
        self.link.open()
        self.h = Harness(self.link, self.fake, self.clock)
        self.received: list[Received] = []
        self.gcs_hb: list[float] = []

    def _harvest(self) -> None:
        self.fake.poll()
        self.received += self.fake.received
        self.gcs_hb += self.fake.gcs_heartbeats_s
        self.fake.received, self.fake.gcs_heartbeats_s = [], []

    def apply(self, action: tuple) -> None:
        kind = action[0]
        if kind == "run":
            self.h.run(action[1], MOVE, fresh=action[2], dt=DT_S)
        elif kind == "gcs":
            self.fake.gcs_alive = action[1]
        elif kind == "mode":
            self.fake.mode = action[1]
        elif kind == "armed":
            self.fake.armed = action[1]
        elif kind == "enable":
            self.fake.operator(True)
        elif kind == "reconnect":
            self._harvest()
            state = dict(armed=self.fake.armed, mode=self.fake.mode, gcs_alive=self.fake.gcs_alive)
            self.fake.close()
            self.h.run(0.1, MOVE, dt=DT_S)
            conn = mavutil.mavlink_connection(f"tcpin:127.0.0.1:{self.port}", source_system=1, source_component=1)
            use_mavlink2(conn)
            self.h.fake = self.fake = FakeAutopilot(conn=conn, clock=self.clock, **state)
            self.h.run(1.0, MOVE, dt=DT_S)
        elif kind == "close_open":
            self.link.close()
            self.h.run(0.1, MOVE, dt=DT_S)  # the fake server sees the EOF and accepts again
            self.link.open()
        self._harvest()

    def finish(self) -> None:
        self.link.close()
        self._harvest()
        self.fake.close()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(ACTIONS, min_size=1, max_size=8))
@example([("gcs", False), ("run", 4.0, True)])                       # the stop stream after the loss
@example([("gcs", False), ("run", 2.0, True), ("close_open",)])       # close() during the stop stream
@example([("gcs", False), ("run", 2.0, False), ("reconnect",)])       # a reconnect while lost
def test_no_message_carries_the_gcs_id_while_the_gcs_is_lost(actions: list[tuple]) -> None:
    w = _TcpWorld()
    try:
        w.h.run(1.5, MOVE, dt=DT_S)
        for action in actions:
            w.apply(action)
    finally:
        w.finish()
    timeout_s = w.link.config.gcs_timeout_s
    bad = gcs_id_violations(w.received, w.gcs_hb, timeout_s)
    assert not bad, (f"{len(bad)} message(s) with the GCS id while the GCS was lost, first "
                     f"{bad[0].kind} at t={bad[0].t:.2f}; actions {actions}; events {w.link.events}")


def test_gcs_lost_then_close_sends_nothing_with_its_id() -> None:
    """The case seen on the firmware: engaged, GCS lost, much later the controller shuts down."""
    w = _TcpWorld()
    try:
        w.h.run(2.0, MOVE, dt=DT_S)
        assert w.link.engaged
        w.apply(("gcs", False))
        w.apply(("run", 4.0, True))
        assert "ground station" in w.link.disengage_reason
        w.apply(("run", 4.0, True))
    finally:
        w.finish()
    assert any(r.kind == "MANUAL_CONTROL" for r in w.received)
    assert not gcs_id_violations(w.received, w.gcs_hb, w.link.config.gcs_timeout_s)


def test_gcs_back_allows_manual_control_again() -> None:
    """The rule ends when the GCS is heard again: the operator can re-enable and the controller drives."""
    w = _TcpWorld()
    try:
        w.h.run(2.0, MOVE, dt=DT_S)
        w.apply(("gcs", False))
        w.apply(("run", 4.0, True))
        w.apply(("gcs", True))
        w.apply(("run", 1.0, True))
        w.apply(("enable",))
        w.apply(("run", 1.0, True))
        assert w.link.engaged
        t_back = w.gcs_hb[-1]
        assert [r for r in w.received if r.kind == "MANUAL_CONTROL" and r.t > t_back - 1.0 and r.msg.x != 0]
    finally:
        w.finish()

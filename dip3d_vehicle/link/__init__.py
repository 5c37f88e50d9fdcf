"""MAVLink link to the ArduSub autopilot: identity, state, engage gating, setpoint streaming, signing.

Modules: ``vehicle_link`` (the VehicleLink the mission loop calls), ``link_config`` (the resolved
``link.*`` parameters), ``autopilot_requests`` (SYSID_MYGCS reads and message intervals asked of the
autopilot, retried), ``engage`` (pure gating), ``setpoints`` (pure VelocityCommand -> MAVLink
mappings), ``state`` (what is known about the peers), ``connection`` (URLs, MAVLink 2, the
ground-station encoder), ``signing`` (key files; signing and counting on a connection),
``command_hold`` (the autopilot's pilot-input timeout while the controller holds the sticks),
``guided_turns`` (GUIDED turns as headings that end by themselves), ``statustext`` (long
STATUSTEXT split into chunks and put back together), ``tcp_reconnect`` (the clock-paced reconnect of a ``tcp:`` link).
"""

from .engage import EngageDecision, EngageInputs, blockers, decide
from .link_config import LinkConfig
from .setpoints import (NEUTRAL_STICKS, ZERO_GUIDED, GuidedVelocity, ManualControl,
                        guided_from_velocity, manual_control_from_velocity)
from .state import AutopilotState, GcsState, LinkStats
from .vehicle_link import MAV_CMD_USER_1, VehicleLink

__all__ = [
    "VehicleLink", "LinkConfig", "MAV_CMD_USER_1", "AutopilotState", "GcsState", "LinkStats",
    "EngageInputs", "EngageDecision", "blockers", "decide", "ManualControl", "GuidedVelocity",
    "NEUTRAL_STICKS", "ZERO_GUIDED", "manual_control_from_velocity", "guided_from_velocity",
]

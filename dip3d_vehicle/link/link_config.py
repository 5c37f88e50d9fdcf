"""The ``link.*`` parameters resolved into one frozen LinkConfig, checked for combinations that cannot work."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from ..errors import LinkError

__all__ = ["LinkConfig", "ENGAGE_MODE_AUTO"]

ENGAGE_MODE_AUTO = {"manual_control": "ALT_HOLD", "guided_velocity": "GUIDED"}
"""The engage mode used when ``link.engage_mode`` is ``auto``."""


@dataclass(frozen=True)
class LinkConfig:
    """The ``link.*`` parameters (see params/schema/link.yaml), resolved."""

    url: str
    baud: int
    output_mode: str
    engage_mode: str
    system_id: int
    component_id: int
    target_system: int
    target_component: int
    gcs_system_id: int
    setpoint_rate_hz: float
    heartbeat_rate_hz: float
    autopilot_timeout_s: float
    gcs_timeout_s: float
    require_gcs: bool
    perception_timeout_s: float
    auto_enable: bool
    stop_zero_s: float
    param_retry_s: float
    param_give_up_s: float
    reconnect_s: float
    signing_key_file: str
    max_command_hold_s: float
    rates_hz: tuple[tuple[str, float], ...]

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "LinkConfig":
        """Build from a Params (or any mapping of ``link.*`` keys; missing keys take the schema default).

        Raises:
            LinkError: the combination does not fit (e.g. guided_velocity with engage_mode ALT_HOLD).
        """
        from ..config import schema

        defaults = {k: p.default for k, p in schema().items() if k.startswith("link.")}
        get = lambda key: params[key] if key in params else defaults[key]  # noqa: E731
        output_mode = get("link.output_mode")
        engage_mode = get("link.engage_mode")
        if engage_mode == "auto":
            engage_mode = ENGAGE_MODE_AUTO[output_mode]
        if output_mode == "guided_velocity" and engage_mode != "GUIDED":
            raise LinkError(f"link.engage_mode = {engage_mode}: guided_velocity needs GUIDED "
                            f"(ArduSub ignores SET_POSITION_TARGET_LOCAL_NED in other modes)")
        if output_mode == "manual_control" and engage_mode == "GUIDED":
            raise LinkError("link.engage_mode = GUIDED: manual_control needs ALT_HOLD or STABILIZE "
                            "(use link.output_mode guided_velocity for GUIDED)")
        hold = get("link.max_command_hold_s")
        if 0 < hold < 5.0 / get("link.setpoint_rate_hz"):
            raise LinkError(f"link.max_command_hold_s = {hold:g}: shorter than five setpoint periods "
                            f"(link.setpoint_rate_hz {get('link.setpoint_rate_hz'):g}); the autopilot would "
                            f"drop the controller's own stream between messages (0 = leave FS_PILOT_TIMEOUT)")
        rates = [("ATTITUDE", get("link.rate.attitude_hz")),
                 ("GLOBAL_POSITION_INT", get("link.rate.global_position_int_hz")),
                 ("VFR_HUD", get("link.rate.vfr_hud_hz")),
                 ("SYS_STATUS", get("link.rate.sys_status_hz"))]
        if output_mode == "guided_velocity":
            rates.append(("LOCAL_POSITION_NED", get("link.rate.local_position_ned_hz")))
        names = ("url", "baud", "system_id", "component_id", "target_system", "target_component",
                 "gcs_system_id", "setpoint_rate_hz", "heartbeat_rate_hz", "autopilot_timeout_s",
                 "gcs_timeout_s", "require_gcs", "perception_timeout_s", "auto_enable", "stop_zero_s",
                 "param_retry_s", "param_give_up_s", "reconnect_s", "signing_key_file", "max_command_hold_s")
        return cls(output_mode=output_mode, engage_mode=engage_mode,
                   rates_hz=tuple((n, float(r)) for n, r in rates if r > 0),
                   **{n: get(f"link.{n}") for n in names})

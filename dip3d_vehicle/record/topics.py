"""The run record's channels: one table of topics, each with its schema (Foxglove's where one fits).

Foxglove's well-known schemas (``foxglove.CompressedImage``, ``foxglove.ImageAnnotations``,
``foxglove.SceneUpdate``, ``foxglove.Log``) are encoded with
foxglove-sdk's message classes (protobuf, with the schema's FileDescriptorSet), so Foxglove shows
them as images, overlays, a 3D scene and a log panel. Everything else is JSON with a JSON schema,
plottable field by field. The same table serves the MCAP file and the live WebSocket server.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

__all__ = ["Topic", "topic", "all_topics", "encode_json"]


@dataclass(frozen=True)
class Topic:
    """One channel: its topic, schema name, schema encoding and data, and message encoding."""

    name: str
    schema_name: str
    schema_encoding: str  # "protobuf" or "jsonschema"
    schema_data: bytes
    message_encoding: str  # "protobuf" or "json"
    doc: str


def _foxglove(name: str, cls_name: str, doc: str) -> Topic:
    import foxglove.messages as fm

    schema = getattr(fm, cls_name).get_schema()
    return Topic(name, schema.name, schema.encoding, bytes(schema.data), schema.encoding, doc)


def _num(*names: str) -> dict:
    return {n: {"type": ["number", "null"]} for n in names}


def _json(name: str, schema_name: str, properties: dict, doc: str) -> Topic:
    schema = {"title": schema_name, "type": "object", "properties": properties}
    return Topic(name, schema_name, "jsonschema", json.dumps(schema).encode(), "json", doc)


_COMMAND = {"type": ["object", "null"], "properties": _num("surge_m_s", "sway_m_s", "heave_m_s", "yaw_rate_rad_s")}


def _build() -> dict[str, Topic]:
    rows = [
        _foxglove("/camera/left/image", "CompressedImage", "kept left frames (JPEG/PNG, original pixels)"),
        _foxglove("/camera/right/image", "CompressedImage", "kept right frames"),
        _foxglove("/camera/left/annotations", "ImageAnnotations",
                  "arm, projected pointing ray, candidates with probability, chosen target, tracked box"),
        _foxglove("/scene", "SceneUpdate", "3D, rectified left camera frame: arm, its ray, candidates, target"),
        _foxglove("/mission/log", "Log", "mission state changes"),
        _foxglove("/story", "Log", "the run's story lines (link and mission events)"),
        _foxglove("/mavlink/statustext", "Log", "STATUSTEXT sent and received"),
        _json("/mission/state", "dip3d.MissionState",
              {"state": {"type": "string"}, "previous": {"type": ["string", "null"]},
               "trigger": {"type": ["string", "null"]}, "engaged": {"type": "boolean"},
               "hold_reason": {"type": "string"}, "t_s": {"type": "number"}}, "state on every change"),
        _json("/servo", "dip3d.Servo",
              {**_num("t_s", "pixel_error_px", "range_m", "range_error_m"), "command": _COMMAND,
               "engaged": {"type": "boolean"}, "perception_fresh": {"type": "boolean"},
               "state": {"type": "string"}}, "servo error and command at the telemetry rate"),
        _json("/autopilot/attitude", "dip3d.Attitude", _num("roll_rad", "pitch_rad", "yaw_rad", "yawspeed_rad_s"),
              "ATTITUDE from the autopilot"),
        _json("/autopilot/depth", "dip3d.Depth", _num("depth_m", "climb_m_s"), "VFR_HUD depth (-alt)"),
        _json("/autopilot/status", "dip3d.AutopilotStatus",
              {"mode": {"type": "string"}, "mode_number": {"type": ["integer", "null"]},
               "armed": {"type": "boolean"}, "system_status": {"type": "integer"}}, "HEARTBEAT of the autopilot"),
        _json("/link/status", "dip3d.LinkStatus",
              {"engaged": {"type": "boolean"}, "operator_enabled": {"type": "boolean"},
               "not_engaged_reason": {"type": "string"}, **_num("autopilot_age_s", "gcs_age_s"),
               "received": {"type": "integer"}, "sent": {"type": "integer"}}, "the controller's link, 1 Hz"),
        _json("/dip3d/frame", "dip3d.FrameRecord", {"index": {"type": ["integer", "null"]}},
              "per perception result: status, target, keypoints (what replay compares)"),
        _json("/dip3d/telemetry", "dip3d.Telemetry", {}, "simulator truth / controller telemetry records"),
        _json("/dip3d/event", "dip3d.Event", {"text": {"type": "string"}}, "events with fields"),
        _json("/dip3d/kept", "dip3d.KeptFrame", {"frame_index": {"type": "integer"}, "format": {"type": "string"}},
              "one per kept stereo pair (same log time as its two images)"),
    ]
    return {t.name: t for t in rows}


_TOPICS: dict[str, Topic] | None = None


def topic(name: str) -> Topic:
    """Return the Topic of ``name`` (KeyError for an unknown topic)."""
    global _TOPICS
    if _TOPICS is None:
        _TOPICS = _build()
    return _TOPICS[name]


def all_topics() -> dict[str, Topic]:
    """Return every topic of the run record by name."""
    topic("/story")
    return dict(_TOPICS or {})


def encode_json(obj: Any) -> bytes:
    """Return compact UTF-8 JSON of ``obj`` (numpy, NaN -> null, dataclasses: see ``to_jsonable``)."""
    from .jsonable import to_jsonable

    return json.dumps(to_jsonable(obj), separators=(",", ":"), allow_nan=False).encode()

"""One exception type per kind of failure; every message names the file/field/value at fault."""

from __future__ import annotations

__all__ = [
    "Dip3dError", "ParamsError", "CalibrationError", "ImageError", "KeypointsError",
    "ModelError", "LinkError", "ScenarioError", "SourceError", "LogError", "DatasetError", "FirmwareError",
]


class Dip3dError(Exception):
    """Base of every error the project raises on bad input; the message is one line."""


class ParamsError(Dip3dError):
    """A parameter file, key or value is invalid."""


class CalibrationError(Dip3dError):
    """A calibration file is missing, malformed or inconsistent with the frames."""


class ImageError(Dip3dError):
    """An image is missing, unreadable or of the wrong size."""


class KeypointsError(Dip3dError):
    """A keypoints file is missing or malformed."""


class ModelError(Dip3dError):
    """A neural model file is missing, altered or cannot be loaded."""


class LinkError(Dip3dError):
    """The MAVLink connection cannot be made or its peer does not fit the configuration."""


class ScenarioError(Dip3dError):
    """A simulator scenario file is missing or malformed."""


class SourceError(Dip3dError):
    """A stereo source (folder, video, camera, bag) cannot be opened or read."""


class LogError(Dip3dError):
    """A run log cannot be written or read."""


class DatasetError(Dip3dError):
    """An evaluation dataset is missing files or annotations."""


class FirmwareError(Dip3dError):
    """The ArduSub SITL binary is missing, not executable, or did not start / connect."""

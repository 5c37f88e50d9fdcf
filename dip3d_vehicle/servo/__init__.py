"""The servo: IBVS of the chosen target point with stereo depth, producing body velocity commands.

``analysis`` (python-control) is not imported here, so the onboard loop does not load it.
"""

from .command import NEUTRAL, VelocityCommand
from .gain import AdaptiveGain
from .ibvs import PointServo, ServoErrors
from .interaction import depth_interaction, normalise, point_interaction
from .mount import VEHICLE_AXES, CameraMount

__all__ = ["NEUTRAL", "VelocityCommand", "AdaptiveGain", "PointServo", "ServoErrors", "depth_interaction",
           "normalise", "point_interaction", "VEHICLE_AXES", "CameraMount"]

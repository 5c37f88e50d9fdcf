"""dip3d-vehicle: DIP-3D diver pointing as an ArduSub MAVLink behaviour controller."""

__version__ = "0.1.0"

"""Tell the diver the vehicle has chosen a target: a yaw nod or a flash of the lights.

``nod``: a short yaw swing right, back left past the start, and right again to the start heading
(swing, 2 x swing, swing at ``ack_nod_yaw_rate_rad_s``), ``ack_nod_cycles`` times, through the
normal velocity output while otherwise stationary; the net heading change is zero.
``lights``: ``ack_flashes`` on/off cycles of MAV_CMD_DO_SET_SERVO on the lights' servo output
(BlueROV2: SERVO9), the vehicle holding still. ``none``: nothing.
Each ends with ``ack_settle_s`` of stillness so the tracker can re-lock before the servo starts.

``shake`` ("nothing there"): yaw LEFT first, then right, left and right back to the start heading
(swing, 2 x swing, 2 x swing, swing at ``shake_yaw_rate_rad_s``): two reversals more than the nod,
which starts to the right; the net heading change is zero.
"""

from __future__ import annotations

from dataclasses import dataclass

from dip3d_vehicle.servo.command import VelocityCommand

from .blackboard import BehaviourConfig, SetServo

__all__ = ["AckStep", "ack_schedule", "shake_schedule", "Acknowledgement"]


@dataclass(frozen=True)
class AckStep:
    """From ``start_s`` (after the acknowledgement began): command a yaw rate and/or set a servo."""

    start_s: float
    yaw_rate_rad_s: float = 0.0
    servo: SetServo | None = None


def ack_schedule(config: BehaviourConfig) -> tuple[list[AckStep], float]:
    """Return the acknowledgement's steps and its total duration, seconds.

    Examples:
        >>> steps, total = ack_schedule(BehaviourConfig(ack_kind="nod", ack_nod_swing_s=0.5, ack_settle_s=1.0))
        >>> [(s.start_s, s.yaw_rate_rad_s) for s in steps], total
        ([(0.0, 0.35), (0.5, -0.35), (1.5, 0.35), (2.0, 0.0)], 3.0)
    """
    steps: list[AckStep] = []
    t = 0.0
    if config.ack_kind == "nod":
        r, s = config.ack_nod_yaw_rate_rad_s, config.ack_nod_swing_s
        for _ in range(config.ack_nod_cycles):
            for rate, dur in ((r, s), (-r, 2 * s), (r, s)):
                steps.append(AckStep(t, rate))
                t += dur
        steps.append(AckStep(t))
    elif config.ack_kind == "lights":
        half = config.ack_flash_period_s / 2.0
        for _ in range(config.ack_flashes):
            steps.append(AckStep(t, servo=SetServo(config.ack_lights_servo, config.ack_lights_on_pwm)))
            t += half
            steps.append(AckStep(t, servo=SetServo(config.ack_lights_servo, config.ack_lights_off_pwm)))
            t += half
    return steps, t + config.ack_settle_s


def shake_schedule(config: BehaviourConfig) -> tuple[list[AckStep], float]:
    """Return the "nothing there" shake's steps and its total duration, seconds.

    Examples:
        >>> steps, total = shake_schedule(BehaviourConfig(shake_swing_s=0.5, shake_yaw_rate_rad_s=0.3, ack_settle_s=1.0))
        >>> [(s.start_s, s.yaw_rate_rad_s) for s in steps], total
        ([(0.0, -0.3), (0.5, 0.3), (1.5, -0.3), (2.5, 0.3), (3.0, 0.0)], 4.0)
    """
    r, s = config.shake_yaw_rate_rad_s, config.shake_swing_s
    steps, t = [], 0.0
    for rate, dur in ((-r, s), (r, 2 * s), (-r, 2 * s), (r, s)):
        steps.append(AckStep(t, rate))
        t += dur
    steps.append(AckStep(t))
    return steps, t + config.ack_settle_s


class Acknowledgement:
    """Plays the schedule against the clock: ``start(now)``, then ``tick(now)`` each loop tick.

    Args:
        config: the behaviour parameters.
        shake: play the "nothing there" shake instead of the acknowledgement.
    """

    def __init__(self, config: BehaviourConfig, shake: bool = False) -> None:
        self.steps, self.duration_s = shake_schedule(config) if shake else ack_schedule(config)
        self._t0 = 0.0
        self._next = 0

    def start(self, now_s: float) -> None:
        """Begin at ``now_s``."""
        self._t0, self._next = now_s, 0

    def tick(self, now_s: float) -> tuple[VelocityCommand | None, list[SetServo], bool]:
        """Return (command to hold, servo messages due now, finished)."""
        elapsed = now_s - self._t0
        due: list[SetServo] = []
        while self._next < len(self.steps) and self.steps[self._next].start_s <= elapsed + 1e-9:
            if self.steps[self._next].servo is not None:
                due.append(self.steps[self._next].servo)
            self._next += 1
        current = self.steps[self._next - 1] if self._next > 0 else None
        rate = current.yaw_rate_rad_s if current is not None else 0.0
        command = VelocityCommand(yaw_rate_rad_s=rate) if rate else None
        return command, due, elapsed >= self.duration_s

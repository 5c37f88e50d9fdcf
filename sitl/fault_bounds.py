"""What the fault campaign promises per fault: the bound on the last motion command after its onset,
the expected safe outcome, and the plan file of its fast-tier trial (``sitl/faults/NAME.yaml``)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["FAULT_DIR", "BOUNDS_S", "EXPECTED", "TRIAL_PLANS"]

FAULT_DIR = Path(__file__).resolve().parent / "faults"

# The promised bound on "last motion command after the fault's onset", seconds, from the defaults:
# link.autopilot_timeout_s 0.6, link.gcs_timeout_s 2.5 (GCS HEARTBEAT 1 Hz), link.perception_timeout_s
# 0.5, the autopilot's 1 Hz HEARTBEAT, one 0.02 s tick, and (received) one relay / router hop.
BOUNDS_S: dict[str, float | None] = {
    "link_cut": 0.6 + 0.1,
    "autopilot_reboot": 0.6 + 0.1,
    "pilot_mode_change": 1.0 + 0.1,
    "pilot_disarm": 1.0 + 0.1,
    "gcs_loss": 2.5 + 0.1,
    "camera_stall": 0.5 + 0.1,
    "camera_black": 0.5 + 0.1,
    "camera_one_eye": 0.5 + 0.1,
    "camera_wrong_size": 0.5 + 0.1,
    "camera_time_backwards": 0.5 + 0.1,
    "camera_out_of_order": None,   # newer frames are still good: motion may continue (older ones dropped)
    "link_mess": None,              # degraded link: the controller keeps working
    "link_loss": None,              # 20 % loss, 100 +- 50 ms: the controller keeps working
}
EXPECTED = {
    "link_cut": "autopilot lost after 0.6 s: disengage ('autopilot lost'), neutral/zero stream (lost on the "
                "wire), enable latched off; link back: intervals + SYSID_MYGCS re-requested, re-engages "
                "after the operator's re-enable",
    "autopilot_reboot": "silence -> disengage as for a cut; reboot seen (time_boot_ms back / gap): streams and "
                        "SYSID_MYGCS re-requested; autopilot comes back disarmed in MANUAL: no command until "
                        "the pilot arms, selects the mode and re-enables",
    "pilot_mode_change": "hands off at the autopilot's next HEARTBEAT ('mode changed'), enable latched off; "
                         "re-engages only after the pilot selects the mode and re-enables",
    "pilot_disarm": "hands off at the next HEARTBEAT ('disarmed'), enable latched off; re-engages after re-arm "
                    "and re-enable",
    "gcs_loss": "ground station not heard for 2.5 s: disengage ('ground station lost'), enable latched off "
                "(ArduSub's own GCS failsafe may disarm); re-engages after the GCS is back and re-enables",
    "camera_stall": "no new frame: perception stale after 0.5 s -> hold (neutral), enable kept; resumes by itself",
    "camera_black": "black frames rejected at the perception boundary: stale -> hold; resumes by itself",
    "camera_one_eye": "frame with a missing eye rejected: no 3D decision, stale -> hold; resumes by itself",
    "camera_wrong_size": "frames of the wrong size rejected: stale -> hold; resumes by itself",
    "camera_out_of_order": "a frame older than the last one used is rejected; newer frames still used (here "
                           "every other frame: brief holds whenever the newest usable result is > 0.5 s old)",
    "camera_time_backwards": "frames whose stamp goes back rejected: stale -> hold; resumes by itself",
    "link_loss": "20 % loss, 100 +- 50 ms each way: keeps working (autopilot liveness from ~25 msg/s, "
                 "0.6 s timeout); GCS timeout 5 s for this link (see sitl/faults/link_loss.yaml)",
    "link_mess": "duplicates / reordered / corrupted packets: corrupted ones fail the CRC (counted as bad "
                 "data), the controller keeps working",
}
TRIAL_PLANS = {k: FAULT_DIR / f"{k}.yaml" for k in BOUNDS_S}

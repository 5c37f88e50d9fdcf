"""sitl.arm_eval's summary: direction errors per method and, with --select, the selector's per-frame outcomes."""

from __future__ import annotations

from sitl.arm_eval import summarise


def _row(deg: float, select: str | None = None) -> dict:
    stereo = {"deg": deg, "disp_err_px": [0.5, -1.0, 2.0], "sigma_px": [1.0, 1.0, 1.0]}
    if select is not None:
        stereo["select"] = select
    return {"position": "far-5", "deg_2d_only": 5.0, "stereo": stereo}


def test_the_summary_counts_the_selectors_outcomes_per_method():
    out = summarise([_row(10.0, "right"), _row(30.0, "ambiguous"), _row(50.0, "right"), _row(70.0, "wrong")])
    assert out["frames"] == 4 and out["stereo"]["n"] == 4 and out["stereo"]["median_deg"] == 40.0
    assert out["stereo"]["over_20deg"] == 3 and out["stereo"]["disp_err_median_px"] == [0.5, 1.0, 2.0]
    assert out["stereo"]["select"] == {"ambiguous": 1, "right": 2, "wrong": 1}
    assert "select" not in summarise([_row(10.0)])["stereo"]  # without --select: no outcomes


def test_the_summary_says_which_way_the_frames_lean():
    rows = [_row(10.0, "ambiguous"), _row(20.0, "ambiguous"), _row(5.0, "ambiguous"), _row(8.0, "nothing_on_ray")]
    for r, p in zip(rows, ([0.45, 0.3, 0.1], [0.2, 0.5, 0.1], [0.4, 0.4, 0.2], None)):
        r["stereo"]["p"] = p
    lean = summarise(rows)["stereo"]["lean"]
    assert (lean["right"], lean["wrong"], lean["tie"]) == (1, 1, 1)  # frames without scored objects not counted
    assert lean["p_pointed_median"] == 0.4 and lean["p_best_other_median"] == 0.4
    assert "lean" not in summarise([_row(10.0, "right")])["stereo"]

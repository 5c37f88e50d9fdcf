"""The mission plot (``sitl``'s trajectory.png): every mark in a legend, the outcome in the title."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import pytest

from dip3d_vehicle import plots
from dip3d_vehicle.plots import MissionPlacard, MissionPlot, plot_mission


@pytest.fixture
def wrong_object_plot():
    track = [(0.1 * i, 0.02 * i, 0.005 * i, 1.0 + 0.001 * i, 0.1) for i in range(600)]
    states = [(0.0, "idle"), (1.5, "wait_for_diver")] + [
        (2.0 + 1.2 * k + d, s) for k in range(20) for d, s in ((0.0, "confirm_point"), (0.8, "select_target"))
    ] + [(32.0, "acknowledge"), (35.0, "servo"), (38.4, "arrive"), (58.4, "done")]
    return MissionPlot(track=track, placards=[MissionPlacard(1, 1.6, 0.6, 1.22), MissionPlacard(2, 2.6, 0.6, 1.12),
                                              MissionPlacard(3, 3.7, 0.35, 1.02), MissionPlacard(9, 4, -1, 1, "distractor")],
                       diver_north_east_m=(5.1, -1.0), states=states, sim_time_s=60.0, scenario="far_diver", seed=0,
                       diver_position="far-5", target_id=2, chosen_id=1, outcome="wrong_object",
                       outcome_reason="arrived at placard 1; the diver pointed at placard 2")


def test_every_mark_is_in_a_legend_and_the_title_says_wrong_object(wrong_object_plot, tmp_path, monkeypatch):
    figs = []
    monkeypatch.setattr(plots.plt, "close", lambda fig: figs.append(fig))
    path = plot_mission(wrong_object_plot, tmp_path / "trajectory.png")
    assert path.is_file() and path.stat().st_size > 10_000
    (fig,) = figs
    assert fig._suptitle.get_text().startswith("far_diver seed 0: WRONG_OBJECT")
    ax_map, ax_depth, ax_lane = fig.axes
    for ax in (ax_map, ax_depth, ax_lane):
        legend = {t.get_text() for t in ax.get_legend().get_texts()}
        drawn = {a.get_label() for a in ax.lines + ax.collections if not a.get_label().startswith("_")}
        assert drawn <= legend, drawn - legend
    map_labels = {t.get_text() for t in ax_map.get_legend().get_texts()}
    assert {"pointed placard (2)", "chosen placard (1): WRONG", "other placard", "distractor", "vehicle track",
            "start", "end"} <= map_labels and any(t.startswith("vehicle heading") for t in map_labels)
    lane = {t.get_text() for t in ax_lane.get_legend().get_texts()}
    assert lane == {s for _, s in wrong_object_plot.states}  # one colour key entry per state, no text in the spans
    assert not ax_lane.texts and not ax_depth.texts
    for ax in (ax_map, ax_depth):  # a mark without its own entry looks exactly like one with an entry
        style = lambda a: (a.get_marker(), a.get_color(), a.get_linestyle())  # noqa: E731
        keyed = {style(a) for a in ax.lines if not a.get_label().startswith("_")}
        extra = [a for a in ax.lines if a.get_label().startswith("_") and style(a) not in keyed
                 and a.get_marker() != "x"]  # the white cross drawn over the wrong placard's own mark
        assert not extra
    plt.close(fig)


def test_reached_title(wrong_object_plot, tmp_path, monkeypatch):
    figs = []
    monkeypatch.setattr(plots.plt, "close", lambda fig: figs.append(fig))
    ok = MissionPlot(**{**wrong_object_plot.__dict__, "chosen_id": 2, "outcome": "reached",
                        "outcome_reason": "arrived at the pointed placard 2"})
    plot_mission(ok, tmp_path / "ok.png")
    assert figs[0]._suptitle.get_text().startswith("far_diver seed 0: REACHED")
    assert not math.isnan(figs[0].axes[1].get_ylim()[0])
    plt.close(figs[0])

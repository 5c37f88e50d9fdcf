"""The story of a simulated mission printed as it happens, with a progress line on a terminal.

``LiveStory`` is called by the simulation after every step (``Simulation.on_step``). It prints every
new line of the story (the link's events, the mission's states and decisions, the STATUSTEXTs the
ground station heard, whole and word-wrapped, never cut) in time order. On a terminal it also keeps
one progress line at the bottom (simulated time, state, range to the chosen object), redrawn a few
times per second and erased before each story line; when the output is not a terminal (piped,
redirected) it prints the story lines only.
"""

from __future__ import annotations

import math
import shutil
import sys
import textwrap
import time
from typing import Any, TextIO

__all__ = ["LiveStory", "wrap_story_line"]

_INDENT = "  "
_CONTINUATION = "        "
_PROGRESS_PERIOD_S = 0.2


def wrap_story_line(line: str, width: int) -> list[str]:
    """Return a story line wrapped at ``width`` columns between words (a word longer than a line stays whole)."""
    return textwrap.wrap(line, width=max(40, width), initial_indent=_INDENT, subsequent_indent=_CONTINUATION,
                         break_long_words=False, break_on_hyphens=False) or [_INDENT]


def _story_time(line: str) -> float:
    """Return the time of a story line (``t=12.34 ...``), or infinity."""
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return math.inf


class LiveStory:
    """Print a running Simulation's story as it grows.

    Args:
        sim: the Simulation (its ``link.events``, ``mission.bb.story``, ``pilot.statustexts``).
        stream: where to print (default stdout).
        progress: draw the progress line (default: when ``stream`` is a terminal).
        width: wrap width (default: the terminal's width, 100 when not a terminal).
    """

    def __init__(self, sim: Any, stream: TextIO | None = None, progress: bool | None = None,
                 width: int | None = None) -> None:
        self.sim = sim
        self.stream = stream or sys.stdout
        tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.progress = tty if progress is None else progress
        self.width = width or (shutil.get_terminal_size((100, 24)).columns - 1 if tty else 100)
        self._seen = {"link": 0, "mission": 0, "pilot": 0}
        self._next_progress_wall = 0.0
        self._progress_shown = False
        self.lines_printed = 0
        self.first_line_wall_s: float | None = None

    def __call__(self, now_s: float) -> None:
        """Print what happened since the last call; redraw the progress line when due."""
        new = self._new_lines()
        if new:
            self._clear_progress()
            for line in new:
                self._print(line)
        if self.progress and (new or time.monotonic() >= self._next_progress_wall):
            self._draw_progress(now_s)

    def finish(self) -> None:
        """Print the lines added after the last step (closing the link) and erase the progress line."""
        new = self._new_lines()
        self._clear_progress()
        for line in new:
            self._print(line)
        self.stream.flush()

    def _new_lines(self) -> list[str]:
        """Return the story lines added since the last call, in time order."""
        sim = self.sim
        sources = {"link": sim.link.events, "mission": sim.mission.bb.story,
                   "pilot": [f"t={t:.2f} pilot heard {s}" for t, s in sim.pilot.statustexts[self._seen["pilot"]:]]}
        out = []
        for name, lines in sources.items():
            if name == "pilot":
                out.extend(lines)
                self._seen[name] += len(lines)
            else:
                out.extend(lines[self._seen[name]:])
                self._seen[name] = len(lines)
        return sorted(out, key=_story_time)

    def _print(self, line: str) -> None:
        for part in wrap_story_line(line, self.width):
            self.stream.write(part + "\n")
        self.stream.flush()
        self.lines_printed += 1
        if self.first_line_wall_s is None:
            self.first_line_wall_s = time.monotonic()

    def _draw_progress(self, now_s: float) -> None:
        text = self.progress_text(now_s)[: max(10, self.width)]
        self.stream.write("\r\033[K" + text)
        self.stream.flush()
        self._progress_shown = True
        self._next_progress_wall = time.monotonic() + _PROGRESS_PERIOD_S

    def _clear_progress(self) -> None:
        if self._progress_shown:
            self.stream.write("\r\033[K")
            self._progress_shown = False

    def progress_text(self, now_s: float) -> str:
        """Return the progress line: simulated time, mission state, range to the chosen object."""
        sim = self.sim
        chosen = sim.chosen_placard()
        if chosen is None:
            where = "no object chosen" if sim.mission.bb.target is None else "chosen object: not on a placard"
        else:
            rng = sim.last_meta["placards"][chosen]["range_m"]
            where = f"range to placard {chosen}: {rng:.2f} m"
        return f"{_INDENT}[sim {now_s:6.1f} s] {sim.mission.state:<15} {where}"

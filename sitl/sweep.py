"""Parameter sweep: the closed-loop mission over a grid of named parameters, one table of outcomes per cell.

    python -m sitl.sweep --grid behaviour.confirm_frames=2,3,4 --grid selection.method=default,paper \\
                         [--scenario paper_pool] [--seeds 0-9] [--jobs 1 | --ray auto|local[:N]|ADDRESS]
                         [--json FILE]

Every cell of the grid (the cartesian product of the ``--grid`` values, in the order given) runs the
mission on every seed with the cell's parameters set (``--set`` overrides apply to all cells). The
(cell, seed) runs are independent, so they are spread over local processes or a Ray cluster
(``sitl/parallel.py``); results are gathered in order, so the tables are the same wherever the
runs ran. Per cell: each seed's outcome word (``sitl/outcome.py``) and time to arrive, then the
counts of every outcome; at the end one summary row per cell.
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
import sys
from collections import Counter
from typing import Any, Mapping, Sequence

__all__ = ["Grid", "parse_grid", "sweep", "format_tables", "main"]

Grid = list[tuple[str, list[Any]]]
"""Named parameters and their values, in the order the cells iterate them (last fastest)."""


class SweepError(ValueError):
    """A bad ``--grid`` item (names the item and what was expected)."""


def parse_grid(items: Sequence[str]) -> Grid:
    """Return the grid of ``KEY=V1,V2,...`` items (values parsed as YAML scalars; keys checked in the schema)."""
    import yaml

    from dip3d_vehicle.config import schema

    known = schema()
    grid: Grid = []
    for item in items:
        key, sep, values = item.partition("=")
        key = key.strip()
        if not sep or not values.strip():
            raise SweepError(f"--grid {item!r}: expected KEY=V1,V2,...")
        if key not in known:
            raise SweepError(f"--grid {item!r}: unknown parameter {key!r} (see 'dip3d-vehicle params show')")
        if any(k == key for k, _ in grid):
            raise SweepError(f"--grid {item!r}: {key} is given twice")
        grid.append((key, [yaml.safe_load(v) for v in values.split(",")]))
    if not grid:
        raise SweepError("--grid: give at least one KEY=V1,V2,...")
    return grid


def cells(grid: Grid) -> list[dict[str, Any]]:
    """Return every cell of the grid as a dict of parameter values."""
    keys = [k for k, _ in grid]
    return [dict(zip(keys, combo)) for combo in itertools.product(*(v for _, v in grid))]


def _run(args: tuple) -> dict:
    """One mission of one cell (in whatever process runs it): a small JSON row."""
    from .campaign import _run_one

    cell_index, seed, scenario, sets = args
    r = _run_one((seed, None, {}, scenario, sets))
    return {"cell": cell_index, "seed": seed, "outcome": r["outcome"], "chosen_id": r["chosen_id"],
            "target_id": r["target_id"], "time_to_arrive_s": r["time_to_arrive_s"],
            "range_error_at_arrival_m": r["range_error_at_arrival_m"], "sim_time_s": r["sim_time_s"],
            "wall_time_s": r["wall_time_s"]}


def sweep(grid: Grid, seeds: Sequence[int], scenario: str = "paper_pool", sets: Mapping[str, Any] | None = None,
          jobs: int = 1, ray: str | None = None, verbose: bool = True) -> dict:
    """Run every (cell, seed) mission; return {"grid", "cells": [{"params", "runs", "outcomes", ...}]}."""
    from .parallel import map_runs

    grid_cells = cells(grid)
    items = [(i, seed, scenario, {**dict(sets or {}), **cell}) for i, cell in enumerate(grid_cells) for seed in seeds]
    out_cells = [{"params": cell, "runs": []} for cell in grid_cells]
    for row in map_runs(_run, items, jobs, ray):
        out_cells[row["cell"]]["runs"].append(row)
        if verbose:
            print(json.dumps(row), flush=True)
    for cell in out_cells:
        runs = cell["runs"]
        times = [r["time_to_arrive_s"] for r in runs if r["outcome"] == "reached" and r["time_to_arrive_s"] is not None]
        cell["outcomes"] = dict(sorted(Counter(r["outcome"] for r in runs).items()))
        cell["reached"] = sum(r["outcome"] == "reached" for r in runs)
        cell["median_time_to_arrive_s"] = statistics.median(times) if times else None
    return {"grid": [[k, v] for k, v in grid], "scenario": scenario, "seeds": list(seeds), "cells": out_cells}


def format_tables(result: Mapping[str, Any]) -> str:
    """Return one outcome table per cell and a summary table (text)."""
    lines = []
    words = sorted({w for c in result["cells"] for w in c["outcomes"]})
    for c in result["cells"]:
        name = ", ".join(f"{k}={v}" for k, v in c["params"].items())
        lines += ["", f"cell {name}", f"{'seed':>6}  {'outcome':<18}{'chosen':>8}{'target':>8}{'t arrive s':>12}"]
        for r in c["runs"]:
            t = "-" if r["time_to_arrive_s"] is None else f"{r['time_to_arrive_s']:.1f}"
            lines.append(f"{r['seed']:>6}  {r['outcome']:<18}{str(r['chosen_id']):>8}{str(r['target_id']):>8}{t:>12}")
    head = f"{'cell':<48}" + "".join(f"{w:>16}" for w in words) + f"{'median t s':>12}"
    lines += ["", f"summary ({result['scenario']}, seeds {result['seeds']})", head, "-" * len(head)]
    for c in result["cells"]:
        name = ", ".join(f"{k}={v}" for k, v in c["params"].items())
        t = c["median_time_to_arrive_s"]
        lines.append(f"{name[:47]:<48}" + "".join(f"{c['outcomes'].get(w, 0):>16}" for w in words)
                     + f"{'-' if t is None else f'{t:.1f}':>12}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Command line (see the module doc)."""
    from .campaign import _sets
    from .parallel import add_executor_arguments
    from .point_campaign import _seeds

    ap = argparse.ArgumentParser(prog="python -m sitl.sweep", description=__doc__.split("\n")[0])
    ap.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                    help="a parameter and its values (repeatable: the grid is every combination)")
    ap.add_argument("--scenario", default="paper_pool", help="built-in scenario name or file")
    ap.add_argument("--seeds", default="0-9", help="seeds: A-B or A,B,C")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                    help="a parameter override for every cell (repeatable)")
    ap.add_argument("--json", metavar="FILE")
    add_executor_arguments(ap)
    args = ap.parse_args(argv)
    try:
        grid = parse_grid(args.grid)
    except SweepError as exc:
        ap.error(str(exc))
    result = sweep(grid, _seeds(args.seeds), args.scenario, _sets(args.sets), args.jobs, args.ray)
    print(format_tables(result))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(result, fh, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())

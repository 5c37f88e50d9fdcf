"""A new folder for every run, so that no run replaces another.

By default a run writes into ``<sitl.out_dir>/<UTC time>_<scenario>_s<seed>/`` (``runs/`` in the
current folder; the project's ``.gitignore`` holds ``runs/``), with ``_2``, ``_3`` ... appended when
two runs start in the same second. A folder given with ``--out`` is used as it is when it does not
exist yet or is empty; a folder that already holds files is refused (one line, exit 2).
"""

from __future__ import annotations

import re
from datetime import datetime, timezone
from pathlib import Path

from .errors import Dip3dError

__all__ = ["new_run_folder", "explicit_run_folder"]


def _slug(text: str) -> str:
    """Return a file-name-safe version of a scenario name (letters, digits, - and _)."""
    return re.sub(r"[^A-Za-z0-9_-]+", "-", text).strip("-") or "run"


def new_run_folder(parent: str | Path, scenario: str, seed: int, when: datetime | None = None) -> Path:
    """Create and return ``parent/<YYYYmmdd-HHMMSS>_<scenario>_s<seed>[_N]/`` (never an existing folder).

    Raises:
        Dip3dError: the folder cannot be created (naming it and the reason).
    """
    stamp = (when or datetime.now(timezone.utc)).strftime("%Y%m%d-%H%M%S")
    base = Path(parent) / f"{stamp}_{_slug(scenario)}_s{seed}"
    for n in range(1, 1000):
        path = base if n == 1 else base.with_name(f"{base.name}_{n}")
        try:
            path.mkdir(parents=True, exist_ok=False)
            return path
        except FileExistsError:
            continue
        except OSError as exc:
            raise Dip3dError(f"{path}: cannot create the run folder ({exc.strerror})") from None
    raise Dip3dError(f"{base}: 999 run folders with this name already exist")


def explicit_run_folder(path: str | Path) -> Path:
    """Return ``path`` (created if missing) for a run; refuse a folder that already holds files.

    Raises:
        Dip3dError: ``path`` is a file, holds files, or cannot be created.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise Dip3dError(f"{p}: --out must be a folder, this is a file")
    if p.is_dir() and any(p.iterdir()):
        raise Dip3dError(f"{p}: --out folder already holds files (a run never overwrites another); "
                         f"give a new or empty folder, or leave out --out for a new folder under sitl.out_dir")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise Dip3dError(f"{p}: cannot create output folder ({exc.strerror})") from None
    return p

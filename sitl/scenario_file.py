"""Reading a scenario file: the built-in scenarios, ``base`` chains (deep merge), and ``ScenarioNode``,
a mapping with typed, checked accessors whose errors name the file and the field."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import yaml

from dip3d_vehicle.errors import ScenarioError

__all__ = ["SCENARIO_DIR", "ScenarioNode", "scenario_names", "resolve_scenario_path", "read_scenario_yaml"]

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"
"""Folder of the built-in scenario files."""


class ScenarioNode:
    """A mapping from a scenario file with typed, checked accessors that name file and field."""

    def __init__(self, data: Any, where: str, path: str) -> None:
        if not isinstance(data, dict):
            raise ScenarioError(f"{where}: {path or 'top level'}: expected a mapping, got {type(data).__name__}")
        self.data, self.where, self.path = data, where, path
        self.used: set[str] = set()

    def _name(self, key: str) -> str:
        """Return the dotted name of ``key`` in the file."""
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, problem: str) -> ScenarioError:
        """Return a ScenarioError for ``key``."""
        return ScenarioError(f"{self.where}: {self._name(key)}: {problem}")

    def has(self, key: str) -> bool:
        """Return True when ``key`` is present and not null."""
        return key in self.data and self.data[key] is not None

    def raw(self, key: str, default: Any = ...) -> Any:
        """Return the value of ``key`` as read (``default`` when absent; ``...``: required)."""
        self.used.add(key)
        if key not in self.data or self.data[key] is None:
            if default is ...:
                raise self.fail(key, "missing (required)")
            return default
        return self.data[key]

    def num(self, key: str, default: Any = ..., lo: float | None = None, hi: float | None = None) -> float:
        """Return ``key`` as a finite number within [lo, hi]."""
        value = self.raw(key, default)
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.fail(key, f"{value!r} is not a finite number")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            raise self.fail(key, f"{value!r} is out of range [{lo}, {hi}]")
        return float(value)

    def vec(self, key: str, n: int, default: Any = ..., lo: float | None = None,
            hi: float | None = None) -> tuple[float, ...]:
        """Return ``key`` as ``n`` finite numbers within [lo, hi]."""
        value = self.raw(key, default)
        if value is None:
            return None
        ok = isinstance(value, (list, tuple)) and len(value) == n and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
        if not ok:
            raise self.fail(key, f"{value!r} is not a list of {n} numbers")
        if any((lo is not None and v < lo) or (hi is not None and v > hi) for v in value):
            raise self.fail(key, f"{value!r} has values out of range [{lo}, {hi}]")
        return tuple(float(v) for v in value)

    def text(self, key: str, default: Any = ..., choices: tuple[str, ...] | None = None) -> str:
        """Return ``key`` as text, one of ``choices`` when given."""
        value = self.raw(key, default)
        if not isinstance(value, str):
            raise self.fail(key, f"{value!r} is not text")
        if choices and value not in choices:
            raise self.fail(key, f"{value!r} is not one of {', '.join(choices)}")
        return value

    def integer(self, key: str, default: Any = ..., lo: int | None = None) -> int:
        """Return ``key`` as an integer >= ``lo``."""
        value = self.raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(key, f"{value!r} is not an integer")
        if lo is not None and value < lo:
            raise self.fail(key, f"{value!r} must be >= {lo}")
        return value

    def child(self, key: str, required: bool = False) -> "ScenarioNode":
        """Return the mapping ``key`` as a node (empty when absent and not required)."""
        value = self.raw(key, ... if required else {})
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a mapping, got {type(value).__name__}")
        return ScenarioNode(value, self.where, self._name(key))

    def items(self, key: str) -> list["ScenarioNode"]:
        """Return the non-empty list ``key`` as nodes."""
        value = self.raw(key)
        if not isinstance(value, list) or not value:
            raise self.fail(key, "expected a non-empty list")
        return [ScenarioNode(v, self.where, f"{self._name(key)}[{i}]") for i, v in enumerate(value)]

    def done(self) -> None:
        """Raise ScenarioError on keys that were never read (typos, unsupported fields)."""
        extra = [k for k in self.data if k not in self.used]
        if extra:
            raise self.fail(str(extra[0]), "unknown field")


def scenario_names() -> list[str]:
    """Return the names of the built-in scenarios (``sitl/scenarios/*.yaml``)."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.yaml"))


def resolve_scenario_path(name_or_path: str, relative_to: Path | None = None) -> Path:
    """Return the file of a built-in scenario name or a path; ScenarioError when there is none."""
    text = str(name_or_path)
    if text in scenario_names():
        return SCENARIO_DIR / f"{text}.yaml"
    path = Path(text)
    if relative_to is not None and not path.is_absolute() and not path.exists():
        path = relative_to / path
    if path.is_file():
        return path
    if not text.endswith((".yaml", ".yml")) and "/" not in text:
        raise ScenarioError(f"{text}: unknown scenario (built-in: {', '.join(scenario_names())})")
    raise ScenarioError(f"{text}: scenario file not found")


def read_scenario_yaml(path: Path, chain: tuple[str, ...] = ()) -> dict:
    """Read a scenario file and merge it over its ``base`` (recursively)."""
    where = str(path)
    if where in chain:
        raise ScenarioError(f"{where}: base: circular base chain ({' -> '.join(chain + (where,))})")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f":{mark.line + 1}" if mark else ""
        raise ScenarioError(f"{where}{line}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{where}: cannot read scenario file ({exc.__class__.__name__})") from None
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: top level: expected a mapping of sections")
    base = data.pop("base", None)
    if base is None:
        return data
    if not isinstance(base, str):
        raise ScenarioError(f"{where}: base: {base!r} is not a scenario name or path")
    try:
        base_path = resolve_scenario_path(base, path.parent)
    except ScenarioError as exc:
        raise ScenarioError(f"{where}: base: {exc}") from None
    return _merge(read_scenario_yaml(base_path, chain + (where,)), data)


def _merge(base: dict, over: dict) -> dict:
    """Deep-merge mappings (``over`` wins; lists and scalars are replaced)."""
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out

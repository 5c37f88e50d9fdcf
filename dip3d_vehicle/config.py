"""Parameters: one schema (name, default, unit, range, doc) and the files/overrides that set them.

Like ``control/config.py`` every tunable of the project lives in one dictionary keyed
``'topic.name'``. The schema is data: ``params/schema/<topic>.yaml`` (installed as the package
``dip3d_vehicle.params``). Profiles (``params/<profile>.yaml``) and user files hold flat
``key: value`` lines (nested mappings are flattened with dots). Effective values are layered:
schema default < profile < ``--params`` files (in order) < ``--set key=value``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Iterable, Iterator, Mapping

import yaml

from .errors import ParamsError

__all__ = ["Param", "Params", "schema", "load_params", "profile_names", "check_file"]

_KINDS = {"float": float, "int": int, "bool": bool, "str": str}


@dataclass(frozen=True)
class Param:
    """One tunable: its key, default, unit, allowed range or choices, and a one-line doc."""

    key: str
    kind: str
    default: Any
    unit: str
    doc: str
    min: float | None = None
    max: float | None = None
    choices: tuple[str, ...] | None = None
    nullable: bool = False

    def allowed(self) -> str:
        """Return the allowed values as text, for error messages and help."""
        if self.choices:
            text = "one of " + ", ".join(self.choices)
        elif self.kind in ("float", "int"):
            lo = "-inf" if self.min is None else f"{self.min:g}"
            hi = "inf" if self.max is None else f"{self.max:g}"
            text = f"{self.kind} in [{lo}, {hi}]"
        else:
            text = self.kind
        return text + (" or null" if self.nullable else "")

    def coerce(self, value: Any, where: str) -> Any:
        """Check and convert a value for this parameter; raise ParamsError naming ``where``."""
        if value is None:
            if self.nullable:
                return None
            raise ParamsError(f"{where}: {self.key} = null is not allowed (expected {self.allowed()})")
        try:
            out = _convert(self.kind, value)
        except (TypeError, ValueError):
            raise ParamsError(
                f"{where}: {self.key} = {value!r} is not valid (expected {self.allowed()})"
            ) from None
        if self.kind in ("float", "int"):
            if not math.isfinite(out) or (self.min is not None and out < self.min) or (
                self.max is not None and out > self.max
            ):
                raise ParamsError(
                    f"{where}: {self.key} = {value!r} is out of range (allowed {self.allowed()})"
                )
        if self.choices and out not in self.choices:
            raise ParamsError(f"{where}: {self.key} = {value!r} is not allowed (expected {self.allowed()})")
        return out


def _convert(kind: str, value: Any) -> Any:
    """Convert a YAML or command-line value to ``kind``; raise ValueError when it does not fit."""
    if kind == "bool":
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.lower() in ("true", "false", "yes", "no", "on", "off", "1", "0"):
            return value.lower() in ("true", "yes", "on", "1")
        raise ValueError(value)
    if kind == "int":
        if isinstance(value, bool):
            raise ValueError(value)
        if isinstance(value, float) and not value.is_integer():
            raise ValueError(value)
        return int(value) if not isinstance(value, str) else int(value.strip())
    if kind == "float":
        if isinstance(value, bool):
            raise ValueError(value)
        return float(value)
    if isinstance(value, (dict, list)):
        raise ValueError(value)
    return str(value)


def _params_dir() -> resources.abc.Traversable:
    """Return the folder holding the schema and profiles (``params/`` in the source tree).

    An installed wheel carries it as the data package ``dip3d_vehicle.params``; an editable
    install or a source checkout reads the top-level ``params/`` directly.
    """
    source_tree = Path(__file__).resolve().parent.parent / "params"
    if (source_tree / "schema").is_dir():
        return source_tree
    return resources.files("dip3d_vehicle.params")


def _schema_entry(key: str, spec: Any, where: str) -> Param:
    """Build one Param from its schema mapping; a malformed schema is a ParamsError."""
    if not isinstance(spec, dict) or "default" not in spec or "doc" not in spec:
        raise ParamsError(f"{where}: schema entry {key} needs at least 'default' and 'doc'")
    kind = spec.get("kind") or _infer_kind(spec["default"], spec)
    if kind not in _KINDS:
        raise ParamsError(f"{where}: schema entry {key} has unknown kind {kind!r}")
    choices = tuple(spec["choices"]) if spec.get("choices") else None
    param = Param(key=key, kind=kind, default=None, unit=str(spec.get("unit", "")), doc=str(spec["doc"]),
                  min=spec.get("min"), max=spec.get("max"), choices=choices,
                  nullable=bool(spec.get("nullable", False)))
    default = param.coerce(spec["default"], where)
    return Param(**{**param.__dict__, "default": default})


def _infer_kind(default: Any, spec: dict) -> str:
    """Guess a schema entry's kind from its default when 'kind' is not given."""
    if spec.get("choices"):
        return "str"
    for name, typ in (("bool", bool), ("int", int), ("float", float), ("str", str)):
        if isinstance(default, typ):
            return name
    return "str"


_SCHEMA: dict[str, Param] | None = None


def schema() -> dict[str, Param]:
    """Return the whole parameter schema, read once from ``params/schema/*.yaml``."""
    global _SCHEMA
    if _SCHEMA is None:
        out: dict[str, Param] = {}
        folder = _params_dir() / "schema"
        for entry in sorted(folder.iterdir(), key=lambda e: e.name):
            if not entry.name.endswith(".yaml"):
                continue
            where = f"params/schema/{entry.name}"
            data = yaml.safe_load(entry.read_text()) or {}
            for key, spec in _flatten_schema(data):
                if key in out:
                    raise ParamsError(f"{where}: schema key {key} is defined twice")
                out[key] = _schema_entry(key, spec, where)
        _SCHEMA = out
    return _SCHEMA


def _flatten_schema(data: Mapping, prefix: str = "") -> Iterator[tuple[str, dict]]:
    """Yield (dotted key, spec) from a nested schema mapping; a spec is a dict with 'doc'."""
    for name, value in data.items():
        key = f"{prefix}{name}"
        if isinstance(value, dict) and "doc" in value:
            yield key, value
        elif isinstance(value, dict):
            yield from _flatten_schema(value, key + ".")
        else:
            raise ParamsError(f"params/schema: entry {key} is not a mapping with 'doc'")


def profile_names() -> list[str]:
    """Return the names of the built-in profiles (``params/<name>.yaml``)."""
    return sorted(e.name[:-5] for e in _params_dir().iterdir() if e.name.endswith(".yaml"))


def _read_yaml_lines(text: str, where: str) -> list[tuple[str, Any, int]]:
    """Parse a flat or nested YAML mapping into (dotted key, value, line) triples."""
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f":{mark.line + 1}" if mark else ""
        raise ParamsError(f"{where}{line}: not valid YAML ({' '.join(str(getattr(exc, 'problem', exc)).split())})") from None
    if node is None:
        return []
    if not isinstance(node, yaml.MappingNode):
        raise ParamsError(f"{where}:{node.start_mark.line + 1}: expected a mapping of key: value")
    return list(_walk(node, "", where))


def _walk(node: yaml.MappingNode, prefix: str, where: str) -> Iterator[tuple[str, Any, int]]:
    """Walk a YAML mapping node, yielding dotted keys, Python values and 1-based line numbers."""
    loader = yaml.SafeLoader("")
    for key_node, value_node in node.value:
        key = prefix + str(key_node.value)
        line = key_node.start_mark.line + 1
        if isinstance(value_node, yaml.MappingNode):
            yield from _walk(value_node, key + ".", where)
        else:
            try:
                value = loader.construct_object(value_node, deep=True)
            except yaml.YAMLError as exc:
                raise ParamsError(f"{where}:{line}: {key}: bad value ({' '.join(str(exc).split())})") from None
            yield key, value, line


class Params(Mapping[str, Any]):
    """Effective parameter values with the source of each (schema, profile, file:line, --set)."""

    def __init__(self, values: dict[str, Any], sources: dict[str, str], profile: str) -> None:
        self._values = values
        self._sources = sources
        self.profile = profile

    def __getitem__(self, key: str) -> Any:
        try:
            return self._values[key]
        except KeyError:
            raise ParamsError(f"unknown parameter {key!r}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def source(self, key: str) -> str:
        """Return where the effective value of ``key`` came from."""
        return self._sources[key]

    def section(self, prefix: str) -> dict[str, Any]:
        """Return the values under ``prefix.`` with the prefix stripped."""
        cut = len(prefix) + 1
        return {k[cut:]: v for k, v in self._values.items() if k.startswith(prefix + ".")}

    def with_overrides(self, overrides: Mapping[str, Any], source: str = "override") -> "Params":
        """Return a copy with some values replaced (validated against the schema)."""
        values, sources = dict(self._values), dict(self._sources)
        for key, value in overrides.items():
            values[key] = _lookup(key, source).coerce(value, source)
            sources[key] = source
        return Params(values, sources, self.profile)


def _lookup(key: str, where: str) -> Param:
    """Return the schema entry of ``key`` or raise ParamsError naming ``where``."""
    spec = schema().get(key)
    if spec is None:
        near = [k for k in schema() if k.split(".")[-1] == key.split(".")[-1]]
        hint = f" (did you mean {near[0]}?)" if near else ""
        raise ParamsError(f"{where}: unknown parameter {key!r}{hint}")
    return spec


def _apply_text(text: str, where: str, values: dict, sources: dict) -> None:
    """Apply the key: value lines of one YAML text to ``values``, recording their sources."""
    for key, value, line in _read_yaml_lines(text, where):
        loc = f"{where}:{line}"
        values[key] = _lookup(key, loc).coerce(value, loc)
        sources[key] = loc


def check_file(path: str | Path) -> int:
    """Validate a parameter file; return the number of keys or raise ParamsError (file:line)."""
    path = Path(path)
    text = _read_text(path)
    values: dict = {}
    _apply_text(text, str(path), values, {})
    return len(values)


def _read_text(path: Path) -> str:
    """Read a parameter file, raising ParamsError if it is missing or not text."""
    try:
        return path.read_text()
    except FileNotFoundError:
        raise ParamsError(f"{path}: parameter file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ParamsError(f"{path}: cannot read parameter file ({exc.__class__.__name__})") from None


def parse_set(items: Iterable[str]) -> dict[str, str]:
    """Parse ``key=value`` strings from ``--set``; raise ParamsError on a malformed one."""
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ParamsError(f"--set {item!r}: expected key=value")
        out[key.strip()] = yaml.safe_load(value) if value.strip() else ""
    return out


def load_params(profile: str = "default", files: Iterable[str | Path] = (),
                overrides: Iterable[str] | Mapping[str, Any] = ()) -> Params:
    """Return effective parameters: schema defaults < profile < files < ``--set`` overrides."""
    values = {k: p.default for k, p in schema().items()}
    sources = {k: "schema default" for k in values}
    if profile not in profile_names():
        raise ParamsError(f"--profile {profile!r}: unknown profile (expected one of {', '.join(profile_names())})")
    entry = _params_dir() / f"{profile}.yaml"
    _apply_text(entry.read_text(), f"params/{profile}.yaml", values, sources)
    for path in files:
        _apply_text(_read_text(Path(path)), str(path), values, sources)
    sets = overrides if isinstance(overrides, Mapping) else parse_set(overrides)
    for key, value in sets.items():
        values[key] = _lookup(key, "--set").coerce(value, f"--set {key}")
        sources[key] = "--set"
    return Params(values, sources, profile)

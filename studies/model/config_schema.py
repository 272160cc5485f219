"""The schema of the assembly file: per key its unit, what it allows and its default, in one place.

Each section's keys are declared once, as field metadata on the section's dataclass
(studies/model/config.py: `material: str = material()`, `bore_diameter_mm: float =
number("mm", sign=ZERO_OK, default=0.0)`); the two tables whose dataclasses are not the config's
own, `[assembly]` (fields of `Assembly`) and `[bearing]` (`analytic.bearing.geometry.BearingSpec`,
which knows nothing of files), are declared here as tables of the same `Key`s. From a `Key` come
the parsing of one value (`parse_value`, the one-line messages of `ConfigError`), the summary the
template states for the key (`Key.summary`, tested against studies/configs/template.toml) and the
rows of the key tables in docs/cli.md (`markdown_table`, tested against the file;
`python -m studies.model.config_docs docs/cli.md` rewrites them).

Relations between keys (a bore smaller than its seat, a preload below C0, T_min_C below T_max_C)
are checked with the assembly as a whole (studies/model/config_checks.py); a key's `note` says
which, and bounds declared without a message (`Range.error` empty: the operating range, the mesh
target whose range studies/model/mesh_size.py measured) are checked there too.

Why not pydantic: the sections are frozen dataclasses the whole model reads (and `[bearing]` is
`analytic`'s `BearingSpec`), the messages are one line in a fixed wording that the tests and users
rely on (pydantic's are multi-line and would have to be rewritten anyway), and the rules are a few
kinds of value: this module carries them without a dependency.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

#: mesh.target_error: the targets the mesh-size rule was measured over (studies/model/mesh_size.py)
MESH_TARGET_RANGE = (3e-4, 1e-2)


class ConfigError(ValueError):
    """Bad assembly configuration: the message is one line naming the file, the key and the problem."""


#: the optional layers between outer rings and housing, from the inside out (tables [sleeve],
#: [cartridge] and keys `[fits] <layer>_interference_um`)
LAYERS = ("sleeve", "cartridge")
#: the toleranced surfaces of the fits (keys `[fits] <surface>_class`, `<surface>_deviation_um`):
#: the inner and outer fits' four, then per layer the outside of the layer (`<layer>_shaft`, the
#: member inside the fit) and the bore it sits in (`<layer>_bore`: the next layer's or the housing's)
TOLERANCE_SURFACES = ("inner_shaft", "inner_ring_bore", "outer_housing", "outer_ring_od",
                      *(f"{n}_{m}" for n in LAYERS for m in ("shaft", "bore")))


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: the default of a key the file must give
REQUIRED = _Required()

#: number keys: > 0 (default), >= 0, or either sign
POSITIVE, ZERO_OK, SIGNED = "positive", "zero_ok", "signed"


@dataclass(frozen=True)
class Range:
    """Bounds of a number beyond its sign. `error` is the message when the value alone is
    checked (formatted with `v`, the value); without one the bounds are checked with the
    assembly, where they meet another key (config_checks.py)."""
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False            # lo itself is refused
    hi_open: bool = False
    error: str = ""

    def holds(self, v: float) -> bool:
        above = self.lo is None or (v > self.lo if self.lo_open else v >= self.lo)
        below = self.hi is None or (v < self.hi if self.hi_open else v <= self.hi)
        return above and below

    def text(self) -> str:
        if self.lo is not None and self.hi is not None and not (self.lo_open or self.hi_open):
            return f"{self.lo:g}..{self.hi:g}"
        parts = []
        if self.lo is not None:
            parts.append(f"{'>' if self.lo_open else '>='} {self.lo:g}")
        if self.hi is not None:
            parts.append(f"{'<' if self.hi_open else '<='} {self.hi:g}")
        return " and ".join(parts)


@dataclass(frozen=True)
class Key:
    """One key of a config table.

    kind: "number" (float), "integer", "text", "choice" (one of `choices`), "material" (a
    material by name, resolved with the assembly), "limits" ([lower, upper] in um, or []),
    "choice_or_number" (one of `choices` or a number with `sign`) or "table" (a table of names
    to numbers >= 0 in `unit`, held as sorted (name, value) pairs).
    `default` is REQUIRED for a key the file must give; `default_text` says what a default means when the
    value alone does not (inf = no limit). `note`: a rule with other keys, checked with the
    assembly (config_checks.py)."""
    kind: str
    unit: str = "-"
    doc: str = ""
    default: Any = REQUIRED
    default_text: str = ""
    choices: tuple[str, ...] = ()
    sign: str = POSITIVE
    bounds: Range | None = None
    minimum: int = 0                 # integers
    infinite_ok: bool = False
    note: str = ""

    def __post_init__(self):
        assert self.kind in ("number", "integer", "text", "choice", "material", "limits",
                             "choice_or_number", "table"), self.kind
        assert (self.kind in ("choice", "choice_or_number")) == bool(self.choices)

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def summary(self) -> str:
        """Unit, allowed values and default in a few words: what the template's comment on the
        key starts with (e.g. `mm, >= 0, default 0`)."""
        parts = [self._unit_text(), self.allowed()]
        if not self.required:
            parts.append(f"default {self.default_text or _value_text(self.default)}")
        return ", ".join(p for p in parts if p)

    def _unit_text(self) -> str:
        return self.unit if self.kind in ("number", "limits", "choice_or_number", "table") else ""

    def allowed(self) -> str:
        """What the key accepts, in words (`> 0`, `"DB" or "DF"`, `integer >= 3`)."""
        if self.kind == "choice":
            q = [f'"{c}"' for c in self.choices]
            return ", ".join(q[:-1]) + " or " + q[-1]
        if self.kind == "choice_or_number":
            q = [f'"{c}"' for c in self.choices]
            return " or ".join([*q, "a number " + {POSITIVE: "> 0", ZERO_OK: ">= 0",
                                                   SIGNED: ""}[self.sign]]).strip()
        if self.kind == "table":
            return "table of name = number >= 0"
        if self.kind != "number":
            return {"integer": f"integer >= {self.minimum}", "material": "material by name",
                    "limits": "[lower, upper] or []", "text": "text"}[self.kind]
        sign = {POSITIVE: "> 0", ZERO_OK: ">= 0", SIGNED: ""}[self.sign]
        if self.bounds is None:
            return sign
        if self.bounds.lo is not None:
            return self.bounds.text()      # the bound says the sign
        return ", ".join(p for p in (sign, self.bounds.text()) if p)


def _value_text(v) -> str:
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, tuple):
        return "[]"
    return f"{v:g}"


# --------------------------------------------------------------- declaring keys on dataclasses
def _field(key: Key):
    """A dataclass field carrying `key` as its metadata, its default the key's."""
    if key.required:
        return dataclasses.field(metadata={"key": key})
    return dataclasses.field(default=key.default, metadata={"key": key})


def number(unit: str, doc: str = "", **kw):
    return _field(Key("number", unit, doc, **kw))


def text(doc: str = "", **kw):
    return _field(Key("text", "-", doc, **kw))


def choice(*choices: str, doc: str = "", **kw):
    return _field(Key("choice", "-", doc, choices=choices, **kw))


MATERIAL_DOC = "a library material (analytic/materials.py) or one of the file's [materials.NAME]"


def material(doc: str = MATERIAL_DOC, **kw):
    return _field(Key("material", "-", doc, **kw))


def choice_or_number(*choices: str, unit: str, doc: str = "", **kw):
    return _field(Key("choice_or_number", unit, doc, choices=choices, **kw))


def table(unit: str, doc: str = "", **kw):
    return _field(Key("table", unit, doc, **kw))


def limits(doc: str = "", **kw):
    return _field(Key("limits", "um", doc, default=(), **kw))


# ----------------------------------------------------------- the tables that are not dataclasses
#: the temperature range of the material data (C): T_ref_C and the operating range lie inside it
MATERIAL_T_RANGE_C = (-150.0, 300.0)

#: [assembly]: fields of `Assembly` (studies/model/config.py)
ASSEMBLY_KEYS: dict[str, Key] = {
    "name": Key("text", doc="any text; used in reports"),
    "arrangement": Key("choice", choices=("DB", "DF"), doc="back-to-back or face-to-face"),
    "T_ref_C": Key("number", "C", "temperature at which fits and preload are set", sign=SIGNED,
                   bounds=Range(*MATERIAL_T_RANGE_C,
                                error="must be a number in -150..300 C (range of the material "
                                      "data), got {v!r}")),
    "source": Key("text", doc="where the design comes from", default=""),
}

_RATIO = Range(0.5, 0.6, lo_open=True, error="{v:g} is outside 0.5..0.6 (groove radius / ball diameter)")
_mm = "mm"

#: [bearing]: fields of `analytic.bearing.geometry.BearingSpec` (both bearings of the pair)
BEARING_KEYS: dict[str, Key] = {
    "designation": Key("text", doc="any text"),
    "bore_mm": Key("number", _mm),
    "outside_diameter_mm": Key("number", _mm),
    "width_mm": Key("number", _mm, note="at least the ball diameter"),
    "ball_diameter_mm": Key("number", _mm),
    "ball_count": Key("integer", doc="number of balls", minimum=3,
                      note="the balls must not overlap on the pitch circle"),
    "pitch_diameter_mm": Key("number", _mm,
                             note="the balls must fit between bore and outside diameter"),
    # Harris & Kotzalas Vol. 1 ch. 2: 0.515..0.54 in ball bearings; 0.5 is a ball in a
    # conforming groove (no contact ellipse), above 0.6 not a raceway groove
    "inner_groove_ratio": Key("number", "-", "groove radius / ball diameter f_i", bounds=_RATIO),
    "outer_groove_ratio": Key("number", "-", "groove radius / ball diameter f_o", bounds=_RATIO),
    "contact_angle_free_deg": Key("number", "deg", "the free, unloaded contact angle",
                                  bounds=Range(hi=90.0, hi_open=True, error="must be below 90 deg")),
    "inner_ring_outer_diameter_mm": Key("number", _mm, "effective FE section of the inner ring",
                                        note="inner groove bottom <= this < outer_ring_inner_diameter_mm"),
    "outer_ring_inner_diameter_mm": Key("number", _mm, "effective FE section of the outer ring",
                                        note="this <= outer groove bottom (< outside_diameter_mm)"),
    "ring_material": Key("material", doc=f"inner and outer rings: {MATERIAL_DOC}"),
    "ball_material": Key("material", doc=MATERIAL_DOC),
    "inner_land_diameter_mm": Key("number", _mm, "shoulder (land) diameter on the loaded side",
                                  sign=ZERO_OK, default=0.0, default_text="0 = inferred",
                                  note="between the inner groove bottom and the pitch diameter"),
    "outer_land_diameter_mm": Key("number", _mm, "shoulder (land) diameter on the loaded side",
                                  sign=ZERO_OK, default=0.0, default_text="0 = inferred",
                                  note="between the pitch diameter and the outer groove bottom"),
}


def keys_of(cls) -> dict[str, Key]:
    """The keys of a section's dataclass, in field order."""
    from analytic.bearing.geometry import BearingSpec

    if cls is BearingSpec:
        return BEARING_KEYS
    return {f.name: f.metadata["key"] for f in dataclasses.fields(cls)}


# --------------------------------------------------------------------------------- parsing
def parse_value(path: str, where: str, key: Key, v):
    """One value checked against its key: the value as the dataclass holds it (float, int, str,
    (lower, upper) tuple), or ConfigError `path: where: problem` (one line)."""
    try:
        return _PARSERS[key.kind](key, v)
    except _Bad as exc:
        raise ConfigError(f"{path}: {where}: {exc.args[0]}") from None


class _Bad(Exception):
    """A value its key refuses; the argument is the problem."""


def _string(key: Key, v) -> str:
    if not isinstance(v, str):
        raise _Bad(f"must be a string, got {v!r}")
    if key.choices and v not in key.choices:
        raise _Bad(f"'{v}' is not one of {', '.join(key.choices)}")
    return v


def _limits(key: Key, v) -> tuple:
    if v in ((), []):
        return ()
    if (not isinstance(v, list) or len(v) != 2
            or not all(_is_number(x) and math.isfinite(x) for x in v) or v[0] > v[1]):
        raise _Bad(f"must be [lower, upper] in um with lower <= upper, got {v!r}")
    return float(v[0]), float(v[1])


def _integer(key: Key, v) -> int:
    if not isinstance(v, int) or isinstance(v, bool) or v < key.minimum:
        raise _Bad(f"must be an integer >= {key.minimum}, got {v!r}")
    return v


def _choice_or_number(key: Key, v):
    if isinstance(v, str):
        return _string(key, v)
    if not _is_number(v):
        raise _Bad(f"must be {key.allowed()}, got {v!r}")
    return _number(key, v)


def _table(key: Key, v) -> tuple:
    if v == ():
        return ()
    if not isinstance(v, dict):
        raise _Bad(f"must be a table of name = number in {key.unit}, got {v!r}")
    for name, x in v.items():
        if not _is_number(x) or not math.isfinite(x) or x < 0:
            raise _Bad(f"{name}: must be a finite number >= 0 ({key.unit}), got {x!r}")
    return tuple(sorted((str(n), float(x)) for n, x in v.items()))


def _number(key: Key, v) -> float:
    if not _is_number(v) or not math.isfinite(v):
        if key.infinite_ok and v == math.inf:
            return v
        raise _Bad(f"must be a finite number, got {v!r}")
    v = float(v)
    if key.sign != SIGNED and (v < 0 or (v == 0 and key.sign == POSITIVE)):
        raise _Bad(f"must be positive, got {v:g}")
    if key.bounds is not None and key.bounds.error and not key.bounds.holds(v):
        raise _Bad(key.bounds.error.format(v=v))
    return v


_PARSERS = {"text": _string, "choice": _string, "material": _string, "limits": _limits,
            "integer": _integer, "number": _number, "choice_or_number": _choice_or_number,
            "table": _table}


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def parse_table(path: str, name: str, table, keys: dict[str, Key]) -> dict[str, Any]:
    """A section's TOML table checked against its keys: unknown keys first (with a hint when
    only the unit differs), then each key in order, missing or bad. Returns the values by key
    (defaults filled in); ConfigError (one line) on the first problem."""
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [{name}]: must be a table")
    for k in table:
        if k not in keys:
            raise ConfigError(f"{path}: {name}.{k}: unknown key{unit_hint(k, keys)}")
    values = {}
    for k, key in keys.items():
        if k in table:
            v = table[k]
        elif not key.required:
            v = key.default
        else:
            raise ConfigError(f"{path}: {name}.{k}: missing key")
        values[k] = parse_value(path, f"{name}.{k}", key, v)
    return values


def unit_hint(key: str, names) -> str:
    """` (wrong unit name? expected 'x_mm')` when `key` differs from a known name only in its
    last `_` part (the unit), else the nearest known name (`infra.names.did_you_mean`), else ""."""
    from infra.names import did_you_mean

    stem = key.rsplit("_", 1)[0]
    for f in names:
        if f.rsplit("_", 1)[0] == stem:
            return f" (wrong unit name? expected '{f}')"
    return did_you_mean(key, names)


# --------------------------------------------------------------------------- documentation
def markdown_table(keys: dict[str, Key]) -> str:
    """The key table of a section for docs/cli.md: key, unit, allowed, default, meaning."""
    rows = ["| key | unit | allowed | default | meaning |", "| --- | --- | --- | --- | --- |"]
    for k, key in keys.items():
        default = "required" if key.required else (key.default_text or _value_text(key.default))
        meaning = "; ".join(p for p in (key.doc, key.note) if p)
        rows.append(f"| `{k}` | {key.unit} | {key.allowed().replace('|', '/')} | "
                    f"{default.replace('|', '/')} | {meaning} |")
    return "\n".join(rows)

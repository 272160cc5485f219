"""Assembly configuration: a TOML file describing the axisymmetric shaft-bearing-housing stack.

Every key names its unit. Axial positions are derived from the stack, starting at the shaft
shoulder face (z = 0) and running +z: inner ring A, inner spacer, inner ring B, nut; the housing
shoulder face is also at z = 0 and the outer stack is outer ring A, outer spacer, outer ring B,
cover. Bearing A is the one at the lower z. See `studies/configs/*.toml` for annotated examples
and `studies/configs/template.toml` for every key.

Each section is a frozen dataclass (studies/model/assembly.py) whose fields declare their key: unit, allowed values, default
(studies/model/config_schema.py: one place per section, from which the parsing, the template's
statements and the docs' key tables follow). Relations between keys are checked with the whole
assembly (studies/model/config_checks.py).

Errors are `ConfigError` with one line: file, key, problem.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path

from analytic.bearing.geometry import BearingGeometry, BearingSpec
from analytic.lubrication import Lubricant, get_lubricant, lubricant_from_table
from analytic.materials import Material, get_material, material_from_table
from infra.names import did_you_mean
from studies.model.assembly import (Assembly, Clamp, Fits, Housing, Layer, Limits, Lubrication,
                                    Mesh, Operating, Preload, Shaft, Spacer, Thermal)
from studies.model.config_checks import (check_assembly, check_bearing, check_friction,
                                         check_friction_keys_used)
from studies.model.provenance import with_origin
from studies.model.config_schema import (ASSEMBLY_KEYS, LAYERS, TOLERANCE_SURFACES, ConfigError,
                                         keys_of, parse_table, unit_hint)

__all__ = ["Assembly", "BearingSpec", "CONFIG_DIR", "Clamp", "ConfigError", "Fits", "Housing",
           "LAYERS", "Layer", "Limits", "Lubrication", "Mesh", "OPTIONAL_SECTIONS", "Operating",
           "Preload", "SECTIONS", "SHIPPED", "Shaft", "SingleBearingConfig", "Spacer", "Thermal",
           "TOLERANCE_SURFACES", "assembly_from_dict", "check_bearing", "load_assembly",
           "load_bearing", "load_shipped", "parse_lubricants", "parse_materials"]


#: the tables of the assembly file and their dataclasses, in file order ([assembly] apart)
SECTIONS = {"shaft": Shaft, "housing": Housing, "nut": Clamp, "cover": Clamp,
            "inner_spacer": Spacer, "outer_spacer": Spacer, "bearing": BearingSpec,
            "sleeve": Layer, "cartridge": Layer, "fits": Fits, "preload": Preload,
            "lubrication": Lubrication, "limits": Limits, "mesh": Mesh, "operating": Operating,
            "thermal": Thermal}
#: sections that may be left out (their defaults); the LAYERS are optional parts
OPTIONAL_SECTIONS = {"limits", "mesh", "operating", "thermal"}


def _section(path: str, raw: dict, name: str):
    """One section of the file as its dataclass (config_schema.parse_table)."""
    cls = SECTIONS[name]
    if name not in raw:
        if name in OPTIONAL_SECTIONS:
            return cls()
        raise ConfigError(f"{path}: [{name}]: missing section")
    return cls(**parse_table(path, name, raw[name], keys_of(cls)))

def _read_toml(path: str) -> dict:
    """The parsed TOML file (UTF-8, with or without a byte order mark); ConfigError (one line
    naming the file) when it cannot be read."""
    return _parse_toml(path, _read_bytes(path))


def _read_bytes(path: str) -> bytes:
    try:
        with open(path, "rb") as fh:
            return fh.read()
    except FileNotFoundError:
        raise ConfigError(f"{path}: file not found") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read ({exc.strerror})") from None


def _parse_toml(path: str, data: bytes) -> dict:
    try:
        # a UTF-8 byte order mark (Windows editors) is not TOML: read past it
        return tomllib.loads(data.removeprefix(b"\xef\xbb\xbf").decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None


def load_assembly(path: str | Path) -> Assembly:
    """Read and validate an assembly TOML file. Raises ConfigError (one line) on any problem.
    The assembly keeps its file's path, SHA-256 and text (`provenance.Origin`): what a report
    of it lists as its source."""
    path = str(path)
    data = _read_bytes(path)
    return with_origin(assembly_from_dict(_parse_toml(path, data), path), path, data)


@dataclass(frozen=True)
class SingleBearingConfig:
    """A single bearing's file (`bearingfem bearing`): its [bearing] table, the config's own
    materials, and the diametral radial internal clearance when the file gives one (the free
    contact angle of `spec` then follows from it)."""
    spec: BearingSpec
    materials: tuple[Material, ...]
    radial_internal_clearance_um: float | None
    lubrication: Lubrication | None = None   # optional [lubrication]: the friction torque
    lubricants: tuple[Lubricant, ...] = ()   # the file's own [lubricants.NAME] tables

    @property
    def geometry(self) -> BearingGeometry:
        return BearingGeometry.from_spec(self.spec, self.materials)

    def oil(self) -> Lubricant | None:
        """The oil of `[lubrication] lubricant`, None without [lubrication] or for a film."""
        if self.lubrication is None or self.lubrication.kind != "oil":
            return None
        return get_lubricant(self.lubrication.lubricant, self.lubricants)


def load_bearing(path: str | Path) -> SingleBearingConfig:
    """Read and validate a single bearing's TOML file: a [bearing] table with the keys of an
    assembly's [bearing] section (parsed by the same `_section`, checked by `check_bearing`),
    either `contact_angle_free_deg` or `radial_internal_clearance_um` (total diametral play,
    ISO 5753; the free contact angle follows from cos a0 = 1 - P_d / (2 A0),
    `analytic.bearing.single.free_contact_angle_deg`), optional [materials.NAME] tables, and an
    optional [lubrication] section (the assembly's keys; its friction torque) with optional
    [lubricants.NAME] tables. ConfigError (one line naming file and key) on any problem."""
    from analytic.bearing.single import free_contact_angle_deg

    path = str(path)
    raw = lubricant_alias(_read_toml(path), path)
    for name in raw:
        if name not in ("bearing", "materials", "lubrication", "lubricants"):
            raise ConfigError(f"{path}: [{name}]: unknown section (a bearing file has [bearing], "
                              "[lubrication], [materials.NAME] and [lubricants.NAME] tables)")
    table = raw.get("bearing")
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [bearing]: missing section")
    table = dict(table)
    clearance = _clearance_um(path, table)
    materials = parse_materials(raw, path)
    spec = _section(path, {"bearing": table}, "bearing")
    for k, name in (("bearing.ring_material", spec.ring_material),
                    ("bearing.ball_material", spec.ball_material)):
        try:
            get_material(name, materials)
        except KeyError as exc:
            raise ConfigError(f"{path}: {k}: {exc.args[0]}") from None
    if clearance is not None:
        A0 = (spec.inner_groove_ratio + spec.outer_groove_ratio - 1.0) * spec.ball_diameter_mm
        try:      # 0 <= P_d < 2 A0 gives 0 <= alpha0 < 90 deg: the key's bounds
            alpha0 = free_contact_angle_deg(A0, 1e-3 * float(clearance))
        except ValueError as exc:
            raise ConfigError(f"{path}: bearing.{_CLEARANCE}: {exc.args[0]}") from None
        spec = replace(spec, contact_angle_free_deg=alpha0)
    check_bearing(spec, materials, path)
    lubrication = _section(path, raw, "lubrication") if "lubrication" in raw else None
    if lubrication is not None:
        check_friction(lubrication, path)
        check_friction_keys_used(lubrication, path)
    cfg = SingleBearingConfig(spec, materials, None if clearance is None else float(clearance),
                              lubrication, parse_lubricants(raw, path))
    if lubrication is not None and lubrication.kind == "oil":   # an oil needs a Walther law
        try:
            cfg.oil().walther()
        except (KeyError, ValueError) as exc:
            raise ConfigError(f"{path}: lubrication.lubricant: {exc.args[0]}") from None
    return cfg


_CLEARANCE = "radial_internal_clearance_um"


def _clearance_um(path: str, table: dict) -> float | None:
    """A bearing file's radial internal clearance (um, >= 0), taken out of `table`, or None;
    with it `table` gets a placeholder free contact angle (the clearance sets it)."""
    clearance = table.pop(_CLEARANCE, None)
    if clearance is None:
        if "contact_angle_free_deg" not in table:
            raise ConfigError(f"{path}: bearing.contact_angle_free_deg: missing key (or give "
                              f"bearing.{_CLEARANCE})")
        return None
    if "contact_angle_free_deg" in table:
        raise ConfigError(f"{path}: bearing.{_CLEARANCE}: conflicts with "
                          "bearing.contact_angle_free_deg (the clearance sets the free contact "
                          "angle; give one of them)")
    if (isinstance(clearance, bool) or not isinstance(clearance, (int, float))
            or not math.isfinite(clearance) or clearance < 0):
        raise ConfigError(f"{path}: bearing.{_CLEARANCE}: must be a number >= 0, got {clearance!r}")
    table["contact_angle_free_deg"] = 45.0        # placeholder, replaced by the caller
    return clearance


def assembly_from_dict(raw: dict, path: str = "<config>") -> Assembly:
    """An assembly from a parsed TOML file: each section against its keys, then the relations
    between keys (config_checks.check_assembly). ConfigError (one line) on the first problem."""
    raw = lubricant_alias(raw, path)
    top = _header(path, raw.get("assembly"))
    for name in raw:
        if name not in ("assembly", "materials", "lubricants") and name not in SECTIONS:
            raise ConfigError(f"{path}: [{name}]: unknown section"
                              + did_you_mean(name, ["assembly", "materials", "lubricants", *SECTIONS]))
    parts = {name: _section(path, raw, name) for name in SECTIONS
             if name not in LAYERS or name in raw}
    asm = Assembly(**top, materials=parse_materials(raw, path),
                   lubricants=parse_lubricants(raw, path), **parts)
    check_assembly(asm, path)
    check_friction_keys_used(asm.lubrication, path)
    return asm


def lubricant_alias(raw: dict, path: str) -> dict:
    """`[lubricant] name = "X"` (the CLI contract's spelling) is `[lubrication] lubricant = "X"`:
    the file with the one moved into the other. ConfigError (one line) for any other key in
    [lubricant], or the oil given both ways."""
    alias = raw.get("lubricant")
    if alias is None:
        return raw
    if not isinstance(alias, dict) or set(alias) != {"name"}:
        extra = sorted(set(alias) - {"name"}) if isinstance(alias, dict) else []
        raise ConfigError(f"{path}: [lubricant]{' ' + extra[0] if extra else ''}: only `name` (the "
                          "oil, same as [lubrication] lubricant); the other keys belong in "
                          "[lubrication]")
    lub = raw.get("lubrication", {})
    if isinstance(lub, dict) and "lubricant" in lub:
        raise ConfigError(f"{path}: [lubricant] name: the oil is also given as [lubrication] "
                          "lubricant; give it once")
    out = {k: v for k, v in raw.items() if k != "lubricant"}
    out["lubrication"] = {**(lub if isinstance(lub, dict) else {}), "lubricant": alias["name"]}
    return out


def _header(path: str, top) -> dict:
    """The [assembly] table: name, arrangement, T_ref_C, source (ASSEMBLY_KEYS)."""
    if not isinstance(top, dict):
        raise ConfigError(f"{path}: [assembly]: missing section")
    for key in top:          # unknown first: a typo explains the missing key it leaves
        if key not in ASSEMBLY_KEYS:
            raise ConfigError(f"{path}: assembly.{key}: unknown key{unit_hint(key, list(ASSEMBLY_KEYS))}")
    for key, spec in ASSEMBLY_KEYS.items():
        if spec.required and key not in top:
            raise ConfigError(f"{path}: assembly.{key}: missing key")
    arrangements = ASSEMBLY_KEYS["arrangement"].choices
    if top["arrangement"] not in arrangements:
        raise ConfigError(f"{path}: assembly.arrangement: '{top['arrangement']}' is not "
                          f"{' or '.join(arrangements)}")
    T_ref, T_key = top["T_ref_C"], ASSEMBLY_KEYS["T_ref_C"]
    if isinstance(T_ref, bool) or not isinstance(T_ref, (int, float)) or not T_key.bounds.holds(T_ref):
        raise ConfigError(f"{path}: assembly.T_ref_C: {T_key.bounds.error.format(v=T_ref)}")
    return {"name": str(top["name"]), "arrangement": top["arrangement"], "T_ref_C": float(T_ref),
            "source": str(top.get("source", ""))}


def _named_tables(raw: dict, path: str, section: str, what: str, build) -> tuple:
    """A config's `[SECTION.NAME]` tables, each built by `build(name, table)`, in file order;
    ConfigError (one line naming the file and key) on a bad table."""
    tables = raw.get(section, {})
    if not isinstance(tables, dict) or not all(isinstance(t, dict) for t in tables.values()):
        raise ConfigError(f"{path}: [{section}]: give one table per {what}, [{section}.NAME]")
    try:
        return tuple(build(name, t) for name, t in tables.items())
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc.args[0]}") from None


def parse_materials(raw: dict, path: str) -> tuple[Material, ...]:
    """A config's `[materials.NAME]` tables (analytic.materials.material_from_table)."""
    return _named_tables(raw, path, "materials", "material", material_from_table)


def parse_lubricants(raw: dict, path: str) -> tuple[Lubricant, ...]:
    """A config's `[lubricants.NAME]` tables (analytic.lubrication.lubricant_from_table)."""
    return _named_tables(raw, path, "lubricants", "oil", lubricant_from_table)


CONFIG_DIR = Path(__file__).parents[1] / "configs"
SHIPPED = {"seed000": "seed000_71807C_TC4.toml", "seed001": "seed001_flywheel_hybrid.toml",
           "seed003": "seed003_25TAC62B.toml"}


def load_shipped(name: str) -> Assembly:
    """One of the shipped configurations by short name (seed000, seed001, seed003)."""
    return load_assembly(CONFIG_DIR / SHIPPED[name])

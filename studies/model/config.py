"""Assembly configuration: a TOML file describing the axisymmetric shaft-bearing-housing stack.

Every key names its unit. Axial positions are derived from the stack, starting at the shaft
shoulder face (z = 0) and running +z: inner ring A, inner spacer, inner ring B, nut; the housing
shoulder face is also at z = 0 and the outer stack is outer ring A, outer spacer, outer ring B,
cover. Bearing A is the one at the lower z. See `studies/configs/*.toml` for annotated examples.

Errors are `ConfigError` with one line: file, key, problem.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from analytic.bearing.geometry import BearingGeometry, BearingSpec
from analytic.bearing.land import groove_bottom_diameter_mm
from analytic.materials import Material, get_material, material_from_table
from analytic.safety import static_load_rating_C0_N


class ConfigError(ValueError):
    """Bad assembly configuration: the message is one line naming the file, the key and the problem."""


@dataclass(frozen=True)
class Shaft:
    material: str
    seat_diameter_mm: float
    bore_diameter_mm: float          # 0 for a solid shaft
    shoulder_diameter_mm: float
    shoulder_width_mm: float
    extension_mm: float              # free shaft length beyond the nut


@dataclass(frozen=True)
class Housing:
    material: str
    bore_diameter_mm: float
    outer_diameter_mm: float
    shoulder_diameter_mm: float      # inner diameter of the housing shoulder (< bore)
    shoulder_width_mm: float


@dataclass(frozen=True)
class Clamp:
    """Nut (on the shaft) or cover (on the housing): a ring clamping the stack end."""
    material: str
    diameter_mm: float               # nut: outer diameter; cover: inner diameter
    width_mm: float
    clamp: str = "rigid"             # "rigid": the clamped face is tied axially (the clamp sets
    #                                  the stack length); "compliant": the face is not tied (a
    #                                  soft clamp: the stack keeps its own length)


@dataclass(frozen=True)
class Spacer:
    material: str
    diameter_mm: float               # inner spacer: outer diameter; outer spacer: inner diameter
    length_mm: float


@dataclass(frozen=True)
class Layer:
    """A sleeve or a cartridge (optional `[sleeve]`, `[cartridge]`): a plain cylinder between the
    outer rings and the housing (the sleeve inside, the cartridge outside when both are given),
    as long as the outer-ring stack, resting on the housing shoulder and clamped by the cover,
    at the housing temperature. Its fit on the outside: `[fits] sleeve_interference_um` /
    `cartridge_interference_um`; the outer rings' fit (`outer_interference_um`) is then in the
    sleeve (or cartridge)."""
    material: str
    radial_thickness_mm: float
    length_mm: float


#: the optional layers between outer rings and housing, from the inside out
LAYERS = ("sleeve", "cartridge")


@dataclass(frozen=True)
class Fits:
    inner_interference_um: float     # diametral, + interference, - clearance
    outer_interference_um: float
    contact: str                     # "frictionless" or "bonded"
    sleeve_interference_um: float = 0.0      # sleeve in the next layer out (or the housing)
    cartridge_interference_um: float = 0.0   # cartridge in the housing
    # tolerances (docs/cli.md "tolerance"): an ISO class or explicit (lower, upper) limit
    # deviations in um per surface; "" / () = none. Deviations add to the nominal interference.
    inner_shaft_class: str = ""                  # ISO 286 shaft class, e.g. "k5"
    inner_ring_bore_class: str = ""              # ISO 492 class: Normal, P6, P5, P4, P2
    outer_housing_class: str = ""                # ISO 286 hole class, e.g. "J6"
    outer_ring_od_class: str = ""                # ISO 492 class
    inner_shaft_deviation_um: tuple = ()
    inner_ring_bore_deviation_um: tuple = ()
    outer_housing_deviation_um: tuple = ()
    outer_ring_od_deviation_um: tuple = ()
    distribution: str = "uniform"                # "uniform" within limits or "normal" (+-3 sigma)


@dataclass(frozen=True)
class Preload:
    kind: str                        # "position" or "spring"
    assembled_N: float
    path_compliance: str = "fe"      # "fe": axial compliance of spacers/nut/housing from the FE
    #                                  enters the pair equilibrium; "rigid": none


@dataclass(frozen=True)
class Lubrication:
    kind: str                        # "solid_film" or "oil"
    lubricant: str = ""
    friction_coefficient: float = 0.0
    viscous_factor_f0: float = 0.0
    speed_rpm: float = 0.0
    hysteresis_loss_factor: float = 0.0   # solid film: elastic hysteresis loss factor alpha_h
    load_term: str = "coulomb"            # oil: "coulomb" (mu F dm/2) or "palmgren" (f1 F dm)


@dataclass(frozen=True)
class Limits:
    max_contact_pressure_MPa: float = math.inf
    min_static_safety: float = 0.0


@dataclass(frozen=True)
class Operating:
    """The temperature range the assembly must work over (the default conditions of `report`)."""
    T_min_C: float = -40.0
    T_max_C: float = 80.0
    speed_max_rpm: float = 0.0       # highest shaft speed (report's "Speed"); 0 = [lubrication] speed_rpm
    ball_model: str = "static"       # "static": quasi-static balls; "quasi_dynamic": each ball in
    #                                  its own equilibrium at the row's speed (centrifugal force,
    #                                  gyroscopic moment; analytic/bearing/dynamic.py)
    raceway_control: str = "outer"   # quasi-dynamic: "outer", "inner" or "jones" (per ball)

    def max_speed_rpm(self, lubrication_speed_rpm: float) -> float:
        """The highest speed the assembly runs at (rpm): speed_max_rpm, else the given speed."""
        return self.speed_max_rpm if self.speed_max_rpm > 0 else float(lubrication_speed_rpm)


@dataclass(frozen=True)
class Mesh:
    """Element sizes in mm; 0 = chosen for `target_error` by studies/model/mesh_size.py (given
    sizes win, the others follow the rule)."""
    size_mm: float = 0.0             # bulk element size
    fit_size_mm: float = 0.0         # size along fits and raceways
    corner_size_mm: float = 0.0      # size at the ends of fits and clamped faces
    target_error: float = 1e-3       # relative discretisation error of fit pressures and
    #                                  groove-centre shifts the sizes are chosen for
    ring_section: str = "rectangle"  # "rectangle": the effective ring sections; "grooved": rings
    #                                  with their raceway grooves and lands (studies/model/stack.py)


@dataclass(frozen=True)
class Assembly:
    name: str
    arrangement: str                 # "DB" or "DF"
    T_ref_C: float
    shaft: Shaft
    housing: Housing
    nut: Clamp
    cover: Clamp
    inner_spacer: Spacer
    outer_spacer: Spacer
    bearing: BearingSpec
    fits: Fits
    preload: Preload
    lubrication: Lubrication
    limits: Limits = field(default_factory=Limits)
    mesh: Mesh = field(default_factory=Mesh)
    operating: Operating = field(default_factory=Operating)
    source: str = ""
    sleeve: Layer | None = None
    cartridge: Layer | None = None
    materials: tuple[Material, ...] = ()   # the config's own [materials.NAME] tables

    def layers(self) -> list[tuple[str, Layer]]:
        """The sleeve and cartridge present, from the inside out: (name, layer)."""
        return [(n, getattr(self, n)) for n in LAYERS if getattr(self, n) is not None]

    @property
    def outer_seat_diameter_mm(self) -> float:
        """Diameter of the outer rings' fit (mm): the housing bore, or with a sleeve or a
        cartridge the bearing outside diameter (their bore)."""
        return self.bearing.outside_diameter_mm if self.layers() else self.housing.bore_diameter_mm

    def mean_fits_um(self) -> tuple[float, float]:
        """Diametral interference (inner, outer) in um of the mean assembly: the [fits] values
        plus, where tolerances are given, every deviation at the middle of its band. This is
        the fit `simulate`, `report` and the studies use (studies/model/tolerances.py)."""
        from studies.model.tolerances import mid_band_offsets_um

        mid_i, mid_o = mid_band_offsets_um(self)
        return self.fits.inner_interference_um + mid_i, self.fits.outer_interference_um + mid_o

    def material(self, part: str) -> Material:
        """Material of a part: shaft, housing, nut, cover, inner_spacer, outer_spacer,
        inner_ring, outer_ring, ball."""
        names = {"shaft": self.shaft.material, "housing": self.housing.material,
                 "nut": self.nut.material, "cover": self.cover.material,
                 "inner_spacer": self.inner_spacer.material,
                 "outer_spacer": self.outer_spacer.material,
                 "inner_ring": self.bearing.ring_material,
                 "outer_ring": self.bearing.ring_material,
                 "ball": self.bearing.ball_material,
                 **{n: layer.material for n, layer in self.layers()}}
        return get_material(names[part], self.materials)


#: the toleranced surfaces of the two fits (keys `<surface>_class`, `<surface>_deviation_um`)
TOLERANCE_SURFACES = ("inner_shaft", "inner_ring_bore", "outer_housing", "outer_ring_od")

SECTIONS = {
    "shaft": (Shaft, {"bore_diameter_mm": 0.0, "extension_mm": 0.0}),
    "housing": (Housing, {}),
    "nut": (Clamp, {"clamp": "rigid"}),
    "cover": (Clamp, {"clamp": "rigid"}),
    "inner_spacer": (Spacer, {}),
    "outer_spacer": (Spacer, {}),
    "bearing": (BearingSpec, {"inner_land_diameter_mm": 0.0, "outer_land_diameter_mm": 0.0}),
    "sleeve": (Layer, {}),
    "cartridge": (Layer, {}),
    "fits": (Fits, {"contact": "frictionless", "distribution": "uniform",
                    "sleeve_interference_um": 0.0, "cartridge_interference_um": 0.0,
                    **{f"{k}_class": "" for k in TOLERANCE_SURFACES},
                    **{f"{k}_deviation_um": () for k in TOLERANCE_SURFACES}}),
    "preload": (Preload, {"path_compliance": "fe"}),
    "lubrication": (Lubrication, {"lubricant": "", "friction_coefficient": 0.0,
                                  "viscous_factor_f0": 0.0, "speed_rpm": 0.0,
                                  "hysteresis_loss_factor": 0.0, "load_term": "coulomb"}),
    "limits": (Limits, {"max_contact_pressure_MPa": math.inf, "min_static_safety": 0.0}),
    "mesh": (Mesh, {"size_mm": 0.0, "fit_size_mm": 0.0, "corner_size_mm": 0.0,
                    "target_error": 1e-3, "ring_section": "rectangle"}),
    "operating": (Operating, {"T_min_C": -40.0, "T_max_C": 80.0, "speed_max_rpm": 0.0,
                              "ball_model": "static", "raceway_control": "outer"}),
}
OPTIONAL_SECTIONS = {"limits", "mesh", "operating"}
STRING_KEYS = {"material", "designation", "ring_material", "ball_material", "contact", "kind",
               "lubricant", "load_term", "clamp", "path_compliance", "distribution", "ring_section",
               "ball_model", "raceway_control",
               *(f"{k}_class" for k in TOLERANCE_SURFACES)}
LIMIT_KEYS = {f"{k}_deviation_um" for k in TOLERANCE_SURFACES}
CHOICES = {("fits", "contact"): ("frictionless", "bonded"),
           ("fits", "distribution"): ("uniform", "normal"),
           ("preload", "kind"): ("position", "spring"),
           ("preload", "path_compliance"): ("fe", "rigid"),
           ("lubrication", "kind"): ("solid_film", "oil"),
           ("lubrication", "load_term"): ("coulomb", "palmgren"),
           ("nut", "clamp"): ("rigid", "compliant"), ("cover", "clamp"): ("rigid", "compliant"),
           ("mesh", "ring_section"): ("grooved", "rectangle"),
           ("operating", "ball_model"): ("static", "quasi_dynamic"),
           ("operating", "raceway_control"): ("outer", "inner", "jones")}
# keys allowed to be zero (everything else numeric must be > 0)
ZERO_OK = {("shaft", "bore_diameter_mm"), ("shaft", "extension_mm"),
           ("fits", "inner_interference_um"), ("fits", "outer_interference_um"),
           ("fits", "sleeve_interference_um"), ("fits", "cartridge_interference_um"),
           ("preload", "assembled_N"), ("lubrication", "friction_coefficient"),
           ("lubrication", "viscous_factor_f0"), ("lubrication", "speed_rpm"),
           ("lubrication", "hysteresis_loss_factor"),
           ("limits", "min_static_safety"), ("bearing", "inner_land_diameter_mm"),
           ("bearing", "outer_land_diameter_mm"), ("mesh", "size_mm"), ("mesh", "fit_size_mm"),
           ("mesh", "corner_size_mm"), ("operating", "speed_max_rpm")}
SIGNED = {("fits", "inner_interference_um"), ("fits", "outer_interference_um"),
          ("fits", "sleeve_interference_um"), ("fits", "cartridge_interference_um"),
          ("operating", "T_min_C"), ("operating", "T_max_C")}


def _section(path: str, raw: dict, name: str):
    cls, defaults = SECTIONS[name]
    table = raw.get(name)
    if table is None:
        if name in OPTIONAL_SECTIONS:
            return cls()
        raise ConfigError(f"{path}: [{name}]: missing section")
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [{name}]: must be a table")
    fields = cls.__dataclass_fields__
    for key in table:
        if key not in fields:
            hint = _unit_hint(key, fields)
            raise ConfigError(f"{path}: {name}.{key}: unknown key{hint}")
    values = {}
    for key, f in fields.items():
        if key in table:
            v = table[key]
        elif key in defaults:
            v = defaults[key]
        else:
            raise ConfigError(f"{path}: {name}.{key}: missing key")
        if key in STRING_KEYS:
            if not isinstance(v, str):
                raise ConfigError(f"{path}: {name}.{key}: must be a string, got {v!r}")
            choices = CHOICES.get((name, key))
            if choices and v not in choices:
                raise ConfigError(f"{path}: {name}.{key}: '{v}' is not one of {', '.join(choices)}")
        elif key in LIMIT_KEYS:
            if v in ((), []):
                v = ()
            else:
                if (not isinstance(v, list) or len(v) != 2
                        or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                   and math.isfinite(x) for x in v) or v[0] > v[1]):
                    raise ConfigError(f"{path}: {name}.{key}: must be [lower, upper] in um with "
                                      f"lower <= upper, got {v!r}")
                v = (float(v[0]), float(v[1]))
        elif key == "ball_count":
            if not isinstance(v, int) or isinstance(v, bool) or v < 3:
                raise ConfigError(f"{path}: {name}.{key}: must be an integer >= 3, got {v!r}")
        else:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                if (name, key) == ("limits", "max_contact_pressure_MPa") and v == math.inf:
                    values[key] = v
                    continue
                raise ConfigError(f"{path}: {name}.{key}: must be a finite number, got {v!r}")
            v = float(v)
            if (name, key) not in SIGNED:
                if v < 0 or (v == 0 and (name, key) not in ZERO_OK):
                    raise ConfigError(f"{path}: {name}.{key}: must be positive, got {v:g}")
        values[key] = v
    return cls(**values)


def _unit_hint(key: str, fields) -> str:
    stem = key.rsplit("_", 1)[0]
    for f in fields:
        if f.rsplit("_", 1)[0] == stem:
            return f" (wrong unit name? expected '{f}')"
    return ""


def _read_toml(path: str) -> dict:
    """The parsed TOML file (UTF-8, with or without a byte order mark); ConfigError (one line
    naming the file) when it cannot be read."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
        # a UTF-8 byte order mark (Windows editors) is not TOML: read past it
        return tomllib.loads(data.removeprefix(b"\xef\xbb\xbf").decode("utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"{path}: file not found") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read ({exc.strerror})") from None


def load_assembly(path: str | Path) -> Assembly:
    """Read and validate an assembly TOML file. Raises ConfigError (one line) on any problem."""
    path = str(path)
    raw = _read_toml(path)
    return assembly_from_dict(raw, path)


@dataclass(frozen=True)
class SingleBearingConfig:
    """A single bearing's file (`bearingfem bearing`): its [bearing] table, the config's own
    materials, and the diametral radial internal clearance when the file gives one (the free
    contact angle of `spec` then follows from it)."""
    spec: BearingSpec
    materials: tuple[Material, ...]
    radial_internal_clearance_um: float | None

    @property
    def geometry(self) -> BearingGeometry:
        return BearingGeometry.from_spec(self.spec, self.materials)


def load_bearing(path: str | Path) -> SingleBearingConfig:
    """Read and validate a single bearing's TOML file: a [bearing] table with the keys of an
    assembly's [bearing] section (parsed by the same `_section`, checked by `check_bearing`),
    either `contact_angle_free_deg` or `radial_internal_clearance_um` (total diametral play,
    ISO 5753; the free contact angle follows from cos a0 = 1 - P_d / (2 A0),
    `analytic.bearing.single.free_contact_angle_deg`), and optional [materials.NAME] tables.
    ConfigError (one line naming file and key) on any problem."""
    from dataclasses import replace

    from analytic.bearing.single import free_contact_angle_deg

    path = str(path)
    raw = _read_toml(path)
    for name in raw:
        if name not in ("bearing", "materials"):
            raise ConfigError(f"{path}: [{name}]: unknown section (a bearing file has [bearing] "
                              "and [materials.NAME] tables)")
    table = raw.get("bearing")
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [bearing]: missing section")
    table = dict(table)
    key = "radial_internal_clearance_um"
    clearance = table.pop(key, None)
    if clearance is not None:
        if "contact_angle_free_deg" in table:
            raise ConfigError(f"{path}: bearing.{key}: conflicts with bearing.contact_angle_free_deg "
                              "(the clearance sets the free contact angle; give one of them)")
        if (isinstance(clearance, bool) or not isinstance(clearance, (int, float))
                or not math.isfinite(clearance) or clearance < 0):
            raise ConfigError(f"{path}: bearing.{key}: must be a number >= 0, got {clearance!r}")
        table["contact_angle_free_deg"] = 45.0        # placeholder, replaced below
    elif "contact_angle_free_deg" not in table:
        raise ConfigError(f"{path}: bearing.contact_angle_free_deg: missing key (or give "
                          f"bearing.{key})")
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
        try:
            alpha0 = free_contact_angle_deg(A0, 1e-3 * float(clearance))
        except ValueError as exc:
            raise ConfigError(f"{path}: bearing.{key}: {exc.args[0]}") from None
        spec = replace(spec, contact_angle_free_deg=alpha0)
    check_bearing(spec, materials, path)
    return SingleBearingConfig(spec, materials, None if clearance is None else float(clearance))


def assembly_from_dict(raw: dict, path: str = "<config>") -> Assembly:
    top = raw.get("assembly")
    if not isinstance(top, dict):
        raise ConfigError(f"{path}: [assembly]: missing section")
    for key in ("name", "arrangement", "T_ref_C"):
        if key not in top:
            raise ConfigError(f"{path}: assembly.{key}: missing key")
    for key in top:
        if key not in ("name", "arrangement", "T_ref_C", "source"):
            raise ConfigError(f"{path}: assembly.{key}: unknown key{_unit_hint(key, ['T_ref_C'])}")
    if top["arrangement"] not in ("DB", "DF"):
        raise ConfigError(f"{path}: assembly.arrangement: '{top['arrangement']}' is not DB or DF")
    T_ref = top["T_ref_C"]
    if isinstance(T_ref, bool) or not isinstance(T_ref, (int, float)) or not -150 <= T_ref <= 300:
        raise ConfigError(f"{path}: assembly.T_ref_C: must be a number in -150..300 C "
                          f"(range of the material data), got {T_ref!r}")
    for name in raw:
        if name not in ("assembly", "materials") and name not in SECTIONS:
            raise ConfigError(f"{path}: [{name}]: unknown section")
    parts = {name: _section(path, raw, name) for name in SECTIONS
             if name not in LAYERS or name in raw}
    asm = Assembly(name=str(top["name"]), arrangement=top["arrangement"], T_ref_C=float(T_ref),
                   source=str(top.get("source", "")), materials=parse_materials(raw, path),
                   **parts)
    _check_materials(asm, path)
    _check_geometry(asm, path)
    _check_tolerances(asm, path)
    if asm.lubrication.kind == "oil":
        from analytic.lubrication import get_lubricant
        try:
            get_lubricant(asm.lubrication.lubricant)
        except (KeyError, ValueError) as exc:
            raise ConfigError(f"{path}: lubrication.lubricant: {exc.args[0]}") from None
    return asm


def parse_materials(raw: dict, path: str) -> tuple[Material, ...]:
    """A config's `[materials.NAME]` tables (analytic.materials.material_from_table), in file
    order; ConfigError (one line naming the file and key) on a bad table."""
    tables = raw.get("materials", {})
    if not isinstance(tables, dict) or not all(isinstance(t, dict) for t in tables.values()):
        raise ConfigError(f"{path}: [materials]: give one table per material, [materials.NAME]")
    try:
        return tuple(material_from_table(name, t) for name, t in tables.items())
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc.args[0]}") from None


def _check_tolerances(a: Assembly, path: str) -> None:
    """A class or explicit limits per surface, not both, and a class the tables carry at the
    surface's nominal diameter (analytic/tolerances.py)."""
    from studies.model.tolerances import deviation_limits_um

    f = a.fits
    for k in TOLERANCE_SURFACES:
        if getattr(f, f"{k}_class") and getattr(f, f"{k}_deviation_um"):
            raise ConfigError(f"{path}: fits.{k}_class: give the class or {k}_deviation_um, not both")
    try:
        deviation_limits_um(a)
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc.args[0]}") from None


def _check_materials(a: Assembly, path: str) -> None:
    keys = {"shaft.material": a.shaft.material, "housing.material": a.housing.material,
            "nut.material": a.nut.material, "cover.material": a.cover.material,
            "inner_spacer.material": a.inner_spacer.material,
            "outer_spacer.material": a.outer_spacer.material,
            "bearing.ring_material": a.bearing.ring_material,
            "bearing.ball_material": a.bearing.ball_material,
            **{f"{n}.material": layer.material for n, layer in a.layers()}}
    for key, name in keys.items():
        try:
            get_material(name, a.materials)
        except KeyError as exc:
            raise ConfigError(f"{path}: {key}: {exc.args[0]}") from None


def check_bearing(b: BearingSpec, materials: tuple[Material, ...], path: str) -> BearingGeometry:
    """The checks of a [bearing] table on its own (an assembly's or a single bearing's file):
    groove ratios, land diameters, ring width, contact angle, pitch diameter and ball count.
    Returns the resolved `BearingGeometry`; ConfigError (one line naming file and key)."""
    def need(cond: bool, key: str, msg: str) -> None:
        if not cond:
            raise ConfigError(f"{path}: {key}: {msg}")

    for key, f in (("bearing.inner_groove_ratio", b.inner_groove_ratio),
                   ("bearing.outer_groove_ratio", b.outer_groove_ratio)):
        # Harris & Kotzalas Vol. 1 ch. 2: 0.515..0.54 in ball bearings; 0.5 is a ball in a
        # conforming groove (no contact ellipse), above 0.6 not a raceway groove
        need(0.5 < f <= 0.6, key, f"{f:g} is outside 0.5..0.6 (groove radius / ball diameter)")
    g = BearingGeometry.from_spec(b, materials)
    for side, d in (("inner", b.inner_land_diameter_mm), ("outer", b.outer_land_diameter_mm)):
        if d > 0:        # given: the groove edge lies between the groove bottom and the pitch circle
            bottom = groove_bottom_diameter_mm(g, side)
            lo, hi = sorted((bottom, b.pitch_diameter_mm))
            need(lo < d < hi, f"bearing.{side}_land_diameter_mm",
                 f"{d:g} mm must lie between the groove bottom ({bottom:.3f} mm) and the pitch "
                 f"diameter ({b.pitch_diameter_mm:g} mm)")
    need(b.width_mm >= b.ball_diameter_mm, "bearing.width_mm",
         f"ring width {b.width_mm:g} mm is narrower than its ball ({b.ball_diameter_mm:g} mm)")
    need(b.contact_angle_free_deg < 90.0, "bearing.contact_angle_free_deg", "must be below 90 deg")
    Dw, dm = b.ball_diameter_mm, b.pitch_diameter_mm
    need(b.bore_mm < dm - Dw and dm + Dw < b.outside_diameter_mm, "bearing.pitch_diameter_mm",
         "balls do not fit between bore and outside diameter")
    need(b.ball_count * Dw < math.pi * dm, "bearing.ball_count", "balls overlap on the pitch circle")
    return g


def _check_geometry(a: Assembly, path: str) -> None:
    """Overlaps, rings that do not touch their seats, and impossible bearing geometry."""
    s, h, b = a.shaft, a.housing, a.bearing

    def need(cond: bool, key: str, msg: str) -> None:
        if not cond:
            raise ConfigError(f"{path}: {key}: {msg}")

    need(s.bore_diameter_mm < s.seat_diameter_mm, "shaft.bore_diameter_mm",
         f"bore {s.bore_diameter_mm:g} mm must be smaller than the seat {s.seat_diameter_mm:g} mm")
    need(s.shoulder_diameter_mm > s.seat_diameter_mm, "shaft.shoulder_diameter_mm",
         "must exceed the seat diameter")
    need(abs(b.bore_mm - s.seat_diameter_mm) <= 0.01 * b.bore_mm, "bearing.bore_mm",
         f"inner ring bore {b.bore_mm:g} mm does not sit on the shaft seat {s.seat_diameter_mm:g} mm")
    t_layers = sum(layer.radial_thickness_mm for _, layer in a.layers())
    if not t_layers:
        need(abs(b.outside_diameter_mm - h.bore_diameter_mm) <= 0.01 * b.outside_diameter_mm,
             "bearing.outside_diameter_mm",
             f"outer ring {b.outside_diameter_mm:g} mm does not sit in the housing bore {h.bore_diameter_mm:g} mm")
    else:
        _check_layers(a, need, t_layers)
    seat = a.outer_seat_diameter_mm             # where the outer rings sit
    need(b.bore_mm < b.inner_ring_outer_diameter_mm < b.outer_ring_inner_diameter_mm
         < b.outside_diameter_mm, "bearing.inner_ring_outer_diameter_mm",
         "ring sections must satisfy bore < inner ring OD < outer ring ID < outside diameter")
    need(s.shoulder_diameter_mm < b.outer_ring_inner_diameter_mm, "shaft.shoulder_diameter_mm",
         "shaft shoulder overlaps the outer ring")
    need(h.shoulder_diameter_mm < seat, "housing.shoulder_diameter_mm",
         "must be smaller than the housing bore" if not t_layers
         else "must be smaller than the bearing outside diameter (it holds outer ring A)")
    need(h.shoulder_diameter_mm > b.inner_ring_outer_diameter_mm, "housing.shoulder_diameter_mm",
         "housing shoulder overlaps the inner ring")
    need(h.outer_diameter_mm > h.bore_diameter_mm, "housing.outer_diameter_mm",
         "must exceed the housing bore")
    need(b.inner_ring_outer_diameter_mm >= a.inner_spacer.diameter_mm > s.seat_diameter_mm,
         "inner_spacer.diameter_mm", "must lie between the shaft seat and the inner ring OD")
    need(b.outer_ring_inner_diameter_mm <= a.outer_spacer.diameter_mm < seat,
         "outer_spacer.diameter_mm", "must lie between the outer ring ID and the housing bore"
         if not t_layers else "must lie between the outer ring ID and the bearing OD")
    need(s.seat_diameter_mm < a.nut.diameter_mm < b.outer_ring_inner_diameter_mm,
         "nut.diameter_mm", "must lie between the shaft seat and the outer ring ID")
    need(b.inner_ring_outer_diameter_mm < a.cover.diameter_mm < seat,
         "cover.diameter_mm", "must lie between the inner ring OD and the housing bore"
         if not t_layers else "must lie between the inner ring OD and the bearing OD")
    g = check_bearing(b, a.materials, path)
    # a typo in one dimension (a housing 1e9 mm wide) would mesh until memory runs out: every
    # length of the stack stays within 20 bearing outside diameters
    big = 20.0 * b.outside_diameter_mm
    for key, val in (("shaft.shoulder_width_mm", s.shoulder_width_mm),
                     ("shaft.extension_mm", s.extension_mm),
                     ("housing.outer_diameter_mm", h.outer_diameter_mm),
                     ("housing.shoulder_width_mm", h.shoulder_width_mm),
                     ("nut.width_mm", a.nut.width_mm), ("cover.width_mm", a.cover.width_mm),
                     ("inner_spacer.length_mm", a.inner_spacer.length_mm),
                     ("outer_spacer.length_mm", a.outer_spacer.length_mm)):
        need(val <= big, key, f"{val:g} mm is more than 20 bearing outside diameters "
                              f"({big:g} mm): a typo?")
    Dw, dm = b.ball_diameter_mm, b.pitch_diameter_mm
    for key, val, d in (("fits.inner_interference_um", a.fits.inner_interference_um, s.seat_diameter_mm),
                        ("fits.outer_interference_um", a.fits.outer_interference_um, h.bore_diameter_mm)):
        # 2 per mille of the diameter is far beyond any bearing fit (ISO 286 n6/P7 at 35 mm:
        # about 40 um) and would yield a hardened ring
        need(abs(val) <= 2.0 * d, key, f"{val:g} um is beyond 2 per mille of the {d:g} mm diameter")
    d = b.outside_diameter_mm
    for name, layer in a.layers():
        d += 2 * layer.radial_thickness_mm
        val = getattr(a.fits, f"{name}_interference_um")
        need(abs(val) <= 2.0 * d, f"fits.{name}_interference_um",
             f"{val:g} um is beyond 2 per mille of the {d:g} mm diameter")
    for name in LAYERS:
        need(getattr(a, name) is not None or getattr(a.fits, f"{name}_interference_um") == 0,
             f"fits.{name}_interference_um", f"given, but the assembly has no [{name}]")
    need(a.lubrication.friction_coefficient <= 1.0, "lubrication.friction_coefficient",
         "must not exceed 1")
    C0 = static_load_rating_C0_N(b.ball_count, Dw, dm, b.contact_angle_free_deg)
    need(a.preload.assembled_N <= C0, "preload.assembled_N",
         f"{a.preload.assembled_N:g} N exceeds the bearing's static load rating C0 = {C0:.0f} N "
         "(ISO 76): the raceways would be dented at assembly")
    op = a.operating
    need(-150.0 <= op.T_min_C < op.T_max_C <= 300.0, "operating.T_min_C",
         f"the range {op.T_min_C:g}..{op.T_max_C:g} C must be increasing and inside -150..300 C")
    _check_mesh(a, need)
    if a.mesh.ring_section == "grooved":
        _check_grooved(a, g, need)


def _check_layers(a: Assembly, need, t_layers: float) -> None:
    """Sleeve / cartridge: the housing bore takes them, each as long as the outer-ring stack
    (it rests on the housing shoulder and the cover clamps it with outer ring B)."""
    b, h = a.bearing, a.housing
    want = b.outside_diameter_mm + 2 * t_layers
    names = " + ".join(n for n, _ in a.layers())
    need(abs(h.bore_diameter_mm - want) <= 1e-6 * want, "housing.bore_diameter_mm",
         f"{h.bore_diameter_mm:g} mm must be the bearing OD + 2 x ({names} radial thickness) = "
         f"{want:g} mm")
    stack = 2 * b.width_mm + a.outer_spacer.length_mm
    for name, layer in a.layers():
        need(abs(layer.length_mm - stack) <= 1e-6 * stack, f"{name}.length_mm",
             f"{layer.length_mm:g} mm must equal the outer-ring stack (2 x bearing width + outer "
             f"spacer = {stack:g} mm): it rests on the housing shoulder and the cover clamps it")


def _check_grooved(a: Assembly, g: BearingGeometry, need) -> None:
    """Grooved ring sections (`[mesh] ring_section = "grooved"`): each groove leaves a ring wall
    under its bottom and ends inside the ring width, and the lands clear the neighbouring parts
    (the land is the ring's radial extent on the ball side)."""
    from analytic.bearing.land import groove_centre_radius_mm, land_angle_deg, land_diameters_mm

    b, s, h = a.bearing, a.shaft, a.housing
    d_i, d_o, _ = land_diameters_mm(b, a.materials)
    for side, wall, name in (("inner", groove_bottom_diameter_mm(g, "inner") - b.bore_mm, "inner"),
                             ("outer", b.outside_diameter_mm - groove_bottom_diameter_mm(g, "outer"),
                              "outer")):
        need(wall > 0, f"bearing.{name}_ring_outer_diameter_mm" if side == "inner"
             else "bearing.outer_ring_inner_diameter_mm",
             f"the {side} groove bottom leaves no ring wall ({wall / 2:.3f} mm) for "
             "mesh.ring_section = \"grooved\"")
        f = g.f_i if side == "inner" else g.f_o
        d_land = d_i if side == "inner" else d_o
        half = f * g.Dw_mm * math.sin(math.radians(land_angle_deg(g, side, d_land)))
        need(half + (f - 0.5) * g.Dw_mm < b.width_mm / 2, f"bearing.{side}_land_diameter_mm",
             f"the {side} groove ({2 * half:.3f} mm wide at the land) does not fit in the ring "
             f"width {b.width_mm:g} mm")
        need(abs(groove_centre_radius_mm(g, side) - d_land / 2) < f * g.Dw_mm,
             f"bearing.{side}_land_diameter_mm", "the land does not meet the groove")
    need(d_i < b.pitch_diameter_mm < d_o, "bearing.inner_land_diameter_mm",
         f"the lands ({d_i:.3f} and {d_o:.3f} mm) must lie either side of the pitch diameter "
         f"({b.pitch_diameter_mm:g} mm)")
    for key, cond, msg in (   # the faces that clamp one ring must not reach the other ring
            ("shaft.shoulder_diameter_mm", s.shoulder_diameter_mm < d_o, "outer ring land"),
            ("nut.diameter_mm", a.nut.diameter_mm < d_o, "outer ring land"),
            ("housing.shoulder_diameter_mm", h.shoulder_diameter_mm > d_i, "inner ring land"),
            ("cover.diameter_mm", a.cover.diameter_mm > d_i, "inner ring land")):
        need(cond, key, f"overlaps the {msg} diameter ({d_i if 'inner' in msg else d_o:.3f} mm) "
                        "of the grooved ring section (or set mesh.ring_section = \"rectangle\")")


def _check_mesh(a: Assembly, need) -> None:
    """Given sizes in order (corner <= fit <= size <= bearing width); a target the size rule was
    measured for (studies/model/mesh_size.py)."""
    from studies.model.mesh_size import TARGET_RANGE

    m, B = a.mesh, a.bearing.width_mm
    lo, hi = TARGET_RANGE
    need(lo <= m.target_error <= hi, "mesh.target_error",
         f"{m.target_error:g} is outside {lo:g}..{hi:g} (the range the size rule was measured "
         "over); give explicit sizes for other meshes")
    need(m.size_mm <= B, "mesh.size_mm",
         f"must not exceed the bearing width ({B:g} mm): the rings would not be resolved")
    need(not (m.fit_size_mm and m.size_mm) or m.fit_size_mm <= m.size_mm, "mesh.fit_size_mm",
         "must not exceed mesh.size_mm")
    for big in ("fit_size_mm", "size_mm"):
        need(not (m.corner_size_mm and getattr(m, big)) or m.corner_size_mm <= getattr(m, big),
             "mesh.corner_size_mm", f"must not exceed mesh.{big}")


CONFIG_DIR = Path(__file__).parents[1] / "configs"
SHIPPED = {"seed000": "seed000_71807C_TC4.toml", "seed001": "seed001_flywheel_hybrid.toml",
           "seed003": "seed003_25TAC62B.toml"}


def load_shipped(name: str) -> Assembly:
    """One of the shipped configurations by short name (seed000, seed001, seed003)."""
    return load_assembly(CONFIG_DIR / SHIPPED[name])

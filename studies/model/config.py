"""Assembly configuration: a TOML file describing the axisymmetric shaft-bearing-housing stack.

Every key names its unit. Axial positions are derived from the stack, starting at the shaft
shoulder face (z = 0) and running +z: inner ring A, inner spacer, inner ring B, nut; the housing
shoulder face is also at z = 0 and the outer stack is outer ring A, outer spacer, outer ring B,
cover. Bearing A is the one at the lower z. See `studies/configs/*.toml` for annotated examples
and `studies/configs/template.toml` for every key.

Each section is a frozen dataclass whose fields declare their key: unit, allowed values, default
(studies/model/config_schema.py: one place per section, from which the parsing, the template's
statements and the docs' key tables follow). Relations between keys are checked with the whole
assembly (studies/model/config_checks.py).

Errors are `ConfigError` with one line: file, key, problem.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from analytic.bearing.geometry import BearingGeometry, BearingSpec
from analytic.lubrication import Lubricant, get_lubricant, lubricant_from_table
from analytic.materials import Material, get_material, material_from_table
from studies.model.config_checks import check_assembly, check_bearing
from studies.model.config_schema import (ASSEMBLY_KEYS, LAYERS, MATERIAL_T_RANGE_C, MESH_TARGET_RANGE,
                                         SIGNED,
                                         TOLERANCE_SURFACES, ZERO_OK, ConfigError, Range, choice,
                                         choice_or_number, keys_of, limits,
                                         material, number, parse_table, table as _field_table,
                                         text, unit_hint)

__all__ = ["Assembly", "BearingSpec", "CONFIG_DIR", "Clamp", "ConfigError", "Fits", "Housing",
           "LAYERS", "Layer", "Limits", "Lubrication", "Mesh", "OPTIONAL_SECTIONS", "Operating",
           "Preload", "SECTIONS", "SHIPPED", "Shaft", "SingleBearingConfig", "Spacer", "Thermal",
           "TOLERANCE_SURFACES", "assembly_from_dict", "check_bearing", "load_assembly",
           "load_bearing", "load_shipped", "parse_lubricants", "parse_materials"]

_MM = "mm"


@dataclass(frozen=True, kw_only=True)
class Shaft:
    material: str = material()
    seat_diameter_mm: float = number(_MM, note="equals bearing.bore_mm (within 1 %)")
    bore_diameter_mm: float = number(_MM, "0 for a solid shaft", sign=ZERO_OK, default=0.0,
                                     note="below the seat")
    shoulder_diameter_mm: float = number(_MM, note="above the seat, below the outer ring's inner "
                                                   "diameter")
    shoulder_width_mm: float = number(_MM)
    extension_mm: float = number(_MM, "free shaft length beyond the nut", sign=ZERO_OK, default=0.0)


@dataclass(frozen=True, kw_only=True)
class Housing:
    material: str = material()
    bore_diameter_mm: float = number(_MM, note="equals bearing.outside_diameter_mm (within 1 %); "
                                               "with a sleeve or cartridge: the bearing OD + 2 x "
                                               "their radial thicknesses")
    outer_diameter_mm: float = number(_MM, note="above the bore")
    shoulder_diameter_mm: float = number(_MM, "inner diameter of the housing shoulder",
                                         note="below the bore, above the inner ring's outer "
                                              "diameter")
    shoulder_width_mm: float = number(_MM)


@dataclass(frozen=True, kw_only=True)
class Clamp:
    """Nut (on the shaft) or cover (on the housing): a ring clamping the stack end."""
    material: str = material()
    diameter_mm: float = number(_MM, "nut: outer diameter; cover: inner diameter",
                                note="nut: between the shaft seat and the outer ring ID; cover: "
                                     "between the inner ring OD and the housing bore")
    width_mm: float = number(_MM)
    clamp: str = choice("rigid", "compliant", "force", default="rigid",
                        doc='"force": a preloaded clamp (nut or bolted cover) tightened to '
                            'clamp_force_N at T_ref, its face a contact that opens when the '
                            'force is used up, a spring of clamp_stiffness_N_per_um in series; '
                            '"rigid" and "compliant" are its two limits: "rigid" ties the face '
                            'axially (infinitely stiff, never opens: it may pull the stack), '
                            '"compliant" leaves it untied (no force, no stiffness)')
    clamp_force_N: float = number("N", "the clamp force at T_ref, at rest (clamp = \"force\")",
                                  sign=ZERO_OK, default=0.0,
                                  note='> 0 with clamp = "force", which needs frictionless fits')
    clamp_stiffness_N_per_um: float = number(
        "N/um", "the clamp's own spring (thread or bolts) in series with the clamped face "
        '(clamp = "force")', sign=ZERO_OK, default=0.0,
        default_text="0 = from the part's section (VDI 2230 engaged thread and nut)")


@dataclass(frozen=True, kw_only=True)
class Spacer:
    material: str = material()
    diameter_mm: float = number(_MM, "inner spacer: outer diameter; outer spacer: inner diameter",
                                note="inner: between the shaft seat and the inner ring OD; outer: "
                                     "between the outer ring ID and the housing bore")
    length_mm: float = number(_MM)


@dataclass(frozen=True, kw_only=True)
class Layer:
    """A sleeve or a cartridge (optional `[sleeve]`, `[cartridge]`): a plain cylinder between the
    outer rings and the housing (the sleeve inside, the cartridge outside when both are given),
    as long as the outer-ring stack, resting on the housing shoulder and clamped by the cover,
    at the housing temperature. Its fit on the outside: `[fits] sleeve_interference_um` /
    `cartridge_interference_um`; the outer rings' fit (`outer_interference_um`) is then in the
    sleeve (or cartridge)."""
    material: str = material()
    radial_thickness_mm: float = number(_MM, note="housing.bore_diameter_mm must be the bearing "
                                                  "OD + 2 x (sleeve + cartridge thickness)")
    length_mm: float = number(_MM, note="= 2 x bearing.width_mm + outer_spacer.length_mm")


_FIT = "diametral; + interference, - clearance"
_PER_MILLE = "|x| <= 2 per mille of the diameter"


@dataclass(frozen=True, kw_only=True)
class Fits:
    inner_interference_um: float = number("um", f"{_FIT}: inner rings on the shaft", sign=SIGNED,
                                          note=_PER_MILLE)
    outer_interference_um: float = number("um", f"{_FIT}: outer rings in the housing (or the "
                                                "sleeve)", sign=SIGNED, note=_PER_MILLE)
    contact: str = choice("frictionless", "bonded", default="frictionless",
                          doc='"bonded": tied, tension allowed')
    sleeve_interference_um: float = number("um", f"{_FIT}: the sleeve in the next layer out (or "
                                                 "the housing)", sign=SIGNED, default=0.0,
                                           note=f"only with a [sleeve]; {_PER_MILLE}")
    cartridge_interference_um: float = number("um", f"{_FIT}: the cartridge in the housing",
                                              sign=SIGNED, default=0.0,
                                              note=f"only with a [cartridge]; {_PER_MILLE}")
    # tolerances (docs/cli.md "tolerance"): an ISO class or explicit (lower, upper) limit
    # deviations in um per surface; "" / () = none. Deviations add to the nominal interference.
    inner_shaft_class: str = text('ISO 286 shaft class: f g h js k m n p, grade 4..7 (e.g. '
                                  '"k5"); "" = none', default="",
                                  note="the class or inner_shaft_deviation_um, not both")
    inner_ring_bore_class: str = text('ISO 492 class: Normal, P6, P5, P4, P2; "" = none',
                                      default="", note="the class or inner_ring_bore_deviation_um, "
                                                       "not both")
    outer_housing_class: str = text('ISO 286 hole class: G H JS J K M N, grade 4..7 (e.g. "J6"); '
                                    '"" = none', default="",
                                    note="the class or outer_housing_deviation_um, not both")
    outer_ring_od_class: str = text('ISO 492 class; "" = none', default="",
                                    note="the class or outer_ring_od_deviation_um, not both")
    inner_shaft_deviation_um: tuple = limits("limit deviations of the shaft seat")
    inner_ring_bore_deviation_um: tuple = limits("limit deviations of the inner ring bore")
    outer_housing_deviation_um: tuple = limits("limit deviations of the housing bore")
    outer_ring_od_deviation_um: tuple = limits("limit deviations of the outer ring OD")
    distribution: str = choice("uniform", "normal", default="uniform",
                               doc='of a deviation: "uniform" within the limits or "normal" '
                                   '(limits at +-3 sigma)')


@dataclass(frozen=True, kw_only=True)
class Preload:
    kind: str = choice("position", "spring", doc='"position": rigid offset set at assembly')
    assembled_N: float = number("N", "set at T_ref_C", sign=ZERO_OK,
                                note="at most the static load rating C0 (ISO 76)")
    path_compliance: str = choice("fe", "rigid", default="fe",
                                  doc='"fe": the axial compliance of spacers, nut and housing from '
                                      'the FE in series with the bearings; "rigid": none')


@dataclass(frozen=True, kw_only=True)
class Lubrication:
    kind: str = choice("solid_film", "oil")
    lubricant: str = text("oil: a library oil (analytic/lubrication.py) or one of the file's "
                               "[lubricants.NAME]", default="")
    friction_coefficient: float = number("-", "oil: Coulomb load term mu F dm/2; solid film: mu "
                                              "of the film", sign=ZERO_OK, default=0.0,
                                         bounds=Range(hi=1.0, error="must not exceed 1"))
    viscous_factor_f0: float = number("-", "Palmgren f0 (oil)", sign=ZERO_OK, default=0.0)
    speed_rpm: float = number("rpm", "the default speed when the conditions give none",
                              sign=ZERO_OK, default=0.0)
    hysteresis_loss_factor: float = number("-", "solid film: elastic hysteresis loss factor "
                                                "alpha_h", sign=ZERO_OK, default=0.0)
    load_term: str = choice("coulomb", "palmgren", default="coulomb",
                            doc='oil: "coulomb" (mu F dm/2) or "palmgren" (f1 F dm)')


@dataclass(frozen=True, kw_only=True)
class Limits:
    max_contact_pressure_MPa: float = number("MPa", "the per-row check of simulate",
                                             infinite_ok=True, default=math.inf,
                                             default_text="none: the ISO 76 static limit, "
                                                          "4200 MPa")
    min_static_safety: float = number("-", "the per-row check of simulate", sign=ZERO_OK,
                                      default=0.0, default_text="0 = 3 (GB/T 28878.2 B.4)")


@dataclass(frozen=True, kw_only=True)
class Operating:
    """The temperature range the assembly must work over (the default conditions of `report`)."""
    T_min_C: float = number("C", "coldest operating temperature", sign=SIGNED, default=-40.0,
                            bounds=Range(*MATERIAL_T_RANGE_C), note="below T_max_C")
    T_max_C: float = number("C", "hottest operating temperature", sign=SIGNED, default=80.0,
                            bounds=Range(*MATERIAL_T_RANGE_C), note="above T_min_C")
    speed_max_rpm: float = number("rpm", "highest shaft speed (report: fit loosening, speed "
                                         "effects)", sign=ZERO_OK, default=0.0,
                                  default_text="0 = [lubrication] speed_rpm")
    ball_model: str = choice("static", "quasi_dynamic", default="static",
                             doc='"static": quasi-static balls; "quasi_dynamic": each ball in its '
                                 'own equilibrium at the row\'s speed (centrifugal force, '
                                 'gyroscopic moment; analytic/bearing/dynamic.py)')
    raceway_control: str = choice("outer", "inner", "jones", default="outer",
                                  doc='quasi_dynamic: raceway control, "jones" per ball (Jones\'s '
                                      'criterion)')

    def max_speed_rpm(self, lubrication_speed_rpm: float) -> float:
        """The highest speed the assembly runs at (rpm): speed_max_rpm, else the given speed."""
        return self.speed_max_rpm if self.speed_max_rpm > 0 else float(lubrication_speed_rpm)


@dataclass(frozen=True, kw_only=True)
class Mesh:
    """Element sizes in mm; 0 = chosen for `target_error` by studies/model/mesh_size.py (given
    sizes win, the others follow the rule)."""
    size_mm: float = number(_MM, "bulk element size", sign=ZERO_OK, default=0.0,
                            default_text="0 = from the target", note="at most the bearing width")
    fit_size_mm: float = number(_MM, "size along fits and raceways", sign=ZERO_OK, default=0.0,
                                default_text="0 = from the target", note="at most size_mm")
    corner_size_mm: float = number(_MM, "size where fits and clamped faces end", sign=ZERO_OK,
                                   default=0.0, default_text="0 = from the target",
                                   note="at most fit_size_mm")
    target_error: float = number("-", "relative discretisation error of fit pressures and "
                                      "groove-centre shifts the sizes left at 0 are chosen for",
                                 default=1e-3, bounds=Range(*MESH_TARGET_RANGE),
                                 note="the range the size rule was measured over "
                                      "(studies/model/mesh_size.py)")
    ring_section: str = choice("grooved", "rectangle", default="rectangle",
                               doc='"rectangle": the effective ring sections of [bearing]; '
                                   '"grooved": rings with their raceway grooves and lands '
                                   '(studies/model/stack.py)')


@dataclass(frozen=True, kw_only=True)
class Thermal:
    """How the part temperatures of a row are found: given by the conditions, or computed by the
    transient conduction FE of the stack (studies/model/transient_route.py)."""
    mode: str = choice("given", "transient", default="given",
                       doc='"given": part temperatures from the conditions; "transient": computed '
                           'by the transient conduction FE from time_s and the environment')
    films: tuple = _field_table("W/m2K", "transient: film coefficient per face group "
                                "([thermal.films]; a name may be a pattern such as raceway_*, an "
                                "exact name wins; docs/cli.md lists the groups)",
                                default=(), default_text="none: adiabatic")
    sink_C: float = number("C", "transient: radiation sink when the conditions give no "
                                "T_sink_C", sign=SIGNED, infinite_ok=True, default=math.inf,
                           default_text="none: the environment (T_ambient_C)")
    emissivity: float = number("-", "transient: of every exterior face but the raceways "
                                    "(radiation to the sink)", sign=ZERO_OK, default=0.0,
                               bounds=Range(hi=1.0, error="must lie in 0..1, got {v:g}"))
    gas: str = choice("air", "vacuum", default="air",
                      doc='transient: the gas in the gaps of fits and spacer bores: "air" (gas '
                          'conduction across them) or "vacuum" (none: an open fit conducts nothing)')
    fit_conductance: object = choice_or_number(
        "pressure", unit="W/m2K", default="pressure",
        doc='transient: thermal contact conductance of every fit; "pressure": from the fit '
            'pressure each step (Yovanovich; an open fit: gas gap)')

    def films_W_m2K(self) -> dict[str, float]:
        return dict(self.films)


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
    thermal: Thermal = field(default_factory=Thermal)
    source: str = ""
    sleeve: Layer | None = None
    cartridge: Layer | None = None
    materials: tuple[Material, ...] = ()   # the config's own [materials.NAME] tables
    lubricants: tuple[Lubricant, ...] = ()  # the config's own [lubricants.NAME] tables

    def oil(self) -> Lubricant | None:
        """The oil of `[lubrication] lubricant` (the file's own table first, then the library);
        None for a solid film."""
        if self.lubrication.kind != "oil":
            return None
        return get_lubricant(self.lubrication.lubricant, self.lubricants)

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
    raw = _read_toml(path)
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
    top = _header(path, raw.get("assembly"))
    for name in raw:
        if name not in ("assembly", "materials", "lubricants") and name not in SECTIONS:
            raise ConfigError(f"{path}: [{name}]: unknown section")
    parts = {name: _section(path, raw, name) for name in SECTIONS
             if name not in LAYERS or name in raw}
    asm = Assembly(**top, materials=parse_materials(raw, path),
                   lubricants=parse_lubricants(raw, path), **parts)
    check_assembly(asm, path)
    return asm


def _header(path: str, top) -> dict:
    """The [assembly] table: name, arrangement, T_ref_C, source (ASSEMBLY_KEYS)."""
    if not isinstance(top, dict):
        raise ConfigError(f"{path}: [assembly]: missing section")
    for key, spec in ASSEMBLY_KEYS.items():
        if spec.required and key not in top:
            raise ConfigError(f"{path}: assembly.{key}: missing key")
    for key in top:
        if key not in ASSEMBLY_KEYS:
            raise ConfigError(f"{path}: assembly.{key}: unknown key{unit_hint(key, ['T_ref_C'])}")
    arrangements = ASSEMBLY_KEYS["arrangement"].choices
    if top["arrangement"] not in arrangements:
        raise ConfigError(f"{path}: assembly.arrangement: '{top['arrangement']}' is not "
                          f"{' or '.join(arrangements)}")
    T_ref, T_key = top["T_ref_C"], ASSEMBLY_KEYS["T_ref_C"]
    if isinstance(T_ref, bool) or not isinstance(T_ref, (int, float)) or not T_key.bounds.holds(T_ref):
        raise ConfigError(f"{path}: assembly.T_ref_C: {T_key.bounds.error.format(v=T_ref)}")
    return {"name": str(top["name"]), "arrangement": top["arrangement"], "T_ref_C": float(T_ref),
            "source": str(top.get("source", ""))}


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


def parse_lubricants(raw: dict, path: str) -> tuple[Lubricant, ...]:
    """A config's `[lubricants.NAME]` tables (analytic.lubrication.lubricant_from_table), in
    file order; ConfigError (one line naming the file and key) on a bad table."""
    tables = raw.get("lubricants", {})
    if not isinstance(tables, dict) or not all(isinstance(t, dict) for t in tables.values()):
        raise ConfigError(f"{path}: [lubricants]: give one table per oil, [lubricants.NAME]")
    try:
        return tuple(lubricant_from_table(name, t) for name, t in tables.items())
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc.args[0]}") from None


CONFIG_DIR = Path(__file__).parents[1] / "configs"
SHIPPED = {"seed000": "seed000_71807C_TC4.toml", "seed001": "seed001_flywheel_hybrid.toml",
           "seed003": "seed003_25TAC62B.toml"}


def load_shipped(name: str) -> Assembly:
    """One of the shipped configurations by short name (seed000, seed001, seed003)."""
    return load_assembly(CONFIG_DIR / SHIPPED[name])

"""The ladder rung `thermal_transient_fe`: the part temperatures of every row from the stack's
own reduced transient conduction FE, with the mount it is bolted to, fitted to the data
(docs/diagnosis.md "The transient conduction rung").

Physics. The conduction FE of the assembly under diagnosis (`fem.transient.TransientConduction`,
its geometry and materials, one ball node per bearing), reduced once per assembly
(`fem.reduced_thermal.krylov_basis`, cached beside the FE set-ups, `transient_route.
cached_basis`), plus one lumped state for the mount (bracket, base plate, machine bed):

    M q' + A(p) q = b_env(p) T_amb(t) + a_heat s Q(t) + hm b_face T_m
    C_mount T_m' = G_face (T_face - T_m) + G_env (T_amb - T_m)

q the reduced coordinates of the field, A(p) = K + h sum_g F_g (the face groups to the
surroundings, `face_kind`: housing, cover, shaft ends, nut; the shaft's bore at
h x bore_film_ratio; the faces inside the housing none; film h = 1 / film_resistance: convection and, with an emissivity, the
radiation linearised about the mean ambient, Incropera ch. 1.2.3 eq. 1.9; in vacuum the
radiation alone, its film per interval between rows the secant eps sigma (T + T_s)(T^2 + T_s^2)
between the sink and the housing, `radiating_part_temperatures_C`) + f sum_k h_k C_k (the fits' contact conductances h_k from their assembled
pressure, Yovanovich's plastic correlation, `fem.transient.contact_conductance_W_m2K`, open
fits through their solid spots, scaled by f = fit_conductance_factor) + f_b B (the ball links'
term at the assembled state, `transient_route.contacts`, scaled by f_b =
ball_conductance_factor) + the spacer bores' term + hm F_face; the mount couples to
the housing's outer face (`housing_outer`, a housing held in a bracket's bore or on its
flange's rim) with hm = G_face / A_face uniformly over the face (W/(mm^2 K)); Q(t) the pair's
friction heat at the bearing's own temperature (the mean of its rings and balls, as the
transient route couples its heat at the state, `transient_route.run_transient`): the torque
model's heat (`transient_route.pair_heat` through the one route) at the row's speed,
assembled preload and loads with every part at that temperature, tabulated once per
conditions over the temperature (`HeatCurve`, `ThermalTransientFE.heat_curve`; an oil's
viscous heat falls tenfold or more from -60 C to 20 C, so a heat taken at the ambient is far
from the bearing's); split half to the raceways and half to the ball nodes as the transient
route splits an extra heat (`transient_route.extra_share`), scaled by s = heat_scale. Each
interval's heat is held at its value at the interval's end, where it balances the bearing's
temperature it makes (`HeatCurve.solve`, a scalar root per row: stable however steeply the
heat falls; the listed effects' changes of the friction coefficient or the preload do not
move it). The system is symmetric (conduction, films, contact and the mount's
coupling are), so one generalised eigen-decomposition A phi = lambda M phi of the augmented
(m + 1) system per trial diagonalises it; each mode then obeys z' = -lambda z + g(t) with g
piecewise linear between the rows (the conditions' ambient and heat interpolated linearly in
time, as `thermal_lag` takes the ambient), integrated exactly over each interval:

    z_{k+1} = e^{-lambda h} z_k + g_k (1 - e^{-lambda h}) / lambda
              + s_k (lambda h - 1 + e^{-lambda h}) / lambda^2

(the variation-of-constants formula, e.g. Ogata, Modern Control Engineering ch. 9 for a
first-order-hold input; the heat held over the interval adds Q w (1 - e^{-lambda h}) / lambda).
Initial state: the steady state of the first row (the stack at rest at the first ambient,
with the heat that balances it). The rows' part temperatures are the volume
means of the `inputs.PARTS` groups (`transient_route.group_rows`, the means the transient
route writes as T_<part>_C) and go into the rows' inputs as every temperature does: the
pipeline's one route (`studies.model.pipeline.Pipeline`) takes them, parts with a measured
temperature of their own left as measured.

Fast trial: within a trial the contact conductances are held (the fits' at
their assembled pressure times the factor, the balls' at the assembled state), so the
conduction is linear and a trial costs one (m + 1)^2 eigen-decomposition and the exact
recursion over the rows, no time stepping between them (`bearingfem bench --diagnose`,
kind "thermal_transient_fe", prints its time); the heat curve of the rows is computed once
per conditions (memo) from the configured model.

Parameters (bounds and sources):

- film_resistance_m2K_W = 1 / h (m^2 K / W), off 0: the configured model (every part at the
  ambient, no heat rise; returned exactly). Not the form's limit: at any finite film the
  faces follow the ambient but the stack's interior still lags them by conduction (0.3 K on
  seed 000's cycles at 1e-10 m^2 K/W), a jump at off that `fitting.fit_from_off` sees; up to
  FILM_RESISTANCE_MAX_AIR = 1 / 1 (natural convection in air 2..25 W/(m^2 K), forced 25..250
  in gases, Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., Table 1.1;
  forced air past a rotating shaft to ~500; 1 W/(m^2 K): small temperature differences, or
  radiation alone in the cold, `FILM_RESISTANCE_MAX_AIR`) or in vacuum 1 / (EMISSIVITY_MIN 4 sigma T^3)
  (radiation alone: emissivity from 0.03, polished aluminium / gold, to 0.95, black anodise,
  Incropera Table A.11; T the reference temperature: the parameter is the film at T_ref, each
  interval's the secant at its sink and faces, `radiation_film_factor`).
- bore_film_ratio (-), 0..1, off 1: the film in the shaft's bore / the outside one (a cavity
  open at its ends sees still air or none: 0 a closed bore, 1 the outside film; natural
  convection in a tube 1..5 W/(m^2 K) against 2..500 outside, Incropera Table 1.1).
- G_face_W_K (W/K), off 0 (no mount): the mount's conductance to the housing's outer face,
  up to JOINT_CONDUCTANCE_MAX_W_M2K x A_face (bolted and clamped metal joints 100..10^4
  W/(m^2 K) in air, Madhusudana, Thermal Contact Conductance, 2nd ed. 2014, ch. 1 and 8;
  Gilmore, Spacecraft Thermal Control Handbook Vol. 1, 2nd ed. 2002, ch. 7 for vacuum).
- G_env_W_K (W/K), off 0: the mount's conductance to the environment, up to
  MOUNT_AREA_MAX_M2 x 25 W/(m^2 K) (a plate of up to 1 m^2 of free face in natural
  convection, Incropera Table 1.1; 0: the mount stores heat only).
- C_mount_J_K (J/K), from C_MOUNT_MIN_J_K (no mount; off) to C_MOUNT_MAX_J_K = 2.5e5 J/K (500 kg
  of cast iron or steel, c ~ 460..500 J/(kg K), Incropera Table A.1).
- fit_conductance_factor (-), 1/3..3, off 1: the fits' contact conductance about Yovanovich's
  correlation (the spread of measured conductances about the correlations for ground metal
  joints, a factor of about 2..3: Madhusudana 2014 ch. 3; an assumption stated as such).
- ball_conductance_factor (-), 1/3..3, off 1: the ball-raceway conductances about the rolling
  contacts' constriction (`analytic.heat.rolling_contact_conductance`: the Hertz ellipse at
  the assembled state; Holm's 1/(4 k a) of a static contact at the free contact angle differs
  from it by tens of per cent, and the surface films and the contact angle's change with
  temperature spread measured ball-bearing conductances by a factor of about 2..3: an
  assumption stated as such). Fitted in vacuum only, where the balls are the rotor's one path
  to the housing (`RungModel.ball_matters`); in a gas the shaft's faces exchange with the air
  beside them and the films and the balls trade against each other (seed 000's speed
  staircase in still air: 3 +- 14), so it is held at 1 there.
- heat_scale (-), 0..3, off 1: the bearing's friction heat in the stack x heat_scale (the
  friction laws' own spread about measured torques; `analytic.friction`); 1 is the torque
  model's own heat, and at film resistance 0 the heat raises nothing, so off is still the
  configured model. Fitted where the speed varies or where the heat shapes the history
  (`heat_matters`: an oil's viscous heat at the lowest ambient raising the stack by more than
  HEAT_MATTERS_K); held at 1 otherwise (`fitspec.held_fixed`: a small heat's steady rise is
  a constant the mount and the films trade against each other, and the model's own heat is the
  best statement of it).

Environment from the assembly's `[thermal]`: `gas = "vacuum"` makes the films radiation (their
bound above; radiation alone changes threefold between -60 and 80 C, 4 eps sigma T^3, so each
interval takes its own: the system is then piecewise constant, one eigen-decomposition per
FILM_BIN_LN bin of the film, and the film is found by Picard passes, about the sink first,
then at the housing's temperature of the pass before, to their fixed point: until a pass's bins
are the pass before's, at most RADIATION_PASSES_MAX) and takes the gas out of the fits and spacer bores (`transient_route.contacts`);
an `emissivity` in air is part of the fitted film; a finite `sink_C` in vacuum is what the
films (radiation) see, the mount's environment staying `T_ambient_C` (a thermal-vacuum
chamber's shroud and its controlled base plate).

A parameter whose effect vanishes at the off values of the others (the mount's capacity and
G_env at G_face = 0) is found from the fit specification's starts (`starts`).

Units: s, C, W, J, K; films in W/(m^2 K), areas in mm^2 inside (FE units, `fem.transient`).
"""
from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass, fields
from functools import cached_property

import numpy as np
import scipy.linalg as sla
from scipy.optimize import brentq

from fem.reduced_thermal import ReducedConduction
from fem.transient import PER_M2_TO_PER_MM2, ThermalParameters, radiation_h_W_mm2K
from infra.memo import Memo
from studies.model.effects import Effect
from studies.model.inputs import PARTS

NAME = "thermal_transient_fe"
#: assembly -> the pipeline the last diagnosis of it bound the rung to (`ThermalTransientFE.bind`)
_BOUND: Memo = Memo(4)
#: the mount's face group (module docstring)
MOUNT_FACE = "housing_outer"
#: film resistance bound in air (m^2 K / W): a film of 1 W/(m^2 K), below natural convection's
#: 2 W/(m^2 K) of Incropera Table 1.1 (given for differences of tens of K; laminar natural
#: convection goes as dT^0.25, Incropera ch. 9.6, so a difference of a few K halves it) and
#: below radiation alone at -60 C (eps 0.8: 4 eps sigma T^3 = 1.8 W/(m^2 K)): a file that
#: says nothing of its gas may be run in vacuum
FILM_RESISTANCE_MAX_AIR = 1.0 / 1.0
#: the lowest emissivity of a technical surface in vacuum (polished aluminium, gold plate:
#: 0.03..0.05, Incropera Table A.11)
EMISSIVITY_MIN = 0.03
#: bolted / clamped metal joints: up to 1e4 W/(m^2 K) (Madhusudana 2014 ch. 1)
JOINT_CONDUCTANCE_MAX_W_M2K = 1.0e4
#: the mount's free face (m^2) and its film (natural convection's top, W/(m^2 K))
MOUNT_AREA_MAX_M2 = 1.0
MOUNT_FILM_MAX_W_M2K = 25.0
#: mount capacity bounds (J/K): none (a massless node) to 500 kg of cast iron
C_MOUNT_MIN_J_K = 1.0
C_MOUNT_MAX_J_K = 2.5e5
FIT_FACTOR = (1.0 / 3.0, 3.0)
BALL_FACTOR = (1.0 / 3.0, 3.0)
HEAT_SCALE_MAX = 3.0
#: training film coefficients of the reduction (W/(m^2 K)) on the exterior faces, with the fits'
#: conductance factor, the mount face's own film (the mount's coupling hm up to
#: JOINT_CONDUCTANCE_MAX_W_M2K) and the ball links' factor
TRAINING = ((2.0, 1.0 / 3.0, 0.0, 3.0), (20.0, 1.0, 0.0, 1.0), (200.0, 3.0, 0.0, 1.0 / 3.0),
            (10.0, 1.0, 1.0e4, 1.0 / 3.0), (500.0, 1.0 / 3.0, 1.0e3, 3.0))


@dataclass(frozen=True)
class RungModel:
    """The reduced conduction of one assembly's stack, term by term, for the rung's trials.

    M, K0 (m, m): capacity (J/K) and the conduction with the spacer bores' and ball links'
    terms (W/K); F_ext, b_ext: the outside faces' film matrix and drive (mm^2), F_bore, b_bore
    the shaft bore's (`face_kind`); C_fit: the
    fits' term at their assembled conductances (W/K); B_ball: the ball links' (W/K, in K0); F_face, b_face, area_face_mm2: the mount
    face's; a_heat (m,): the load of 1 W of the pair's heat; groups (len(PARTS), m): the part
    group means per coordinate (NaN rows: a group the stack lacks); h_rad_W_m2K: the file's
    emissivity's linearised radiation (air; 0 without), vacuum: the films are radiation."""
    M: np.ndarray
    K0: np.ndarray
    F_ext: np.ndarray
    b_ext: np.ndarray
    F_bore: np.ndarray
    b_bore: np.ndarray
    C_fit: np.ndarray
    B_ball: np.ndarray
    F_face: np.ndarray
    b_face: np.ndarray
    area_face_mm2: float
    a_heat: np.ndarray
    groups: np.ndarray
    vacuum: bool
    capacity_J_K: float
    fit_matters: bool = True
    #: the ball links' factor is fitted (in vacuum, where it moves the time constants)
    ball_matters: bool = True
    rc: ReducedConduction | None = None
    nominal: ThermalParameters | None = None
    exterior: tuple = ()

    @property
    def m(self) -> int:
        return self.M.shape[0]


def rung_model(pl) -> RungModel:
    """The `RungModel` of a pipeline's stack: kept on the pipeline; from the set-up cache when a
    diagnosis of the same assembly built it before (`cached_rung_model`), else `build`."""
    hit = getattr(pl, "_rung_model", None)
    if hit is None:
        hit = pl._rung_model = cached_rung_model(pl)
    return hit


#: format of the cached rung model (raise when its arrays or `TRAINING` change; 2: the faces
#: by kind, `face_kind`; 3: open fits and spacer bores with their solid spots,
#: `transient_route.contacts`, and the ball links' term B_ball; 4: the ball factor fitted in
#: vacuum only)
RUNG_FORMAT = 4
#: the arrays of a cached `RungModel` (its scalars are stored as 0-d arrays)
_ARRAYS = ("M", "K0", "F_ext", "b_ext", "F_bore", "b_bore", "C_fit", "B_ball", "F_face",
           "b_face",
           "a_heat", "groups")
_SCALARS = ("area_face_mm2", "vacuum", "capacity_J_K", "fit_matters", "ball_matters")
_SCALAR_TYPES = {"area_face_mm2": float, "vacuum": bool, "capacity_J_K": float,
                 "fit_matters": bool, "ball_matters": bool}


@dataclass(frozen=True)
class RungParameters:
    """One trial's parameters of the rung (`ThermalTransientFE.parameters`, units there):
    film_resistance_m2K_W (m2 K/W; 0: no film, the configured model), bore_film_ratio (-),
    G_face_W_K, G_env_W_K (W/K), C_mount_J_K (J/K), fit_conductance_factor (-),
    ball_conductance_factor (-), heat_scale (-)."""
    film_resistance_m2K_W: float
    bore_film_ratio: float
    G_face_W_K: float
    G_env_W_K: float
    C_mount_J_K: float
    fit_conductance_factor: float
    ball_conductance_factor: float
    heat_scale: float

    @classmethod
    def of(cls, p) -> "RungParameters":
        """From a parameter mapping (the fitting's dict) or a `RungParameters`."""
        if isinstance(p, cls):
            return p
        return cls(**{f.name: float(p[f.name]) for f in fields(cls)})


class RungCacheError(RuntimeError):
    """A cached rung model that is not sound for its key (one line)."""


def cached_rung_model(pl) -> RungModel:
    """`build`'s arrays, cached beside the FE set-ups (`meshes.cache`: hash-named .npz, atomic
    write, checked on read, rebuilt with a warning), keyed by the FE set-up's key, the whole
    assembly (the contact state: preload, speed, lubricant, [thermal]), the mesh factor,
    TRAINING and RUNG_FORMAT. A diagnosis then needs neither the full FE model nor the
    conduction's assembly (seconds) once a diagnosis of the assembly has run."""
    import hashlib
    import json

    from meshes.cache import cache_dir, cached_file, npz_arrays

    key = hashlib.sha256(json.dumps({"format": RUNG_FORMAT, "setup": pl.setup.key,
                                     "asm": repr(pl.asm), "mesh_factor": pl.mesh_factor,
                                     "training": repr(TRAINING)}).encode()).hexdigest()[:24]
    path = cache_dir("setups", "transient rung model") / f"rung_{key}.npz"

    def make(tmp):
        rm = build(pl)
        with open(tmp, "wb") as fh:
            np.savez(fh, key=np.array(key), exterior=np.array(rm.exterior),
                     **{k: getattr(rm, k) for k in _ARRAYS + _SCALARS})

    def read(p):
        a = npz_arrays(p, RungCacheError)
        stored_key, exterior = (a.pop(k, None) for k in ("key", "exterior"))
        if set(a) != {*_ARRAYS, *_SCALARS} or str(stored_key) != key or exterior is None:
            raise RungCacheError("not the rung model of this assembly")
        rm = RungModel(**{k: a[k] for k in _ARRAYS},
                       **{k: _SCALAR_TYPES[k](a[k]) for k in _SCALARS},
                       exterior=tuple(str(x) for x in exterior))
        m = rm.m
        if (rm.M.shape != (m, m) or rm.groups.shape != (len(PARTS), m)
                or not all(np.all(np.isfinite(a[k])) for k in _ARRAYS if k != "groups")):
            raise RungCacheError("its arrays are not sound")
        return rm

    return cached_file(path, make, read, what="transient rung model", writer="bearingfem",
                       error=RungCacheError)


def build(pl) -> RungModel:
    """The `RungModel` of `pl`'s stack (module docstring): the conduction FE, its contact
    coefficients at the assembled state (`transient_route.contacts`), the reduction
    (`transient_route.cached_basis`) and the sums the trials take."""
    from dataclasses import replace

    from fem.solver import single_thread_blas
    from studies.model import transient_route as tr

    @single_thread_blas
    def make():
        tc = tr.stack_conduction(pl)
        c = tr.contacts(pl, tc)
        ext = [g for g in tc.groups if face_kind(g) == "outside"]
        bore = [g for g in tc.groups if face_kind(g) == "bore"]
        filmed = [g for g in tc.groups if not g.startswith("raceway_")]
        nominal = ThermalParameters(fit_conductance_W_m2K=tuple(c.fit_W_m2K),
                                    ball_inner_W_K=c.ball_W_K[0], ball_outer_W_K=c.ball_W_K[1],
                                    bore_conductance_W_m2K=c.bore_W_m2K,
                                    T_rad_lin_C=pl.asm.T_ref_C)
        training = []
        for h, f, h_face, f_b in TRAINING:
            films = {g: h for g in filmed}
            if MOUNT_FACE in films:
                films[MOUNT_FACE] = h + h_face
            training.append(replace(nominal, film_W_m2K=films,
                                    fit_conductance_W_m2K=tuple(c.fit_W_m2K * f),
                                    ball_inner_W_K=c.ball_W_K[0] * f_b,
                                    ball_outer_W_K=c.ball_W_K[1] * f_b))
        inputs = tr.heat_inputs(tc) + ([MOUNT_FACE] if MOUNT_FACE in tc.a else [])
        rc = ReducedConduction(tc, tr.cached_basis(pl, tc, training, inputs))
        K0 = rc.operator(nominal) - _fit_part(rc, c.fit_W_m2K)
        keys = tr.heat_inputs(tc)
        a_heat = sum(tr.extra_share(k, dict.fromkeys(keys, 0.0)) * rc.a[k] for k in keys)
        face = MOUNT_FACE if MOUNT_FACE in rc.F else None
        zero = np.zeros((rc.m, rc.m))
        out = RungModel(
            M=rc.M, K0=K0, F_ext=sum(rc.F[g] for g in ext), b_ext=sum(rc.b[g] for g in ext),
            F_bore=sum((rc.F[g] for g in bore), zero), b_bore=sum((rc.b[g] for g in bore),
                                                                  np.zeros(rc.m)),
            C_fit=_fit_part(rc, c.fit_W_m2K), B_ball=_ball_part(rc, c.ball_W_K), F_face=rc.F[face] if face else zero,
            b_face=rc.b[face] if face else np.zeros(rc.m),
            area_face_mm2=float(tc.b[face].sum()) if face else 0.0, a_heat=a_heat,
            groups=tr.group_rows(tc) @ rc.V, vacuum=pl.asm.thermal.gas == "vacuum",
            capacity_J_K=float(tc.M.sum()), rc=rc, nominal=nominal, exterior=tuple(ext))
        return replace(out, fit_matters=_term_matters(out, "fit"),
                       ball_matters=out.vacuum and _term_matters(out, "ball"))
    return make()


#: the fits' (the ball links') conductance factor is fitted when its range (FIT_FACTOR,
#: BALL_FACTOR) moves one of the stack's FIT_MATTERS_MODES slowest time constants by more than
#: this share (at a film of 20 W/(m^2 K), no mount); else it is held at 1 (`held_fixed`): the
#: term then conducts so much more than the films and contacts in series with it that no data
#: can see its conductance
FIT_MATTERS_REL = 0.01
FIT_MATTERS_MODES = 4


def _term_matters(rm: RungModel, which: str) -> bool:
    """Whether the fits' (which "fit", over FIT_FACTOR) or the ball links' ("ball", over
    BALL_FACTOR) conductance factor moves one of the FIT_MATTERS_MODES slowest time constants
    by more than FIT_MATTERS_REL, the other factor at 1."""
    lam = []
    for f in (FIT_FACTOR if which == "fit" else BALL_FACTOR):
        fit, ball = (f, 1.0) if which == "fit" else (1.0, f)
        A = (rm.K0 + fit * rm.C_fit + (ball - 1.0) * rm.B_ball
             + (20.0 * PER_M2_TO_PER_MM2) * (rm.F_ext + rm.F_bore))
        lam.append(sla.eigh(0.5 * (A + A.T), rm.M, eigvals_only=True)[:FIT_MATTERS_MODES])
    return bool(np.max(np.abs(lam[1] - lam[0]) / lam[1]) > FIT_MATTERS_REL)


#: face groups inside the housing: the rings' and spacers' free faces face the bearing's annulus
#: and the gap between the spacers, not the surroundings (their gas layers are left out, a few
#: mW/K); the raceways take the bearing's heat
INSIDE = ("raceway_", "free_inner_ring", "free_outer_ring", "free_inner_spacer",
          "free_outer_spacer")


def face_kind(group: str) -> str:
    """The kind of a face group (`fem.transient.face_groups`): "inside" (INSIDE: no film),
    "bore" (the shaft's bore, a cavity open at its ends: its own film, a share of the outside
    one), "outside" (to the surroundings: the housing, the cover, the shaft's ends and free
    faces, the nut)."""
    if group.startswith(INSIDE):
        return "inside"
    return "bore" if group == "shaft_bore" else "outside"


def _ball_part(rc: ReducedConduction, ball_W_K) -> np.ndarray:
    """The reduced ball links' term (W/K) at the (inner, outer) conductances ball_W_K (W/K per
    bearing, ball nodes), as `fem.transient.TransientConduction` sums it."""
    out = np.zeros((rc.m, rc.m))
    for Ci, Co in zip(rc.ball_inner, rc.ball_outer):
        out += ball_W_K[0] * Ci + ball_W_K[1] * Co
    return out


def _fit_part(rc: ReducedConduction, h_fit_W_m2K) -> np.ndarray:
    """sum_k h_k C_k of the reduced fits' terms (W/K); zero with perfect contact."""
    out = np.zeros((rc.m, rc.m))
    if rc.tc.perfect_contact:
        return out
    for h, C in zip(np.asarray(h_fit_W_m2K, float), rc.C_fit):
        out += (h * PER_M2_TO_PER_MM2) * C
    return out


# ====================================================================== a trial
def _phi(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e^-x, (1 - e^-x) / x, (x - 1 + e^-x) / x^2) for x = lambda h >= 0, the last two by their
    series where x < 1e-4 (cancellation)."""
    E = np.exp(-x)
    small = x < 1e-4
    xs = np.where(small, 1.0, x)
    f1 = np.where(small, 1.0 - x / 2.0 + x * x / 6.0, -np.expm1(-xs) / xs)
    f2 = np.where(small, 0.5 - x / 6.0 + x * x / 24.0, (xs + np.expm1(-xs)) / (xs * xs))
    return E, f1, f2


#: width of the bins of ln(film / the parameter's film) over which a radiation film is held
#: constant in a trial (`film_levels`): +-2.5 %; each interval takes its bin's centre, so the
#: error alternates over a ramp
FILM_BIN_LN = 0.05


def radiation_film_factor(T_sink_C: np.ndarray, T_face_C: np.ndarray | None,
                          T_ref_C: float) -> np.ndarray:
    """h_r / h_r(T_ref) of radiation between a face at T_face_C and its sink T_sink_C (-):
    eps sigma (T^4 - T_s^4) = eps sigma (T + T_s)(T^2 + T_s^2)(T - T_s) (Incropera & DeWitt
    6th ed. eq. 1.9, the secant), over 4 eps sigma T_ref^3; T_face_C None: linearised about
    the sink, 4 eps sigma T_s^3. Temperatures in C, absolute inside."""
    K = 273.15
    Ts = np.asarray(T_sink_C, float) + K
    T = Ts if T_face_C is None else np.asarray(T_face_C, float) + K
    return (T + Ts) * (T * T + Ts * Ts) / (4.0 * (T_ref_C + K) ** 3)


def _levels(film_factor, ball_factor, n: int):
    """(film factor per level, ball factor per level, level of each interval): the intervals'
    distinct pairs of the film's bin (`film_levels`) and the ball links' factor."""
    k = max(n - 1, 1)
    if film_factor is None or n < 2:
        f_lv, f_of = np.ones(1), np.zeros(k, int)
    else:
        f_lv, f_of = film_levels(film_factor)
    b = np.ones(k) if ball_factor is None or n < 2 else np.asarray(ball_factor, float)
    if np.all(f_of == f_of[0]) and np.all(b == b[0]):           # one level
        return f_lv[f_of[:1]], b[:1].copy(), np.zeros(k, int)
    pairs, level = np.unique(np.column_stack([f_of, b]), axis=0, return_inverse=True)
    return f_lv[pairs[:, 0].astype(int)], pairs[:, 1], level.reshape(-1)


def film_bins(factor: np.ndarray) -> np.ndarray:
    """The FILM_BIN_LN bin (an integer-valued float) of each interval's film factor (-):
    round(ln(factor) / FILM_BIN_LN)."""
    return np.round(np.log(np.asarray(factor, float)) / FILM_BIN_LN)


def film_levels(factor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(factor per level, level of each interval): the film factor of each interval (-) held
    at the centre of its FILM_BIN_LN bin of ln(factor) (`film_bins`)."""
    centres, level = np.unique(film_bins(factor), return_inverse=True)
    return np.exp(centres * FILM_BIN_LN), level.reshape(-1)


#: the parts whose mean temperature is the bearing's (its oil's, as `transient_route` takes
#: it for the torque and the EHL film): the rings and the balls
OIL_PARTS = ("inner_ring", "outer_ring", "ball")
#: the grid of the heat curve (`heat_curve`): from HEAT_GRID_BELOW_K under the lowest ambient
#: to HEAT_GRID_ABOVE_K over the highest, every HEAT_GRID_STEP_K (the heat held beyond it)
HEAT_GRID_BELOW_K, HEAT_GRID_ABOVE_K, HEAT_GRID_STEP_K = 20.0, 120.0, 5.0
#: the heat curve is interpolated in ln(heat + HEAT_FLOOR_W) (a viscous heat goes nearly as
#: exp(-T / a few tens of K) with the oil's viscosity; the floor keeps a zero heat finite)
HEAT_FLOOR_W = 1e-9


@dataclass(frozen=True)
class HeatCurve:
    """The pair's friction heat as a function of the bearing's own temperature, per row:
    T_C (n_T,) the grid of the bearing's (rings' and balls' mean) temperature (C), increasing;
    ln_heat (n_cond, n_T) ln(heat (W) + HEAT_FLOOR_W) of each distinct set of the rows'
    conditions (speed, preload, loads) at every grid temperature (the one route's heat of the
    pair with every part at that temperature, `ThermalTransientFE.heat_curve`); row (n,) the
    condition set of each row. A trial holds each interval's heat at its value at the
    interval's end, at the bearing's temperature there (`solve`: backward in the coupling,
    stable however steeply the heat falls as the oil warms, as `transient_route`'s steady
    `equilibrium` is a fixed point of the same coupling). Between grid points ln(heat) is
    linear in T (np.interp's formula), held at the ends beyond the grid."""
    T_C: np.ndarray
    ln_heat: np.ndarray
    row: np.ndarray

    @cached_property
    def _tables(self) -> list[_HeatTable]:
        """Per condition set its `_HeatTable` (plain floats: a trial evaluates the curve a few
        times per row, where numpy's per-call overhead would dominate)."""
        grid = [float(x) for x in self.T_C]
        out = []
        for ln in np.asarray(self.ln_heat, float):
            ln_l = [float(x) for x in ln]
            slope = [(ln_l[i + 1] - ln_l[i]) / (grid[i + 1] - grid[i])
                     for i in range(len(grid) - 1)]
            # the largest rates of rise and fall of the heat with T (W/K) on each segment: at
            # its end of the larger heat (ln(heat) is linear there, d heat / dT = slope heat)
            big = [math.exp(max(ln_l[i], ln_l[i + 1])) for i in range(len(slope))]
            rise = max([s * b for s, b in zip(slope, big) if s > 0.0], default=0.0)
            fall = max([-s * b for s, b in zip(slope, big) if s < 0.0], default=0.0)
            out.append(_HeatTable(grid, ln_l, slope, math.exp(max(ln_l)) - HEAT_FLOOR_W,
                                  rise, fall))
        return out

    def heat_W(self, k: int, T_C: float) -> float:
        """The heat (W) of row k's conditions with the bearing at T_C (C)."""
        return self._tables[int(self.row[k])].heat(float(T_C))[0]

    def solve(self, k: int, T0_C: float, dT_per_W: float, guess: float = 0.0) -> float:
        """The heat Q (W) of row k that is consistent with the bearing's temperature it makes,
        T = T0_C + dT_per_W Q (K/W: the trial's linear response): the root of
        f(Q) = Q - heat(T0 + dT_per_W Q) in [0, the curve's largest heat] (it exists: the left
        end is <= 0, the right >= 0). Where f rises over the whole bracket (f' = 1 -
        dT_per_W d heat / dT > 0: always where the heat falls with the temperature and the
        response is positive, else where |dT_per_W| times the curve's largest rate of the
        wrong sign is below 1) the root is unique and a safeguarded Newton iteration from
        `guess` (the row before's heat) finds it (`_HeatTable.newton`); otherwise Brent's method
        on the bracket (scipy's brentq), the same tolerances (xtol 1e-12 W, rtol 1e-11)."""
        tab = self._tables[int(self.row[k])]
        T0, d = float(T0_C), float(dT_per_W)
        hi = tab.largest_W
        lo_v = -tab.heat(T0)[0]
        if lo_v >= 0.0 or hi <= 0.0:
            return 0.0
        hi_v = hi - tab.heat(T0 + d * hi)[0]
        if hi_v <= 0.0:
            return hi
        if (tab.rise if d >= 0.0 else tab.fall) * abs(d) < 1.0:
            Q = tab.newton(T0, d, 0.0, hi, guess)
            if Q is not None:
                return Q
        f = lambda Q: Q - tab.heat(T0 + d * Q)[0]        # noqa: E731
        return float(brentq(f, 0.0, hi, xtol=HEAT_XTOL_W, rtol=HEAT_RTOL))


#: tolerances of the heat's root (`HeatCurve.solve`): W and relative
HEAT_XTOL_W, HEAT_RTOL = 1e-12, 1e-11
#: Newton iterations of `_HeatTable.newton` before it gives the root to Brent's method
HEAT_NEWTON_MAX = 60


@dataclass(frozen=True)
class _HeatTable:
    """One condition set's heat curve as plain floats (`HeatCurve`): the grid (C), ln(heat +
    HEAT_FLOOR_W) at its points, the slope of ln(heat) per segment (1/K), the largest heat (W)
    and the largest rates of rise and of fall of the heat with the temperature (W/K)."""
    grid: list
    ln: list
    slope: list
    largest_W: float
    rise: float
    fall: float

    def heat(self, T: float) -> tuple[float, float]:
        """(heat (W), d heat / dT (W/K)) at T (C): ln(heat) interpolated linearly between the
        grid points as np.interp does, held beyond them (rate 0 there)."""
        g = self.grid
        if T <= g[0]:
            return math.exp(self.ln[0]) - HEAT_FLOOR_W, 0.0
        if T >= g[-1]:
            return math.exp(self.ln[-1]) - HEAT_FLOOR_W, 0.0
        i = bisect_right(g, T) - 1
        e = math.exp(self.slope[i] * (T - g[i]) + self.ln[i])
        return e - HEAT_FLOOR_W, self.slope[i] * e

    def newton(self, T0: float, d: float, a: float, b: float, guess: float) -> float | None:
        """The root of f(Q) = Q - heat(T0 + d Q) in [a, b] (f(a) < 0 < f(b), f rising: one
        root) by Newton's method kept inside the bracket (a step leaving it bisects it), each
        value of f narrowing the bracket; converged when a step is below HEAT_XTOL_W +
        HEAT_RTOL |Q| or the bracket narrower; None after HEAT_NEWTON_MAX iterations."""
        Q = guess if a < guess < b else 0.5 * (a + b)
        for _ in range(HEAT_NEWTON_MAX):
            H, dH = self.heat(T0 + d * Q)
            f = Q - H
            if f == 0.0:
                return Q
            if f < 0.0:
                a = Q
            else:
                b = Q
            slope = 1.0 - d * dH
            step = f / slope if slope > 0.0 else math.inf
            new = Q - step
            if not a < new < b:
                new, step = 0.5 * (a + b), Q - 0.5 * (a + b)
            tol = HEAT_XTOL_W + HEAT_RTOL * abs(new)
            if abs(step) <= tol or b - a <= tol:
                return new
            Q = new
        return None


def part_temperatures_C(rm: RungModel, p: dict, t_s: np.ndarray, T_amb_C: np.ndarray,
                        heat_W, T_film_C: np.ndarray | None = None,
                        film_factor: np.ndarray | None = None,
                        ball_factor: np.ndarray | None = None) -> np.ndarray:
    """(n, len(PARTS)) part group mean temperatures (C) of one trial at parameters p (module
    docstring), the ambient T_amb_C and the pair's heat heat_W per row at times t_s (s,
    strictly increasing): an array (W per row, interpolated linearly between rows), a
    `HeatCurve` (the heat at the bearing's own temperature, each interval's held at its end,
    times heat_scale) or None (no heat); T_film_C: what the films see when it is not the ambient
    (a radiation sink), the mount's environment staying the ambient. ball_factor (n - 1,): the
    ball links' conductance of each interval / the model's (B_ball's: at the assembly's speed;
    the rows' speed moves the rolling contacts' constriction and film,
    `ThermalTransientFE.ball_factors`), times ball_conductance_factor; None: 1. film_factor (n - 1,): the
    films of each interval between rows / the parameter's (radiation, `radiation_film_factor`),
    held per bin (`film_levels`): the system is then piecewise constant, each piece exact; None:
    the parameter's film throughout. NaN columns: groups the stack lacks."""
    m = rm.m
    q = RungParameters.of(p)
    h_W_m2K = 1.0 / q.film_resistance_m2K_W
    h_bore = h_W_m2K * q.bore_film_ratio
    G_face, G_env, C_m = q.G_face_W_K, q.G_env_W_K, q.C_mount_J_K
    hm = G_face / rm.area_face_mm2 if rm.area_face_mm2 > 0 else 0.0
    A0 = np.zeros((m + 1, m + 1))
    A0[:m, :m] = rm.K0 + q.fit_conductance_factor * rm.C_fit + hm * rm.F_face
    B = np.zeros((m + 1, m + 1))
    B[:m, :m] = rm.B_ball
    A0[:m, m] = A0[m, :m] = -hm * rm.b_face
    A0[m, m] = G_face + G_env
    A_film = np.zeros((m + 1, m + 1))
    A_film[:m, :m] = PER_M2_TO_PER_MM2 * (h_W_m2K * rm.F_ext + h_bore * rm.F_bore)
    M = np.zeros((m + 1, m + 1))
    M[:m, :m] = rm.M
    M[m, m] = C_m
    M = 0.5 * (M + M.T)
    e_film, e_env = np.zeros(m + 1), np.zeros(m + 1)
    e_film[:m] = PER_M2_TO_PER_MM2 * (h_W_m2K * rm.b_ext + h_bore * rm.b_bore)
    e_env[m] = G_env
    amb = np.asarray(T_amb_C, float)
    # the state is the deviation from the ambient-following field (`_uniform`): the films'
    # sink, when it is not the ambient, drives it through the film's drive e_film
    film_dev = (None if T_film_C is None
                else np.broadcast_to(np.asarray(T_film_C, float), amb.shape) - amb)
    s = q.heat_scale
    e_heat = np.zeros(m + 1)
    e_heat[:m] = rm.a_heat
    curve = heat_W if isinstance(heat_W, HeatCurve) and s > 0.0 else None
    # the drive of each row, sum_j column_j (n,) x load_j (m + 1,): the heat given per row (W)
    loads = []
    if heat_W is not None and curve is None and s > 0.0:
        loads.append((s * np.asarray(heat_W, float), e_heat))
    u = _uniform(rm)
    Mu = M @ u                               # the ambient's rate drives -M u dT_amb/dt
    g_oil = np.zeros(m + 1)                  # the bearing's (oil's) temperature of a state
    g_oil[:m] = rm.groups[[PARTS.index(k) for k in OIL_PARTS]].mean(axis=0)
    G = np.zeros((len(PARTS), m + 1))        # the part means of a state
    G[:, :m] = rm.groups
    t = np.asarray(t_s, float)
    n = t.size
    factors, balls, level = _levels(film_factor, ball_factor, n)
    amb = np.broadcast_to(amb, (n,))

    def modes(lv):
        A = A0 + factors[lv] * A_film + (q.ball_conductance_factor * balls[lv] - 1.0) * B
        lam, Phi = sla.eigh(0.5 * (A + A.T), M, check_finite=False)
        return np.maximum(lam, 0.0), Phi

    def modal_drive(lv, Phi_l):
        """(n, m + 1) every row's drive of the deviation in level lv's modes."""
        out = np.zeros((n, m + 1))
        if film_dev is not None:
            out += np.outer(film_dev, factors[lv] * (e_film @ Phi_l))
        for col, load in loads:
            out += np.outer(col, load @ Phi_l)
        return out

    lv0 = int(level[0])
    lam, Phi = modes(lv0)
    g_all = modal_drive(lv0, Phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(lam > 0, 1.0 / np.where(lam > 0, lam, 1.0), 0.0)
    z = g_all[0] * inv                                                # steady first row
    Q = 0.0
    if curve is not None:            # with the heat that row's steady bearing temperature makes
        dz = s * inv * (Phi.T @ e_heat)
        Q = curve.solve(0, float(amb[0]) + g_oil @ Phi @ z, g_oil @ Phi @ dz)
        z = z + Q * dz
    Z = np.empty((n, m + 1))            # the states, each in the modes of its interval's level
    Z[0] = z
    out = np.empty((n, len(PARTS)))
    out[0] = (G @ Phi) @ z + amb[0]
    if n > 1:
        # per level: its modes and, for its intervals, the exact step's decay and drive (the
        # decay factors once per distinct interval length)
        h = np.diff(t)
        rate = np.diff(amb) / h                    # the ambient's rate per interval (K/s)
        steps, row = {}, np.empty(n - 1, int)
        for lv in np.unique(level).tolist():
            sel = np.flatnonzero(level == lv)
            lam_l, Phi_l, g = (lam, Phi, g_all) if lv == lv0 else (*modes(lv), None)
            g = modal_drive(lv, Phi_l) if g is None else g
            h_u, of = np.unique(h[sel], return_inverse=True)
            E_u, f1, f2 = _phi(np.outer(h_u, lam_l))
            of = of.reshape(-1)
            if h_u.size > 1:
                f1, f2 = f1[of], f2[of]
            ga, gb = g[sel], g[sel + 1]
            hs = h[sel, None]
            oil = g_oil @ Phi_l
            # a held heat of 1 W over the interval (the heat at its end, `HeatCurve`) and the
            # bearing's temperature it makes
            dh = (s * hs * f1) * (Phi_l.T @ e_heat) if curve is not None else None
            # the ambient's rate over the interval, held: -M u rate (1 - e^-lh) / l
            ramp = (-hs * f1) * (rate[sel, None] * (Mu @ Phi_l))
            steps[lv] = (Phi_l, [E_u[i] for i in of], hs * (ga * f1 + (gb - ga) * f2) + ramp,
                         dh,
                         oil, None if dh is None else (dh @ oil).tolist(), sel)
            row[sel] = np.arange(sel.size)
        current, Phi_c = lv0, Phi
        for k, (lv, r) in enumerate(zip(level.tolist(), row.tolist())):
            Phi_l, E, c, dh, oil, oil_d, _ = steps[lv]
            z = Z[k]
            if lv != current:                       # the state into the new level's modes
                z = Phi_l.T @ (M @ (Phi_c @ z))      # M-orthonormal: Phi^T M Phi = I
                current, Phi_c = lv, Phi_l
            nxt = Z[k + 1]                          # z_{k+1} = E z_k + c (+ Q d), in place
            np.multiply(E[r], z, out=nxt)
            nxt += c[r]
            if dh is not None:
                Q = curve.solve(k + 1, float(amb[k + 1]) + float(oil @ nxt), oil_d[r], Q)
                nxt += Q * dh[r]
        for Phi_l, *_, sel in steps.values():      # the part means, level by level
            out[sel + 1] = Z[sel + 1] @ (G @ Phi_l).T + amb[sel + 1, None]
    return out


def _uniform(rm: RungModel) -> np.ndarray:
    """(m + 1,) the augmented state of the uniform field 1 K with the mount at 1 K: the
    reduction's first vector is the uniform field (`fem.reduced_thermal.krylov_basis`), its
    coordinate 1 / its value. This state follows the ambient: A u = e_film + e_env (conduction
    and contacts carry no heat in a uniform field, F_g 1 = b_g for every film group, the
    mount's row -hm b_face . 1 + G_face + G_env = G_env), so with x = u T_amb(t) + y the
    trial integrates the deviation y, M y' + A y = heat + e_film (T_film - T_amb) -
    M u dT_amb/dt: it vanishes with the heat and the ambient's rate, and no O(T_amb) terms of
    the films' large modes cancel in it (a trial near film resistance 0 kept ~3e-7 K of their
    round-off)."""
    ok = ~np.isnan(rm.groups[:, 0])
    out = np.zeros(rm.m + 1)
    out[0] = 1.0 / rm.groups[ok, 0][0]
    out[rm.m] = 1.0
    return out


#: the most Picard passes of the radiation film (`radiating_part_temperatures_C`): the first
#: about the sink, each further one the secant at the faces' temperatures of the one before,
#: until the film's bins repeat (seed 000's cycles in vacuum: 4-5 passes at emissivity 0.3-0.8;
#: two passes left the parts 2.5-3.1 K from the fixed point)
RADIATION_PASSES_MAX = 12


def radiating_part_temperatures_C(rm: RungModel, p: dict, t_s: np.ndarray, T_amb_C: np.ndarray,
                                  heat_W: np.ndarray | None, T_film_C: np.ndarray | None,
                                  T_ref_C: float, ball_factor: np.ndarray | None = None
                                  ) -> np.ndarray:
    """`part_temperatures_C` with the films radiation (vacuum): the parameter's film is
    4 eps sigma T_ref^3 (the emissivity's, at T_ref_C), each interval's the secant eps sigma
    (T + T_s)(T^2 + T_s^2) (`radiation_film_factor`) between the sink T_s (T_film_C, else the
    ambient) and the faces' temperature T: first linearised about the sink (T = T_s), then
    at the housing's mean temperature of the pass before (the exterior faces are the housing's
    but for the shaft's ends), each interval at its mean: Picard iteration to its fixed point,
    reached when a pass's film bins (`film_bins`) are those of the pass before (the next pass
    would repeat it exactly), at most RADIATION_PASSES_MAX passes."""
    sink = np.broadcast_to(np.asarray(T_amb_C if T_film_C is None else T_film_C, float),
                           np.shape(T_amb_C))
    mid = 0.5 * (sink[:-1] + sink[1:])
    T, bins = None, None
    for _ in range(RADIATION_PASSES_MAX):
        face = None if T is None else T[:, PARTS.index("housing")]
        factor = radiation_film_factor(mid, None if face is None else 0.5 * (face[:-1] + face[1:]),
                                       T_ref_C)
        now = film_bins(factor)
        if bins is not None and np.array_equal(now, bins):
            break
        bins = now
        T = part_temperatures_C(rm, p, t_s, T_amb_C, heat_W, T_film_C, factor, ball_factor)
    return T


# ====================================================================== the candidate
#: trials kept per rung object (`ThermalTransientFE._apply`): a fit's Jacobian columns of the
#: nuisance repeat the trial at its centre
TRIALS_KEPT = 4


class ThermalTransientFE(Effect):
    """thermal_transient_fe: the part temperatures from the stack's own reduced transient
    conduction FE and a lumped mount (module docstring), written into the rows' inputs for
    every part without a measured temperature of its own."""
    name = NAME
    kind = "model_form"            # `ladder.KIND`
    parameters = ("film_resistance_m2K_W", "bore_film_ratio", "G_face_W_K", "G_env_W_K",
                  "C_mount_J_K", "fit_conductance_factor", "ball_conductance_factor",
                  "heat_scale")
    units = {"film_resistance_m2K_W": "m2 K/W", "bore_film_ratio": "-", "G_face_W_K": "W/K",
             "G_env_W_K": "W/K",
             "C_mount_J_K": "J/K", "fit_conductance_factor": "-",
             "ball_conductance_factor": "-", "heat_scale": "-"}
    requires = ("time_s", "T_ambient_C")
    cost = "inputs"
    acts_through = ("dTdt_K_per_s", "time_since_start_s", "temperature_C", "speed_rpm")
    change = ("part temperatures from the stack's reduced transient conduction FE with a lumped "
              "mount (films, mount, fit conductance and heat fitted)")
    hint = ("measure a ring or the housing temperature beside the chamber's (or the mount's): "
            "the stack's own conduction sets how each part lags the ambient and how far the "
            "bearing's heat raises it")

    def __init__(self, asm, pipeline=None):
        self.asm, self.pipeline = asm, pipeline
        vacuum = asm.thermal.gas == "vacuum"
        self.vacuum = vacuum
        # in vacuum the films are radiation: to the file's sink when it states one (the mount's
        # environment, the chamber's controlled plate, stays T_ambient_C)
        self.sink_C = (float(asm.thermal.sink_C) if vacuum and math.isfinite(asm.thermal.sink_C)
                       else None)
        area_face = _face_area_mm2(asm)
        r_max = (1.0 / (EMISSIVITY_MIN * radiation_h_W_mm2K(asm.T_ref_C) / PER_M2_TO_PER_MM2)
                 if vacuum else FILM_RESISTANCE_MAX_AIR)
        G_face_max = JOINT_CONDUCTANCE_MAX_W_M2K * area_face * PER_M2_TO_PER_MM2
        self.film_resistance_max_m2K_W, self.G_face_max_W_K = r_max, G_face_max
        G_env_max = MOUNT_AREA_MAX_M2 * MOUNT_FILM_MAX_W_M2K
        self.bounds = {"film_resistance_m2K_W": (0.0, r_max), "bore_film_ratio": (0.0, 1.0),
                       "G_face_W_K": (0.0, G_face_max),
                       "G_env_W_K": (0.0, G_env_max),
                       "C_mount_J_K": (C_MOUNT_MIN_J_K, C_MOUNT_MAX_J_K),
                       "fit_conductance_factor": FIT_FACTOR,
                       "ball_conductance_factor": BALL_FACTOR,
                       "heat_scale": (0.0, HEAT_SCALE_MAX)}
        self.off = {"film_resistance_m2K_W": 0.0, "bore_film_ratio": 1.0, "G_face_W_K": 0.0,
                    "G_env_W_K": 0.0,
                    "C_mount_J_K": C_MOUNT_MIN_J_K, "fit_conductance_factor": 1.0,
                    "ball_conductance_factor": 1.0,
                    "heat_scale": 1.0}
        self.scale = {"film_resistance_m2K_W": (0.2 if vacuum else 0.01), "bore_film_ratio": 0.1,
                      # a power-of-two share: the bound round-trips exactly through the fit's
                      # scaled coordinates (hi / s * s == hi), as the claim rules compare it
                      "G_face_W_K": G_face_max / 16.0, "G_env_W_K": 1.0,
                      "C_mount_J_K": 2000.0, "fit_conductance_factor": 0.2,
                      "ball_conductance_factor": 0.2, "heat_scale": 0.1}
        self._heat, self._balls, self._trials = Memo(4), Memo(4), Memo(TRIALS_KEPT, read_only=True)

    def bind(self, pipeline) -> "ThermalTransientFE":
        """The rung evaluated on `pipeline` (the diagnosis's, `ladder.FormRoute`); the rung of
        the same assembly unbound (the engine's candidate object) then evaluates there too."""
        out = ThermalTransientFE.__new__(ThermalTransientFE)
        out.__dict__.update(self.__dict__)
        out.pipeline, out._heat, out._balls = pipeline, Memo(4), Memo(4)
        out._trials = Memo(TRIALS_KEPT, read_only=True)
        _BOUND.put(self.asm, pipeline)
        return out

    def evaluated_on(self):
        """The pipeline the rung evaluates on: its own, the last one bound for its assembly,
        else the assembly's shared one (`Pipeline.shared`)."""
        if self.pipeline is not None:
            return self.pipeline
        hit = _BOUND.get(self.asm)
        if hit is None:
            from studies.model.pipeline import Pipeline
            hit = Pipeline.shared(self.asm)
        return hit

    _pl = evaluated_on

    def _apply(self, inputs, p, T_ref_C):
        q = RungParameters.of(p)
        if q.film_resistance_m2K_W == 0.0:       # the configured model: the form's limit
            return inputs.copy()
        pl = self._pl()
        T = self._trials.get_or_make((pl,) + self._trial_key(inputs, q),
                                     lambda: self.part_temperatures(inputs, q))
        Tc = dict(inputs.T_C)
        for i, part in enumerate(PARTS):
            if part in inputs.measured_parts:
                continue
            col = T[:, i] if not np.isnan(T[:, i]).any() else T[:, PARTS.index("shaft")]
            Tc[part] = np.array(col, float)
        return inputs.copy(T_C=Tc)

    def part_temperatures(self, inputs, q: RungParameters) -> np.ndarray:
        """(n, len(PARTS)) the trial's part means (`part_temperatures_C`, in vacuum
        `radiating_part_temperatures_C`) at the rows of `inputs`."""
        heat = self.heat_curve(inputs) if q.heat_scale > 0.0 else None
        args = (rung_model(self._pl()), q, inputs.time_s, inputs.T_ambient_C, heat, self.sink_C)
        balls = self.ball_factors(inputs)
        return (radiating_part_temperatures_C(*args, self.asm.T_ref_C, balls) if self.vacuum
                else part_temperatures_C(*args, None, balls))

    @staticmethod
    def _trial_key(inputs, q: RungParameters) -> tuple:
        """What a trial's temperatures depend on besides the pipeline: its parameters, the
        rows' times and the conditions of the heat and the ball links (`heat_curve`,
        `ball_factors`). Fits of the nuisance (a friction scale, a sensor's offset) with the
        rung's parameters held repeat it."""
        speed = np.broadcast_to(np.asarray(inputs.speed_rpm, float), np.shape(inputs.T_ambient_C))
        return (tuple(getattr(q, f.name) for f in fields(q)),
                np.asarray(inputs.time_s, float).tobytes(), _conditions_key(inputs),
                speed.tobytes())

    def ball_factors(self, inputs) -> np.ndarray | None:
        """(n - 1,) the ball links' conductance of each interval between rows over the rung
        model's (at the assembly's speed, `transient_route.contacts`): the rolling contacts'
        conductance at the speed of the interval's end row (`transient_route.ball_contacts`,
        the pair at that speed at the reference temperature, as `contacts` takes it), the sum
        of the inner and outer links'; None with one row. Kept per speeds."""
        from studies.model import transient_route as tr
        from studies.model.inputs import baseline_inputs

        speed = np.broadcast_to(np.asarray(inputs.speed_rpm, float), np.shape(inputs.T_ambient_C))
        if speed.size < 2:
            return None

        def make():
            asm, pl = self.asm, self._pl()
            T_ref = asm.T_ref_C
            speeds, at = np.unique(np.concatenate([[asm.lubrication.speed_rpm], speed[1:]]),
                                   return_inverse=True)
            base = baseline_inputs({"speed_rpm": speeds}, speeds.size, T_ref,
                                   asm.preload.assembled_N, asm.lubrication.speed_rpm)
            pair = pl.run(base, remember=False).pair
            G = np.array([sum(c.G_W_K for c in tr.ball_contacts(pl, _row_of(pair, j),
                                                                float(v), T_ref))
                          for j, v in enumerate(speeds)])
            at = at.reshape(-1)
            return G[at[1:]] / G[at[0]]
        return self._balls.get_or_make(speed.tobytes(), make)

    def heat_curve(self, inputs) -> HeatCurve:
        """The pair's friction heat per row as a function of the bearing's temperature
        (`HeatCurve`): the one route (`Pipeline.run`, `transient_route.pair_heat`) at each
        distinct set of the rows' speed, preload and loads with every part at each temperature
        of the grid (HEAT_GRID_*: the lowest ambient - 20 K .. the highest + 120 K, every 5 K);
        the configured model's friction law, its viscosity at the bearing's temperature. Kept
        per conditions."""
        from studies.model import transient_route as tr

        amb = np.asarray(inputs.T_ambient_C, float)
        cond = _heat_conditions(inputs)
        key = _conditions_key(inputs)

        def make():
            sets, row = np.unique(cond, axis=0, return_inverse=True)
            lo = float(amb.min()) - HEAT_GRID_BELOW_K
            n_T = int(np.ceil((float(amb.max()) + HEAT_GRID_ABOVE_K - lo) / HEAT_GRID_STEP_K)) + 1
            grid = lo + HEAT_GRID_STEP_K * np.arange(n_T)
            first = np.array([int(np.flatnonzero(row.reshape(-1) == j)[0])
                              for j in range(sets.shape[0])])
            take = np.repeat(first, n_T)                   # (set, temperature) rows
            T = np.tile(grid, sets.shape[0])
            at = inputs.take(take)
            at = at.copy(T_C={p: T.copy() for p in at.T_C}, T_ambient_C=T.copy())
            pl = self._pl()
            res = pl.run(at, remember=False)
            heat = np.asarray(tr.pair_heat(pl, res, at).total_W, float).reshape(sets.shape[0],
                                                                               n_T)
            return HeatCurve(grid, np.log(np.maximum(heat, 0.0) + HEAT_FLOOR_W),
                             row.reshape(-1))
        return self._heat.get_or_make(key, make)

    def describe(self) -> str:
        return "model form: " + self.change


#: the rows' conditions the pair's heat depends on besides the temperature (`heat_curve`)
HEAT_CONDITIONS = ("speed_rpm", "preload_assembled_N", "axial_load_N", "radial_load_N",
                   "moment_Nmm")


def _heat_conditions(inputs) -> np.ndarray:
    """(n, k) the rows' HEAT_CONDITIONS that the inputs give."""
    shape = np.shape(inputs.T_ambient_C)
    return np.column_stack([np.broadcast_to(np.asarray(getattr(inputs, k), float), shape)
                            for k in HEAT_CONDITIONS if getattr(inputs, k) is not None])


def _conditions_key(inputs) -> bytes:
    """The key of a `heat_curve`: the rows' heat conditions and ambient."""
    return _heat_conditions(inputs).tobytes() + np.asarray(inputs.T_ambient_C, float).tobytes()


def _row_of(pair, j: int):
    """Point j of a pair state (`analytic.bearing.state.take_rows`) as a one-point state."""
    from analytic.bearing.state import take_rows

    return take_rows(pair, np.array([j]))


def _face_area_mm2(asm) -> float:
    """Area (mm^2) of the housing's outer face, 2 pi r L (`meshes.section.boundary_lines`)."""
    from meshes.section import boundary_lines
    from studies.model.stack import section_from_assembly

    lines = boundary_lines(section_from_assembly(asm))
    if MOUNT_FACE not in lines:
        return 0.0
    _, r, z0, z1 = lines[MOUNT_FACE]
    return 2.0 * math.pi * float(r) * abs(float(z1) - float(z0))


def speed_varies(conditions) -> bool:
    """True when the conditions' speed column varies (the heat is then fitted)."""
    v = conditions.get("speed_rpm")
    return v is not None and float(np.ptp(np.asarray(v, float))) > 0.0


#: the heat scale is fitted at a constant speed where the pair's heat at the lowest ambient
#: would raise the stack by more than this (K) in a film of HEAT_MATTERS_FILM_W_M2K on its
#: outside faces: the heat then changes with the bearing's temperature over the record (an
#: oil's viscous heat) and shapes the history; below it the heat's rise is a constant the
#: films and the mount trade against each other
HEAT_MATTERS_K = 1.0
HEAT_MATTERS_FILM_W_M2K = 20.0


def heat_matters(effect, conditions) -> bool:
    """Whether the pair's heat at the conditions' lowest ambient (`ThermalTransientFE.
    heat_curve`) raises the stack by more than HEAT_MATTERS_K in a HEAT_MATTERS_FILM_W_M2K film
    over its outside faces (Q / (h A), the steady rise of a lumped body, Incropera eq. 1.3a)."""
    from studies.model.inputs import baseline_inputs

    amb = conditions.get("T_ambient_C")
    if amb is None:
        return False
    asm = effect.asm
    n = len(amb)
    inputs = baseline_inputs(dict(conditions), n, asm.T_ref_C, asm.preload.assembled_N,
                             asm.lubrication.speed_rpm)
    curve = effect.heat_curve(inputs)
    k = int(np.argmin(np.asarray(amb, float)))
    rm = rung_model(effect.evaluated_on())
    ok = ~np.isnan(rm.groups[:, 0])
    # the reduction's first vector is the uniform field (`fem.reduced_thermal.krylov_basis`):
    # every part's mean the same per unit of its coordinate
    area_mm2 = float((rm.b_ext[0] + rm.b_bore[0]) / rm.groups[ok, 0][0])
    G_W_K = HEAT_MATTERS_FILM_W_M2K * PER_M2_TO_PER_MM2 * area_mm2
    return curve.heat_W(k, float(amb[k])) / G_W_K > HEAT_MATTERS_K


def held_fixed(effect, conditions) -> tuple[str, ...]:
    """`fitspec.held_fixed` of the rung: the heat scale at 1 when the speed is constant and the
    heat does not matter (`heat_matters`); the
    fits' conductance factor at 1 where it cannot move the stack's time constants
    (`RungModel.fit_matters`); the bore's film ratio where the shaft has no bore."""
    held = () if speed_varies(conditions) or heat_matters(effect, conditions) else ("heat_scale",)
    rm = rung_model(effect.evaluated_on())
    if not rm.fit_matters:
        held += ("fit_conductance_factor",)
    if not rm.ball_matters:
        held += ("ball_conductance_factor",)
    if not np.any(rm.b_bore):
        held += ("bore_film_ratio",)
    return held


def starts(effect, conditions, T_ref_C) -> list[dict]:
    """Starting points (`fitspec.starts`): films from forced to natural convection (in vacuum
    emissivities 0.8 to 0.1), each without and with a mount of one to ten stacks' capacity
    well coupled to the face and the environment."""
    hi = effect.film_resistance_max_m2K_W
    rs = ([1.0 / 100.0, 1.0 / 20.0, 1.0 / 5.0] if not effect.vacuum
          else [hi * EMISSIVITY_MIN / e for e in (0.8, 0.3, 0.1)])
    G = effect.G_face_max_W_K
    out = []
    for r in rs:
        out.append({"film_resistance_m2K_W": r})
        for C in (2000.0, 20000.0):
            out.append({"film_resistance_m2K_W": r, "G_face_W_K": 0.1 * G, "G_env_W_K": 2.0,
                        "C_mount_J_K": C})
    return out

"""A second source of measured data: data made another way than the model the diagnosis fits,
for the tests and the confusion-matrix study.

Every hidden-effect test before this module built its "measured" data with the diagnosed model
itself (the same pipeline, mesh and effect code), so its rates were those of a perfectly specified
model. Here each case's data differ from the diagnosed model the way a real rig does, by one stated
mechanism (or two), with the label of the true cause kept beside the data:

- model form (`kind = "model_form"`): a finer mesh with direct (non-superposed) FE solves (a null:
  discretisation only); quasi-dynamic balls under a static config; grooved ring sections under a
  rectangle config; a steel sleeve, a spring preload, an unlogged moment, a housing material lot
  with another CTE, all of which the config lacks; a friction law of another form (exponential in
  the ring temperature where the listed effect is linear); a different inner groove curvature (the
  ladder's `groove_conformity` rung); an inner fit 2.5 um outside its ISO band (on the finer mesh
  with direct solves: right when nothing is claimed and `at_bound` names the fit error,
  `CaseSpec.lead`); a hidden sleeve, 3 mm 17-4PH sleeve in a 6061 housing the file
  has without a sleeve (finer mesh, direct solves);
- listed (`"listed"`): a listed cause made on another model than the diagnosed one (the inner fit
  5 um tighter on a finer mesh with direct FE solves);
- history (`"history"`): part temperatures from the transient conduction FE of the stack
  (`fem.transient`, full FE, films on every face: `transient_fe_temperatures`) or from a two-node network
  (housing side from the chamber, rotor side from the housing side: a series of two first-order
  systems, `network_temperatures`) in place of the one-constant `thermal_lag`; two causes at once
  (`"multiple"`: a 4 um fit error and a 1500 s lag; and, made another way, on the finer mesh
  with direct FE solves, `PAIRS`: a fit error and a lag, a housing material lot and a preload
  settling, a preload-path compliance and a solid-film run-in, each cause alone 5 sigma or
  more, `Case.cause_sigma`);
- noise (`"noise"`): nulls with AR(1) noise of phi 0.9 and 0.95 at 120 s, spikes, quantisation;
- sensor (`"sensor"`): a torque-sensor zero drift linear in time (unlisted), a chamber
  thermometer offset within its data-sheet class.

The diagnosed model is the shipped assembly (or the case's stated config) on the pipeline of
`mesh_factor`; the truth is made on its own pipeline (`Pipeline.shared` of the truth assembly,
the same mesh family unless the case says otherwise), always through the one route
(`Pipeline.run`, columns by `columns.to_columns`), with the rig's friction MU_TRUE x the
configured one (the baseline's nuisance calibration has to absorb it).

Noise: the stated level of a column is NOISE_SHARE (1 %) of its mean absolute noise-free value
(a good rig's torque and load cells, as the same-model study), white Gaussian unless the case
states AR(1) (marginal standard deviation = the level), spikes or a quantisation step.

API (stable; `diag` and `ladder` helpers build on it):

    CASES                        name -> CaseSpec(kind, design, truth, right, text)
    KINDS                        ("model_form", "listed", "history", "multiple", "noise", "sensor")
    DESIGNS                      design name -> (shipped assembly key, conditions function)
    make_case(name, seed=0, mesh_factor=1.0) -> Case     the data of one trial (cached truth)
    diagnose_case(case, workers=1) -> DiagnosisResult    today's engine as `diagnose` runs it
    judge(case, verdict, causes, rivals=()) -> str       one of OUTCOMES
    judge_result(case, result) -> str                    judge of a DiagnosisResult
    interval_coverage(case, result) -> (inside, entries) the claimed interval on a repeat draw
    named_causes(result) -> list[str]                    the causes a result names
    Case: name, kind, design, seed, truth, right, assembly, conditions, measured, noise_free,
          sigma, noise, change_sigma, text; Case.columns, Case.table(), Case.visible
    Noise, add_noise, ar1, lag1_autocorrelation, network_temperatures,
    transient_fe_temperatures, FILMS_W_M2K

Truth labels (`Case.truth`): listed effect names (`thermal_lag`, `interference_error`,
`friction_temperature`), the model-form candidate names of docs/cli.md ("Added for the next
round": `ball_model_quasi_dynamic`, `ring_section_grooved`, `sleeve`, `preload_spring`,
`material_lot`, `unlogged_load`, `fits_in_band`, `groove_conformity`), or names of causes
nothing in the tool models (`sensor_drift`, `sensor_offset`). `Case.right` is what a diagnosis may name
and be right: a cause counts by its family (`thermal_lag.per_part` is `thermal_lag`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy import optimize, signal

from infra.memo import Memo, inputs_key
from studies.diagnosis.designs import cycles, speed_steps

#: the rig's friction coefficient relative to the configured one (nuisance, unknown to the tool)
MU_TRUE = 1.2
#: stated noise level: this share of a column's mean absolute noise-free value
NOISE_SHARE = 0.01
#: measured columns of every case
COLUMNS = ("torque_Nmm", "preload_N")
#: a truth is visible when its largest change against the refitted baseline is this many sigma
VISIBLE_SIGMA = 3.0
#: film coefficient of every face of the stack in the transient FE case (W/(m^2 K)): free
#: convection in a gas-filled climate chamber (Incropera ch. 9: 2..25 W/(m^2 K) for gases)
FILMS_W_M2K = (("*", 15.0),)
#: the transient FE case's time step (s): BDF2, against the stack's lumped time constant of
#: about 15 min
TRANSIENT_DT_S = 10.0

KINDS = ("model_form", "listed", "history", "multiple", "noise", "sensor")
#: outcome of one trial (`judge`)
OUTCOMES = ("right", "named", "partial", "unexplained", "missed", "false_alarm", "wrong")


def steady_grid() -> dict[str, np.ndarray]:
    """Seed 000 steady points without time: T_ambient -60..80 C in 20 K steps x assembled preload
    50, 100, 200, 350 N, every point measured twice (64 rows)."""
    T, P = np.meshgrid(np.arange(-60.0, 81.0, 20.0), np.array([50.0, 100.0, 200.0, 350.0]),
                       indexing="ij")
    return {"T_ambient_C": np.repeat(T.ravel(), 2), "preload_assembled_N": np.repeat(P.ravel(), 2)}


def thin_cycles(n: int = 240, dt: float = 120.0) -> dict[str, np.ndarray]:
    """The thin-section rig's range (-45..+60 C): from 20 C to +60, -45, +60, back to
    20 C at 2 K/min with one-hour dwells, sampled every `dt` s (240 x 120 s = 8 h)."""
    t = np.arange(n) * dt
    leg = [(60.0, 20), (60.0, 60), (-45.0, 52), (-45.0, 60), (60.0, 52), (60.0, 60),
           (20.0, 20), (20.0, 30)]                          # (set point C, minutes)
    kt, kT = [0.0], [20.0]
    while kt[-1] < t[-1]:
        for T, minutes in leg:
            kt.append(kt[-1] + 60.0 * minutes)
            kT.append(T)
    return {"time_s": t, "T_ambient_C": np.interp(t, kt, kT)}


#: design -> (shipped assembly, conditions the diagnosis is given)
DESIGNS: dict[str, tuple[str, Callable[[], dict]]] = {
    "thin_cycles": ("rig_thin_section_hub.toml", thin_cycles),  # the thin-section rig
    "cycles": ("seed000", cycles),             # -60 <-> 80 C, 240 rows x 120 s
    "steady_grid": ("seed000", steady_grid),   # T x preload, 64 rows, no time
    "speed_steps": ("seed001", speed_steps),   # 0..60 C steps at 6000/3000/9000 rpm, 240 x 120 s
}


# ============================================================================ noise and sensors
def ar1(rng: np.random.Generator, n: int, sigma: float, phi: float) -> np.ndarray:
    """Stationary AR(1) noise e_k = phi e_(k-1) + w_k of marginal standard deviation sigma
    (w white, std sigma sqrt(1 - phi^2); e_0 from the stationary law). Box, Jenkins & Reinsel,
    Time Series Analysis, ch. 3.2.4."""
    if not 0.0 <= phi < 1.0:
        raise ValueError(f"phi must lie in [0, 1), got {phi}")
    w = rng.normal(0.0, sigma * math.sqrt(1.0 - phi * phi), n)
    w[0] = rng.normal(0.0, sigma)
    return signal.lfilter([1.0], [1.0, -phi], w)


def lag1_autocorrelation(x: np.ndarray) -> float:
    """Sample lag-1 autocorrelation r1 = sum (x_k - m)(x_(k+1) - m) / sum (x_k - m)^2 (Box,
    Jenkins & Reinsel ch. 2.1.5); its large-sample standard error for AR(1) is
    sqrt((1 - phi^2) / n) (Bartlett's formula, ibid. ch. 2.1.6)."""
    x = np.asarray(x, float) - np.mean(x)
    return float(np.dot(x[:-1], x[1:]) / np.dot(x, x))


@dataclass(frozen=True)
class Noise:
    """What the rig adds to the noise-free truth, per measured column (column units).

    sigma: marginal standard deviation; phi: AR(1) coefficient per row (0 = white); spikes:
    number of spikes in the first column, sizes uniform in spike_sigma x sigma, random sign;
    quantum: the reading's resolution (the value is rounded to it); drift: a zero drift linear
    in time (rows when there is no time column) from 0 to this value at the last row; offset: a
    constant zero offset."""
    sigma: Mapping[str, float]
    phi: float = 0.0
    spikes: int = 0
    spike_sigma: tuple[float, float] = (50.0, 150.0)
    quantum: Mapping[str, float] = field(default_factory=dict)
    drift: Mapping[str, float] = field(default_factory=dict)
    offset: Mapping[str, float] = field(default_factory=dict)


def add_noise(truth: Mapping[str, np.ndarray], noise: Noise, rng: np.random.Generator,
              time_s: np.ndarray | None = None) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """(measured columns, 1-based rows of the spikes) of noise-free columns (`Noise`)."""
    out = {}
    spikes = np.zeros(0, int)
    for i, (c, v) in enumerate(truth.items()):
        v = np.asarray(v, float)
        n = v.size
        s = noise.sigma[c]
        e = ar1(rng, n, s, noise.phi) if noise.phi > 0 else rng.normal(0.0, s, n)
        m = v + e + noise.offset.get(c, 0.0)
        if c in noise.drift:
            t = np.asarray(time_s, float) if time_s is not None else np.arange(n, dtype=float)
            m = m + noise.drift[c] * (t - t[0]) / (t[-1] - t[0])
        if i == 0 and noise.spikes:
            spikes = rng.choice(n, noise.spikes, replace=False)
            m[spikes] += rng.choice([-1.0, 1.0], noise.spikes) * rng.uniform(
                *noise.spike_sigma, noise.spikes) * s
        if c in noise.quantum:
            q = noise.quantum[c]
            m = q * np.round(m / q)
        out[c] = m
    return out, np.sort(spikes) + 1


# ============================================================================ temperature sources
def network_temperatures(time_s: np.ndarray, T_ambient_C: np.ndarray, tau_outer_s: float = 600.0,
                         tau_rotor_s: float = 240.0) -> dict[str, np.ndarray]:
    """Part temperatures of a two-node network: the outer node (housing, outer rings, outer
    spacer) exchanges with the chamber, tau_o dT_o/dt = T_amb - T_o; the rotor node (shaft,
    inner rings, inner spacer) only with the outer node through the bearings,
    tau_r dT_r/dt = T_o - T_r; the balls at the mean of the two. Lumped capacitance per node
    (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, ch. 5.1-5.3; the rotor's
    capacity small against the housing's, so the outer node is not loaded by it). Integrated
    exactly for the ambient piecewise linear between samples (`scipy.signal.lsim`, matrix
    exponential with linear interpolation of the input), starting in equilibrium. Unlike the
    `thermal_lag` effect (one constant, every part alike) the parts lag differently and the rotor
    by a second-order response: on a ramp of rate a the outer node trails by a tau_o and the
    rotor by a (tau_o + tau_r) (the delays of a series of first-order systems add)."""
    t = np.asarray(time_s, float)
    u = np.asarray(T_ambient_C, float)
    A = np.array([[-1.0 / tau_outer_s, 0.0], [1.0 / tau_rotor_s, -1.0 / tau_rotor_s]])
    B = np.array([[1.0 / tau_outer_s], [0.0]])
    sys = signal.StateSpace(A, B, np.eye(2), np.zeros((2, 1)))
    _, y, _ = signal.lsim(sys, u, t - t[0], X0=[u[0], u[0]], interp=True)
    To, Tr = y[:, 0], y[:, 1]
    return {"T_housing_C": To, "T_outer_ring_C": To, "T_spacer_C": 0.5 * (To + Tr),
            "T_shaft_C": Tr, "T_inner_ring_C": Tr, "T_ball_C": 0.5 * (To + Tr)}


def shaft_side_lag(time_s: np.ndarray, T_ambient_C: np.ndarray,
                   tau_shaft_s: float) -> dict[str, np.ndarray]:
    """Part temperatures with the housing side (housing, sleeve, outer rings, spacers) at the
    chamber and the shaft side (shaft, inner rings, balls) a first-order lag tau_shaft_s behind
    it, made another way than `thermal_lag.lag_response` (the exact solution for an
    ambient piecewise linear): the backward-Euler recursion on a 1 s grid (Incropera ch. 5.3
    lumped body), sampled at the rows. The spacers follow the housing side (the inner spacer
    lies on the shaft side in the stack, but one `T_spacer_C` column serves both)."""
    t = np.asarray(time_s, float)
    u = np.asarray(T_ambient_C, float)
    fine = np.arange(t[0], t[-1] + 0.5, 1.0)
    uf = np.interp(fine, t, u)
    a = 1.0 / (1.0 + 1.0 / float(tau_shaft_s))       # backward Euler, h = 1 s
    y = signal.lfilter([1.0 - a], [1.0, -a], uf, zi=[a * uf[0]])[0]
    Ts = np.interp(t, fine, y)
    return {"T_housing_C": u.copy(), "T_outer_ring_C": u.copy(), "T_spacer_C": u.copy(),
            "T_shaft_C": Ts, "T_inner_ring_C": Ts, "T_ball_C": Ts}


def transient_asm(asm):
    """The assembly in transient mode with FILMS_W_M2K on every face (the stack in a chamber)."""
    from studies.model.config import Thermal

    return replace(asm, thermal=Thermal(mode="transient", films=FILMS_W_M2K))


def transient_fe_temperatures(asm, time_s: np.ndarray, T_ambient_C: np.ndarray,
                              mesh_factor: float = 1.0) -> dict[str, np.ndarray]:
    """Part temperature columns T_<part>_C (volume means of the `inputs.PARTS` groups, the balls
    at their ball nodes) of the stack in a chamber following T_ambient_C: the full transient
    conduction FE (`fem.transient.TransientConduction` as the transient route builds it,
    `transient_route.thermal_model`: contact conductances of the fits from the assembled fit
    pressures, ball nodes linked by Hertz-constriction conductances), films FILMS_W_M2K on every
    face, BDF2 with step TRANSIENT_DT_S (`fem.transient.Stepper`), starting uniform at the first
    row's ambient; the ambient linear between rows. No friction heat: seed 000's pair at 60 rpm
    makes about 2 N mm x 6.3 rad/s = 0.013 W, against 15 W/(m^2 K) x 0.02 m^2 x 1 K = 0.3 W per
    kelvin of the stack above the chamber (a rise below 0.05 K). (The coupled route,
    `transient_route.run_transient`, cannot run seed 000 today: its pair solve fails at rest on a
    stack with a clearance fit, one line per row.)"""
    key = inputs_key({"asm": repr(asm), "mesh_factor": float(mesh_factor), "t": time_s,
                      "T": T_ambient_C})
    return {k: v.copy() for k, v in _TEMPERATURES.get_or_make(
        key, lambda: _transient_fe(asm, time_s, T_ambient_C, mesh_factor)).items()}


#: transient FE temperatures by their exact inputs (the tests and the study ask twice)
_TEMPERATURES = Memo(max_items=4)


def _transient_fe(asm, time_s, T_ambient_C, mesh_factor) -> dict[str, np.ndarray]:
    """The work of `transient_fe_temperatures`."""
    from fem.transient import StepLoads, Stepper
    from studies.model.inputs import PARTS
    from studies.model.pipeline import Pipeline
    from studies.model.transient_route import thermal_model

    pl = Pipeline.shared(transient_asm(asm), mesh_factor=mesh_factor, progress=lambda s: None)
    tm = thermal_model(pl)
    t = np.asarray(time_s, float)
    u = np.asarray(T_ambient_C, float)
    k = max(1, int(np.ceil((t[-1] - t[0]) / TRANSIENT_DT_S - 1e-9)))
    grid = t[0] + (t[-1] - t[0]) * np.arange(k + 1) / k
    st = Stepper(tm.tc, tm.nominal, grid[1] - grid[0], float(u[0]))
    G = np.empty((grid.size, len(PARTS)))
    G[0] = tm.group_rows @ st.T
    amb = np.interp(grid, t, u)
    for i in range(1, grid.size):
        G[i] = tm.group_rows @ st.step(StepLoads(float(amb[i])))
    return {f"T_{p}_C": np.interp(t, grid, G[:, j]) for j, p in enumerate(PARTS)
            if not np.isnan(G[:, j]).any()}


# ============================================================================ cases
@dataclass(frozen=True)
class CaseSpec:
    """What a case is before any data: kind (KINDS), design (DESIGNS), truth (labels of the
    hidden causes, () = none), right (causes a diagnosis may name and be right), text."""
    kind: str
    design: str
    truth: tuple[str, ...]
    right: tuple[str, ...]
    text: str
    #: a truth beyond its candidate's bounds: the candidate that must be named in `at_bound`
    #: of a diagnosis that claims nothing (`judge_result`)
    lead: str | None = None


@dataclass(frozen=True)
class Case:
    """One trial's data and its label.

    assembly: the config the diagnosis is given (`studies.model.config.Assembly`); conditions:
    the condition columns it is given; measured: the measured columns (noise and sensor errors
    included); noise_free: the truth before them; sigma: the stated noise level per column;
    change_sigma: largest |truth - baseline| / sigma over the measured entries, the baseline the
    diagnosed model with its friction calibration refitted (what the data can show);
    spike_rows: 1-based rows of injected spikes; mesh_factor: the diagnosed pipeline's."""
    name: str
    kind: str
    design: str
    seed: int
    truth: tuple[str, ...]
    right: tuple[str, ...]
    assembly: object
    conditions: dict[str, np.ndarray]
    measured: dict[str, np.ndarray]
    noise_free: dict[str, np.ndarray]
    sigma: dict[str, float]
    noise: Noise
    change_sigma: float
    text: str
    spike_rows: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    mesh_factor: float = 1.0
    #: two causes made another way (`PAIRS`): each cause's change alone, as `change_sigma`
    #: (the data made with it alone, the same way, against the refitted baseline)
    cause_sigma: dict[str, float] = field(default_factory=dict)

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(self.measured)

    @property
    def visible(self) -> bool:
        """Whether the truth changes the data by VISIBLE_SIGMA or more (nulls: False)."""
        return bool(self.truth) and self.change_sigma >= VISIBLE_SIGMA

    def table(self) -> dict[str, np.ndarray]:
        """The measured table as `diagnose` reads it: conditions then measured columns."""
        return {**self.conditions, **self.measured}


def _lot(asm, part_attr: str, factor: float):
    """The assembly with the housing (or another part's) material replaced by a lot whose CTE is
    `factor` x the library value."""
    from analytic.materials import get_material

    sec = getattr(asm, part_attr)
    base = get_material(sec.material, asm.materials)
    lot = replace(base, name=f"{base.name}_lot", alpha_per_K=base.alpha_per_K * factor)
    return replace(asm, materials=(*asm.materials, lot), **{part_attr: replace(sec, material=lot.name)})


def _sleeve(asm, thickness_mm: float = 2.0, material: str = "9Cr18"):
    """The assembly with a steel sleeve of `thickness_mm` between the outer rings and the
    housing (`sleeve_rung.sleeve_assembly`: the housing bore opened by 2 x the thickness; the
    sleeve's fit in the housing 0)."""
    from studies.diagnosis.sleeve_rung import sleeve_assembly

    return sleeve_assembly(asm, material, thickness_mm)


def _aluminium_housing(asm, material: str = "6061"):
    """The assembly with an aluminium alloy housing (6061-T6, `analytic.materials`) in place of
    the file's."""
    return replace(asm, housing=replace(asm.housing, material=material))


def _banded(asm):
    """Seed 000 with tolerance classes on every fit surface (ISO 286 js4 shaft, JS4 housing,
    ISO 492 P4 rings): the diagnosis then bounds the fit offsets by the band."""
    return replace(asm, fits=replace(asm.fits, inner_shaft_class="js4", inner_ring_bore_class="P4",
                                     outer_housing_class="JS4", outer_ring_od_class="P4"))


def _beyond_band_um(asm, beyond_um: float = 2.5) -> float:
    """The inner fit offset (um, from the mean fit) `beyond_um` tighter than the band's edge."""
    from studies.model.tolerances import worst_case_bands

    band = next(b for b in worst_case_bands(asm) if b.fit == "inner")
    return band.upper_um - asm.mean_fits_um()[0] + beyond_um


def _friction_exp(b_per_K: float = 6e-3):
    """A friction law of another form: mu = mu_cal exp(-b (T_rings - T_ref)) (MoS2 friction
    rises in the cold: Roberts, Tribology International 23 (1990) 95-104, fig. 8, about x1.5
    from 20 to -100 C in vacuum); the listed `friction_temperature` is linear in T_rings."""
    def law(inp, mu_cal, T_ref_C):
        T_r = 0.5 * (np.asarray(inp.T_C["inner_ring"], float)
                     + np.asarray(inp.T_C["outer_ring"], float))
        return mu_cal * np.exp(-b_per_K * (T_r - T_ref_C))
    return law


#: name -> CaseSpec (the builders are in `_truth`)
CASES: dict[str, CaseSpec] = {
    "finer_mesh_direct": CaseSpec(
        "model_form", "cycles", (), (),
        "truth on a finer mesh (0.7 x the element sizes) with direct FE solves; nothing hidden"),
    "quasi_dynamic_balls": CaseSpec(
        "model_form", "speed_steps", ("ball_model_quasi_dynamic",), ("ball_model_quasi_dynamic",),
        "quasi-dynamic balls (centrifugal force, gyroscopic moment) under a static config"),
    "grooved_sections": CaseSpec(
        "model_form", "cycles", ("ring_section_grooved",), ("ring_section_grooved",),
        "rings with their grooves and lands under a rectangle-section config"),
    "steel_sleeve": CaseSpec(
        "model_form", "cycles", ("sleeve",), ("sleeve",),
        "the outer rings in a 2 mm 9Cr18 sleeve in the TC4 housing; the config has none"),
    "spring_preload": CaseSpec(
        "model_form", "cycles", ("preload_spring",), ("preload_spring", "preload_path_compliance"),
        "a spring preload (constant force) under a position-preload config (a preload path "
        "compliant without limit: `preload_path_compliance` names the same mechanism)"),
    "unlogged_moment": CaseSpec(
        "model_form", "steady_grid", ("unlogged_load",), ("unlogged_load",),
        "a constant tilting moment of 5000 N mm nobody logged"),
    "housing_lot": CaseSpec(
        "model_form", "cycles", ("material_lot",), ("material_lot",),
        "a TC4 housing lot with a CTE 3 % below the library's 9.0e-6 /K (8.73e-6 /K, inside the "
        "data sheets' 8.6..9.0e-6 /K for 20-100 C and the material_lot rung's scatter, "
        "ladder.CTE_LOT_SCATTER +-5 %)"),
    "housing_lot_beyond": CaseSpec(
        "model_form", "cycles", ("material_lot_beyond_scatter",), (),
        "a TC4 housing lot with a CTE 6 % above the library's, beyond the scatter the "
        "material_lot rung allows (+-5 %): no candidate covers it, so no cause may be claimed "
        "(the lot at its edge is the lead)"),
    "friction_law_exp": CaseSpec(
        "model_form", "cycles", ("friction_temperature",), ("friction_temperature",),
        "friction exponential in the ring temperature (6e-3 /K) where the listed law is linear"),
    "groove_curvature": CaseSpec(
        "model_form", "steady_grid", ("groove_conformity",), ("groove_conformity",),
        "inner groove curvature ratio 0.54 instead of the file's 0.52, made on a finer "
        "mesh (0.7 x) with direct FE solves: the ladder's groove_conformity rung (inner ratio "
        "0.51..0.56)"),
    "fit_outside_band": CaseSpec(
        "model_form", "steady_grid", ("interference_error",), (),
        "a config with ISO tolerance classes; the inner fit 2.5 um tighter than its band allows, "
        "made on a finer mesh (0.7 x) with direct FE solves: the fit error can reach "
        "only the band's edge, so it may not be claimed and must be named in `at_bound`",
        lead="interference_error"),
    "sleeve_in_aluminium": CaseSpec(
        "model_form", "cycles", ("sleeve",), ("sleeve",),
        "a hidden sleeve: 3 mm 17-4PH between the outer rings and a 6061 "
        "aluminium housing, the file has the aluminium housing and no sleeve; made on a finer "
        "mesh (0.7 x) with direct FE solves (a fit error would need more than its +-20 um)"),
    "fit_error_finer_mesh": CaseSpec(
        "listed", "cycles", ("interference_error",), ("interference_error", "fits_in_band"),
        "the listed cause made on another model: the inner fit 5 um tighter, the truth on a "
        "finer mesh (0.7 x the element sizes) with direct FE solves"),
    "transient_fe_lag": CaseSpec(
        "history", "cycles", ("thermal_lag",), ("thermal_lag",),
        "part temperatures from the transient conduction FE of the stack in a chamber "
        f"(films {FILMS_W_M2K[0][1]:g} W/m2K) instead of the one-constant lag"),
    "network_lag": CaseSpec(
        "history", "cycles", ("thermal_lag",), ("thermal_lag",),
        "part temperatures from a two-node network (housing side 600 s from the chamber, rotor "
        "240 s from the housing side)"),
    "fit_error_and_lag": CaseSpec(
        "multiple", "cycles", ("interference_error", "thermal_lag"),
        ("interference_error", "thermal_lag", "fits_in_band"),
        "two causes at once: the inner fit 4 um tighter and a 1500 s thermal lag"),
    # two causes at once, made another way: each pair on the finer mesh (0.7 x)
    # with direct FE solves, each cause alone changing the data by 5 sigma or more
    # (`Case.cause_sigma`); the right names of each pair's causes only
    "fit_error_lag_finer": CaseSpec(
        "multiple", "cycles", ("interference_error", "thermal_lag"),
        ("interference_error", "thermal_lag", "fits_in_band"),
        "two causes made another way: the inner fit 5 um tighter and a 1500 s thermal lag, the "
        "truth on a finer mesh (0.7 x) with direct FE solves"),
    "lot_settling_finer": CaseSpec(
        "multiple", "cycles", ("material_lot", "preload_settling"),
        ("material_lot", "preload_settling"),
        "two causes made another way: a TC4 housing lot with a CTE 3 % below the library's (a "
        "material of its own) and the preload settling by 8 N beyond a 50 K excursion, on a "
        "finer mesh (0.7 x) with direct FE solves"),
    "compliance_runin_finer": CaseSpec(
        "multiple", "cycles", ("preload_path_compliance", "solid_film_runin"),
        ("preload_path_compliance", "solid_film_runin", "preload_spring"),
        "two causes made another way: 10 um/kN more compliance in the preload path and a "
        "solid-film run-in of the friction coefficient by -0.006 over 10 krev, on a finer mesh "
        "(0.7 x) with direct FE solves"),
    "shaft_lag_numpy": CaseSpec(
        "history", "thin_cycles", ("thermal_lag",), ("thermal_lag",),
        "the shaft, inner rings and balls lag 900 s behind the hub, which follows "
        "the chamber; the lag made in numpy (a first-order filter, `shaft_side_lag`), the "
        "temperatures fed to the finer mesh (0.7 x) with direct FE solves"),
    "ar1_090_null": CaseSpec(
        "noise", "cycles", (), (), "nothing hidden; AR(1) noise phi 0.9 at 120 s"),
    "ar1_095_null": CaseSpec(
        "noise", "cycles", (), (), "nothing hidden; AR(1) noise phi 0.95 at 120 s"),
    "spikes_quantised_null": CaseSpec(
        "noise", "cycles", (), (),
        "nothing hidden; 6 torque spikes of 50..150 sigma, readings quantised to 1.5 sigma"),
    "torque_drift": CaseSpec(
        "sensor", "cycles", ("sensor_drift",), (),
        "a torque-sensor zero drift linear in time, 6 sigma over the 8 h"),
    "chamber_offset": CaseSpec(
        "sensor", "cycles", ("sensor_offset",), (),
        "the chamber thermometer reads 0.5 K high (IEC 60751 class B: +-(0.3 + 0.005 |t|) K); made "
        "on a finer mesh (0.7 x) with direct FE solves"),
}

#: the truth's noise-free columns and its pipelines are the same for every seed: kept here
_TRUTH_CACHE: dict[tuple, tuple] = {}


def _pipeline(asm, mesh_factor: float, superpose: bool = True):
    from studies.model.pipeline import Pipeline

    if superpose:
        return Pipeline.shared(asm, mesh_factor=mesh_factor, progress=lambda s: None)
    return Pipeline(asm, mesh_factor=mesh_factor, superpose=False, progress=lambda s: None)


def _run(asm, mesh_factor, conditions, effects=None, friction=None, direct=False,
         superpose=True, ball_model=None) -> dict[str, np.ndarray]:
    """Noise-free measured columns of the truth through the one route, friction MU_TRUE x the
    configured coefficient (or `friction(inputs, mu_cal, T_ref_C)` per row)."""
    from studies.diagnosis.files import ModelPredictor
    from studies.model.columns import to_columns

    pl = _pipeline(asm, mesh_factor, superpose)
    pred = ModelPredictor(pl, conditions, COLUMNS)
    inp = pred.inputs(effects or {}, {"mu_scale": MU_TRUE})
    if friction is not None:
        mu0 = asm.lubrication.friction_coefficient
        inp = inp.copy(friction_coefficient=friction(inp, MU_TRUE * mu0, asm.T_ref_C) - mu0)
    out = to_columns(pl.run(inp, direct=direct, ball_model=ball_model), flags=False)
    return {c: np.asarray(out[c], float) for c in COLUMNS}


def design_assembly(design: str):
    """The assembly a design is diagnosed with: a shipped one by its key (`SHIPPED`), else a
    file of studies/configs by its name."""
    from studies.model.config import CONFIG_DIR, SHIPPED, load_assembly, load_shipped

    key = DESIGNS[design][0]
    return load_shipped(key) if key in SHIPPED else load_assembly(CONFIG_DIR / key)


def _truth(name: str, mesh_factor: float):
    """(diagnosed assembly, conditions given, noise-free truth, Noise without sigma) of a case."""
    spec = CASES[name]
    _, make = DESIGNS[spec.design]
    asm = design_assembly(spec.design)
    cond = make()
    mf = mesh_factor
    noise: dict = {}
    if name == "finer_mesh_direct":
        truth = _run(asm, 0.7 * mf, cond, direct=True)
    elif name == "quasi_dynamic_balls":
        truth = _run(asm, mf, cond, ball_model="quasi_dynamic")
    elif name == "grooved_sections":
        truth = _run(replace(asm, mesh=replace(asm.mesh, ring_section="grooved")), mf, cond)
    elif name == "steel_sleeve":
        truth = _run(_sleeve(asm), mf, cond)
    elif name == "spring_preload":
        truth = _run(replace(asm, preload=replace(asm.preload, kind="spring")), mf, cond)
    elif name == "unlogged_moment":
        truth = _run(asm, mf, {**cond, "moment_Nmm": np.full(len(cond["T_ambient_C"]), 5000.0)})
    elif name == "housing_lot":
        truth = _run(_lot(asm, "housing", 0.97), mf, cond)
    elif name == "housing_lot_beyond":
        truth = _run(_lot(asm, "housing", 1.06), mf, cond)
    elif name == "fit_error_finer_mesh":
        truth = _run(asm, 0.7 * mf, cond, {"interference_error": {"inner_um": 5.0, "outer_um": 0.0}},
                     direct=True)
    elif name == "friction_law_exp":
        truth = _run(asm, mf, cond, friction=_friction_exp())
    elif name == "groove_curvature":
        # on the finer mesh with direct solves: the rung evaluates the same pipeline route
        truth = _run(replace(asm, bearing=replace(asm.bearing, inner_groove_ratio=0.54)), 0.7 * mf,
                     cond, direct=True)
    elif name == "fit_outside_band":
        asm = _banded(asm)
        truth = _run(asm, 0.7 * mf, cond, {"interference_error": {
            "inner_um": _beyond_band_um(asm), "outer_um": 0.0}}, direct=True)
    elif name == "sleeve_in_aluminium":
        asm = _aluminium_housing(asm)
        truth = _run(_sleeve(asm, 3.0, "17-4PH"), 0.7 * mf, cond, direct=True)
    elif name == "transient_fe_lag":
        parts = transient_fe_temperatures(asm, cond["time_s"], cond["T_ambient_C"], mf)
        truth = _run(asm, mf, {**cond, **parts})
    elif name == "network_lag":
        truth = _run(asm, mf, {**cond, **network_temperatures(cond["time_s"], cond["T_ambient_C"])})
    elif name == "fit_error_and_lag":
        truth = _run(asm, mf, cond, {"interference_error": {"inner_um": 4.0, "outer_um": 0.0},
                                     "thermal_lag": {"tau_s": 1500.0}})
    elif name == "shaft_lag_numpy":
        truth = _run(asm, 0.7 * mf, {**cond, **shaft_side_lag(cond["time_s"],
                                                              cond["T_ambient_C"], 900.0)},
                     direct=True)
    elif name in PAIRS:
        # every pair and each of its causes alone, the same way (finer mesh, direct solves)
        parts = PAIRS[name]
        made = {k: _pair_truth(asm, 0.7 * mf, cond, {k: v}) for k, v in parts.items()}
        truth = _pair_truth(asm, 0.7 * mf, cond, parts)
        noise["alone"] = made
    elif name in ("ar1_090_null", "ar1_095_null"):
        truth = _run(asm, mf, cond)
        noise["phi"] = 0.9 if name == "ar1_090_null" else 0.95
    elif name == "spikes_quantised_null":
        truth = _run(asm, mf, cond)
        noise["spikes"] = 6
        noise["quantum_sigma"] = 1.5
    elif name == "torque_drift":
        truth = _run(asm, mf, cond)
        noise["drift_sigma"] = {"torque_Nmm": 6.0}
    elif name == "chamber_offset":
        # on the finer mesh with direct solves: the look-alike is the same change of temperatures
        truth = _run(asm, 0.7 * mf, {**cond, "T_ambient_C": cond["T_ambient_C"] - 0.5},
                     direct=True)
    else:
        raise KeyError(f"unknown case {name!r} (known: {', '.join(CASES)})")
    return asm, cond, truth, noise


#: the two-cause cases made another way: cause label -> what makes it (listed effects as
#: {effect: parameters}; `material_lot` as the housing's lot of a CTE factor, a material of its
#: own in the truth's assembly)
PAIRS: dict[str, dict[str, dict]] = {
    "fit_error_lag_finer": {"interference_error": {"inner_um": 5.0, "outer_um": 0.0},
                            "thermal_lag": {"tau_s": 1500.0}},
    "lot_settling_finer": {"material_lot": {"housing": 0.97},
                           "preload_settling": {"loss_N": 8.0, "threshold_K": 50.0}},
    "compliance_runin_finer": {"preload_path_compliance": {"extra_compliance_um_per_kN": 10.0},
                               "solid_film_runin": {"dmu": -0.006, "runin_krev": 10.0}},
}


def _pair_truth(asm, mesh_factor, conditions, parts: Mapping[str, Mapping]) -> dict:
    """Noise-free columns of the causes `parts` (PAIRS entries) made on `mesh_factor` with
    direct FE solves."""
    parts = dict(parts)
    lot = parts.pop("material_lot", None)
    if lot is not None:
        for part, factor in lot.items():
            asm = _lot(asm, part, factor)
    return _run(asm, mesh_factor, conditions, parts, direct=True)


def stated_sigma(truth: Mapping[str, np.ndarray]) -> dict[str, float]:
    """The stated noise level of each column: NOISE_SHARE x its mean absolute value."""
    return {c: NOISE_SHARE * float(np.mean(np.abs(v))) for c, v in truth.items()}


def change_sigma(asm, conditions, truth, sigma, mesh_factor: float) -> float:
    """Largest |truth - baseline| / sigma over the measured entries, the baseline the diagnosed
    model with its friction scale refitted (bounded least squares in the nuisance range)."""
    from studies.diagnosis.files import NUISANCE, ModelPredictor

    pred = ModelPredictor(_pipeline(asm, mesh_factor), conditions, tuple(truth))
    lo, hi = NUISANCE["mu_scale"][:2]

    def res(x):
        b = pred({}, {"mu_scale": float(x[0])})
        return np.concatenate([(truth[c] - b[c]) / sigma[c] for c in truth])
    x = optimize.least_squares(res, [MU_TRUE], bounds=([lo], [hi]), diff_step=1e-4).x
    return float(np.max(np.abs(res(x))))


def make_case(name: str, seed: int = 0, mesh_factor: float = 1.0) -> Case:
    """The data of one trial of case `name` (CASES): the noise-free truth (built once per
    process and mesh factor), the case's noise and sensor errors drawn with `seed`."""
    spec = CASES[name]
    key = (name, float(mesh_factor))
    if key not in _TRUTH_CACHE:
        asm, cond, truth, extra = _truth(name, mesh_factor)
        sigma = stated_sigma(truth)
        # the sensor errors are part of what the data show (the drift and the offset)
        shown = dict(truth)
        for c, k in extra.get("drift_sigma", {}).items():
            t = np.asarray(cond.get("time_s", np.arange(len(truth[c]))), float)
            shown[c] = truth[c] + k * sigma[c] * (t - t[0]) / (t[-1] - t[0])
        ch = change_sigma(asm, cond, shown, sigma, mesh_factor)
        alone = {k: change_sigma(asm, cond, v, sigma, mesh_factor)
                 for k, v in extra.pop("alone", {}).items()}
        _TRUTH_CACHE[key] = (asm, cond, truth, extra, sigma, ch, alone)
    asm, cond, truth, extra, sigma, ch, alone = _TRUTH_CACHE[key]
    noise = Noise(sigma=sigma, phi=extra.get("phi", 0.0), spikes=extra.get("spikes", 0),
                  quantum={c: extra["quantum_sigma"] * s for c, s in sigma.items()}
                  if "quantum_sigma" in extra else {},
                  drift={c: k * sigma[c] for c, k in extra.get("drift_sigma", {}).items()})
    rng = np.random.default_rng([seed, sum(map(ord, name))])
    measured, spikes = add_noise(truth, noise, rng, cond.get("time_s"))
    return Case(name, spec.kind, spec.design, seed, spec.truth, spec.right, asm,
                {k: np.asarray(v, float) for k, v in cond.items()}, measured,
                {c: v.copy() for c, v in truth.items()}, dict(sigma), noise, ch, spec.text,
                spikes, float(mesh_factor), dict(alone))


# ============================================================================ diagnosis and judging
def diagnose_case(case: Case, workers: int = 1, noise_model=None):
    """Today's diagnosis of a case as `bearingfem diagnose` runs it: the diagnosed assembly's
    pipeline (`case.mesh_factor`), `files.ModelPredictor`, the CLI's candidates (the listed
    effects, then the model-form ladder's rungs) and nuisance calibration, `engine.diagnose_full`;
    noise_model: a sensor's stated noise ({column: `noisemodel.StatedNoise`}, as `--noise`).
    Returns its `DiagnosisResult`."""
    from studies.diagnosis.engine import diagnose_full
    from studies.diagnosis.files import NUISANCE, ModelPredictor, candidate_effects

    from studies.diagnosis.ladder import candidates as ladder_candidates

    pred = ModelPredictor(_pipeline(case.assembly, case.mesh_factor), case.conditions, case.columns)
    cands = candidate_effects(case.assembly) + ladder_candidates(case.assembly)   # as the CLI
    return diagnose_full(pred, case.measured, case.conditions, cands, NUISANCE, T_ref_C=case.assembly.T_ref_C, predict_at=pred.at,
                         seed=case.seed, workers=workers, noise_model=noise_model)


#: seed offset of the repeat draw of `interval_coverage` (another draw than the diagnosed one)
REPEAT_SEED = 10_000


def interval_coverage(case: Case, result) -> tuple[int, int] | None:
    """(entries inside, entries) of the claimed model's predictive interval (`result.interval`,
    `studies.diagnosis.interval`) over a repeat of the case's run: its noise-free truth with a
    fresh draw of the case's noise and sensor errors (`add_noise`, seed case.seed + REPEAT_SEED),
    every measured column on every row. None without an interval (nothing claimed). A repeat
    the fit never saw tests the interval as a prediction of the rig's next run."""
    iv = getattr(result, "interval", None)
    if iv is None:
        return None
    rng = np.random.default_rng([case.seed + REPEAT_SEED, sum(map(ord, case.name))])
    again, _ = add_noise(case.noise_free, case.noise, rng, case.conditions.get("time_s"))
    inside = total = 0
    for c, ci in iv.columns.items():
        ok = np.isfinite(ci.lo)
        v = again[c][ok]
        inside += int(np.sum((v >= ci.lo[ok]) & (v <= ci.hi[ok])))
        total += int(ok.sum())
    return inside, total


def named_causes(result) -> list[str]:
    """The causes a `DiagnosisResult` names, in order: its `causes` (several accepted causes:
    names or entries with `.effect` / `.name`) when it has them, else `cause`."""
    many = getattr(result, "causes", None)
    if many:
        return [c if isinstance(c, str) else getattr(c, "effect", None) or getattr(c, "name")
                for c in many]
    return [result.cause] if result.cause else []


def judge_result(case: Case, result) -> str:
    """`judge` of a `DiagnosisResult` (`named_causes`, its rivals); for a truth beyond its
    candidate's bounds (`CaseSpec.lead`) `right` also needs the lead named in `at_bound`,
    else `unexplained`."""
    out = judge(case, result.verdict, named_causes(result), result.indistinguishable)
    lead = CASES[case.name].lead if case.name in CASES else None
    if out == "right" and lead and not any(family(b.effect) == lead
                                           for b in getattr(result, "at_bound", ())):
        return "unexplained"
    return out


def family(cause: str) -> str:
    """The listed effect or model form a cause name belongs to (`thermal_lag.per_part` ->
    `thermal_lag`)."""
    return cause.split(".", 1)[0]


def judge(case: Case | CaseSpec, verdict: str, causes: Sequence[str] | str | None,
          rivals: Sequence[str] = (), visible: bool | None = None) -> str:
    """The outcome of a diagnosis of a case (OUTCOMES):

    - `wrong`: a cause claimed (explained, explained_partly, or ambiguous with no right cause
      among the rivals) that is not in `case.right`;
    - `right`: every cause of the truth named (explained / explained_partly: as many distinct
      names of `case.right` as true causes); on a null or an
      invisible truth `no_discrepancy`; on a truth no candidate can name (`right` empty)
      `unexplained`;
    - `partial`: some but not all of several true causes named, nothing wrong;
    - `named`: ambiguous with a right cause among the rivals;
    - `unexplained`: `unexplained` where a candidate could have named the truth;
    - `missed`: `no_discrepancy` on a visible truth;
    - `false_alarm`: any other verdict than `no_discrepancy` on a null that claims no cause.
    causes: the cause(s) the diagnosis names (one name, a list for several causes, or None);
    visible: whether the truth is visible (default `case.visible`, True for a CaseSpec)."""
    if isinstance(causes, str):
        causes = [causes]
    named = [family(c) for c in (causes or []) if c]
    right = set(case.right)
    vis = (case.visible if isinstance(case, Case) else True) if visible is None else visible
    if verdict in ("explained", "explained_partly"):
        if not named or any(c not in right for c in named) or not case.truth:
            return "wrong"
        # every true cause covered: as many distinct right names as causes (`right` may hold
        # alternatives: `fits_in_band` for a fit error, a path compliance for a spring)
        return "right" if len(set(named)) >= len(case.truth) else "partial"
    if verdict == "ambiguous":
        pool = {*named, *(family(r) for r in rivals)}
        return "named" if case.truth and pool & right else "wrong"
    if verdict == "no_discrepancy":
        return "right" if not case.truth or not vis else "missed"
    # unexplained (or any verdict that names no cause)
    if not case.truth:
        return "false_alarm"
    return "right" if not right else "unexplained"

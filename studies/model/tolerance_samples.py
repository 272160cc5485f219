"""The Monte Carlo samples of the fit tolerances through the exact model (`tolerances.py` draws
them and holds the bands): each sample's fits and contact state solved by the pipeline, nothing
linearised, in blocks here or on Dask with the same numbers in every mode."""
from __future__ import annotations

import numpy as np

from studies.model.inputs import baseline_inputs
from studies.model.parallel import map_blocks
from studies.model.pipeline import FEOptions, Pipeline
from studies.model.tolerances import SampleResults, mid_band_fit_offsets_um, mid_band_offsets_um


#: rows (samples x conditions) evaluated together: bounds memory for any number of samples
CHUNK_ROWS = 10_000


def sample_order(d_inner_um: np.ndarray, d_outer_um: np.ndarray) -> np.ndarray:
    """The samples in the order their fits are solved: neighbouring rows then share the contact
    active set, which `fem.solver.Superposition.evaluate` reuses. Bands of 1 um outer
    interference, each swept in inner interference, up in even bands and down in odd ones (a
    serpentine: the last sample of a band is near the first of the next). `run_samples` puts all
    samples in this order before it cuts blocks, so a block covers a narrow range of fits: CPU
    per block of 1e4 samples of the bench case 0.20 s, vs 0.74 s in drawn order and 0.43 s
    with 0.1 um outer bands swept upwards only (measured, studies/bench/bench_tolerance.py)."""
    band = np.floor(np.asarray(d_outer_um, float))
    return np.lexsort((np.where(band % 2 == 0, d_inner_um, -np.asarray(d_inner_um, float)), band))


def evaluate(pl, conditions: dict[str, np.ndarray], d_inner_um: np.ndarray,
             d_outer_um: np.ndarray, d_layers_um: np.ndarray | None = None) -> SampleResults:
    """Every sample (interference offsets from the [fits] values, length S; d_layers_um (S,
    n_layers) those of the sleeve / cartridge fits, None = nominal) at every condition (length C)
    through the pipeline, whose rows are the mean (mid-band) assembly with its preload
    (`Assembly.mean_fits_um`); returns the `SampleResults` as (S, C) arrays."""
    a = pl.asm
    C = len(next(iter(conditions.values())))
    S = len(d_inner_um)
    base = baseline_inputs(conditions, C, a.T_ref_C, a.preload.assembled_N, a.lubrication.speed_rpm)
    mid_i, mid_o = mid_band_offsets_um(a)
    d_inner_um, d_outer_um = np.asarray(d_inner_um, float), np.asarray(d_outer_um, float)
    # rows condition by condition, samples ordered by their fits: neighbouring rows then share
    # the contact active set (`sample_order`); results are put back
    order = sample_order(d_inner_um, d_outer_um)
    rows_c, rows_s = np.repeat(np.arange(C), S), np.tile(order, C)
    inp = base.take(rows_c)
    inp = inp.copy(interference_inner_um=d_inner_um[rows_s] - mid_i,
                   interference_outer_um=d_outer_um[rows_s] - mid_o)
    mid = mid_band_fit_offsets_um(a)
    for k, (name, _) in enumerate(a.layers() if d_layers_um is not None else ()):
        inp = inp.copy(**{f"interference_{name}_um": d_layers_um[rows_s, k] - mid[name]})
    # the preload is set in the mean assembly (the [fits] values), whatever the sample's fits
    res = pl.run(inp, fe_options=FEOptions(reference="nominal_fits"))

    def per_sample(rows: np.ndarray) -> np.ndarray:
        v = np.empty((S, C))
        v[rows_s, rows_c] = rows
        return v
    return SampleResults(
        interference_inner_um=per_sample(res.fe.interference_um[:, 0]),
        interference_outer_um=per_sample(res.fe.interference_um[:, 1]),
        fit_pressure_inner_MPa=per_sample(res.fits.inner_MPa),
        fit_pressure_outer_MPa=per_sample(res.fits.outer_MPa),
        preload_N=per_sample(res.preload_N), contact_angle_deg=per_sample(res.contact_angle_deg),
        max_contact_pressure_MPa=per_sample(res.max_contact_pressure_MPa),
        torque_Nmm=per_sample(res.torque_Nmm),
        **{q: per_sample(v) for k, (name, _) in enumerate(a.layers())
           for q, v in ((f"interference_{name}_um", res.fe.layer_interference_um[:, k]),
                        (f"fit_pressure_{name}_MPa", res.fits.layer_MPa(name)))})


def warm(asm) -> None:
    """Build this process's shared pipeline of `asm` and run one sample (the [fits] values)
    through it: the set-up and the lazy imports the first block would otherwise do (the results
    of later blocks do not depend on it)."""
    evaluate(Pipeline.shared(asm), {"T_ambient_C": np.array([asm.T_ref_C])}, np.zeros(1),
             np.zeros(1))


def evaluate_block(asm, conditions: dict[str, np.ndarray], d_inner_um: np.ndarray,
                   d_outer_um: np.ndarray, d_layers_um: np.ndarray | None = None) -> SampleResults:
    """`evaluate` on the process's shared pipeline of `asm`: one task of `run_samples`."""
    return evaluate(Pipeline.shared(asm), conditions, d_inner_um, d_outer_um, d_layers_um)


def run_samples(asm, conditions: dict[str, np.ndarray], d_inner_um: np.ndarray,
                d_outer_um: np.ndarray, workers: int | None = None, scheduler: str | None = None,
                progress=None, where=None,
                d_layers_um: np.ndarray | None = None) -> SampleResults:
    """All samples in blocks of whole samples (about CHUNK_ROWS rows each), here or on Dask
    (`studies.model.parallel.map_blocks`): the same blocks in every mode, so the same numbers.
    The samples are put in `sample_order` before the blocks are cut and the results put back in
    the order given. `where`: an open `parallel.Blocks` to run on (workers / scheduler unused)."""
    C = len(next(iter(conditions.values())))
    S = len(d_inner_um)
    per = max(1, CHUNK_ROWS // C)
    order = sample_order(d_inner_um, d_outer_um)     # blocks of neighbouring fits
    di, do = np.asarray(d_inner_um, float)[order], np.asarray(d_outer_um, float)[order]
    dl = None if d_layers_um is None else np.asarray(d_layers_um, float)[order]
    blocks = [(asm, conditions, di[s0:s0 + per], do[s0:s0 + per],
               None if dl is None else dl[s0:s0 + per]) for s0 in range(0, S, per)]
    parts = map_blocks(evaluate_block, blocks, workers=workers, scheduler=scheduler,
                       progress=progress, where=where)

    def put_back(v: np.ndarray) -> np.ndarray:
        out = np.empty_like(v)
        out[order] = v
        return out
    return SampleResults.concatenate(parts).map(put_back)

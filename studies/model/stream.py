"""`bearingfem simulate` of a conditions file in chunks: memory that does not grow with the rows.

The conditions file is read a chunk of rows at a time (`studies.model.table.iter_table`), twice:
`check_conditions` checks all of it first (bad input anywhere stops the run before any FE work),
then `simulate_file` evaluates each chunk through the one route (`pipeline.table_inputs` ->
`Pipeline.run` -> `columns.to_columns`) and streams its rows into the temporary output file
(`table.TableWriter`),
renamed onto the output only at the end; `simulate_columns` hands the same chunks of a table in
memory to the same evaluation (`simulate_chunks`) and keeps the columns it would write (the
Python API's `simulate`). An effect may depend on earlier rows (a thermal lag, a
settling after the first excursion): with effects switched on, the inputs of the whole table are
formed first (the condition columns and `PhysicsInputs`, about 0.1 kB per row) and evaluated
chunk by chunk.

The checks of `studies.model.checks` run on each chunk inside the route (the flag and margin
columns are per row); `CheckTally` combines their violations over all rows. The plausibility warnings and the violation
summaries read a few columns over all rows, kept for them (8 bytes per row each): the
temperature columns of the conditions and WARNING_OUTPUTS; the rows of a violated check are kept
as indices (8 bytes per violating row). Everything else lives for one chunk.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator

import numpy as np

from analytic.friction.ranges import merge as merge_ranges
from studies.model.checks import Check, Checks, Violation, assembly_checks, plausibility_warnings
from studies.model.columns import to_columns
from studies.model.inputs import CONDITION_COLUMNS
from studies.model.pipeline import Pipeline, table_inputs
from studies.model.result import SimulationResult
from studies.model.table import CHUNK_ROWS, TableError, TableWriter, iter_table

#: output columns `plausibility_warnings` reads over all rows (a test holds the streamed warnings
#: equal to those of the whole table, so a column read there and missing here is caught)
WARNING_OUTPUTS = ("torque_viscous_Nmm", "torque_load_Nmm", "land_margin_inner_deg",
                   "land_margin_outer_deg", "viscosity_mm2_s")


class CheckTally:
    """The violations of `checks` over a table evaluated chunk by chunk: `add` takes one chunk's
    checks (`SimulationResult.checks`), `violations` gives what `Checks.violations` gives for
    the whole table (rows, worst row and value, the first of equal worst values)."""

    def __init__(self, checks: list[Check]):
        self.checks = checks
        self._rows: dict[str, list[np.ndarray]] = {c.name: [] for c in checks}
        self._worst: dict[str, tuple[int, float]] = {}

    def add(self, checks: Checks, first_row: int) -> None:
        """Add the checks of one chunk (0-based rows first_row, first_row + 1, ... of the
        table)."""
        for v in checks.violations():
            name = v.check.name
            self._rows[name].append(v.rows + first_row)
            old = self._worst.get(name)
            if old is None or (v.worst_value > old[1] if v.check.upper else v.worst_value < old[1]):
                self._worst[name] = (v.worst_row + first_row, v.worst_value)

    def violations(self) -> list[Violation]:
        return [Violation(c, np.concatenate(self._rows[c.name]), *self._worst[c.name])
                for c in self.checks if c.name in self._worst]


@dataclass(frozen=True)
class SimulateRun:
    """What `simulate_file` did. n_rows: rows written. violations: the violated checks over all
    rows. warnings: the plausibility warnings (one line each). kept: the columns over all rows
    the summaries read (temperature columns of the conditions)."""
    n_rows: int
    violations: list[Violation]
    warnings: list[str]
    kept: dict[str, np.ndarray]

    def summaries(self) -> list[str]:
        """One line per violated check (`checks.Violation.summary`)."""
        return [v.summary(self.n_rows, self.kept) for v in self.violations]


def check_conditions(path: Path, chunk_rows: int = CHUNK_ROWS, columns: set[str] | None = None) -> int:
    """Read and check a whole conditions file, one chunk in memory at a time; its row count.
    Bad input raises the one-line `TableError` of `table.iter_table`. columns: the allowed
    columns (default CONDITION_COLUMNS; transient mode: `transient_route.condition_columns`)."""
    allowed = set(CONDITION_COLUMNS) if columns is None else columns
    return sum(len(c["_line"]) for c in iter_table(path, allowed, chunk_rows))


def simulate_file(asm, conditions: Path, out: Path, effects: dict | None = None,
                  provenance: dict | None = None, direct: bool = False,
                  pipeline: Pipeline | None = None, chunk_rows: int = CHUNK_ROWS,
                  progress: Callable[[str], None] | None = None,
                  n_rows: int | None = None, workers: int | None = None,
                  scheduler: str | None = None) -> SimulateRun:
    """Evaluate the conditions file `conditions` chunk by chunk and write the output table `out`
    (condition columns, model outputs, flag and margin columns; with its provenance sidecar) as
    one atomic file: nothing is left at `out` on an error. `n_rows`: the file's row count when
    known (`check_conditions`), else it is counted first. The evaluation is `simulate_chunks`'
    (see there for `workers` and `scheduler`). See the module docstring."""
    if asm.thermal.mode == "transient":
        raise ValueError("simulate_file: [thermal] mode = \"transient\" runs through "
                         "studies.model.transient_route.simulate_transient_file")
    total = check_conditions(conditions, chunk_rows) if n_rows is None else n_rows
    with TableWriter(out, provenance) as w:
        return simulate_chunks(asm, iter_table(conditions, set(CONDITION_COLUMNS), chunk_rows),
                               total, w.write, str(conditions), effects, direct, pipeline,
                               progress, workers, scheduler)


def simulate_columns(asm, columns: dict[str, np.ndarray], effects: dict | None = None,
                     direct: bool = False, pipeline: Pipeline | None = None,
                     chunk_rows: int = CHUNK_ROWS, progress: Callable[[str], None] | None = None,
                     workers: int | None = None,
                     scheduler: str | None = None) -> tuple[SimulateRun, dict[str, np.ndarray]]:
    """`simulate_file` of a table in memory (checked condition columns, `table.check_columns`):
    the same chunks through `simulate_chunks`, the columns it would write collected instead
    (condition columns first, then the outputs, flags and margins; full float precision)."""
    n = _n_rows(columns)
    chunks = ({k: v[i:i + chunk_rows] for k, v in columns.items()} for i in range(0, n, chunk_rows))
    parts: list[dict] = []
    run = simulate_chunks(asm, chunks, n, parts.append, "conditions", effects, direct, pipeline,
                          progress, workers, scheduler)
    return run, {k: np.concatenate([p[k] for p in parts]) for k in parts[0] if not k.startswith("_")}


def simulate_chunks(asm, chunks: Iterable[dict], total: int, write: Callable[[dict], None],
                    where: str, effects: dict | None = None, direct: bool = False,
                    pipeline: Pipeline | None = None,
                    progress: Callable[[str], None] | None = None, workers: int | None = None,
                    scheduler: str | None = None) -> SimulateRun:
    """The evaluation of `bearingfem simulate`: each chunk of condition columns (`_line`, the
    file's line numbers, optional) through the one route, its columns (conditions, then
    `columns.to_columns`) handed to `write`, the checks tallied and the warnings read over all
    `total` rows. With `workers` (processes forked from this one) or `scheduler` (an existing
    Dask cluster) the chunks are evaluated as tasks (`run_block` on each worker's shared
    pipeline, `studies.model.parallel.Blocks.imap`), the same chunks by the same function, so
    the same bytes. `where` names the table in errors."""
    from studies.model.parallel import Blocks

    tally = CheckTally(assembly_checks(asm))
    kept: dict[str, np.ndarray] = {}
    ranges: tuple = ()                 # the friction law's rows outside its source's range
    n = 0
    with Blocks(workers, scheduler) as place:
        if place.here:
            pl = pipeline or Pipeline.shared(asm)
            fn = lambda a, f, inputs, d, first: pl.run(inputs, direct=d,  # noqa: E731
                                                      first_row=first, remember=False)
        else:
            fn = run_block
        factor = pipeline.mesh_factor if pipeline is not None else 1.0
        conds: deque[dict] = deque()       # the condition columns of the blocks under way

        def blocks():
            for cond, inputs, first in _inputs(asm, chunks, effects):
                conds.append(cond)
                yield asm, factor, inputs, direct, first

        for res in place.imap(fn, blocks()):
            cond = conds.popleft()
            m = _n_rows(cond)
            if n + m > total:
                raise TableError(f"{where}: changed while it was read")
            cols = {k: v for k, v in cond.items() if not k.startswith("_")}
            out_cols = to_columns(res, friction_split=True)
            cols.update(out_cols)
            tally.add(res.checks, n)
            ranges = merge_ranges(ranges, res.torque.range_notes)
            write(cols)
            keep = [c for c in cols if c.startswith("T_") and c.endswith("_C")]
            for k in keep + [c for c in WARNING_OUTPUTS if c in out_cols]:
                kept.setdefault(k, np.empty(total))[n:n + m] = cols[k]
            n += m
            if progress:
                progress(f"simulate: {n} of {total} rows")
        if n != total:
            raise TableError(f"{where}: changed while it was read")
    temps = {k: v for k, v in kept.items() if k not in WARNING_OUTPUTS}
    outputs = {k: v for k, v in kept.items() if k in WARNING_OUTPUTS}
    return SimulateRun(n, tally.violations(), plausibility_warnings(asm, temps, outputs)
                       + [r.message(n) for r in ranges], temps)


def _n_rows(columns: dict) -> int:
    """Rows of a table of equal-length columns."""
    return len(next(iter(columns.values())))


def run_block(asm, mesh_factor: float, inputs, direct: bool, first_row: int) -> SimulationResult:
    """The model's result for one chunk's inputs on this process's shared pipeline of `asm` at
    `mesh_factor` (one Dask task of `simulate_file`; rows numbered from 0-based `first_row` in
    its errors)."""
    return Pipeline.shared(asm, mesh_factor).run(inputs, direct=direct, first_row=first_row,
                                                 remember=False)


def _inputs(asm, chunks: Iterable[dict],
            effects: dict | None) -> Iterator[tuple[dict, object, int]]:
    """(condition columns, `PhysicsInputs`, 0-based first row) per chunk of a conditions table."""
    first = 0
    if not effects:
        for cond in chunks:
            yield cond, table_inputs(asm, cond), first
            first += _n_rows(cond)
        return
    parts = list(chunks)            # an effect may depend on earlier rows: the whole table's inputs
    whole = {c: np.concatenate([p[c] for p in parts]) for c in parts[0]}
    sizes = [_n_rows(p) for p in parts]
    del parts
    inputs = table_inputs(asm, whole, effects)
    for m in sizes:
        rows = np.arange(first, first + m)
        yield {c: v[first:first + m] for c, v in whole.items()}, inputs.take(rows), first
        first += m

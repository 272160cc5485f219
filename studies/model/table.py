"""Conditions / measured CSV tables: strict reading with one-line errors, atomic writing.

Read (docs/cli.md): header row, comma separated, `#` lines are comments. Every value numeric and
finite; `time_s` strictly increasing when present.

Written: the one CSV dialect of bearingfem, for `simulate` and every study table alike
(`write_table`, `TableWriter`): UTF-8, a header row of column names (units in the names), no
comment lines, comma separated, "\n" line ends, numbers as '%.10g' of their float value, booleans
1/0, text as it is (quoted by the csv module when it holds a comma or a quote); what a table is
goes into its provenance sidecar or the report beside it. `pandas.read_csv(path)` reads it with
its defaults.
"""
from __future__ import annotations

import codecs
import csv
import json
import math
from pathlib import Path

import numpy as np

from infra.files import AtomicFile, write_atomic
from infra.names import did_you_mean
from studies.model.inputs import CONDITION_COLUMNS


class TableError(ValueError):
    """Bad table: one line naming the file, the row or column, and the problem."""


#: rows per chunk when a table is read or evaluated in pieces (memory ~ this, not the file)
CHUNK_ROWS = 10_000


def read_table(path: Path, allowed: set[str] | None = None,
               required_any: tuple[str, ...] = ()) -> dict[str, np.ndarray]:
    """Read a numeric CSV into column arrays. `allowed`: known column names (others are an
    error). Rows are numbered as in the file (1-based line numbers)."""
    chunks = list(iter_table(path, allowed, check=False))
    cols = {c: np.concatenate([ch[c] for ch in chunks]) for c in chunks[0]}
    check_columns(path, cols)
    if required_any and not any(c in cols for c in required_any):
        raise TableError(f"{path}: needs at least one of the columns {', '.join(required_any)}")
    return cols


def iter_table(path: Path, allowed: set[str] | None = None, chunk_rows: int = CHUNK_ROWS,
               check: bool = True):
    """The rows of a numeric CSV in chunks of up to `chunk_rows` rows: column arrays plus `_line`
    (1-based line numbers), read as the file is read (memory: one chunk). With `check`, every
    chunk gets `check_columns`, and `time_s` must increase across chunk boundaries too, so bad
    input anywhere is the same one-line TableError as from `read_table` (which checks the whole
    table at once instead)."""
    path = Path(path)
    if not path.exists():
        raise TableError(f"{path}: file not found")
    header, rows, lines, last = None, [], [], None
    for lineno, line in enumerate(_text_lines(path), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = next(csv.reader([line]))
        if header is None:
            header = _header(path, lineno, fields, allowed)
            continue
        rows.append(_values(path, lineno, header, fields))
        lines.append(lineno)
        if len(rows) == chunk_rows:
            last = yield from _chunk(path, header, rows, lines, check, last)
            rows, lines = [], []
    if header is None:
        raise TableError(f"{path}: empty table (no header)")
    if rows:
        yield from _chunk(path, header, rows, lines, check, last)
    elif last is None:
        raise TableError(f"{path}: empty table (no data rows)")


def _text_lines(path: Path):
    """The lines of a UTF-8 file (a byte-order mark skipped, as Excel's "CSV UTF-8" writes), read
    piece by piece; bytes that are not UTF-8 are one TableError naming their offset."""
    offset = 0
    try:
        with open(path, "rb") as fh:
            for raw in fh:
                if offset == 0 and raw.startswith(codecs.BOM_UTF8):
                    raw = raw[len(codecs.BOM_UTF8):]
                try:
                    text = raw.decode("utf-8")
                except UnicodeDecodeError as exc:
                    raise TableError(f"{path}: not a UTF-8 text file ({exc.reason} at byte "
                                     f"{offset + exc.start})") from None
                offset += len(raw)
                yield from text.splitlines(keepends=True)
    except OSError as exc:
        raise TableError(f"{path}: cannot read ({exc.strerror})") from None


def _header(path: Path, lineno: int, fields: list[str], allowed: set[str] | None) -> list[str]:
    header = [f.strip() for f in fields]
    for col in header:
        if not col:
            raise TableError(f"{path}: line {lineno}: empty column name in the header")
        if allowed is not None and col not in allowed:
            raise TableError(f"{path}: column '{col}': unknown column"
                             f"{did_you_mean(col, sorted(allowed))}")
    dup = {c for c in header if header.count(c) > 1}
    if dup:
        raise TableError(f"{path}: column '{sorted(dup)[0]}': appears twice")
    return header


def _values(path: Path, lineno: int, header: list[str], fields: list[str]) -> list[float]:
    if len(fields) != len(header):
        raise TableError(f"{path}: line {lineno}: {len(fields)} values for {len(header)} columns")
    vals = []
    for col, f in zip(header, fields):
        try:
            v = float(f)
        except ValueError:
            raise TableError(f"{path}: line {lineno}, column '{col}': "
                             f"'{f.strip()}' is not a number") from None
        if not math.isfinite(v):
            raise TableError(f"{path}: line {lineno}, column '{col}': value is {f.strip()}")
        vals.append(v)
    return vals


def _chunk(path: Path, header: list[str], rows: list, lines: list, check: bool, last):
    """Yield one chunk's columns (checked when asked, `time_s` against the previous chunk's
    last row `last` = (line, time)); return this chunk's last (line, time)."""
    data = np.array(rows, float)
    cols = {c: data[:, i] for i, c in enumerate(header)}
    cols["_line"] = np.array(lines)
    if check:
        check_columns(path, cols)
        if "time_s" in cols and last is not None and last[1] is not None:
            check_columns(path, {"time_s": np.array([last[1], cols["time_s"][0]]),
                                 "_line": np.array([last[0], lines[0]])})
    yield cols
    return lines[-1], (float(cols["time_s"][-1]) if "time_s" in cols else None)


#: physical ranges of condition columns: the material and lubricant data hold from -150 to 300 C
#: (beyond, CTE and viscosity laws are extrapolations the model does not stand behind)
RANGES = {**{c: (-150.0, 300.0, "C") for c in CONDITION_COLUMNS if c.startswith("T_")},
          "speed_rpm": (0.0, 1e5, "rpm"), "preload_assembled_N": (0.0, 1e5, "N"),
          "axial_load_N": (-1e6, 1e6, "N"), "radial_load_N": (-1e6, 1e6, "N"),
          "moment_Nmm": (-1e9, 1e9, "N mm"),
          # single bearing loads (bearingfem bearing)
          "radial_load_y_N": (-1e6, 1e6, "N"), "moment_x_Nmm": (-1e9, 1e9, "N mm"),
          "moment_y_Nmm": (-1e9, 1e9, "N mm"),
          # measured outputs (diagnose): beyond these no bearing this tool models goes
          "torque_Nmm": (-1e7, 1e7, "N mm"), "preload_N": (-1e6, 1e6, "N"),
          "contact_angle_deg": (-90.0, 90.0, "deg"), "max_contact_pressure_MPa": (0.0, 1e5, "MPa"),
          "interference_inner_um": (-1e4, 1e4, "um"), "interference_outer_um": (-1e4, 1e4, "um"),
          "fit_pressure_inner_MPa": (-1e4, 1e4, "MPa"), "fit_pressure_outer_MPa": (-1e4, 1e4, "MPa")}


def check_columns(where, cols: dict[str, np.ndarray], allowed: set[str] | None = None) -> None:
    """The checks every table gets, from a file or from Python: known names (when `allowed` is
    given), equal lengths, finite numbers, `time_s` strictly increasing, every value inside its
    column's physical range (RANGES). One-line TableError naming `where`, the line (file rows:
    the `_line` column) or row, and the column."""
    names = [c for c in cols if not c.startswith("_")]
    for c in names:
        if allowed is not None and c not in allowed:
            raise TableError(f"{where}: column '{c}': unknown column"
                             f"{did_you_mean(c, sorted(allowed))}")
    sizes = {np.size(cols[c]) for c in names}
    if len(sizes) > 1:
        raise TableError(f"{where}: columns have different lengths {sorted(sizes)}")
    n = sizes.pop() if sizes else 0
    if n == 0:
        raise TableError(f"{where}: empty table (no data rows)")
    line = cols.get("_line")
    label = (lambda i: f"line {line[i]}") if line is not None else (lambda i: f"row {i + 1}")
    for c in names:
        v = np.asarray(cols[c], float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise TableError(f"{where}: {label(bad[0])}, column '{c}': value is {v[bad[0]]}")
        if c in RANGES:
            lo, hi, unit = RANGES[c]
            bad = np.flatnonzero((v < lo) | (v > hi))
            if bad.size:
                raise TableError(f"{where}: {label(bad[0])}, column '{c}': {v[bad[0]]:g} outside "
                                 f"{lo:g}..{hi:g} {unit}")
    if "time_s" in cols:
        bad = np.flatnonzero(np.diff(np.asarray(cols["time_s"], float)) <= 0)
        if bad.size:
            raise TableError(f"{where}: {label(bad[0] + 1)}, column 'time_s': time not increasing")


def read_conditions(path: Path) -> dict[str, np.ndarray]:
    """A conditions table: only the condition columns of the spec, values in range."""
    return read_table(path, allowed=set(CONDITION_COLUMNS))


def write_table(path: Path, columns: dict[str, np.ndarray], provenance: dict | None = None) -> None:
    """Write columns to CSV atomically (temporary file in the same folder, then rename): a header
    row and numbers only, so that `pandas.read_csv(path)` reads it with its defaults. With
    `provenance` (what made the table: command, inputs and their hashes, version), a sidecar
    `<name>.json` is written beside it the same way. Files get the mode of the file they replace,
    or the user's default (0666 less the umask); a write error is one line (TableError) and leaves
    neither a temporary file nor a folder created for it. (`TableWriter` writes the same bytes
    chunk by chunk.)"""
    with TableWriter(path, provenance) as w:
        w.write(columns)


def sidecar_path(path: Path) -> Path:
    """Where the provenance of a table is written: `<name>.json` beside it."""
    return Path(f"{path}.json")


class TableWriter:
    """A CSV table written chunk by chunk (`write`, the same columns every time) into a temporary
    file beside `path` (`infra.files.AtomicFile`), renamed onto `path` when the `with` block ends
    without an error, its provenance sidecar written just before (see `write_table`, whose bytes
    it writes for the chunks put together). On an error or an interruption the temporary file, a
    new sidecar and the folders created for them are removed: no partial output."""

    def __init__(self, path: Path, provenance: dict | None = None):
        self.path, self.provenance = Path(path), provenance
        self.rows = 0
        self._names: list[str] | None = None
        self._file = AtomicFile(self.path)

    def __enter__(self) -> "TableWriter":
        self._side = sidecar_path(self.path) if self.provenance is not None else None
        self._side_existed = self._side is not None and self._side.exists()
        try:
            self._fh = self._file.open()
        except OSError as exc:
            raise TableError(f"{self.path}: cannot write ({exc.strerror or exc})") from None
        self._csv = csv.writer(self._fh, lineterminator="\n")
        return self

    def write(self, columns: dict[str, np.ndarray]) -> None:
        """Append the rows of `columns` (names starting with `_` are left out)."""
        names = [c for c in columns if not c.startswith("_")]
        arrays = [np.asarray(columns[c]) for c in names]
        try:
            if self._names is None:
                self._names = names
                self._csv.writerow(names)
            elif names != self._names:
                raise ValueError(f"{self.path}: a chunk with other columns than the first")
            n = len(arrays[0]) if arrays else 0
            if all(a.dtype.kind in "biuf" for a in arrays):
                self._fh.write(format_rows(arrays))
            else:
                for i in range(n):
                    self._csv.writerow([_fmt(a[i]) for a in arrays])
            self.rows += n
        except OSError as exc:
            raise TableError(f"{self.path}: cannot write ({exc.strerror or exc})") from None

    def __exit__(self, exc_type, exc_value, tb) -> bool:
        if exc_type is not None:
            self._file.discard()
            return False
        try:
            if self._names is None:
                self._csv.writerow([])          # no columns: what write_table({}) always wrote
            if self._side is not None:
                write_atomic(self._side, json.dumps(self.provenance, indent=2) + "\n")
            self._file.commit()
        except BaseException as exc:
            if self._side is not None and not self._side_existed:
                self._side.unlink(missing_ok=True)     # no partial output: the new sidecar goes
            self._file.discard()
            if isinstance(exc, OSError):
                raise TableError(f"{self.path}: cannot write ({exc.strerror or exc})") from None
            raise
        return False


def format_rows(arrays: list[np.ndarray]) -> str:
    """CSV lines of numeric and boolean columns: the text `_fmt` gives each value (booleans 1/0,
    numbers '%.10g' of their float value), joined by commas, a newline after every row; one
    `%` of a row format per row instead of a csv.writer call and a format call per value (a
    large simulate spent ~40 % of its time formatting, measured)."""
    cols, parts = [], []
    for a in arrays:
        if a.dtype.kind == "b":
            cols.append(a.astype(np.int8).tolist())
            parts.append("%d")
        else:
            cols.append(a.astype(float).tolist())
            parts.append("%.10g")
    fmt = ",".join(parts) + "\n"
    return "".join([fmt % row for row in zip(*cols)])


def _fmt(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "1" if v else "0"
    if isinstance(v, (str, np.str_)):
        return str(v)
    return f"{float(v):.10g}"

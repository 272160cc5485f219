"""What made an output: the command, each input with its SHA-256, the effects switched on, and the
tool version (written beside every output table as `OUT.csv.json` and into reports).

An input is a file (its path and the SHA-256 of its bytes), an assembly loaded from a file (the
path and SHA-256 of the bytes it was read from, kept on it as its `Origin`, so a notebook that
passes a loaded `Assembly` gets the same record as the command given the path), or a value built
or changed in memory (named as such, hashed by its content).
"""
from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass
from pathlib import Path

from infra.version import __version__

#: the path recorded for an input given in memory
IN_MEMORY = "(in memory)"


@dataclass(frozen=True)
class Origin:
    """The file an assembly was read from: its path, the SHA-256 of the bytes read, their text
    (its comments are the file's pedigree: the template asks for the source of every number in
    its comment) and `fingerprint` of the assembly made from them (an assembly changed since,
    e.g. by `dataclasses.replace`, no longer matches: it is not the file any more)."""
    path: str
    sha256: str
    text: str
    fingerprint: str


def fingerprint(value) -> str:
    """SHA-256 of a frozen value's repr (an `Assembly`'s repr leaves its origin out): equal
    values give equal fingerprints, in any process."""
    return hashlib.sha256(repr(value).encode()).hexdigest()


def with_origin(asm, path: str | Path, data: bytes):
    """`asm` carrying the `Origin` of the file `path` whose bytes `data` it was read from."""
    from dataclasses import replace

    text = data.removeprefix(b"\xef\xbb\xbf").decode("utf-8")
    return replace(asm, origin=Origin(str(path), hashlib.sha256(data).hexdigest(), text,
                                      fingerprint(asm)))


def origin_of(asm) -> Origin | None:
    """The file `asm` was read from, or None (built in memory, or changed after loading)."""
    origin = getattr(asm, "origin", None)
    return origin if origin is not None and origin.fingerprint == fingerprint(asm) else None


def assembly_record(asm, path: str | Path | None = None) -> dict:
    """{"path", "sha256"} of an assembly input: the file given (hashed as it is now), else the
    file it was loaded from (the bytes read then), else the assembly in memory (path IN_MEMORY,
    or naming the file it was changed from; SHA-256 of its `fingerprint`)."""
    if path is not None:
        return file_record(path)
    origin = origin_of(asm)
    if origin is not None:
        return {"path": origin.path, "sha256": origin.sha256}
    changed = getattr(asm, "origin", None)
    where = IN_MEMORY if changed is None else f"(in memory: changed after loading {changed.path})"
    return {"path": where, "sha256": fingerprint(asm)}


def file_record(path: str | Path) -> dict:
    """{"path", "sha256"} of an input file."""
    return {"path": str(path), "sha256": _sha256(path)}


def provenance(command: str, inputs: dict[str, Path | dict], effects: dict | None = None) -> dict:
    """{"command", "version", "inputs": {name: {"path", "sha256"}}, "effects"}. An input is a
    file path or its record (`assembly_record`, `file_record`)."""
    return {"command": f"bearingfem {command}", "version": __version__,
            "inputs": {k: dict(p) if isinstance(p, dict) else file_record(p)
                       for k, p in inputs.items()},
            "effects": {k: dict(v) for k, v in (effects or {}).items()}}


def comments_in(text: str) -> dict[tuple[str, str], str]:
    """(table, key) -> the comment on that key's line in a TOML file's text."""
    out, table = {}, ""
    for line in text.splitlines():
        m = re.match(r"\s*\[([^\]]+)\]", line)
        if m:
            table = m.group(1).strip()
            continue
        m = re.match(r"\s*([A-Za-z0-9_]+)\s*=[^#]*#\s*(.*)$", line)
        if m and m.group(2).strip():
            out[(table, m.group(1))] = m.group(2).strip()
    return out


def _sha256(path) -> str:
    """SHA-256 of a file, read piece by piece (a large conditions file is never held whole)."""
    with open(Path(path), "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()

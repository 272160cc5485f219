"""What made an output: the command, each input file with its SHA-256, the effects switched on,
and the tool version (written beside every output table as `OUT.csv.json` and into reports)."""
from __future__ import annotations

import hashlib
from pathlib import Path

from infra.version import __version__


def provenance(command: str, inputs: dict[str, Path], effects: dict | None = None) -> dict:
    """{"command", "version", "inputs": {name: {"path", "sha256"}}, "effects"}."""
    return {"command": f"bearingfem {command}", "version": __version__,
            "inputs": {k: {"path": str(p), "sha256": _sha256(p)} for k, p in inputs.items()},
            "effects": {k: dict(v) for k, v in (effects or {}).items()}}


def _sha256(path) -> str:
    """SHA-256 of a file, read piece by piece (a large conditions file is never held whole)."""
    with open(Path(path), "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()

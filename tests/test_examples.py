"""The worked example docs/examples/new_assembly.py runs as a user runs it (its own process, only
`import bearingfem` from this project) on the coarse mesh with few samples (`--quick`), and
writes what it says: the assembly file, the plots, the tables and the ROSS table."""
import ast
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "docs" / "examples" / "new_assembly.py"
PROJECT_PACKAGES = {"studies", "fem", "analytic", "meshes", "infra"}


def test_the_example_uses_only_the_facade():
    tree = ast.parse(EXAMPLE.read_text())
    roots = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import)
             for a in n.names}
    roots |= {n.module.split(".")[0] for n in ast.walk(tree)
              if isinstance(n, ast.ImportFrom) and n.module}
    assert "bearingfem" in roots and not roots & PROJECT_PACKAGES, roots


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_the_new_assembly_example_runs(tmp_path):
    done = subprocess.run([sys.executable, str(EXAMPLE), "--out", str(tmp_path), "--quick"],
                          capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    for name in ("titanium_pair.toml", "preload_torque.png", "preload_tolerance.png",
                 "stiffness.png", "diagnosis.png", "stiffness.csv", "ross_bearing.csv",
                 "tolerance/tolerance.json", "diagnosis/diagnosis.json", "diagnosis/report.md"):
        assert (tmp_path / name).stat().st_size > 0, name
    ross = pd.read_csv(tmp_path / "ross_bearing.csv", comment="#")
    assert list(ross.columns) == ["frequency", "kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy",
                                  "cyx"] and len(ross) == 5
    lines = done.stdout.splitlines()
    assert any(line.startswith("diagnosis: ") for line in lines), done.stdout
    assert any("ROSS" in line for line in lines), done.stdout

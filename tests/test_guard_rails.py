"""Guard rails: bad inputs and faults against the command line, each held to the contract
(docs/cli.md): exit code, a single stderr line naming the problem, no file left behind, and every
input the user gave unchanged (by hash). Mesh-cache faults against meshes/build.py directly."""
import errno
import hashlib
import os
import re
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from infra.files import HOST_TAG
from meshes.build import MeshError, build_mesh, check_size, section_mesh
from meshes.section import two_cylinder_section
from studies.app.cli import main
from studies.model.config import CONFIG_DIR

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None


def config_with(tmp_path, section, key, value):
    """The seed 000 assembly with one `key = value` changed inside [section]."""
    text = CFG.read_text()
    start = text.index(f"[{section}]")
    end = text.find("\n[", start + 1)
    end = len(text) if end < 0 else end
    body, n = re.subn(rf"(?m)^{key}\s*=\s*[^#\n]*", f"{key} = {value} ", text[start:end], count=1)
    assert n == 1, (section, key)
    path = tmp_path / "asm.toml"
    path.write_text(text[:start] + body + text[end:])
    return path


def run_cli(argv, capsys):
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    return code, err


def assert_refused(code, err, fragment, tmp_path, before):
    assert code == 2
    assert len(err) == 1 and fragment in err[0], err
    for p, h in before.items():
        assert digest(p) == h, f"{p} changed"
    assert not [p for p in tmp_path.rglob(".*") if p.name.startswith((".o.csv", ".out"))]


@pytest.fixture()
def cond(tmp_path):
    c = tmp_path / "cond.csv"
    c.write_text("T_ambient_C\n20\n40\n")
    return c


# ------------------------------------------------------------------ data loss through -o
@pytest.mark.parametrize("target", ["conditions", "assembly"])
def test_output_onto_an_input_is_refused(tmp_path, capsys, cond, target):
    asm = tmp_path / "asm.toml"
    asm.write_text(CFG.read_text())
    before = {cond: digest(cond), asm: digest(asm)}
    out = cond if target == "conditions" else asm
    code, err = run_cli(["simulate", asm, cond, "-o", out], capsys)
    assert_refused(code, err, "is the input file", tmp_path, before)


def test_output_onto_a_symlink_is_refused_and_the_link_kept(tmp_path, capsys, cond):
    target = tmp_path / "target.csv"
    target.write_text("keep\n")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    code, err = run_cli(["simulate", CFG, cond, "-o", link], capsys)
    assert_refused(code, err, "symbolic link", tmp_path, {target: digest(target), cond: digest(cond)})
    assert link.is_symlink()


def test_output_onto_a_fifo_is_refused(tmp_path, capsys, cond):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    code, err = run_cli(["simulate", CFG, cond, "-o", fifo], capsys)
    assert_refused(code, err, "not a regular file", tmp_path, {cond: digest(cond)})
    assert stat.S_ISFIFO(fifo.stat().st_mode)


def test_output_file_modes(tmp_path, capsys, cond):
    old_mask = os.umask(0o022)
    try:
        new = tmp_path / "new.csv"
        assert run_cli(["simulate", CFG, cond, "-o", new], capsys)[0] == 0
        assert stat.S_IMODE(new.stat().st_mode) == 0o644        # the user's default, not 0600
        kept = tmp_path / "kept.csv"
        kept.write_text("old\n")
        kept.chmod(0o640)
        assert run_cli(["simulate", CFG, cond, "-o", kept], capsys)[0] == 0
        assert stat.S_IMODE(kept.stat().st_mode) == 0o640        # an existing target keeps its mode
        assert "preload_N" in kept.read_text()
    finally:
        os.umask(old_mask)


def test_write_error_is_one_line_and_leaves_nothing(tmp_path, capsys, cond, monkeypatch):
    out = tmp_path / "made" / "deeper" / "o.csv"
    real = os.replace

    def full_disk(src, dst):
        if str(dst) == str(out):
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(src, dst)
    monkeypatch.setattr(os, "replace", full_disk)
    code, err = run_cli(["simulate", CFG, cond, "-o", out], capsys)
    assert_refused(code, err, "No space left on device", tmp_path, {cond: digest(cond)})
    assert not (tmp_path / "made").exists()                    # the folder made for -o is gone


def test_out_folder_with_files_added_since_is_refused(tmp_path, capsys):
    out = tmp_path / "study"
    assert run_cli(["study", "lubricant_viscosity", "--out", out], capsys)[0] == 0
    mine = out / "my_notes.txt"
    mine.write_text("precious")
    code, err = run_cli(["study", "lubricant_viscosity", "--out", out], capsys)
    assert code == 2 and len(err) == 1 and "my_notes.txt" in err[0], err
    assert mine.read_text() == "precious"
    mine.unlink()
    assert run_cli(["study", "lubricant_viscosity", "--out", out], capsys)[0] == 0   # its own: replaced


# ------------------------------------------------------------------ a poisoned mesh cache
SEC = two_cylinder_section(0.0, 10.0, 15.0, "9Cr18", "9Cr18", 8.0, size_mm=2.0, fit_size_mm=1.0)
OTHER = two_cylinder_section(0.0, 10.0, 16.0, "9Cr18", "9Cr18", 8.0, size_mm=2.0, fit_size_mm=1.0)


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("BEARINGFEM_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache" / "meshes"


@pytest.mark.parametrize("damage", ["truncated", "empty", "random bytes", "folder", "other section"])
def test_damaged_cache_entry_is_rebuilt_with_one_warning(cache, capsys, damage):
    path = build_mesh(SEC)
    good = section_mesh(SEC)
    if damage == "truncated":
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    elif damage == "empty":
        path.write_bytes(b"")
    elif damage == "random bytes":
        path.write_bytes(np.random.default_rng(0).bytes(4096))
    elif damage == "folder":
        path.unlink()
        path.mkdir()
    else:
        path.write_bytes(build_mesh(OTHER).read_bytes())
    capsys.readouterr()
    mesh = section_mesh(SEC)
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning" in err[0] and str(path) in err[0], err
    assert np.array_equal(mesh.triangles, good.triangles) and np.array_equal(mesh.points, good.points)
    assert section_mesh(SEC).points.shape == good.points.shape              # sound again
    assert capsys.readouterr().err == ""


def test_unusable_cache_location_meshes_in_a_temporary_folder(tmp_path, monkeypatch, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("BEARINGFEM_CACHE", str(blocker))
    mesh = section_mesh(SEC)
    err = capsys.readouterr().err.strip().splitlines()
    assert mesh.triangles.shape[1] > 0
    assert len(err) == 1 and "mesh cache" in err[0] and str(blocker) in err[0], err
    assert blocker.read_text() == "not a folder"


def test_temporary_meshes_of_killed_runs_are_removed(cache):
    build_mesh(SEC)
    dead = 2 ** 22 + 12345                        # above the default pid_max: no such process
    # infra.files.temporary_path: .<name>.<pid>.<8 hex of this host><8 random hex><suffix>
    stale = cache / f".section_{SEC.key()}.msh.{dead}.{HOST_TAG}deadbeef.msh"
    alive = cache / f".section_{SEC.key()}.msh.{os.getpid()}.{HOST_TAG}beefdead.msh"
    elsewhere = cache / f".section_{SEC.key()}.msh.{dead}.{'0' * 8 if HOST_TAG != '0' * 8 else '1' * 8}deadbeef.msh"
    legacy = cache / f"section_{SEC.key()}.{dead}.msh"      # as bearingfem 0.2.0 named them
    for p in (stale, alive, elsewhere, legacy):
        p.write_text("half written")
    section_mesh(OTHER)
    assert not stale.exists() and not legacy.exists()
    assert alive.exists() and elsewhere.exists()    # a live run's, and another machine's


# ------------------------------------------------------------------ no limit on problem size
@pytest.mark.parametrize("section,key,value,fragment", [
    ("housing", "outer_diameter_mm", "1e9", "housing.outer_diameter_mm: 1e+09 mm is more than 20"),
    ("outer_spacer", "length_mm", "1e6", "outer_spacer.length_mm: 1e+06 mm is more than 20"),
    ("bearing", "inner_groove_ratio", "50", "bearing.inner_groove_ratio: 50 is outside 0.5..0.6"),
    ("bearing", "width_mm", "2.0", "narrower than its ball"),
    ("preload", "assembled_N", "1e12", "exceeds the bearing's static load rating"),
])
def test_implausible_assembly_values_are_refused(tmp_path, capsys, cond, section, key, value, fragment):
    asm = config_with(tmp_path, section, key, value)
    before = {asm: digest(asm), cond: digest(cond)}
    code, err = run_cli(["simulate", asm, cond, "-o", tmp_path / "o.csv"], capsys)
    assert_refused(code, err, fragment, tmp_path, before)
    assert not (tmp_path / "o.csv").exists()


def test_a_mesh_too_fine_is_refused_before_meshing(tmp_path, capsys, cond):
    asm = tmp_path / "asm.toml"
    asm.write_text(CFG.read_text() + "\n[mesh]\nsize_mm = 0.02\nfit_size_mm = 0.01\n")
    code, err = run_cli(["simulate", asm, cond, "-o", tmp_path / "o.csv"], capsys)
    assert_refused(code, err, "BEARINGFEM_MAX_ELEMENTS", tmp_path, {cond: digest(cond)})
    with pytest.raises(MeshError, match="triangles"):
        check_size(SEC.scaled(1e-3))


def test_the_condensation_estimate_matches_a_real_set_up():
    # the estimate's condensation (four float64 arrays of DOFs x CONDENSE_BLOCK while a block is
    # solved, three of pairs x pairs kept) against the assembled model's DOFs and pairs, given the
    # mesh's real triangle count (estimate_elements is its own estimate): P2 has about 4 DOF per
    # triangle (2 nodes per triangle in a large mesh), a pair per half fit size
    from fem.model import build_model
    from fem.solver import FitSolver
    from meshes.build import CONDENSE_BLOCK, estimate_memory_GB

    sec = two_cylinder_section(0.0, 10.0, 15.0, "9Cr18", "9Cr18", 8.0, size_mm=1.0, fit_size_mm=0.25)
    model = build_model(sec)
    n = section_mesh(sec).triangles.shape[1]
    pairs = FitSolver(model).n_pairs
    real = 8e-9 * (4 * model.ndofs * CONDENSE_BLOCK + 3 * pairs ** 2)
    est = estimate_memory_GB(sec, n) - 4e-6 * n
    assert est == pytest.approx(real, rel=0.1)   # boundary nodes: 4 DOF/triangle is ~6 % low here


def test_a_section_whose_fits_would_condense_beyond_memory_is_refused(monkeypatch):
    # few triangles (a coarse bulk) but a long fit at a fine fit size: the triangle count passes,
    # the condensation's pairs x pairs arrays (3200 pairs: 0.25 GB) do not
    monkeypatch.setenv("BEARINGFEM_MAX_ELEMENTS", "20000")
    sec = two_cylinder_section(0.0, 10.0, 15.0, "9Cr18", "9Cr18", 400.0, size_mm=2.0,
                               fit_size_mm=0.25)
    from meshes.build import estimate_elements
    assert estimate_elements(sec) < 20000
    with pytest.raises(MeshError, match="condensation"):
        check_size(sec)


@pytest.mark.parametrize("key,value,spacer,spacer_value,fragment", [
    # seed 000 (71807C: dm 41, Dw 3.969 mm): groove bottoms near dm -+ Dw = 37.03 / 44.97 mm
    ("inner_ring_outer_diameter_mm", 35.2, "inner_spacer", 35.1, "35.2 mm leaves the inner ring "
     "thinner than the metal under its groove (groove bottom at 37.0"),
    ("outer_ring_inner_diameter_mm", 46.8, "outer_spacer", 46.9, "46.8 mm leaves the outer ring "
     "thinner than the metal under its groove (groove bottom at 44.9"),
])
def test_a_ring_section_thinner_than_its_groove_is_refused(tmp_path, capsys, cond, key, value,
                                                           spacer, spacer_value, fragment):
    # before: the 0.1 mm inner section passed every check, sized the mesh to 0.1 mm and the
    # fits' condensation grew to 18 GB until the process was killed
    text = re.sub(rf"(?m)^{key}\s*=\s*[^#\n]*", f"{key} = {value} ", CFG.read_text())
    start = text.index(f"[{spacer}]")
    text = text[:start] + re.sub(r"(?m)^diameter_mm\s*=\s*[^#\n]*", f"diameter_mm = {spacer_value} ",
                                 text[start:], count=1)
    asm = tmp_path / "asm.toml"
    asm.write_text(text)
    code, err = run_cli(["simulate", asm, cond, "-o", tmp_path / "o.csv"], capsys)
    assert_refused(code, err, f"bearing.{key}: {fragment}", tmp_path, {asm: digest(asm), cond: digest(cond)})
    assert not (tmp_path / "o.csv").exists()


# ------------------------------------------------------------------ signals, ranges, usage
def test_sigterm_cleans_up_and_exits_143(tmp_path, capsys, cond, monkeypatch):
    from studies.model import pipeline

    real = pipeline.Pipeline.run

    def killed(self, *a, **k):
        os.kill(os.getpid(), signal.SIGTERM)           # what `timeout` or a scheduler sends
        return real(self, *a, **k)
    monkeypatch.setattr(pipeline.Pipeline, "run", killed)
    out = tmp_path / "o.csv"
    code, err = run_cli(["simulate", CFG, cond, "-o", out], capsys)
    assert code == 143 and err == ["bearingfem: terminated"]
    assert not out.exists() and not list(tmp_path.glob(".o.csv*"))


@pytest.mark.parametrize("content,fragment", [
    ("T_ambient_C,axial_load_N\n20,1e300\n", "column 'axial_load_N': 1e+300 outside"),
    ("T_ambient_C\n20\n-400\n", "column 'T_ambient_C': -400 outside"),
])
def test_condition_ranges(tmp_path, capsys, content, fragment):
    c = tmp_path / "c.csv"
    c.write_text(content)
    code, err = run_cli(["simulate", CFG, c, "-o", tmp_path / "o.csv"], capsys)
    assert_refused(code, err, fragment, tmp_path, {c: digest(c)})


def test_measured_torque_range(tmp_path, capsys):
    m = tmp_path / "m.csv"
    rows = "".join(f"{t},{20 + t / 100},{1.0 if t else 1e300}\n" for t in range(0, 1200, 100))
    m.write_text("time_s,T_ambient_C,torque_Nmm\n" + rows)
    code, err = run_cli(["diagnose", CFG, m, "--out", tmp_path / "d"], capsys)
    assert_refused(code, err, "column 'torque_Nmm': 1e+300 outside", tmp_path, {m: digest(m)})
    assert not (tmp_path / "d").exists()


@pytest.mark.parametrize("argv", [["simulate"], ["nope"], ["study"], ["simulate", "a", "b"]])
def test_usage_errors_are_one_line(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and len(err) == 1 and "--help" in err[0], err


def test_a_truncated_gmsh_write_never_enters_the_cache(cache, monkeypatch):
    """On a full disk gmsh writes a short file without raising: it is checked before the move."""
    import meshes.build as mb

    real = mb._mesh_with_gmsh

    def short_write(section, tmp):
        real(section, tmp)
        tmp.write_bytes(tmp.read_bytes()[:200])
    monkeypatch.setattr(mb, "_mesh_with_gmsh", short_write)
    with pytest.raises(MeshError, match="gmsh wrote an unusable mesh"):
        section_mesh(SEC)
    assert not list(cache.glob("section_*"))
    monkeypatch.setattr(mb, "_mesh_with_gmsh", real)
    assert section_mesh(SEC).triangles.shape[1] > 0             # the next run (disk freed) works


def test_temporaries_of_runs_killed_outright_are_removed_by_age(tmp_path, capsys, cond):
    old_file, old_dir = tmp_path / ".o.csv.abc123", tmp_path / ".sout.xyz"
    old_file.write_text("partial")
    old_dir.mkdir()
    fresh = tmp_path / ".o.csv.new456"                  # a run still writing: left alone
    fresh.write_text("partial")
    day_ago = os.stat(cond).st_mtime - 2 * 24 * 3600
    for p in (old_file, old_dir):
        os.utime(p, (day_ago, day_ago))
    assert run_cli(["simulate", CFG, cond, "-o", tmp_path / "o.csv"], capsys)[0] == 0
    assert not old_file.exists() and fresh.exists()
    assert run_cli(["study", "lubricant_viscosity", "--out", tmp_path / "sout"], capsys)[0] == 0
    assert not old_dir.exists()


def test_excel_csv_with_a_byte_order_mark_is_read(tmp_path, capsys):
    plain, bom = tmp_path / "plain.csv", tmp_path / "bom.csv"
    plain.write_text("T_ambient_C\n20\n40\n")
    bom.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    for src, out in ((plain, tmp_path / "a.csv"), (bom, tmp_path / "b.csv")):
        assert run_cli(["simulate", CFG, src, "-o", out], capsys)[0] == 0
    assert (tmp_path / "a.csv").read_text() == (tmp_path / "b.csv").read_text()


def test_output_is_plain_csv_with_its_provenance_beside_it(tmp_path, capsys, cond):
    import csv
    import json

    out = tmp_path / "o.csv"
    assert run_cli(["simulate", CFG, cond, "-o", out], capsys)[0] == 0
    lines = out.read_text().splitlines()
    assert not any(line.startswith("#") for line in lines)       # a default CSV reader's input
    header = next(csv.reader([lines[0]]))
    assert header[0] == "T_ambient_C" and "preload_N" in header and len(lines) == 3
    prov = json.loads((tmp_path / "o.csv.json").read_text())
    assert prov["inputs"]["conditions"]["sha256"] == digest(cond)
    assert prov["inputs"]["assembly"]["sha256"] == digest(CFG)


def test_a_sidecar_path_that_is_a_link_is_refused(tmp_path, capsys, cond):
    target = tmp_path / "elsewhere.json"
    target.write_text("{}")
    (tmp_path / "o.csv.json").symlink_to(target)
    code, err = run_cli(["simulate", CFG, cond, "-o", tmp_path / "o.csv"], capsys)
    assert_refused(code, err, "symbolic link", tmp_path, {target: digest(target), cond: digest(cond)})
    assert not (tmp_path / "o.csv").exists()


# ------------------------------------------------------------------ signals in a real process
# Each runs the command in a subprocess, sends the signal at a point it can see (a hidden file
# appearing) or at a fixed delay inside the start-up, and checks the exit code, the one stderr line
# and that nothing is left: the output, the temporaries beside it, the cache's temporaries.
BIN = Path(sys.executable).with_name("bearingfem")


def _start(argv, cache_dir, **kw):
    env = dict(os.environ, BEARINGFEM_CACHE=str(cache_dir))
    env.pop("BEARINGFEM_VERBOSE", None)
    return subprocess.Popen([str(BIN), *map(str, argv)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, **kw)


def _wait_for(proc, pattern_dir: Path, pattern: str, timeout_s: float = 120.0) -> list[Path]:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        found = list(pattern_dir.glob(pattern)) if pattern_dir.is_dir() else []
        if found:
            return found
        assert proc.poll() is None, f"finished before {pattern} appeared: {proc.stderr.read()}"
        time.sleep(0.005)
    proc.kill()
    raise AssertionError(f"{pattern} did not appear in {timeout_s} s")


def _sigint_as_in_a_terminal() -> None:
    """Run in the child before exec: SIGINT to its default action, as a shell started from a
    terminal has it (pytest-xdist workers ignore SIGINT, and a child inherits that)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _leftovers(*folders: Path) -> list[str]:
    return sorted(str(p) for d in folders if d.is_dir() for p in d.rglob(".*"))


def test_gmsh_leaves_sigterm_to_python(tmp_path):
    """gmsh.initialize resets SIGTERM (and SIGPIPE) to the default action: without undoing it,
    SIGTERM after the first mesh killed the process outright (rc -15) and no clean-up ran."""
    code = ("import os, signal, sys\n"
            "signal.signal(signal.SIGTERM, lambda s, f: sys.exit(43))\n"
            "from meshes.build import build_mesh\n"
            "from meshes.section import two_cylinder_section\n"
            "build_mesh(two_cylinder_section(0.0, 10.0, 15.0, '9Cr18', '9Cr18', 8.0, size_mm=2.0,"
            " fit_size_mm=1.0))\n"
            "os.kill(os.getpid(), signal.SIGTERM)\n"
            "signal.pause()\n")
    env = dict(os.environ, BEARINGFEM_CACHE=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 43, done.stderr


@pytest.mark.slow          # ~10 s: a cold mesh and FE set-up (the cause: test_gmsh_leaves_sigterm_...)
def test_sigterm_on_a_cold_cache_after_the_output_is_opened_leaves_nothing(tmp_path):
    """The FE set-up of a cold cache runs gmsh; SIGTERM once the hidden output file exists (rows
    not written yet: 20 000 of them) must end with 143 and leave neither it nor a sidecar."""
    cond = tmp_path / "cond.csv"
    cond.write_text("T_ambient_C\n" + "".join(f"{20 + 1e-3 * i:.3f}\n" for i in range(20_000)))
    out_dir = tmp_path / "out"
    proc = _start(["simulate", CFG, cond, "-o", out_dir / "o.csv"], tmp_path / "cache")
    _wait_for(proc, out_dir, ".o.csv.*")
    proc.send_signal(signal.SIGTERM)
    err = proc.communicate(timeout=60)[1].strip().splitlines()
    assert proc.returncode == 143 and err == ["bearingfem: terminated"], (proc.returncode, err)
    assert not out_dir.exists() and not _leftovers(tmp_path / "cache")


@pytest.mark.slow
def test_sigterm_during_mesh_convergence_leaves_nothing(tmp_path):
    """SIGTERM while the study meshes its finer levels (after the first level's mesh is cached):
    no temporary output folder and no temporary mesh in the cache."""
    cache = tmp_path / "cache"
    proc = _start(["study", "mesh_convergence", "--out", tmp_path / "mc"], cache)
    _wait_for(proc, cache / "meshes", "section_*.msh")
    time.sleep(0.5)
    proc.send_signal(signal.SIGTERM)
    err = proc.communicate(timeout=120)[1].strip().splitlines()
    assert proc.returncode == 143 and err == ["bearingfem: terminated"], (proc.returncode, err)
    assert not (tmp_path / "mc").exists() and not _leftovers(tmp_path, cache)


@pytest.mark.parametrize("module", ["numpy", "studies.model.config"])
def test_ctrl_c_during_start_up_is_one_line(tmp_path, module):
    """Ctrl-C while the command loads its modules: one line, exit 130. The signal is sent when
    the command starts to import `module` (an import hook in the process: a fixed point, where a
    delay would depend on the machine's load), the way the console script starts the command."""
    cond = tmp_path / "cond.csv"
    cond.write_text("T_ambient_C\n20\n")
    code = ("import os, signal, sys\n"
            "class Hook:\n"
            "    def find_spec(self, name, path=None, target=None):\n"
            f"        if name == {module!r}:\n"
            "            os.kill(os.getpid(), signal.SIGINT)\n"
            "sys.meta_path.insert(0, Hook())\n"
            "from studies.app.cli import main\n"
            "sys.exit(main())\n")
    env = dict(os.environ, BEARINGFEM_CACHE=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", code, "simulate", str(CFG), str(cond), "-o",
                           str(tmp_path / "o.csv")], env=env, capture_output=True, text=True,
                          timeout=120, preexec_fn=_sigint_as_in_a_terminal)
    err = done.stderr.strip().splitlines()
    assert done.returncode == 130 and err == ["bearingfem: interrupted"], err
    assert not (tmp_path / "o.csv").exists() and not _leftovers(tmp_path)


def test_ctrl_c_while_an_image_renders_waits_for_the_plotter(tmp_path):
    """Ctrl-C inside VTK's rendering (here: at the screenshot call) is delivered once the image is
    written and its plotter closed, not in the middle of VTK calls (which crashed the interpreter
    in 1 of 12 trials): the first image exists, no second was started."""
    code = ("import os, signal, sys\n"
            "from pathlib import Path\n"
            "import numpy as np, pyvista as pv\n"
            "from fem.fields import render_fields\n"
            "from fem.model import build_model\n"
            "from meshes.section import two_cylinder_section\n"
            "model = build_model(two_cylinder_section(5.0, 10.0, 15.0, 'TC4', '9Cr18', 10.0))\n"
            "real = pv.Plotter.screenshot\n"
            "def screenshot(self, *a, **k):\n"
            "    os.kill(os.getpid(), signal.SIGINT)\n"
            "    return real(self, *a, **k)\n"
            "pv.Plotter.screenshot = screenshot\n"
            "try:\n"
            "    render_fields(Path(sys.argv[1]), 'f', model, np.zeros(model.ndofs), {}, 't',\n"
            "                  T_vertex_C=np.zeros(model.mesh.p.shape[1]))\n"
            "except KeyboardInterrupt:\n"
            "    sys.exit(130)\n")
    env = dict(os.environ, BEARINGFEM_CACHE=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", code, str(tmp_path / "img")], env=env,
                          capture_output=True, text=True, timeout=120,
                          preexec_fn=_sigint_as_in_a_terminal)
    assert done.returncode == 130, done.stderr
    assert [p.name for p in (tmp_path / "img").iterdir()] == ["f_temperature_C.png"]


@pytest.mark.parametrize("argv,hidden", [
    (["study", "lubricant_viscosity", "--out", "{d}/sout"], ".sout.*"),
    pytest.param(["simulate", CFG, "{d}/cond.csv", "-o", "{d}/o.csv"], ".o.csv.*",
                 marks=pytest.mark.slow),      # ~10 s: a cold FE set-up before the file opens
])
def test_temporaries_of_a_run_killed_outright_are_removed_by_the_next(tmp_path, capsys, argv,
                                                                      hidden):
    """SIGKILL leaves the hidden temporary (nothing can clean up); the next run to the same output
    removes it at once (its PID is gone), not only after a day."""
    (tmp_path / "cond.csv").write_text("T_ambient_C\n" + "".join(f"{20 + 1e-3 * i:.3f}\n"
                                                                   for i in range(20_000)))
    argv = [str(a).format(d=tmp_path) for a in argv]
    proc = _start(argv, tmp_path / "cache")
    left = _wait_for(proc, tmp_path, hidden)
    proc.kill()
    proc.communicate(timeout=60)
    assert all(p.exists() for p in left)
    (tmp_path / "cond.csv").write_text("T_ambient_C\n20\n")
    assert run_cli(argv, capsys)[0] == 0
    assert not any(p.exists() for p in left)


def test_a_study_killed_outright_and_not_yet_reaped_leaves_nothing_after_the_next_run(tmp_path,
                                                                                      capsys):
    """A study killed with SIGKILL whose parent has not reaped it yet (a launcher or a
    notebook still running: the process stays a zombie, and `kill(pid, 0)` still finds it) left
    its hidden output folder `.sout.<pid>.<host><random>` behind the next run of the same study.
    A zombie never writes again: the next run removes the folder, and leaves nothing hidden."""
    argv = ["study", "lubricant_viscosity", "--out", str(tmp_path / "sout")]
    proc = _start(argv, tmp_path / "cache")
    try:
        left = _wait_for(proc, tmp_path, ".sout.*")
        proc.kill()
        t0 = time.monotonic()            # not reaped: wait until the kernel marks it a zombie
        while Path(f"/proc/{proc.pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z":
            assert time.monotonic() - t0 < 30
            time.sleep(0.01)
        assert all(p.exists() for p in left)
        assert run_cli(argv, capsys)[0] == 0
        assert sorted(p.name for p in tmp_path.iterdir() if p.name != "cache") == ["sout"]
    finally:
        proc.kill()
        proc.communicate(timeout=60)

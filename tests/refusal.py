"""One check shared by the config tests: `simulate` refuses an assembly file with exit code 2,
one stderr line holding every fragment, and no output file (docs/cli.md, bad input)."""
from studies.app.cli import main


def simulate_is_refused(tmp_path, capsys, cfg, *fragments: str) -> None:
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", str(cfg), str(cond), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and all(f in err[0] for f in fragments), err
    assert not out.exists()

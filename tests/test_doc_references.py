"""Docstrings and comments cite the project's own documents: no file of the
project names `DESIGN.md` or `spec/cli.md` (briefs outside the project), and every `docs/*.md`,
`README.md` or `CHANGELOG.md` a Python file names exists in the project."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("analytic", "fem", "infra", "meshes", "studies", "bearingfem", "tests")


def python_files():
    for pkg in PACKAGES:
        yield from sorted((ROOT / pkg).rglob("*.py"))


def test_no_citation_of_documents_outside_the_project():
    outside = re.compile(r"DESIGN\.md|spec/cli\.md")
    hits = [f"{p.relative_to(ROOT)}:{i}" for p in python_files()
            for i, line in enumerate(p.read_text().splitlines(), 1)
            if outside.search(line) and p.name != Path(__file__).name]
    assert not hits, hits


def test_cited_project_documents_exist():
    cited = re.compile(r"\b(docs/[\w/-]+\.md|README\.md|CHANGELOG\.md)")
    missing = sorted({f"{p.relative_to(ROOT)}: {m}" for p in python_files()
                      for m in cited.findall(p.read_text()) if not (ROOT / m).exists()})
    assert not missing, missing


#: paths named in the tests as made-up examples (fixtures written into temporary folders)
EXAMPLES = {"tests/test_x.py", "tests/test_a.py", "infra/a.py", "infra/b.py", "infra/q/__init__.py",
            "infra/q/r.py"}


def test_cited_project_files_exist():
    """Every file of the project a Python file names by its path (a module, a test, a config, a
    doc) exists: a docstring that sends the reader to a file that was moved or never written
    is a dead end."""
    cited = re.compile(r"(?<![\w./-])((?:analytic|fem|meshes|studies|infra|tests|bearingfem|docs)"
                       r"/[\w/.-]*\w\.(?:py|md|toml|csv|png|json))")
    missing = sorted({f"{p.relative_to(ROOT)}: {m}" for p in python_files()
                      for m in cited.findall(p.read_text())
                      if m not in EXAMPLES and not (ROOT / m).exists()})
    assert not missing, missing

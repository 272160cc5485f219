"""Docstrings and comments cite the project's own documents (issue 36 item 6): no file of the
project names `DESIGN.md` or `spec/cli.md` (briefs outside the project), and every `docs/*.md`,
`README.md` or `CHANGELOG.md` a Python file names exists in the project."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("analytic", "fem", "infra", "studies", "bearingfem", "tests")


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

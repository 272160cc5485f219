"""The import graph of the project's packages holds the README's layout rule: each row of its
layout table uses only itself and the rows above it, and no module imports itself in a circle.

The graph is read from the source (ast), every import statement counted: module level, inside
functions (a deferred import still needs its target at run time) and under `if TYPE_CHECKING`.
`import a.b.c` / `from a.b import c` is an edge to `a.b.c` and, as Python runs them first, to the
packages `a` and `a.b` (their `__init__.py`) unless the importer lives in them.
"""
from __future__ import annotations

import ast
import functools
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the rows of the README's layout table, top first (a module belongs to its longest prefix)
LAYERS = ("infra", "analytic", "meshes", "fem", "studies", "studies.model", "studies.diagnosis",
          "studies.usecases", "studies.validation", "studies.bench", "studies.app", "bearingfem")
PACKAGES = ("infra", "analytic", "meshes", "fem", "studies", "bearingfem")



def modules(root: Path = ROOT) -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for f in sorted((root / pkg).rglob("*.py")):
            parts = list(f.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = f
    return out


@functools.lru_cache(maxsize=None)
def parsed(path: Path) -> ast.Module:
    """The syntax tree of one source file, parsed once per test process (three tests read them)."""
    return ast.parse(path.read_text(), str(path))


@functools.lru_cache(maxsize=None)
def project_graph() -> dict[str, set[tuple[str, int]]]:
    """`import_graph` of this tree, built once for the tests that read it."""
    return import_graph()


def import_graph(root: Path = ROOT) -> dict[str, set[tuple[str, int]]]:
    """module -> {(imported module, line)} over the project's modules (see the module docstring)."""
    mods = modules(root)

    def known(name: str) -> str | None:
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    graph = {}
    for mod, path in mods.items():
        is_pkg = path.name == "__init__.py"
        edges = set()
        for node in ast.walk(parsed(path)):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    here = mod.split(".") if is_pkg else mod.split(".")[:-1]
                    here = here[:len(here) - node.level + 1]
                    base = ".".join(here + ([node.module] if node.module else []))
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base
                           for a in node.names]
            else:
                continue
            for t in targets:
                t = known(t)
                if t is None:
                    continue
                parts = t.split(".")
                for i in range(1, len(parts) + 1):       # the packages on the way, then t
                    target = ".".join(parts[:i])
                    if target in mods and target != mod and not mod.startswith(target + "."):
                        edges.add((target, node.lineno))
        graph[mod] = edges
    return graph


def cycles(graph) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w, _ in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layer(mod: str) -> int:
    return max((i for i, p in enumerate(LAYERS) if mod == p or mod.startswith(p + ".")),
               key=lambda i: len(LAYERS[i]))


def upward_imports(graph) -> list[str]:
    return sorted(f"{m}:{line} imports {t} (row {LAYERS[layer(t)]} is below {LAYERS[layer(m)]})"
                  for m, edges in graph.items() for t, line in edges
                  if layer(t) > layer(m) and not (LAYERS[layer(m)] == "studies"))


def test_no_import_cycle():
    bad = cycles(project_graph())
    assert not bad, "import cycles:\n" + "\n".join(" -> ".join(c) for c in bad)


def test_no_upward_import():
    bad = upward_imports(project_graph())
    assert not bad, "imports against the layout table (README):\n" + "\n".join(bad)


def test_the_readme_table_lists_the_layers_in_this_order():
    """The README's layout table is the rule; LAYERS above is its copy."""
    text = (ROOT / "README.md").read_text()
    table = text[text.index("## Layout"):]
    table = table[:table.index("\n\n", table.index("| folder |"))]
    rows = [line.split("|")[1].strip().strip("`").rstrip("/").replace("/", ".")
            for line in table.splitlines() if line.startswith("| `")]
    assert [r for r in rows if r in LAYERS] == [r for r in LAYERS if r != "studies"]


def test_the_graph_sees_deferred_and_package_imports(tmp_path):
    """The reader itself, on a made-up tree: a function-level import closes a cycle, and
    importing `p.q.r` runs `p/q/__init__.py` (an edge to it)."""
    for rel, text in {"infra/__init__.py": "", "infra/a.py": "def f():\n    from infra import b\n",
                      "infra/b.py": "import infra.a\n", "infra/q/__init__.py": "import infra.b\n",
                      "infra/q/r.py": "", "analytic/__init__.py": "import infra.q.r\n"}.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    for pkg in ("meshes", "fem", "studies", "bearingfem"):
        (tmp_path / pkg).mkdir()
        (tmp_path / pkg / "__init__.py").write_text("")
    g = import_graph(tmp_path)
    assert cycles(g) == [["infra.a", "infra.b"]]
    assert {t for t, _ in g["analytic"]} == {"infra", "infra.q", "infra.q.r"}


def test_one_csv_writer():
    """Every CSV the project writes goes through studies/model/table.py (one dialect, the one of
    `simulate`): no other module builds csv writers or formats CSV lines itself."""
    writers = []
    for mod, path in modules().items():
        if mod == "studies.model.table":
            continue
        for node in ast.walk(parsed(path)):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id == "csv" and node.attr in ("writer", "DictWriter")):
                writers.append(f"{mod}:{node.lineno} csv.{node.attr}")
    assert not writers, writers

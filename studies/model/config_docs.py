"""The key tables of docs/cli.md generated from the schema (config_schema.py) and the sections
of the assembly file (config.py `SECTIONS`): `python -m studies.model.config_docs docs/cli.md`
rewrites every generated block; a test holds the docs equal to them."""
from __future__ import annotations

import sys

from studies.model.config import SECTIONS
from studies.model.config_schema import ASSEMBLY_KEYS, keys_of, markdown_table


def section_tables() -> dict[str, str]:
    """The markdown key table of every table of the assembly file, in file order; tables with
    the same keys (nut and cover, the two spacers, sleeve and cartridge) share one, named
    "nut, cover"."""
    groups: dict[type, list[str]] = {}
    for name, cls in SECTIONS.items():
        groups.setdefault(cls, []).append(name)
    return {"assembly": markdown_table(ASSEMBLY_KEYS),
            **{", ".join(names): markdown_table(keys_of(cls)) for cls, names in groups.items()}}


def _block(name: str) -> tuple[str, str]:
    return f"<!-- keys [{name}]: generated from studies/model/config_schema.py -->", "<!-- /keys -->"


def with_tables(doc: str) -> str:
    """`doc` with every generated key table block (between its two markers) rewritten."""
    for name, table in section_tables().items():
        start, end = _block(name)
        i = doc.find(start)
        if i < 0:
            continue
        j = doc.index(end, i)
        doc = doc[:i] + start + "\n" + table + "\n" + doc[j:]
    return doc


if __name__ == "__main__":            # python -m studies.model.config_docs docs/cli.md
    for p in sys.argv[1:]:
        with open(p, encoding="utf-8") as fh:
            old = fh.read()
        new = with_tables(old)
        if new != old:
            with open(p, "w", encoding="utf-8") as fh:
                fh.write(new)

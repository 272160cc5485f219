"""`report.pdf` from the report's markdown lines, without LaTeX: the markdown subset the reports
use (headings, paragraphs, tables, images, lists, **bold**, `code`) written as Typst markup and
compiled by the `typst` package from PyPI.

Why typst: its wheels carry the whole compiler and its fonts (no system libraries, no TeX);
weasyprint needs Pango from the operating system. Reproducible: every text run is a Typst string
literal (no markup in the report's text can change the layout), the document date is fixed
(`date: none`) and only the fonts shipped in the wheel are used (`ignore_system_fonts`), so the
same markdown and images give the same bytes.
"""
from __future__ import annotations

import re
from pathlib import Path

#: page and type: A4, narrow margins, small type for the wide tables
PREAMBLE = """#set document(title: {title}, date: none)
#set page(paper: "a4", margin: (x: 1.4cm, y: 1.5cm), numbering: "1 / 1")
#set text(size: 8.5pt)
#set par(justify: false)
#show heading.where(level: 1): set text(size: 15pt)
#show heading.where(level: 2): set text(size: 12pt)
#show heading.where(level: 3): set text(size: 10pt)
#set table(stroke: 0.4pt + luma(160), inset: 2.5pt)
#show table: set text(size: 6.5pt)
#show table: set par(justify: false)
"""

_IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)]+)\)")
_INLINE = re.compile(r"(\*\*[^*]+\*\*|`[^`]+`)")


def _str(text: str) -> str:
    """A Typst string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def inline(text: str) -> str:
    """Markdown text with **bold** and `code` as Typst content (string literals only)."""
    out = []
    for part in _INLINE.split(text):
        if not part:
            continue
        if part.startswith("**") and part.endswith("**"):
            out.append(f"#strong({_str(part[2:-2])})")
        elif part.startswith("`") and part.endswith("`"):
            out.append(f"#raw({_str(part[1:-1])})")
        else:
            out.append(f"#{_str(part)}")
    return "".join(out)


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _breakable(cell: str) -> str:
    """A table cell whose column names (fit_pressure_inner_MPa) may wrap after an underscore
    (a zero-width space there): a narrow column never runs into the next one."""
    return cell.replace("_", "_\u200b")


def _table(rows: list[list[str]]) -> str:
    n = len(rows[0])
    head = ", ".join(f"[#strong({_str(_breakable(c))})]" for c in rows[0])
    cells = ", ".join(f"[{inline(_breakable(c))}]" for r in rows[1:] for c in (r + [""] * n)[:n])
    return f"#table(columns: {n}, table.header({head}), {cells})"


def _images_only(line: str) -> bool:
    return bool(_IMAGE.search(line)) and not _IMAGE.sub("", line).strip()


def to_typst(lines: list[str], out: Path, title: str) -> str:
    """Typst source of the markdown `lines`; images are looked up in `out`."""
    src = [PREAMBLE.format(title=_str(title))]
    lines = "\n".join(lines).split("\n")          # a table is one item holding its rows
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("|"):
            block = []
            while i < len(lines) and lines[i].startswith("|"):
                if not re.fullmatch(r"\|(-+\|)+", lines[i].strip()):
                    block.append(_cells(lines[i]))
                i += 1
            src.append(_table(block) + "\n")
            continue
        m = re.match(r"(#{1,4}) (.*)", line)
        if m:
            src.append("=" * len(m.group(1)) + " " + inline(m.group(2)) + "\n")
        elif _images_only(line):
            # consecutive lines of one image each (the plots) two to a row; a line of
            # several (the field images) as one row
            paths = [p for _, p in _IMAGE.findall(line)]
            if len(paths) == 1:
                while i + 1 < len(lines) and (not lines[i + 1].strip() or _images_only(lines[i + 1])) \
                        and len(_IMAGE.findall(lines[i + 1])) <= 1:
                    i += 1
                    paths += [p for _, p in _IMAGE.findall(lines[i])]
            paths = [p for p in paths if (out / p).is_file()]
            cols = 2 if len(paths) != 3 else 3
            imgs = ", ".join(f"image({_str(p)}, width: 100%)" for p in paths)
            if paths:
                src.append(f"#grid(columns: {cols}, gutter: 6pt, {imgs})\n")
        elif re.match(r"(- |\d+\. )", line):
            m = re.match(r"(- |\d+\. )(.*)", line)
            marker = "-" if m.group(1) == "- " else "+"
            src.append(f"{marker} {inline(m.group(2))}")
        elif line.strip():
            src.append(inline(line) + "\n")
        else:
            src.append("")
        i += 1
    return "\n".join(src) + "\n"


def write_pdf(out: Path, lines: list[str], title: str) -> Path:
    """`report.pdf` in `out` from the report's markdown lines (images from `out`)."""
    import typst

    source = out / "report.typ"
    source.write_text(to_typst(lines, out, title), encoding="utf-8")
    pdf = out / "report.pdf"
    try:
        pdf.write_bytes(typst.compile(str(source), root=str(out), ignore_system_fonts=True))
    finally:
        source.unlink()
    return pdf

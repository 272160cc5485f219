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


#: the page's text width (A4, 210 mm less 2 x 1.4 cm margins), pt
TEXT_WIDTH_PT = (210.0 - 28.0) / 25.4 * 72.0
#: a table's type size (PREAMBLE) and the cell inset on each side, pt
TABLE_FONT_PT, TABLE_INSET_PT = 6.5, 2.5
#: the widest average advance of a glyph of the bold header type, in em (the default serif's
#: bold lower case and digits stay below it; an overestimate only splits a table sooner)
GLYPH_EM = 0.58


def _pieces(cell: str) -> list[str]:
    """The pieces of a cell that cannot wrap: words, split after each underscore (`_breakable`)."""
    return [p for p in re.split(r"\s+|(?<=_)", cell) if p]


def column_width_pt(cells: list[str]) -> float:
    """The narrowest width (pt) a column needs so that none of its pieces (`_pieces`) is broken
    or runs into the next column: the longest piece at GLYPH_EM per character, plus the insets."""
    longest = max((len(p) for c in cells for p in _pieces(c)), default=0)
    return longest * GLYPH_EM * TABLE_FONT_PT + 2.0 * TABLE_INSET_PT


def column_groups(rows: list[list[str]]) -> list[list[int]]:
    """The columns of a table split into groups that each fit the text width (`column_width_pt`),
    the first column (the row's label) repeated at the head of each group; one group when the
    table fits."""
    n = len(rows[0])
    w = [column_width_pt([r[j] for r in rows if j < len(r)]) for j in range(n)]
    groups, cur, width = [], [0], w[0]
    for j in range(1, n):
        if width + w[j] > TEXT_WIDTH_PT and len(cur) > 1:
            groups.append(cur)
            cur, width = [0], w[0]
        cur.append(j)
        width += w[j]
    groups.append(cur)
    return groups


def _table(rows: list[list[str]]) -> str:
    """Typst table(s) of the markdown rows: a table wider than the page is split into column
    groups (`column_groups`), so that no header breaks inside a word or runs into its neighbour."""
    n = len(rows[0])
    rows = [(r + [""] * n)[:n] for r in rows]
    out = []
    for g in column_groups(rows):
        head = ", ".join(f"[#strong({_str(_breakable(rows[0][j]))})]" for j in g)
        cells = ", ".join(f"[{inline(_breakable(r[j]))}]" for r in rows[1:] for j in g)
        out.append(f"#table(columns: {len(g)}, table.header({head}), {cells})")
    return "\n#v(4pt)\n".join(out)


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

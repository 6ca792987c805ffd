"""The report's blocks (headings, paragraphs, tables, images), their Markdown and HTML
renderers (no Markdown library), and the number formats used throughout the report."""
from __future__ import annotations

import html
import math
import re
from dataclasses import dataclass

#: How each phase, metric, axis and ring-centre displacement is named in the text.
PHASE_TITLE = {"startup": "start-up", "steady": "steady", "deceleration": "deceleration"}
METRIC_TITLE = {"range": "variation range", "mean": "mean", "std": "standard deviation"}
AXIS_TITLE = {"speed": "speed", "radial_load": "radial load"}
CENTRE_LABEL = {"radial": "δ_r at the ring centre", "axial": "δ_a at the ring centre"}

# --------------------------------------------------------------------------- blocks


@dataclass
class Heading:
    level: int
    text: str


@dataclass
class Para:
    text: str


@dataclass
class Warning_:
    text: str


@dataclass
class Bullets:
    items: list


@dataclass
class Table:
    header: list
    rows: list
    #: Keep the first two columns in view while a wide table scrolls sideways (HTML only;
    #: for a table whose first two columns are short: the summary's speed and load).
    sticky: bool = False


@dataclass
class Image:
    path: str  # relative to the report folder
    alt: str


def _md_cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def render_markdown(blocks) -> str:
    """Blocks to Markdown text."""
    out = []
    for b in blocks:
        if isinstance(b, Heading):
            out.append("#" * b.level + " " + b.text)
        elif isinstance(b, Para):
            out.append(b.text.strip())
        elif isinstance(b, Warning_):
            out.append("\n".join("> " + line for line in b.text.splitlines()))
        elif isinstance(b, Bullets):
            out.append("\n".join(f"- {item}" for item in b.items))
        elif isinstance(b, Table):
            lines = ["| " + " | ".join(_md_cell(h) for h in b.header) + " |",
                     "|" + "|".join("---" for _ in b.header) + "|"]
            lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in b.rows]
            out.append("\n".join(lines))
        elif isinstance(b, Image):
            out.append(f"![{b.alt}]({b.path})")
    return "\n\n".join(out) + "\n"


def _inline_html(text: str) -> str:
    s = html.escape(str(text), quote=False)
    s = re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", s)
    s = re.sub(r"`(.+?)`", r"<code>\1</code>", s)
    return s


# A wide table (the summary has 18 columns) scrolls inside its own bordered box instead of
# widening the page or being cut at its edge: the box shows its scrollbar, and the first
# two columns (the operating point: speed and load) stay in view while the rest scrolls. Its header stays readable
# (no wrapping into one letter a line). A verdict cell of the headline is coloured.
_CSS = """body{font-family:system-ui,sans-serif;max-width:76em;margin:2em auto;padding:0 1em;line-height:1.45;color:#222}
h1{font-size:1.7em;border-bottom:2px solid #345}h2{font-size:1.3em;margin-top:2em;border-bottom:1px solid #ccd;color:#234}
h3{font-size:1.1em;color:#345}.table{overflow-x:auto;margin:1em 0;max-width:100%}
.table.wide{overflow-x:auto;border:1px solid #9aa7b8}.table.wide table{margin:0}
.sticky td:nth-child(-n+2),.sticky th:nth-child(-n+2){position:sticky;z-index:1;box-sizing:border-box;
width:6.5em;min-width:6.5em;max-width:6.5em}.sticky :is(td,th):first-child{left:0}
.sticky :is(td,th):nth-child(2){left:6.5em;box-shadow:2px 0 3px -1px #9aa7b8}
.sticky th:nth-child(-n+2){z-index:2}.sticky tr:nth-child(odd) td:nth-child(-n+2){background:#fff}
.scrollnote{font-size:85%;color:#555;margin:.2em 0 -.6em}
table{border-collapse:collapse;font-size:88%;font-variant-numeric:tabular-nums}
th,td{border:1px solid #c8c8c8;padding:.25em .55em;text-align:left;vertical-align:top}
th{background:#e8ecf2;position:sticky;top:0;min-width:5em}tr:nth-child(even) td{background:#f7f8fa}
td.pass{background:#e3f4e3 !important;color:#145214;font-weight:600}td.fail{background:#fbe0e0 !important;color:#8b0000;font-weight:700}
.caveat{border-left:.4em solid #c00;background:#fee;padding:.5em 1em;margin:1em 0}
img{max-width:100%;height:auto;display:block;margin:.5em auto}code{background:#f0f2f5;padding:0 .2em;border-radius:3px}"""


#: A table of more columns than this scrolls in a bordered box with a note above it.
WIDE_COLUMNS = 8


def _cell_class(text) -> str:
    """' class="pass"' or ' class="fail"' for a verdict cell ('✓ …', '✗ …'), else ''."""
    t = str(text)
    return ' class="pass"' if t.startswith("✓") else ' class="fail"' if t.startswith("✗") else ""


def render_html(blocks, title: str) -> str:
    """Blocks to a standalone HTML page."""
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           f"<title>{html.escape(title)}</title>", f"<style>{_CSS}</style>", "</head>", "<body>"]
    for b in blocks:
        if isinstance(b, Heading):
            out.append(f"<h{b.level}>{_inline_html(b.text)}</h{b.level}>")
        elif isinstance(b, Para):
            out.append(f"<p>{_inline_html(b.text.strip())}</p>")
        elif isinstance(b, Warning_):
            out.append('<div class="caveat">' + "".join(f"<p>{_inline_html(line)}</p>" for line in b.text.splitlines()) + "</div>")
        elif isinstance(b, Bullets):
            out.append("<ul>" + "".join(f"<li>{_inline_html(i)}</li>" for i in b.items) + "</ul>")
        elif isinstance(b, Table):
            rows = ["<tr>" + "".join(f"<th>{_inline_html(h)}</th>" for h in b.header) + "</tr>"]
            rows += ["<tr>" + "".join(f"<td{_cell_class(c)}>{_inline_html(c)}</td>" for c in r) + "</tr>"
                     for r in b.rows]
            wide = len(b.header) > WIDE_COLUMNS
            sticky = wide and b.sticky
            if wide:
                out.append(f'<p class="scrollnote">{len(b.header)} columns: the table scrolls sideways in its box'
                           + (" (the first two columns stay in view)" if sticky else "") + ".</p>")
            out.append(f'<div class="table{" wide" if wide else ""}{" sticky" if sticky else ""}"><table>'
                       + "".join(rows) + "</table></div>")
        elif isinstance(b, Image):
            out.append(f'<p><img src="{html.escape(b.path)}" alt="{html.escape(b.alt)}"></p>')
    out += ["</body>", "</html>"]
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- formatting


def fmt_number(x, digits: int = 3) -> str:
    """A number with ``digits`` significant digits; 'n/a' for NaN/None."""
    if x is None:
        return "n/a"
    x = float(x)
    if not math.isfinite(x):
        return "n/a"
    return f"{x:.{digits}g}"


def fmt_sci(x, digits: int = 3) -> str:
    """Scientific notation with ``digits`` significant digits."""
    if x is None or not math.isfinite(float(x)):
        return "n/a"
    return f"{float(x):.{digits - 1}e}"


def fmt_kn(newton: float) -> str:
    """A force [N] as '30 kN' (4 significant digits)."""
    return f"{fmt_number(newton / 1e3, 4)} kN"


def fmt_unit(text: str) -> str:
    """A unit string of a reference file as a reader writes it: ``mm/(deg/s)`` -> ``mm/(°/s)``."""
    return text.replace("deg/s", "°/s")


def fmt_speed(deg_s: float) -> str:
    """A speed [°/s] as '390 °/s' (4 significant digits)."""
    return f"{fmt_number(deg_s, 4)} °/s"


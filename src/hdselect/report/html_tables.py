"""The HTML report's building blocks: escaped tables, foldable sections, the page's styles.

Every table fits its page: at 1280 px and on A4 or Letter paper cells wrap between
words (never inside a unit id or a number), and on a phone each row becomes a block
of ``header: value`` lines, as the terminal does on a narrow screen. Sections after
the summary are ``<details open>``: a reader folds what they do not need, and
printing opens every one again (``::details-content``).
"""

from __future__ import annotations

import html
import re
from collections.abc import Sequence

esc = html.escape

STYLE = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;max-width:1200px;
margin:1.5em auto;padding:0 1em;color:#1a1a1a;line-height:1.4}
h1{font-size:1.5em;margin:.3em 0;overflow-wrap:break-word}h2{font-size:1.25em;margin:1.2em 0 .4em;
border-bottom:1px solid #ccc}h3{font-size:1.05em;margin:1em 0 .3em}
details>summary{cursor:pointer;list-style-position:outside;margin-left:1.1em}
details>summary>h2{display:inline-block;margin:.9em 0 .3em;border:none}
details{border-bottom:1px solid #ccc;margin-bottom:.4em}
.fit{max-width:100%}
table{border-collapse:collapse;margin:.4em 0;font-size:.85em;max-width:100%}
td,th{border:1px solid #bbb;padding:2px 5px;text-align:right;vertical-align:top;
overflow-wrap:normal}
th{background:#eee;vertical-align:bottom;font-weight:600}td.t,th.t{text-align:left}
td.wrap{min-width:6em}.id{white-space:nowrap}
td.u small{display:block;font-size:.78em;opacity:.9}
td.fail{font-weight:bold;outline:2px solid #000;outline-offset:-2px;
background-image:repeating-linear-gradient(45deg,rgba(0,0,0,.2) 0 2px,transparent 2px 7px)}
tr.chosen td:first-child{font-weight:bold}
.maps{display:flex;flex-wrap:wrap;gap:.5em 1.5em}.maps>div{min-width:0;max-width:100%}
.maps table{font-size:.78em}
.bar{display:flex;flex-wrap:wrap;align-items:center;gap:.6em;font-size:.85em;margin:.5em 0}
.ramp{position:relative;width:320px;max-width:70vw;height:16px;border:1px solid #555;
background:linear-gradient(to right,#f7fbff 0%,#9ecae1 25%,#2166ac 50%,#fdb863 50%,
#e66101 75%,#7f3b08 100%)}
.ramp .hatch{position:absolute;left:50%;top:0;right:0;bottom:0;background-image:
repeating-linear-gradient(45deg,rgba(0,0,0,.2) 0 2px,transparent 2px 7px)}
.ticks{display:flex;justify-content:space-between;width:320px;max-width:70vw;font-size:.8em}
img{max-width:100%;height:auto}figure{margin:.6em 0}figcaption{font-size:.85em;color:#444}
code,pre{font-family:ui-monospace,Menlo,Consolas,monospace;font-size:.85em;
overflow-wrap:anywhere}
pre{background:#f4f4f4;padding:.5em;white-space:pre-wrap;word-break:break-all}
:target{background:#ffe9a8}
.summary{font-size:.95em}.summary ul{margin:.2em 0;padding-left:1.3em}
.summary h2{margin-top:.6em}.summary h3{margin:.6em 0 .2em}
.facts{display:flex;flex-wrap:wrap;gap:0 2em}.facts>div{min-width:0}
.verdict{font-weight:600}.warn li{margin:.1em 0}.printnote{display:none}
*{-webkit-print-color-adjust:exact;print-color-adjust:exact}
@page{margin:12mm}
@media print{body{max-width:none;margin:0;padding:0;font-size:8.5pt}
table{font-size:7pt}td.u small{font-size:6pt}.maps table{font-size:6.5pt}
details::details-content{content-visibility:visible;display:block;height:auto}
details>summary{list-style:none;margin-left:0}details{border:none}
.summary{break-after:page;font-size:8.5pt}.summary table{font-size:7.5pt}
details[data-of=joint],details[data-of=provenance]{break-before:page}
summary,h2,h3{break-after:avoid}figure,tr{break-inside:avoid}
figure img{max-height:95mm;width:auto}
.bearingfigs figure{display:inline-block;width:49%;vertical-align:top;margin:0}
.bearingfigs img{max-width:100%}
section.pairs .maps,tr.no,tr.out td.u small{display:none}.printnote{display:block}
a{color:inherit}}
@media (max-width:640px){body{padding:0 .5em}
table.stack,table.stack tbody,table.stack tr,table.stack td{display:block;width:auto}
table.stack{border:none}table.stack tr.h{display:none}
table.stack tr{border:1px solid #bbb;margin:.5em 0;padding:.2em .4em}
table.stack td{border:none;border-bottom:1px dotted #ddd;text-align:left;padding:1px 0}
table.stack td::before{content:attr(data-h);font-weight:600;display:inline-block;
min-width:45%;margin-right:.4em;color:#333}
table.stack td.u small{display:inline;margin-left:.4em}}
"""
"""The page's styles: screen, print (A4 and Letter, 12 mm margins) and phone widths."""


def table(header: Sequence[str], rows: Sequence[Sequence[str]], *, left: int = 1,
          classes: Sequence[str] = (), text: Sequence[int] = ()) -> str:
    """A table of already-escaped cells; the first `left` columns, and `text`, align left.

    A cell given as a whole ``<td ...>`` element keeps its own attributes. Every cell
    carries its column's header (``data-h``), which a phone shows beside the value; the
    first `left` columns never wrap inside a word (unit and motor ids).
    """
    labels = [esc(re.sub(r"<[^>]+>", "", h).replace("&nbsp;", " "), quote=True)
              for h in header]
    head = "".join(f'<th{" class=t" if i < left or i in text else ""}>{unbroken(h)}</th>'
                   for i, h in enumerate(header))
    body = "".join(
        (f"<tr class='{classes[k]}'>" if k < len(classes) and classes[k] else "<tr>")
        + "".join(_cell(c, labels[i] if i < len(labels) else "", i < left, i in text)
                  for i, c in enumerate(row)) + "</tr>" for k, row in enumerate(rows))
    return f'<div class=fit><table class=stack><tr class=h>{head}</tr>{body}</table></div>'


def _cell(content: str, label: str, first: bool, words: bool) -> str:
    if content.startswith("<td"):
        return f'<td data-h="{label}"{content[3:]}'
    return f'<td data-h="{label}"{" class=t" if first or words else ""}>' + (
        f"<span class=id>{content}</span>" if first else content) + "</td>"


def unbroken(header: str) -> str:
    """A header that may wrap between words, but not inside a unit like ``[N m]``."""
    for unit in ("[N m]", "L50 h", "L10 h", "[rpm]", "[kg]"):
        header = header.replace(unit, unit.replace(" ", "&nbsp;"))
    return header


def anchor(unit_id: str) -> str:
    """The id of a unit's catalog note."""
    return "note-" + slug(unit_id)


def number(value: float) -> str:
    """A figure for a table: three significant digits, whole numbers from 1000 up."""
    if abs(value) >= 1000.0:
        return f"{value:,.0f}"
    return "0" if abs(value) < 1e-9 else f"{value:.3g}"


def slug(name: str) -> str:
    """A joint name as a fragment of an id or a file name."""
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)

"""The HTML page every HTML output of dcf2bin is (``map -f html``, ``network show -f html``,
``export -f html``): one self-contained page, no script, no outside file, XHTML-clean after
the doctype (a test reads it with an XML parser), and the same every run.

A leaf module: it imports nothing of dcf2bin, so ``plc``, ``network`` and ``export`` use it
without importing each other.
"""
from __future__ import annotations

import html
from dataclasses import dataclass


def escape(text: str) -> str:
    """Text for an element's content or an attribute's value."""
    return html.escape(text, quote=True)


@dataclass(frozen=True)
class Cell:
    """A table cell with a class (``Cell("12", "n")`` for a number set to the right)."""
    text: str
    cls: str = ""


def page(title: str, style: str, body: list[str]) -> str:
    """The page: ``title`` (text, escaped here), ``style`` (CSS, or "" for none) and the
    lines of the body (HTML, as given)."""
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8"/>',
           f"<title>{escape(title)}</title>"]
    if style:
        out.append(f"<style>{style}</style>")
    out += ["</head>", "<body>", *body, "</body>", "</html>", ""]
    return "\n".join(out)


def table(head: list[str] | None, rows, cls: str = "") -> list[str]:
    """A table's lines: a header row (none when ``head`` is None) and one row a line;
    every text is escaped, a cell may be a ``Cell`` to carry a class."""
    out = [f'<table class="{escape(cls)}">' if cls else "<table>"]
    if head is not None:
        out.append("<thead><tr>" + "".join(f"<th>{escape(h)}</th>" for h in head)
                   + "</tr></thead>")
    out.append("<tbody>")
    for row in rows:
        out.append("<tr>" + "".join(_cell(c) for c in row) + "</tr>")
    out += ["</tbody>", "</table>"]
    return out


def _cell(c) -> str:
    if isinstance(c, Cell):
        attr = f' class="{escape(c.cls)}"' if c.cls else ""
        return f"<td{attr}>{escape(c.text)}</td>"
    return f"<td>{escape(c)}</td>"

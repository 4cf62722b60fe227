"""The documentation of a device's object dictionary as one HTML page (``export --format
html``): the page ``markdown.build`` makes, rendered through ``dcf2bin.htmlpage`` (the
frame every HTML output of dcf2bin has), with a table of contents linking every object.
Descriptions keep their lines (``white-space: pre-wrap``); every text is escaped.
"""
from __future__ import annotations

from dcf2bin import htmlpage
from dcf2bin.export.common import ExportResult
from dcf2bin.export.markdown import Block, prepare
from dcf2bin.htmlpage import escape

STYLE = ("body{font-family:DejaVu Sans, Verdana, Arial, sans-serif;margin:1em 2em;"
         "max-width:72em}"
         "table{border-collapse:collapse;font-size:13px;margin:0.5em 0}"
         "th,td{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top}"
         "th{background:#eee}table.info td:first-child{font-weight:bold}"
         "h2{border-bottom:2px solid #1f5fbf;margin-top:1.5em}"
         "h3{margin:1.2em 0 0.3em;font-family:DejaVu Sans Mono, monospace}"
         ".desc{white-space:pre-wrap;font-size:13px;margin:0.3em 0 0.8em;padding:0.3em 0.6em;"
         "background:#f6f6f6;border-left:3px solid #ccc}"
         "nav ul{columns:2;font-size:13px}nav li.area{font-weight:bold;list-style:none;"
         "margin-top:0.4em}")


def to_html(page: list[Block]) -> str:
    title = next((b.text for b in page if b.kind == "h1"), "Object dictionary")
    body: list[str] = []
    for b in page:
        if b.kind in ("h1", "h2", "h3"):
            anchor = f' id="{escape(b.anchor)}"' if b.anchor else ""
            body.append(f"<{b.kind}{anchor}>{escape(b.text)}</{b.kind}>")
        elif b.kind == "info":
            body += htmlpage.table(None, [list(r) for r in b.rows], cls="info")
        elif b.kind == "p":
            body.append(f"<p>{escape(b.text)}</p>")
        elif b.kind == "table":
            body += htmlpage.table(b.head, b.rows)
        elif b.kind == "desc":
            text = "\n".join(ln.rstrip() for ln in b.text.splitlines()).strip()
            body.append(f'<div class="desc">{escape(text)}</div>')
        elif b.kind == "toc" and b.rows:
            body.append("<nav><ul>")
            for anchor, text, depth in b.rows:
                cls = "" if depth else ' class="area"'
                body.append(f'<li{cls}><a href="#{escape(anchor)}">{escape(text)}</a></li>')
            body.append("</ul></nav>")
    return htmlpage.page(title, STYLE, body)


def export(dev, *, source: bytes | None = None, **_ignored) -> ExportResult:
    page, diags = prepare(dev, source)
    if page is None:
        return ExportResult(None, diags)
    return ExportResult(to_html(page), diags)

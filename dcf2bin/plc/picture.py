"""A picture of the process image (SPEC.md §9.1 "Picture", seed 000 Bild 8): SVG written
by hand, and HTML that adds the table.

Two layouts, chosen by size:

* ``bytes`` (images up to ``BYTE_MODE_MAX_BYTES`` bytes with at most
  ``BYTE_MODE_MAX_VARS`` variables): the complete image byte by byte, 16 bytes a row,
  input area, alignment padding, output area; each variable a box over its bytes with
  its name and entry, coloured by data type; unused bytes grey, padding hatched-yellow.
* ``runs`` (anything larger, e.g. 60,000 variables): one bar per run of variables of one
  object that lie back to back (``DigIn_1 ... DigIn_254``), and one per stretch of unused
  bytes or padding, so the picture stays a few thousand pixels tall and quick to draw.
"""
from __future__ import annotations

from dcf2bin import htmlpage
from dcf2bin.htmlpage import Cell
from dcf2bin.layout import INPUT, OUTPUT
from dcf2bin.plc.varmap import VarMap

BYTE_MODE_MAX_BYTES = 4096
BYTE_MODE_MAX_VARS = 1024
COLS = 16
CW, CH = 72, 40          # a byte cell
LEFT = 96                # room for the row labels
BAR_H = 24               # a bar in the runs layout
FONT = "DejaVu Sans, Verdana, Arial, sans-serif"

UNUSED = "#d0d0d0"
PADDING = "#fff0b3"
AREA_COLOURS = {INPUT: "#1f5fbf", OUTPUT: "#bf3f1f"}
TYPE_COLOURS = {
    "BOOLEAN": "#9ecae1", "INTEGER8": "#a1d99b", "UNSIGNED8": "#74c476",
    "INTEGER16": "#fdae6b", "UNSIGNED16": "#fd8d3c", "INTEGER24": "#bcbddc",
    "UNSIGNED24": "#9e9ac8", "INTEGER32": "#fcbba1", "UNSIGNED32": "#fb6a4a",
    "REAL32": "#e7ba52", "UNSIGNED40": "#c7e9c0", "INTEGER40": "#c6dbef",
    "UNSIGNED48": "#dadaeb", "INTEGER48": "#fdd0a2", "UNSIGNED56": "#d9f0a3",
    "INTEGER56": "#f7b6d2", "INTEGER64": "#c49c94", "UNSIGNED64": "#8c6d31",
    "REAL64": "#17becf", "TIME_OF_DAY": "#dbdb8d", "TIME_DIFFERENCE": "#bcbd22",
}
_OTHER = "#b0b0ff"


def colour(type_name: str) -> str:
    return TYPE_COLOURS.get(type_name, _OTHER)


def layout_kind(vm: VarMap) -> str:
    # the byte layout draws every byte of both areas and the padding between them: judge
    # by how far they reach, not by the total size (a damaged container's area offsets
    # and sizes need not agree with it)
    total, in_off, in_size, out_off, out_size = vm.pi
    extent = max(total, in_off + in_size, out_off + out_size)
    if extent <= BYTE_MODE_MAX_BYTES and len(vm.rows) <= BYTE_MODE_MAX_VARS:
        return "bytes"
    return "runs"


def _e(text: str) -> str:
    return htmlpage.escape(text)


def _fit(text: str, width: float, font_px: float) -> str:
    """Shorten a label to about ``width`` pixels (the full text is in the box's title)."""
    n = max(1, int(width / (font_px * 0.6)))
    return text if len(text) <= n else text[:max(1, n - 1)] + "\u2026"


def _blocks(vm: VarMap):
    """(kind, first image byte, number of bytes, rows) for input area, padding, output."""
    total, in_off, in_size, out_off, out_size = vm.pi
    ins = [r for r in vm.rows if r.direction == INPUT]
    outs = [r for r in vm.rows if r.direction == OUTPUT]
    blocks = []
    if in_size:
        blocks.append((INPUT, in_off, in_size, ins))
    if out_size:
        pad_start = in_off + in_size if in_size else 0
        if out_off > pad_start:
            blocks.append(("padding", pad_start, out_off - pad_start, []))
        blocks.append((OUTPUT, out_off, out_size, outs))
    return blocks


def _heading(kind: str, start: int, size: int) -> str:
    span = f"image bytes {start}..{start + size - 1}, {size} byte{'s' if size != 1 else ''}"
    if kind == "padding":
        return f"alignment padding ({span})"
    return f"{kind} area ({span})"


def to_svg(vm: VarMap) -> str:
    return _svg_bytes(vm) if layout_kind(vm) == "bytes" else _svg_runs(vm)


def _frame(width: int, height: int, body: list[str], title: str) -> str:
    return "\n".join([
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="{FONT}">',
        f"<title>{_e(title)}</title>",
        '<defs><pattern id="pad" width="8" height="8" patternUnits="userSpaceOnUse" '
        'patternTransform="rotate(45)"><rect width="8" height="8" fill="' + PADDING + '"/>'
        '<line x1="0" y1="0" x2="0" y2="8" stroke="#e0c060" stroke-width="2"/></pattern></defs>',
        f'<rect x="0" y="0" width="{width}" height="{height}" fill="#ffffff"/>',
        *body, "</svg>", ""])


def _title_lines(vm: VarMap) -> list[str]:
    total, in_off, in_size, out_off, out_size = vm.pi
    return [f"Process image of {vm.source}: {total} bytes, {len(vm.rows)} network variable"
            f"{'s' if len(vm.rows) != 1 else ''}",
            f"input area offset {in_off} size {in_size}, output area offset {out_off} "
            f"size {out_size}"]


def _legend(vm: VarMap, y: int, width: int) -> tuple[list[str], int]:
    types = []
    for r in vm.rows:
        if r.dtype.name not in types:
            types.append(r.dtype.name)
    items = [(t, colour(t)) for t in types] + [("unused", UNUSED)]
    if any(kind == "padding" for kind, *_ in _blocks(vm)):
        items.append(("padding", "url(#pad)"))
    out, x = [], 10
    for label, fill in items:
        w = 26 + int(len(label) * 7.2)
        if x + w > width - 10:
            x, y = 10, y + 22
        out.append(f'<rect x="{x}" y="{y}" width="16" height="16" fill="{fill}" '
                   'stroke="#333333"/>')
        out.append(f'<text x="{x + 20}" y="{y + 13}" font-size="12">{_e(label)}</text>')
        x += w + 12
    return out, y + 30


def _text_width(text: str, font_px: float, bold: bool = False) -> int:
    """About how wide a line of text is drawn (DejaVu Sans averages 0.6 em a character)."""
    return int(len(text) * font_px * (0.66 if bold else 0.6)) + 1


def _bytes_width(vm: VarMap, t1: str, t2: str) -> int:
    """The byte layout's width: the columns it draws (16 only when an area reaches a
    second row), or the widest text line, whichever is wider -- not always 16 columns."""
    blocks = _blocks(vm)
    cols = max([min(COLS, size) for _, _, size, _ in blocks] + [1])
    texts = [_text_width(t1, 15, True), _text_width(t2, 12)]
    texts += [_text_width(_heading(kind, start, size), 13, True)
              for kind, start, size, _ in blocks]
    if not vm.rows and not vm.pi[0]:
        texts.append(_text_width("no network variables", 13))
    return max(LEFT + cols * CW + 20, 10 + max(texts) + 10)


def _svg_bytes(vm: VarMap) -> str:
    t1, t2 = _title_lines(vm)
    width = _bytes_width(vm, t1, t2)
    body: list[str] = []
    body.append(f'<text x="10" y="22" font-size="15" font-weight="bold">{_e(t1)}</text>')
    body.append(f'<text x="10" y="40" font-size="12">{_e(t2)}</text>')
    y = 56
    if not vm.rows and not vm.pi[0]:
        body.append('<text x="10" y="76" font-size="13">no network variables</text>')
        y = 90
    for kind, start, size, rows in _blocks(vm):
        nrows = -(-size // COLS)
        y += 10
        body.append(f'<text x="10" y="{y + 14}" font-size="13" font-weight="bold">'
                    f"{_e(_heading(kind, start, size))}</text>")
        y += 22
        for col in range(min(COLS, size) if kind != "padding" else 0):
            body.append(f'<text x="{LEFT + col * CW + CW // 2}" y="{y + 10}" font-size="10" '
                        f'fill="#555555" text-anchor="middle">+{col}</text>')
        y += 14
        top = y
        for k in range(nrows):
            ry = top + k * CH
            off = k * COLS
            body.append(f'<text x="{LEFT - 10}" y="{ry + 17}" font-size="12" '
                        f'text-anchor="end">{off if kind != "padding" else ""}</text>')
            body.append(f'<text x="{LEFT - 10}" y="{ry + 31}" font-size="9" fill="#555555" '
                        f'text-anchor="end">0x{start + off:04X}</text>')
        # every byte first as unused (or padding); variables are drawn over them
        fill = "url(#pad)" if kind == "padding" else UNUSED
        for b in range(size):
            x = LEFT + (b % COLS) * CW
            ry = top + (b // COLS) * CH
            body.append(f'<rect x="{x}" y="{ry}" width="{CW}" height="{CH}" fill="{fill}" '
                        'stroke="#ffffff" stroke-width="1"><title>'
                        f'{"padding" if kind == "padding" else "unused"} byte, image address '
                        f"0x{start + b:04X}</title></rect>")
        for r in rows:
            tip = (f"{r.name} {r.label} {r.dtype.name} {r.direction} offset {r.offset} "
                   f"address 0x{r.address:04X} size {r.size}")
            b, end = r.offset, r.offset + r.size
            while b < end:
                row_end = min(end, (b // COLS + 1) * COLS)
                x = LEFT + (b % COLS) * CW
                ry = top + (b // COLS) * CH
                w = (row_end - b) * CW
                body.append(f'<g><title>{_e(tip)}</title><rect x="{x + 1}" y="{ry + 1}" '
                            f'width="{w - 2}" height="{CH - 2}" fill="{colour(r.dtype.name)}" '
                            'stroke="#202020" stroke-width="1.5"/>'
                            f'<text x="{x + 5}" y="{ry + 16}" font-size="11">'
                            f"{_e(_fit(r.name, w - 8, 11))}</text>"
                            f'<text x="{x + 5}" y="{ry + 31}" font-size="9" fill="#303030">'
                            f"{_e(_fit(r.label, w - 8, 9))}</text></g>")
                b = row_end
        # the area's bounds: a bar at the left and a frame round its bytes
        height = nrows * CH
        if kind != "padding":
            col = AREA_COLOURS[kind]
            body.append(f'<rect x="{LEFT - 6}" y="{top}" width="4" height="{height}" '
                        f'fill="{col}"/>')
            last_w = ((size - 1) % COLS + 1) * CW
            frames = [(top + height - CH, last_w, CH)]
            if nrows > 1:
                frames.insert(0, (top, COLS * CW, height - CH))
            for fy, fw, fh in frames:
                body.append(f'<rect x="{LEFT}" y="{fy}" width="{fw}" height="{fh}" '
                            f'fill="none" stroke="{col}" stroke-width="3"/>')
        y = top + height + 6
    legend, y = _legend(vm, y + 10, width)
    body += legend
    return _frame(width, y, body, t1)


def runs(rows):
    """Rows grouped into runs: one object, one type, consecutive subindexes back to back."""
    out: list[list] = []
    for r in rows:
        if out:
            last = out[-1][-1]
            if (r.index == last.index and r.sub == last.sub + 1 and r.dtype is last.dtype
                    and r.offset == last.offset + last.size):
                out[-1].append(r)
                continue
        out.append([r])
    return out


def _svg_runs(vm: VarMap) -> str:
    bar_w = COLS * CW
    width = LEFT + bar_w + 20
    body: list[str] = []
    t1, t2 = _title_lines(vm)
    body.append(f'<text x="10" y="22" font-size="15" font-weight="bold">{_e(t1)}</text>')
    body.append(f'<text x="10" y="40" font-size="12">{_e(t2)} (variables grouped into runs '
                "of one object)</text>")
    y = 56
    bar = body.append
    for kind, start, size, rows in _blocks(vm):
        y += 10
        bar(f'<text x="10" y="{y + 14}" font-size="13" font-weight="bold">'
            f"{_e(_heading(kind, start, size))}</text>")
        y += 22
        top = y
        items: list[tuple] = []         # (offset, size, fill, text, title)
        if kind == "padding":
            items.append((0, size, "url(#pad)", f"padding, {size} bytes", "padding"))
        else:
            pos = 0
            for run in runs(rows):
                a, z = run[0], run[-1]
                if a.offset > pos:
                    items.append((pos, a.offset - pos, UNUSED,
                                  f"unused, {a.offset - pos} bytes", "unused"))
                n = len(run)
                names = a.name if n == 1 else f"{a.name} \u2026 {z.name}"
                subs = a.label if n == 1 else f"{a.label}..sub{z.sub:X}"
                text = (f"{names}   {subs}   {n} \u00d7 {a.dtype.name}" if n > 1 else
                        f"{names}   {subs}   {a.dtype.name}")
                end = z.offset + z.size
                items.append((a.offset, end - a.offset, colour(a.dtype.name), text, text))
                pos = max(pos, end)
            if pos < size:
                items.append((pos, size - pos, UNUSED, f"unused, {size - pos} bytes", "unused"))
        for off, n, fill, text, tip in items:
            addr = start + off
            bar(f'<text x="{LEFT - 8}" y="{y + 16}" font-size="11" text-anchor="end">'
                f"{off if kind != 'padding' else ''}</text>")
            bar(f'<g><title>{_e(tip)}, offset {off}..{off + n - 1}, image 0x{addr:04X}..'
                f'0x{addr + n - 1:04X}</title><rect x="{LEFT}" y="{y}" width="{bar_w}" '
                f'height="{BAR_H - 2}" fill="{fill}" stroke="#202020"/>'
                f'<text x="{LEFT + 6}" y="{y + 16}" font-size="11">'
                f"{_e(_fit(text, bar_w - 170, 11))}</text>"
                f'<text x="{LEFT + bar_w - 6}" y="{y + 16}" font-size="11" text-anchor="end">'
                f"0x{addr:04X}..0x{addr + n - 1:04X} ({n} B)</text></g>")
            y += BAR_H
        if kind != "padding":
            bar(f'<rect x="{LEFT - 6}" y="{top}" width="4" height="{y - top}" '
                f'fill="{AREA_COLOURS[kind]}"/>')
        y += 6
    legend, y = _legend(vm, y + 10, width)
    body += legend
    return _frame(width, y, body, t1)


def to_html(vm: VarMap) -> str:
    """The SVG and the table of the variable map, in one self-contained page."""
    t1, t2 = _title_lines(vm)
    svg = to_svg(vm).split("\n", 1)[1]          # without the XML declaration
    style = ("body{font-family:" + FONT + ";margin:1em}"
             "table{border-collapse:collapse;font-size:13px}"
             "th,td{border:1px solid #bbb;padding:2px 6px;text-align:left}"
             "td.n{text-align:right}th{background:#eee;position:sticky;top:0}")
    rows = [[r.name, r.label, r.dtype.name, r.direction, Cell(str(r.offset), "n"),
             Cell(f"0x{r.address:04X}", "n"), Cell(str(r.size), "n")] for r in vm.rows]
    return htmlpage.page(t1, style, [
        f"<h1>{_e(t1)}</h1>", f"<p>{_e(t2)}</p>", svg, "<h2>Variables</h2>",
        *htmlpage.table(["name", "entry", "type", "direction", "offset", "address", "size"],
                        rows)])

"""The picture of a network (`network show -f svg|html`): SVG written by hand.

A bus-style layout that stays readable from 3 nodes to 30 nodes and 200 PDOs:

* each node is a box at the top of its own column, a thin line runs down from it;
* each COB-ID is one horizontal lane across the columns: a dot on the producer's line
  (the source), a line to the farthest consumer and an arrowhead on every consumer's
  line, pointing away from the producer; the lane's colour is its producer's;
* the lane's label sits in the lane's own row, in a column left of the nodes: COB-ID,
  producer and PDO, bytes, rate and load share, then what it carries, wrapped onto as
  many lines as it needs (a lane grows, nothing is cut);
* with many lanes the node boxes are drawn again every 25 lanes and under the last one;
* heartbeats are left to the tables (one more lane per node would say little).

Lanes never share a row and labels never leave their lane, so no two labels can overlap;
:func:`layout` returns every text box so a test can check that from the geometry itself.
The text is DejaVu Sans Mono, whose advance is 0.6 em for every character, so the width of
a label is known exactly without a font library.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import htmlpage
from dcf2bin.network.show import View, rate_text, variable_table, variables_title

FONT = "DejaVu Sans Mono, Menlo, Consolas, monospace"
ADVANCE = 0.6            # em: every character of a monospace font
FS, FS_SMALL = 12, 11    # font sizes (px)
LINE = 15                # px between two text lines of a label
M = 16                   # outer margin
LABEL_W = 560            # the label column
COL_W, BOX_W = 104, 92   # a node column and its box
LANE_PAD = 6
REPEAT_AFTER = 12        # lanes after which the node boxes are drawn again at the bottom
REPEAT_EVERY = 25        # ... and between every REPEAT_EVERY lanes
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
           "#17becf", "#7f7f7f", "#bcbd22"]
MASTER_FILL, SLAVE_FILL = "#dbe8f7", "#f2f2f2"


def chars(width: float, font_px: float) -> int:
    return max(1, int(width // (font_px * ADVANCE)))


def text_width(text: str, font_px: float) -> float:
    return len(text) * font_px * ADVANCE


def wrap(text: str, width: float, font_px: float, sep: str = ", ") -> list[str]:
    """``text`` broken after each ``sep`` (else anywhere) into lines of at most ``width``
    px; joined again with the separator's trailing blanks, the lines give ``text`` back."""
    cap = chars(width, font_px)
    glue = sep[len(sep.rstrip()):]            # ", " -> " ", "_" -> ""
    parts = text.split(sep)
    lines, cur = [], ""
    for k, part in enumerate(parts):
        piece = part + (sep.rstrip() if k < len(parts) - 1 else "")
        cand = piece if not cur else cur + glue + piece
        if len(cand) <= cap:
            cur = cand
            continue
        if cur:
            lines.append(cur)
        while len(piece) > cap:
            lines.append(piece[:cap])
            piece = piece[cap:]
        cur = piece
    if cur or not lines:
        lines.append(cur)
    return lines


@dataclass
class Box:
    """A text's box in the picture (x, y top-left), for drawing and for the overlap test."""
    x: float
    y: float
    w: float
    h: float
    lines: list[str]
    font: int
    kind: str                    # "node", "label", "title"

    def overlaps(self, other: Box) -> bool:
        return (self.x < other.x + other.w and other.x < self.x + self.w
                and self.y < other.y + other.h and other.y < self.y + self.h)


@dataclass
class Lane:
    y: float                     # top of the lane
    h: float
    line_y: float                # the lane's horizontal line
    source: float | None         # x of the producer's column (None: nobody produces it)
    targets: list[float]         # x of each consumer's column
    colour: str
    label: Box
    title: str


@dataclass
class Layout:
    width: float
    height: float
    title: Box
    nodes: list[tuple[Box, bool]]        # (box, master)
    columns: list[float]                 # x of each node's line
    lanes: list[Lane] = field(default_factory=list)
    repeated_nodes: list[Box] = field(default_factory=list)   # rows of len(nodes) boxes
    label_right: float = 0
    lines_top: float = 0
    lines_bottom: float = 0

    def text_boxes(self) -> list[Box]:
        return [self.title, *(b for b, _ in self.nodes), *(ln.label for ln in self.lanes),
                *self.repeated_nodes]


def _node_lines(name: str, node_id: int) -> list[str]:
    lines = wrap(name, BOX_W - 8, FS_SMALL, sep="_")
    return lines + [f"id {node_id}"]


def _label_lines(k) -> tuple[str, list[str]]:
    head = f"{k.cob_text} \u00B7 {k.what}"
    if k.producer is not None:
        head += f" of {k.producer.node}"
    rate = rate_text(k.rate) if k.rate is not None else "rate unknown"
    head += f" \u00B7 {k.bytes} B \u00B7 {rate} \u00B7 {k.share:.2f} %"
    consumers = ", ".join(str(c) for c in k.consumers) or "nobody"
    lines = wrap(head, LABEL_W - 8, FS)
    lines += wrap("\u2192 " + consumers, LABEL_W - 8, FS_SMALL)
    if k.content:
        lines += wrap("carries " + ", ".join(k.content), LABEL_W - 8, FS_SMALL)
    return head, lines


def layout(view: View) -> Layout:
    """Columns: the master first, then the slaves by node-ID; lanes in COB-ID order."""
    order = sorted(view.nodes, key=lambda n: (not n.master, n.node_id))
    heads = [_node_lines(n.node, n.node_id) for n in order]
    links = [k for k in view.links if k.what != "heartbeat"]
    labels = [_label_lines(k) for k in links]
    label_w = min(LABEL_W, max((text_width(t, FS) for _, ls in labels for t in ls),
                               default=0) + 16)
    box_h = max((len(h) for h in heads), default=1) * LINE + 10
    title_lines = [f"{view.path}: {len(view.nodes)} nodes, "
                   f"{sum(k.is_pdo for k in view.links)} PDO COB-IDs, estimated bus load "
                   f"{view.total:.1f} % of {view.bitrate // 1000} kbit/s",
                   "one lane per COB-ID: \u25CF producer, \u25B6 consumer "
                   "(heartbeats: see the tables)"]
    x0 = M + label_w + 16
    width = max(x0 + COL_W * len(view.nodes) + M,
                M + max(text_width(t, FS) for t in title_lines) + M)
    title = Box(M, M, max(text_width(t, FS) for t in title_lines), 2 * LINE, title_lines,
                FS, "title")
    top = M + 2 * LINE + 12
    columns, nodes = [], []
    index = {}
    for k, (n, lines) in enumerate(zip(order, heads)):
        cx = x0 + COL_W * k + COL_W / 2
        columns.append(cx)
        index[n.node_id] = k
        nodes.append((Box(cx - BOX_W / 2, top, BOX_W, box_h, lines, FS_SMALL, "node"),
                      n.master))
    out = Layout(width, 0, title, nodes, columns, label_right=M + label_w)
    y = top + box_h + 12
    out.lines_top = top + box_h
    def node_row(y: float) -> float:
        for b, _master in nodes:
            out.repeated_nodes.append(Box(b.x, y, b.w, b.h, b.lines, b.font, "node"))
        return y + box_h

    for i, (k, (head, lines)) in enumerate(zip(links, labels)):
        if i and i % REPEAT_EVERY == 0:
            y = node_row(y + 8) + 8
        h = len(lines) * LINE + 2 * LANE_PAD
        label = Box(M + 4, y + LANE_PAD, max(text_width(t, FS) for t in lines),
                    len(lines) * LINE, lines, FS, "label")
        src = columns[index[k.producer.node_id]] if k.producer is not None else None
        targets = [columns[index[c.node_id]] for c in k.consumers if c.node_id in index]
        colour = PALETTE[index[k.producer.node_id] % len(PALETTE)] if k.producer else "#000000"
        title_text = "; ".join(lines)
        out.lanes.append(Lane(y, h, y + LANE_PAD + LINE * 0.66, src, targets, colour, label,
                              title_text))
        y += h
    out.lines_bottom = y
    if len(out.lanes) > REPEAT_AFTER:
        y = node_row(y + 12)
    out.height = y + M
    return out


def _e(text: str) -> str:
    return htmlpage.escape(text)


def _text(b: Box, anchor_middle: bool = False, weight_first: bool = False) -> list[str]:
    out = []
    for k, line in enumerate(b.lines):
        size = FS if b.kind != "node" else FS_SMALL
        if b.kind == "label" and k > 0:
            size = FS_SMALL
        x = b.x + b.w / 2 if anchor_middle else b.x
        y = b.y + LINE * (k + 1) - 4
        attrs = f'x="{x:.1f}" y="{y:.1f}" font-size="{size}"'
        if anchor_middle:
            attrs += ' text-anchor="middle"'
        if weight_first and k == 0:
            attrs += ' font-weight="bold"'
        out.append(f"<text {attrs}>{_e(line)}</text>")
    return out


def _node(b: Box, master: bool) -> list[str]:
    fill = MASTER_FILL if master else SLAVE_FILL
    name = " ".join(b.lines[:-1])
    return ([f'<g class="node"><title>{_e(name)} ({_e(b.lines[-1])})</title>',
             f'<rect x="{b.x:.1f}" y="{b.y:.1f}" width="{b.w:.1f}" height="{b.h:.1f}" '
             f'rx="4" fill="{fill}" stroke="#333333"/>']
            + [t.replace("<text ", "<text dy=\"5\" ", 1) for t in _text(b, True, master)]
            + ["</g>"])


def _arrow(x: float, y: float, right: bool, colour: str) -> str:
    d = 8 if right else -8
    return (f'<path d="M{x:.1f},{y:.1f} l{-d},-5 l0,10 z" fill="{colour}"/>')


def to_svg(view: View) -> str:
    lay = layout(view)
    w, h = int(lay.width + 0.5), int(lay.height + 0.5)
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           f'viewBox="0 0 {w} {h}" font-family="{FONT}">',
           f"<title>{_e(view.path)}</title>",
           f'<rect width="{w}" height="{h}" fill="#ffffff"/>']
    out += _text(lay.title, weight_first=True)
    for k, lane in enumerate(lay.lanes):
        if k % 2:
            out.append(f'<rect x="{M}" y="{lane.y:.1f}" width="{lay.width - 2 * M:.1f}" '
                       f'height="{lane.h:.1f}" fill="#f4f6fa"/>')
    for cx in lay.columns:
        out.append(f'<line x1="{cx:.1f}" y1="{lay.lines_top:.1f}" x2="{cx:.1f}" '
                   f'y2="{lay.lines_bottom + (12 if lay.repeated_nodes else 0):.1f}" '
                   'stroke="#b0b0b0" stroke-width="1"/>')
    for lane in lay.lanes:
        out.append(f'<g class="lane"><title>{_e(lane.title)}</title>')
        out += _text(lane.label, weight_first=True)
        ends = ([lane.source] if lane.source is not None else []) + lane.targets
        if ends:
            left, right = min(ends), max(ends)
            y = lane.line_y
            start = lay.columns[0] - COL_W / 2 if lane.source is None else left
            out.append(f'<line x1="{lay.label_right:.1f}" y1="{y:.1f}" x2="{start:.1f}" '
                       f'y2="{y:.1f}" '
                       'stroke="#c8c8c8" stroke-dasharray="2,3"/>')
            out.append(f'<line x1="{min(start, left):.1f}" y1="{y:.1f}" x2="{right:.1f}" '
                       f'y2="{y:.1f}" stroke="{lane.colour}" stroke-width="2"/>')
            if lane.source is not None:
                out.append(f'<circle cx="{lane.source:.1f}" cy="{y:.1f}" r="5" '
                           f'fill="{lane.colour}"/>')
            for t in lane.targets:
                toward_right = lane.source is None or t > lane.source
                out.append(_arrow(t, y, toward_right, lane.colour))
        out.append("</g>")
    for b, master in lay.nodes:
        out += _node(b, master)
    for k, b in enumerate(lay.repeated_nodes):
        out += _node(b, lay.nodes[k % len(lay.nodes)][1])
    out.append("</svg>")
    return "\n".join(out) + "\n"


def to_html(view: View) -> str:
    from dcf2bin.network.show import IDENTITY_NAMES, value_text
    svg = to_svg(view).split("\n", 1)[1]          # without the XML declaration
    out = [f"<h1>{_e(view.path)}</h1>",
           f"<p>{len(view.nodes)} nodes; estimated bus load {view.total:.1f} % of "
           f"{view.bitrate // 1000} kbit/s"
           + (f" ({view.unknown} frames of unknown rate counted as 0)" if view.unknown else "")
           + "</p>", svg, "<h2>Frames</h2>"]
    table = htmlpage.table
    out += table(["COB-ID", "frame", "producer", "consumers", "bytes", "rate", "load", "content"],
                 [[k.cob_text, k.what, str(k.producer) if k.producer else "(nobody)",
                   ", ".join(str(c) for c in k.consumers) or "(nobody)", str(k.bytes),
                   rate_text(k.rate), f"{k.share:.2f} %", ", ".join(k.content)]
                  for k in view.links])
    if view.variables:
        out.append(f"<h2>{variables_title(view)}</h2>")
        out += table(*variable_table(view, short=False))
    if view.slaves:
        out.append("<h2>Identity the master enforces</h2>" if view.kind != "cpj" else
                   "<h2>Identity each node's DCF states</h2>")
        cols = list(IDENTITY_NAMES)
        out += table(["node", *IDENTITY_NAMES.values()],
                     [[f"{s.name} ({s.node_id})",
                       *(f"0x{s.identity[c]:08X}" if c in s.identity else "-" for c in cols)]
                      for s in view.slaves])
    for s in view.slaves:
        if s.writes is not None:
            out.append(f"<h2>{_e(s.name)} (node {s.node_id}): SDO writes</h2>")
            out += table(["#", "entry", "name", "value", "why", "source"],
                         [[str(k + 1), f"0x{w.index:04X}sub{w.sub:X}", w.name, value_text(w),
                           w.why, w.where] for k, w in enumerate(s.writes)])
    return htmlpage.page(view.path, "body{font-family:sans-serif;margin:1em}"
                         "table{border-collapse:collapse;margin:1em 0}"
                         "th,td{border:1px solid #ccc;padding:2px 6px;text-align:left;"
                         "font-family:monospace}th{background:#eee}", out)

"""network show's picture and page: well-formed SVG/HTML naming every node and COB-ID, a
layout whose text boxes never overlap (from its own geometry) at 3 and 30 nodes, and a
rendering through cairosvg. The networks are built by hand (network_helpers)."""
from __future__ import annotations

import io
import itertools
import xml.etree.ElementTree as ET

import pytest
from network_helpers import network

from dcf2bin.network import show, svg

NS = {"s": "http://www.w3.org/2000/svg"}
SMALL = dict(slaves=3)
LARGE = dict(slaves=29, tpdos=4, rpdos=3)          # 30 nodes, 203 PDO COB-IDs


def view(**kw):
    return show.build(network(**kw))


def texts(root) -> list[str]:
    return ["".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text")]


@pytest.mark.parametrize("kw", [SMALL, LARGE], ids=["3 nodes", "30 nodes"])
def test_svg_is_well_formed_and_names_every_node_and_cob_id(kw):
    v = view(**kw)
    root = ET.fromstring(svg.to_svg(v).encode())
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    words = texts(root)
    for n in v.nodes:
        assert n.node in words and f"id {n.node_id}" in words
    heads = [w for w in words if w.startswith("0x")]
    pdo_links = [k for k in v.links if k.what != "heartbeat"]
    assert [h.split(" ")[0] for h in heads] == [k.cob_text for k in pdo_links]
    # one lane per COB-ID: a producer dot for each produced one, an arrowhead per consumer
    lanes = root.findall("s:g[@class='lane']", NS)
    assert len(lanes) == len(pdo_links)
    for lane, k in zip(lanes, pdo_links):
        assert len(lane.findall("s:circle", NS)) == (k.producer is not None)
        assert len(lane.findall("s:path", NS)) == len(k.consumers)


def test_svg_small_network_content():
    v = view(**SMALL)
    words = texts(ET.fromstring(svg.to_svg(v).encode()))
    assert "0x182 \u00B7 TPDO1 of io1 \u00B7 3 B \u00B7 100/s \u00B7 1.70 %" in words
    assert "\u2192 io2 RPDO4, plc RPDO1" in words
    assert "carries io1_6000_1, io1_6401_1" in words
    assert "0x202 \u00B7 TPDO1 of plc \u00B7 1 B \u00B7 rate unknown \u00B7 0.00 %" in words


@pytest.mark.parametrize("kw", [SMALL, LARGE], ids=["3 nodes", "30 nodes"])
def test_no_two_text_boxes_overlap(kw):
    lay = svg.layout(view(**kw))
    boxes = lay.text_boxes()
    assert len(boxes) == 1 + len(lay.nodes) + len(lay.lanes) + len(lay.repeated_nodes)
    # the node boxes again every 25 lanes and under the last lane, with many lanes
    rows = len(lay.repeated_nodes) // len(lay.nodes)
    assert rows == (0 if len(lay.lanes) <= 12 else 1 + (len(lay.lanes) - 1) // 25)
    for a, b in itertools.combinations(boxes, 2):
        assert not a.overlaps(b), (a, b)
    for b in boxes:
        # every line fits its box, and every box lies inside the picture
        assert all(svg.text_width(t, b.font) <= b.w + 0.01 for t in b.lines)
        assert 0 <= b.x and b.x + b.w <= lay.width and 0 <= b.y and b.y + b.h <= lay.height
    for lane in lay.lanes:
        # a lane's label stays in its lane and left of the node columns
        assert lane.y <= lane.label.y and lane.label.y + lane.label.h <= lane.y + lane.h
        assert lane.label.x + lane.label.w <= lay.label_right <= min(lay.columns)
    for a, b in zip(lay.lanes, lay.lanes[1:]):
        assert a.y + a.h <= b.y


def test_a_long_list_is_wrapped_not_cut():
    lines = svg.wrap("carries " + ", ".join(f"var_{k:03d}" for k in range(60)), 300, 11)
    assert len(lines) > 1
    assert all(svg.text_width(t, 11) <= 300 for t in lines)
    assert " ".join(lines) == "carries " + ", ".join(f"var_{k:03d}" for k in range(60))
    assert svg.wrap("cia402_device_1", 80, 11, sep="_") == ["cia402_", "device_1"]
    assert svg.wrap("a_very_long_node_name", 50, 11, sep="_") == ["a_very_", "long_", "node_",
                                                                  "name"]


@pytest.mark.parametrize("kw, scale", [(SMALL, 1), (LARGE, 0.5)], ids=["3 nodes", "30 nodes"])
def test_svg_renders_to_png(kw, scale):
    cairosvg = pytest.importorskip("cairosvg")
    from PIL import Image
    lay = svg.layout(view(**kw))
    png = cairosvg.svg2png(bytestring=svg.to_svg(view(**kw)).encode(), scale=scale)
    img = Image.open(io.BytesIO(png))
    size = (int(lay.width + 0.5) * scale, int(lay.height + 0.5) * scale)
    assert all(abs(a - b) <= 1 for a, b in zip(img.size, size)), (img.size, size)
    # each lane is drawn: its line has its producer's colour between its ends
    rgb = img.convert("RGB")
    for lane in lay.lanes:
        y = round(lane.line_y * scale)
        ends = [lane.source, *lane.targets] if lane.source is not None else lane.targets
        xs = range(round(min(ends) * scale) + 6, round(max(ends) * scale) - 6)
        want = tuple(int(lane.colour[i:i + 2], 16) for i in (1, 3, 5))
        # at half scale the 2-px line is 1 px, which may fall half on two rows: blended
        # with the white background
        half = tuple((c + 255) // 2 for c in want)
        near = [x for x in xs
                if any(max(abs(a - b) for a, b in zip(rgb.getpixel((x, yy)), w)) <= 40
                       for yy in (y - 1, y, y + 1) for w in (want, half))]
        assert len(near) >= len(xs) * 0.9, (lane.title, len(near), len(xs))


def test_html_is_well_formed_with_the_tables():
    v = show.build(network(2), writes="io1")
    page = svg.to_html(v)
    assert page.startswith("<!DOCTYPE html>")
    root = ET.fromstring(page.split("\n", 1)[1])       # XHTML-clean after the doctype
    cells = ["".join(td.itertext()) for td in root.iter("td")]
    for k in v.links:
        assert k.cob_text in cells
    assert "io1_6000_1" in cells and "0x000000AB" in cells
    assert "TPDO1 COB-ID, invalid while configuring" in cells      # io1's writes only
    assert [h.text for h in root.iter("h2")] == [
        "Frames", "PLC variables", "Identity the master enforces", "io1 (node 2): SDO writes"]
    assert root.find(".//{http://www.w3.org/2000/svg}svg") is not None

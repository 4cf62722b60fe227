"""The picture of the process image (SPEC.md §9.1 "Picture"): rendered to PNG by a real SVG
rasterizer (cairosvg) and checked pixel by pixel, not only as XML."""
from __future__ import annotations

import io
import sys
import xml.etree.ElementTree as ET

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin.plc import picture

try:
    import cairosvg
    from PIL import Image
except (ImportError, OSError):          # OSError: cairosvg without libcairo
    cairosvg = None

needs_cairosvg = pytest.mark.skipif(cairosvg is None,
                                    reason="cairosvg (pip install '.[test]') or libcairo missing")
SVG = "{http://www.w3.org/2000/svg}"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def render(svg: str):
    png = cairosvg.svg2png(bytestring=svg.encode("utf-8"))
    return Image.open(io.BytesIO(png)).convert("RGB")


def hex_rgb(colour: str) -> tuple[int, int, int]:
    return tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))


def box(svg: str, title_part: str) -> tuple[float, float, float, float]:
    """x, y, width, height of the rect whose title (its own or its group's) holds the text."""
    root = ET.fromstring(svg)
    for el in root.iter():
        if el.tag in (SVG + "g", SVG + "rect"):
            t = el.find(SVG + "title")
            if t is not None and title_part in (t.text or ""):
                r = el if el.tag == SVG + "rect" else el.find(SVG + "rect")
                return tuple(float(r.get(k)) for k in ("x", "y", "width", "height"))
    raise AssertionError(f"no box titled {title_part!r}")


def pixel_inside(img, b, dx: float = -8, dy: float = -5):
    """A pixel near the box's lower right corner (away from its text)."""
    x, y, w, h = b
    return img.getpixel((int(x + w + dx), int(y + h + dy)))


@needs_cairosvg
def test_bild8_picture_pixels():
    svg = run("map", SAMPLES / "bild8.dcf", "-f", "svg").stdout
    img = render(svg)
    assert img.size == (int(ET.fromstring(svg).get("width")),
                        int(ET.fromstring(svg).get("height")))
    u8, u16 = hex_rgb(picture.colour("UNSIGNED8")), hex_rgb(picture.colour("UNSIGNED16"))
    for sub in (1, 2, 3):            # A4C0 sub1..3 -> bytes 0..2, UNSIGNED8
        b = box(svg, f"0xA4C0sub{sub} UNSIGNED8 output offset {sub - 1} ")
        assert b[0] == picture.LEFT + (sub - 1) * picture.CW + 1
        assert pixel_inside(img, b) == u8
    b = box(svg, "0xA580sub3 UNSIGNED16 output offset 4 ")   # element 2 -> bytes 4..5
    assert b[0] == picture.LEFT + 4 * picture.CW + 1 and b[2] == 2 * picture.CW - 2
    assert pixel_inside(img, b) == u16
    unused = box(svg, "unused byte, image address 0x0003")   # byte 3 is unused
    assert pixel_inside(img, unused) == hex_rgb(picture.UNUSED)
    # the output area's bound: the bar left of its bytes
    assert img.getpixel((picture.LEFT - 4, int(b[1]) + 10)) == \
        hex_rgb(picture.AREA_COLOURS["output"])


@needs_cairosvg
def test_padding_and_both_areas(tmp_path):
    """3 input bytes: the output area starts at 8, bytes 3..7 are alignment padding."""
    csv = tmp_path / "v.csv"
    csv.write_text("name,type,direction\na,UNSIGNED8,in\nb,UNSIGNED8,in\nc,UNSIGNED8,in\n"
                   "d,UNSIGNED32,out\n")
    dcf = tmp_path / "v.dcf"
    assert run("allocate", csv, "-o", dcf).exit_code == 0
    svg = run("map", dcf, "-f", "svg").stdout
    img = render(svg)
    pad = box(svg, "padding byte, image address 0x0005")
    assert pixel_inside(img, pad, -20, -20) in (hex_rgb(picture.PADDING), (0xE0, 0xC0, 0x60))
    d = box(svg, "0xA680sub1 UNSIGNED32 output offset 0 address 0x0008")
    assert pixel_inside(img, d) == hex_rgb(picture.colour("UNSIGNED32"))
    a = box(svg, "0xA040sub1 UNSIGNED8 input offset 0 address 0x0000")
    assert img.getpixel((picture.LEFT - 4, int(a[1]) + 10)) == \
        hex_rgb(picture.AREA_COLOURS["input"])


@needs_cairosvg
def test_large_image_is_drawn_as_runs(tmp_path):
    """6,000 variables: one bar per run of one object, a picture of bounded height."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from gen_dcf import generate
    src = tmp_path / "big.dcf"
    src.write_bytes(generate(6000).encode("ascii"))
    svg = run("map", src, "-f", "svg").stdout
    root = ET.fromstring(svg)
    assert int(root.get("height")) < 2000
    img = render(svg)
    b = box(svg, "0xA080sub1..subFE   254 \u00d7 BOOLEAN")
    assert pixel_inside(img, b) == hex_rgb(picture.colour("BOOLEAN"))
    html = run("map", src, "-f", "html").stdout
    assert html.count("<tr><td>") == 6000


def test_html_is_svg_plus_table():
    html = run("map", SAMPLES / "bild8.dcf", "-f", "html").stdout
    svg = run("map", SAMPLES / "bild8.dcf", "-f", "svg").stdout
    assert svg.split("\n", 1)[1] in html
    assert ("<tr><td>AIN0</td><td>0xA580sub3</td><td>UNSIGNED16</td><td>output</td>"
            '<td class="n">4</td><td class="n">0x0004</td><td class="n">2</td></tr>') in html


def test_docs_picture_is_current(tmp_path):
    """docs/bild8.png (docs/plc.md) is the picture of samples/bild8.dcf."""
    svg = run("map", SAMPLES / "bild8.dcf", "-f", "svg").stdout
    assert svg == (ROOT / "tests" / "golden" / "plc" / "bild8.map.svg").read_text()
    assert (ROOT / "docs" / "bild8.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_names_are_escaped(tmp_path):
    csv = tmp_path / "v.csv"
    csv.write_text('name,type,direction\n"<a&b> ""c""",UNSIGNED8,in\n')
    dcf = tmp_path / "v.dcf"
    assert run("allocate", csv, "-o", dcf).exit_code == 0
    svg = run("map", dcf, "-f", "svg").stdout
    assert "&lt;a&amp;b&gt; &quot;c&quot;" in svg
    assert ET.fromstring(svg).tag == SVG + "svg"          # well-formed XML
    html = run("map", dcf, "-f", "html").stdout
    assert "<tr><td>&lt;a&amp;b&gt; &quot;c&quot;</td>" in html


# benchmarks/fuzz.py --seed 7 --only 8998: a 109-byte container whose PI total is 1 byte
# but whose output area claims offset 1,524,413,890 and size 2,690,827,690 (with
# --address-base area). The byte layout was chosen by the total alone and drew every byte
# of the areas: over 5 GB, a MemoryError. Now it is the runs layout, a few KB.
_AREAS_BEYOND_TOTAL = bytes.fromhex(
    "6d00000001000400280000001d000000450000000200000047000000030000004a00000014000000030000"
    "0040a000010000000140a0010100000000171000020000000070000030f070010000000000000001000000"
    "c2b5dc5aaac562a095b8f9c039766e0000000000000000")


@pytest.mark.parametrize("fmt", ["svg", "html"])
def test_areas_reaching_past_the_total_are_drawn_as_runs(tmp_path, fmt):
    src = tmp_path / "damaged.bin"
    src.write_bytes(_AREAS_BEYOND_TOTAL)
    out = tmp_path / f"map.{fmt}"
    res = CliRunner().invoke(main, ["map", "-q", "--format", fmt, str(src), "-o", str(out),
                                    "--address-base", "area"])
    assert res.exit_code == 0, res.output
    assert out.stat().st_size < 100_000


def test_layout_kind_judges_by_the_areas_extent():
    class VM:
        rows = []
        pi = (1, 0, 1, 1_524_413_890, 2_690_827_690)

    assert picture.layout_kind(VM) == "runs"
    VM.pi = (64, 0, 8, 8, 56)
    assert picture.layout_kind(VM) == "bytes"

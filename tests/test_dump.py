"""dump: the readable report and the lossless JSON form (SPEC §4, issue 3).

Golden files under tests/golden/ were checked by hand against SPEC §3 (see the notes in
test_bin2dcf.py and the report). Property tests: for generated containers (odd headers,
gaps, unknown attribute bits, repeated entries, empty segments, no PI segments)
compile(dump_json(b)) == b and dump_json(compile(j)) == j; and any byte string either
dumps or ends with exactly one error line naming a byte offset.
"""
from __future__ import annotations

import json
import re
import struct

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from conftest import ROOT, SAMPLES

try:
    import jsonschema
except ImportError:  # optional test dependency
    jsonschema = None
from dcf2bin import dump, filekind, schema
from dcf2bin.cli import main
from dcf2bin.container import BinContainer, read

GOLDEN = ROOT / "tests" / "golden"
SAMPLE_NAMES = ["bild8", "plc", "device"]
PROPS = settings(max_examples=300, deadline=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


# -- strategies ---------------------------------------------------------------------------------

INDEXES = st.one_of(
    st.integers(0, 0xFFFF),
    st.sampled_from([0x1000, 0x1017, 0x1400, 0x1600, 0x1800, 0x1A00, 0x2000, 0xA040, 0xA4C0,
                     0xA580, 0xA900, 0x0005]),
    st.integers(0xA000, 0xAFFF),
)
ATTRS = st.one_of(st.integers(0, 255), st.sampled_from([0x30, 0x70, 0x60, 0xF0, 0x61, 0x28,
                                                        0x68, 0x20, 0x40, 0x76]))
ENTRY = st.tuples(INDEXES, st.one_of(st.integers(0, 8), st.integers(0, 255)),
                  st.binary(max_size=9))


@st.composite
def models(draw, max_entries: int = 10) -> BinContainer:
    """A container model: repeated entries, any attribute bits, optional PI segments."""
    entries = draw(st.lists(ENTRY, max_size=max_entries))
    if draw(st.booleans()) and entries:
        entries += draw(st.lists(st.sampled_from(entries), max_size=3))   # repeated writes
    n = len(entries)
    mode = draw(st.sampled_from(["per-entry", "per-entry", "absent", "short", "long"]))
    if mode == "per-entry":
        attrs = bytes(draw(st.lists(ATTRS, min_size=n, max_size=n)))
    elif mode == "absent":
        attrs = None
    elif mode == "short":
        attrs = bytes(draw(st.lists(ATTRS, max_size=n)))
    else:
        attrs = bytes(draw(st.lists(ATTRS, min_size=n, max_size=n + 3)))
    addresses = draw(st.one_of(st.none(), st.lists(st.integers(0, 0xFFFF), min_size=1,
                                                     max_size=6)))
    pi = raw = None
    pmode = draw(st.sampled_from(["none", "pi", "pi", "raw"]))
    if pmode == "pi":
        pi = tuple(draw(st.lists(st.integers(0, 0xFFFFFFFF), min_size=5, max_size=5)))
    elif pmode == "raw":
        raw = draw(st.binary(min_size=1, max_size=24).filter(lambda b: len(b) != 20))
    version = draw(st.one_of(st.just(1), st.integers(0, 0xFFFF)))
    return BinContainer(entries=entries, attributes=attrs, addresses=addresses, pi=pi,
                        version=version, raw_piparam=raw)


@st.composite
def containers(draw, max_entries: int = 10) -> bytes:
    """Container bytes: canonical, or as another tool might lay them out (SPEC §3.1)."""
    c = draw(models(max_entries))
    if not draw(st.booleans()):
        return c.to_bytes()
    segs = c.segments()
    order = draw(st.permutations(schema.SEGMENTS))
    h = {"version": c.version}
    body = b""
    pos = schema.HEADER_SIZE
    for name in order:
        data = segs[name]
        gap = draw(st.binary(max_size=3))
        if data:
            body += gap
            pos += len(gap)
            h[f"{name}_offset"], h[f"{name}_size"] = pos, len(data)
            body += data
            pos += len(data)
        else:
            h[f"{name}_offset"] = draw(st.one_of(st.just(0), st.integers(0, 0xFFFFFFFF)))
            h[f"{name}_size"] = 0
    body += draw(st.binary(max_size=3))
    present = sum(1 for s in schema.SEGMENTS if h[f"{s}_size"])
    h["segment_count"] = draw(st.one_of(st.just(present), st.integers(0, 0xFFFF)))
    h["total_size"] = schema.HEADER_SIZE + len(body)
    return schema.HEADER.pack(*(h[k] for k in schema.HEADER_FIELDS)) + body


@st.composite
def mutated(draw) -> bytes:
    """Random bytes, or a container with flipped bytes, cuts, tails, bad header fields."""
    if draw(st.integers(0, 4)) == 0:
        return draw(st.binary(max_size=120))
    data = bytearray(draw(containers(6)))
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["flip", "cut", "tail", "field", "field"]))
        if kind == "flip" and data:
            i = draw(st.integers(0, len(data) - 1))
            data[i] = draw(st.integers(0, 255))
        elif kind == "cut" and data:
            del data[draw(st.integers(0, len(data) - 1)):]
        elif kind == "tail":
            data += draw(st.binary(min_size=1, max_size=8))
        elif kind == "field" and len(data) >= 40:
            off = draw(st.sampled_from(range(0, 40, 4)))
            value = draw(st.one_of(st.integers(0, 0xFFFFFFFF), st.integers(0, 200),
                                   st.just(0xFFFFFFFF)))
            data[off:off + 4] = struct.pack("<I", value)
    return bytes(data)


# -- golden dumps of the samples ----------------------------------------------------------------

@pytest.mark.parametrize("name", SAMPLE_NAMES)
@pytest.mark.parametrize("fmt", ["txt", "json"])
def test_golden_dump(name, fmt):
    src = SAMPLES / f"{name}.bin"
    r = run("dump", "--format", "text" if fmt == "txt" else "json", src)
    assert r.exit_code == 0, r.stderr
    assert r.stderr == ""
    golden = (GOLDEN / f"{name}.dump.{fmt}").read_text()
    assert r.stdout.replace(str(src), f"{name}.bin") == golden


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_golden_json_compiles_back(name, tmp_path):
    out = tmp_path / f"{name}.bin"
    r = run("compile", GOLDEN / f"{name}.dump.json", "-o", out)
    assert r.exit_code == 0, r.stderr
    assert out.read_bytes() == (SAMPLES / f"{name}.bin").read_bytes()


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_dump_validates_against_the_json_schema(name):
    jsonschema = pytest.importorskip("jsonschema")
    c, _ = read((SAMPLES / f"{name}.bin").read_bytes())
    jsonschema.validate(json.loads(dump.to_json(c)), dump.JSON_SCHEMA)


def test_docs_json_schema_is_the_one_in_the_code():
    doc = (ROOT / "docs" / "dump.md").read_text()
    block = doc.split("### JSON Schema", 1)[1].split("```json\n", 1)[1].split("\n```", 1)[0]
    assert json.loads(block) == dump.JSON_SCHEMA


def test_docs_show_the_current_version_and_keys():
    doc = (ROOT / "docs" / "dump.md").read_text()
    assert f'"version": {dump.SCHEMA_VERSION}' in doc
    for key in ["format", "layout", "header", "entries", "extra_attributes", "addresses",
                "pi_parameters", "gaps"]:
        assert f"`{key}`" in doc, key


# -- the JSON form: lossless both ways ------------------------------------------------------------

@PROPS
@given(containers())
def test_compile_of_dump_json_is_the_same_bytes(data):
    c, _ = read(data)
    text = dump.to_json(c)
    assert json.loads(text) == dump.to_dict(c)            # the formatter writes what it means
    if jsonschema is not None:
        jsonschema.validate(json.loads(text), dump.JSON_SCHEMA)
    back, diags = dump.from_json_bytes(text.encode(), "x.json")
    assert diags == []
    assert back == data


@st.composite
def documents(draw) -> dict:
    """JSON documents in the canonical form that dump writes (built without dump)."""
    c = draw(models())
    data = c.to_bytes()
    h = dict(zip(schema.HEADER_FIELDS, schema.HEADER.unpack_from(data)))
    attrs = c.attributes or b""
    doc = {"format": "dcf2bin-container", "version": 1, "layout": "canonical",
           "header": h,
           "entries": [{"index": f"0x{i:04X}", "subindex": s, "data": d.hex().upper(),
                        "attribute": f"0x{attrs[k]:02X}" if k < len(attrs) else None}
                       for k, (i, s, d) in enumerate(c.entries)],
           "extra_attributes": attrs[len(c.entries):].hex().upper(),
           "addresses": c.addresses,
           "pi_parameters": ({"raw": c.raw_piparam.hex().upper()} if c.raw_piparam else
                             dict(zip(schema.PIPARAM_FIELDS, c.pi)) if c.pi else None),
           "gaps": []}
    return doc


@PROPS
@given(documents())
def test_dump_json_of_compile_is_the_same_document(doc):
    data, diags = dump.from_json_bytes(json.dumps(doc).encode(), "x.json")
    assert diags == [] and data is not None
    c, _ = read(data)
    assert dump.to_dict(c) == doc


@PROPS
@given(containers())
def test_edited_canonical_json_recomputes_the_header(data):
    c, _ = read(data)
    assume(c.header is None)
    doc = dump.to_dict(c)
    doc["entries"].append({"index": "0x2000", "subindex": 0, "data": "01",
                           "attribute": "0x70" if len(c.attributes or b"") ==
                           len(c.entries) else None})
    assume(doc["entries"][-1]["attribute"] is not None or not doc["extra_attributes"])
    out, diags = dump.from_json_bytes(json.dumps(doc).encode(), "x.json")
    assert out is not None
    now = dump.to_dict(read(out)[0])["header"]
    assert [d.message.split(":")[0] for d in diags] == \
        [f"header.{k}" for k in schema.HEADER_FIELDS if now[k] != doc["header"][k]]
    assert all(d.rule == "JSN003" and d.severity.value == "warning" for d in diags)
    assert read(out)[0].entries[-1] == (0x2000, 0, b"\x01")


# -- robust reading: any bytes decode or give one error line with the offset ----------------------

def _error_line(data: bytes) -> re.Pattern:
    """The one error line dump and bin2dcf give for ``data``: a container's rule (CNT), or a
    concise DCF's (CON) where a mutation left bytes that begin as one (a count, then an entry
    of an object: filekind.detect reads them so, as ``.bin`` promises either)."""
    family = "CON" if filekind.detect(data, "x.bin") == filekind.CONCISE else "CNT"
    return re.compile(rf"^x\.bin:0x[0-9A-F]+: error: [^\n]+ \[{family}0\d\d\]$")
WARNING_LINE = re.compile(r"^x\.bin(:0x[0-9A-F]+)?: warning: [^\n]+$")


@PROPS
@given(data=mutated())
def test_any_bytes_dump_or_fail_with_one_line(data, tmp_path_factory):
    path = tmp_path_factory.mktemp("m") / "x.bin"
    path.write_bytes(data)
    for args in (["dump", "x.bin"], ["dump", "-f", "json", "x.bin"],
                 ["bin2dcf", "x.bin", "-o", "-"]):
        r = _run_in(path.parent, args)
        if r.exit_code == 0:
            assert all(WARNING_LINE.match(line) for line in r.stderr.splitlines()), r.stderr
            if args[1] == "-f":
                assert dump.from_json_bytes(r.stdout_bytes, "x.json")[0] == data
        else:
            assert r.exit_code == 1, (r.exit_code, r.stderr)
            lines = r.stderr.splitlines()
            assert len(lines) == 1 and _error_line(data).match(lines[0]), r.stderr
            assert r.stdout == ""


def _run_in(folder, args):
    import os
    old = os.getcwd()
    os.chdir(folder)
    try:
        return CliRunner().invoke(main, args, catch_exceptions=False)
    finally:
        os.chdir(old)


@pytest.mark.parametrize("data, line", [
    (b"", "x.bin:0x0: error: 0 bytes: too short for the 40-byte header [CNT001]"),
    (bytes(39), "x.bin:0x0: error: 39 bytes: too short for the 40-byte header [CNT001]"),
    (struct.pack("<IHH8I", 100, 1, 1, 40, 4, 0, 0, 0, 0, 0, 0) + bytes(4),
     "x.bin:0x0: error: header says 100 bytes, the file has 44 (truncated) [CNT002]"),
    (struct.pack("<IHH8I", 44, 1, 1, 40, 4, 0, 0, 0, 0, 0, 0) + bytes(6),
     "x.bin:0x2C: error: 2 trailing bytes after the container's total size 44 [CNT003]"),
    (struct.pack("<IHH8I", 44, 1, 1, 40, 8, 0, 0, 0, 0, 0, 0) + bytes(4),
     "x.bin:0x8: error: index segment [40, 48) lies outside the container [40, 44) [CNT004]"),
    (struct.pack("<IHH8I", 44, 1, 1, 40, 4, 0, 0, 0, 0, 0, 0) + struct.pack("<I", 1000),
     "x.bin:0x28: error: index segment claims 1000 entries, but 0 bytes hold at most 0 "
     "[CNT011]"),
    # a container whose count and version a mutation turned into a concise DCF's count and
    # first entry (0x1000 sub 0, 1 byte): read as the damaged concise DCF it now looks like
    (struct.pack("<IHBI", 2, 0x1000, 0, 1) + b"\x05" + bytes(33),
     "x.bin:0x13: error: 26 bytes after the last of 2 entries [CON003]"),
])
def test_bad_containers_name_the_offset(tmp_path, data, line):
    (tmp_path / "x.bin").write_bytes(data)
    for cmd in (["dump", "x.bin"], ["bin2dcf", "x.bin", "-o", "-"]):
        r = _run_in(tmp_path, cmd)
        assert (r.exit_code, r.stderr, r.stdout) == (1, line + "\n", "")


def test_a_huge_count_allocates_nothing():
    data = struct.pack("<IHH8I", 44, 1, 1, 40, 4, 0, 0, 0, 0, 0, 0) + struct.pack("<I", 2**32 - 1)
    c, diags = dump.read_bytes(data, "x.bin")
    assert c is None and diags[0].offset == 0x28


# -- JSON errors: one line naming the file, line and JSON path ---------------------------------

GOOD = (GOLDEN / "bild8.dump.json").read_text() if (GOLDEN / "bild8.dump.json").exists() else ""


def _compile_json(tmp_path, text: str):
    src = tmp_path / "x.json"
    src.write_text(text)
    return _run_in(tmp_path, ["compile", "x.json", "-o", "x.bin"])


@pytest.mark.parametrize("edit, line", [
    (lambda t: t.replace('"data": "03"', '"data": "3"', 1),
     'x.json:19: error: entries[0].data: odd number of hex digits (1) [JSN002]'),
    (lambda t: t.replace('"subindex": 1,', '"subindex": 256,', 1),
     "x.json:20: error: entries[1].subindex: 256 is outside 0..255 [JSN002]"),
    (lambda t: t.replace('"attribute": "0x30"', '"attribute": null', 1),
     "x.json:20: error: entries[1].attribute: entry 1 has an attribute but entry 0 has none: "
     "the extended info segment holds one byte per entry from the first [JSN002]"),
    (lambda t: t.replace('  "version": 1,', '  "version": 2,', 1),
     "x.json:3: error: version: schema version 2 is not supported; this dcf2bin reads "
     "version 1 (written by a newer dcf2bin?) [JSN002]"),
    (lambda t: t.replace('"layout": "canonical"', '"layout": "stored"').replace(
        '"total_size": 127', '"total_size": 4000000000'),
     "x.json:6: error: header.total_size: 4000000000, but the header, segments and gaps make "
     "127 bytes [JSN002]"),
    (lambda t: t.replace('"layout": "canonical"', '"layout": "stored"').replace(
        '"index_size": 53', '"index_size": 52'),
     "x.json:10: error: header.index_size: 52, but the entries make 53 bytes of the index "
     "segment [JSN002]"),
    (lambda t: t.replace('"gaps": []', '"gaps": [], "colour": 1'),
     "x.json:31: error: colour: unknown key 'colour' (expected one of format, version, "
     "layout, header, entries, extra_attributes, addresses, pi_parameters, gaps) [JSN002]"),
    (lambda t: t.replace('"entries": [', '"entries": [,', 1),
     "x.json:18: error: invalid JSON: Expecting value [JSN001]"),
    (lambda t: t.replace('    "version": 1,', '    "version": 1, "version": 2,'),
     "x.json:7: error: key 'version' repeated in one object [JSN001]"),
])
def test_json_errors_name_line_and_path(tmp_path, edit, line):
    r = _compile_json(tmp_path, edit(GOOD))
    assert (r.exit_code, r.stderr) == (1, line + "\n")
    assert not (tmp_path / "x.bin").exists()


def test_stale_canonical_header_is_a_warning(tmp_path):
    r = _compile_json(tmp_path, GOOD.replace('"segment_count": 4', '"segment_count": 3'))
    assert r.exit_code == 0
    assert r.stderr == ("x.json:8: warning: header.segment_count: 3 is recomputed as 4 "
                        "(layout \"canonical\") [JSN003]\n")
    assert (tmp_path / "x.bin").read_bytes() == (SAMPLES / "bild8.bin").read_bytes()


def test_compile_from_json_by_option(tmp_path):
    (tmp_path / "dump.txt").write_text(GOOD)
    r = _run_in(tmp_path, ["compile", "--from", "json", "dump.txt", "-o", "x.bin"])
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "x.bin").read_bytes() == (SAMPLES / "bild8.bin").read_bytes()
    r = CliRunner().invoke(main, ["compile", "--from", "json", "-", "-o", "-"], input=GOOD)
    assert r.exit_code == 0 and r.stdout_bytes == (SAMPLES / "bild8.bin").read_bytes()


@pytest.mark.parametrize("version_key", ["version", "schema_version"])   # new and old name
def test_hand_written_minimal_json(tmp_path, version_key):
    text = ('{"format": "dcf2bin-container", "%s": 1, "entries": ['
            '{"index": "0x2000", "subindex": 0, "data": "0102", "attribute": "0x70"}]}'
            % version_key)
    r = _compile_json(tmp_path, text)
    assert r.exit_code == 0, r.stderr
    c, _ = read((tmp_path / "x.bin").read_bytes())
    assert c.entries == [(0x2000, 0, b"\x01\x02")] and c.attributes == b"\x70"
    assert c.version == 1 and c.addresses is None and c.pi is None


def _nested(inner):
    # a named function: hypothesis reads a lambda's source to see that it recurses, and
    # warns (wrongly) when that lambda spans two lines
    return st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner, max_size=3)


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats(allow_nan=False)
    | st.text(max_size=6) | st.sampled_from(["0x30", "0xFFFF", "zz", "", "0x"]),
    _nested, max_leaves=6)


def _paths(doc, at=()):
    yield at
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, at + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from _paths(v, at + (i,))


@st.composite
def edited_documents(draw) -> bytes:
    """A dump with random values put in, keys deleted, or its text cut."""
    c, _ = read(draw(containers(5)))
    doc = dump.to_dict(c)
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(list(_paths(doc))))
        if not path:
            continue
        parent = doc
        for p in path[:-1]:
            parent = parent[p]
        if draw(st.integers(0, 3)) == 0 and isinstance(parent, dict):
            del parent[path[-1]]
        else:
            parent[path[-1]] = draw(JSON_VALUES)
    text = json.dumps(doc, indent=draw(st.sampled_from([None, 1])))
    if draw(st.integers(0, 5)) == 0:
        text = text[:draw(st.integers(0, len(text)))]
    return text.encode()


@PROPS
@given(edited_documents())
def test_any_json_compiles_or_fails_with_one_line(data):
    out, diags = dump.from_json_bytes(data, "x.json")
    errors = [d for d in diags if d.severity.value == "error"]
    if out is None:
        assert len(errors) == 1
        text = errors[0].format()
        assert "\n" not in text and re.match(r"^x\.json(:\d+(:\d+)?)?: error: .+ \[JSN00[12]\]$",
                                            text), text
    else:
        assert errors == []
        read(out)   # a readable container


# -- odd containers keep every byte -------------------------------------------------------------

ODD = bytes.fromhex(
    "4e000000" "0300" "0400"      # total 78, version 3, count 4 (3 segments are present)
    "38000000" "14000000"          # index @56, 20 bytes (last, after the addresses)
    "34000000" "04000000"          # addresses @52, 4 bytes
    "28000000" "03000000"          # extinfo @40, 3 bytes (first)
    "00000000" "00000000"          # no PI parameter segment
    "36f030"                       # attributes: 0x36 has undefined bits 0x06; one extra byte
    "aabbccddeeff00aa00"           # 9 bytes that belong to no segment
    "0000" "0400"                  # addresses 0, 4
    "02000000"                     # 2 entries
    "4ca001" "01000000" "07"       # A04C sub1 = 07
    "4ca001" "01000000" "08"       # A04C sub1 = 08: a repeated write
    "dead"                         # 2 more bytes in no segment, inside the total size
)


def test_odd_container_dump_keeps_every_byte():
    c, warnings = read(ODD)
    assert c.header is not None and c.gaps
    text = dump.to_json(c)
    assert dump.from_json_bytes(text.encode(), "odd.json")[0] == ODD
    assert text == (GOLDEN / "odd.dump.json").read_text()


def test_odd_container_report():
    c, _ = read(ODD)
    assert dump.report(c, "odd.bin") == (GOLDEN / "odd.dump.txt").read_text()


def test_dump_cli_warns_about_odd_layouts(tmp_path):
    (tmp_path / "odd.bin").write_bytes(ODD)
    r = _run_in(tmp_path, ["dump", "odd.bin", "-o", "odd.txt"])
    assert r.exit_code == 0
    assert r.stderr.splitlines() == [
        "odd.bin:0x6: warning: header counts 4 segments, 3 are present [CNT006]",
        "odd.bin:0x2B: warning: 11 bytes between segments belong to no segment [CNT008]",
        "odd.bin:0x28: warning: segments are not in the header's order [CNT008]",
    ]
    assert (tmp_path / "odd.txt").read_text() == (GOLDEN / "odd.dump.txt").read_text()


# -- report details -------------------------------------------------------------------------------

def test_full_shows_long_data():
    c = BinContainer(entries=[(0x2000, 0, bytes(range(40)))], attributes=b"\x60")
    short = dump.report(c, "x.bin")
    full = dump.report(c, "x.bin", full=True)
    assert "000102030405060708090A0B...2627" in short
    assert bytes(range(40)).hex().upper() in full


def test_dump_with_eds_names_variables(tmp_path):
    eds = tmp_path / "plc.eds"
    eds.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    r = run("dump", SAMPLES / "plc.bin", "--eds", eds)
    assert r.exit_code == 0, r.stderr
    assert "  1  0x0000   input        0  0xA040    1     1  UNSIGNED8   DigIn_1" in r.stdout
    assert "  5  0x0004   input        4  0xA0C0    3     2  INTEGER16   AnaIn_3" in r.stdout


def test_dump_output_file_is_atomic_and_not_the_input(tmp_path):
    src = tmp_path / "plc.bin"
    src.write_bytes((SAMPLES / "plc.bin").read_bytes())
    r = run("dump", src, "-o", src)
    assert r.exit_code == 2
    assert src.read_bytes() == (SAMPLES / "plc.bin").read_bytes()


def test_dump_unreadable_file_exits_3(tmp_path):
    r = run("dump", tmp_path / "missing.bin")
    assert r.exit_code == 3


def test_large_container_is_linear():
    import time
    n = 20000
    entries = [(0xA040 + i // 254, i % 254 + 1, b"\x00") for i in range(n)]
    c = BinContainer(entries=entries, attributes=b"\xf0" * n, addresses=list(range(n)),
                     pi=(n, 0, n, 0, 0))
    data = c.to_bytes()
    t = time.perf_counter()
    back, _ = read(data)
    text = dump.to_json(back)
    assert dump.from_json_bytes(text.encode(), "x")[0] == data
    dump.report(back, "x")
    assert time.perf_counter() - t < 10   # generous: catches quadratic behaviour only


# -- old documents still compile (docs/options.md, "JSON outputs") ----------------------

OLD_FORMAT = ROOT / "tests" / "fixtures" / "json" / "plc.old-format.dump.json"


def test_an_old_format_dump_still_compiles_to_the_same_bytes(tmp_path):
    """A dump written before the JSON convention ("schema_version", not "version") is the
    same container: compile accepts both names."""
    text = OLD_FORMAT.read_text()
    assert '"schema_version": 1' in text and '\n  "version"' not in text
    r = _compile_json(tmp_path, text)
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "x.bin").read_bytes() == (SAMPLES / "plc.bin").read_bytes()
    new = dump.to_json(read((SAMPLES / "plc.bin").read_bytes())[0])
    assert new == text.replace('"schema_version": 1', '"version": 1')


def test_version_and_its_old_name_together_is_an_error(tmp_path):
    text = OLD_FORMAT.read_text().replace('"schema_version": 1,',
                                          '"schema_version": 1, "version": 1,')
    r = _compile_json(tmp_path, text)
    assert r.exit_code == 1
    assert "x.json:3: error: schema_version: both 'version' and 'schema_version' (the old name " \
           "of 'version'): give one [JSN002]" in r.stderr

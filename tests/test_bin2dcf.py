"""bin2dcf: containers back to DCF text (SPEC §4, issue 3).

The central promise: for a container compiled with default options from a DCF,
compile(bin2dcf(container)) == container. Where a container cannot be expressed,
bin2dcf says so; its prediction is checked against the real compiler for generated
DCFs and for arbitrary containers.

Golden files (tests/golden/*.bin2dcf.dcf) were reviewed by hand against SPEC §4:
one section per index, ParameterValue = last value written, earlier PDO writes as
comments, DataType from the CiA 405 range / attribute / size, no timestamps.
"""
from __future__ import annotations

import re
import time

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from conftest import ROOT, SAMPLES, compile_corpus_file, compiling_corpus_params
from dcf2bin import datatypes as dt
from dcf2bin import dcfwriter, dump, model, values
from dcf2bin.cli import main
from dcf2bin.cli.bin2dcf import bin2dcf_main
from dcf2bin.compiler import CompileOptions, compile_device, compile_path
from dcf2bin.container import BinContainer, read
from test_dump import containers, models

GOLDEN = ROOT / "tests" / "golden"
SAMPLE_NAMES = ["bild8", "plc", "device"]
PROPS = settings(max_examples=300, deadline=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                        HealthCheck.filter_too_much])


def convert(data: bytes, name: str = "x.bin", **kw) -> dcfwriter.Result:
    c, diags = dump.read_bytes(data, name)
    assert c is not None, diags
    return dcfwriter.convert(c, name, dcf_name="x.dcf", **kw)


def compile_text(text: bytes, name: str = "x.dcf", **opts):
    dev = model.load(name, data=text)
    return compile_device(dev, CompileOptions(**opts))


def roundtrip_ok(data: bytes, res: dcfwriter.Result) -> bool:
    back = compile_text(res.to_bytes())
    return back.data == data


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


@pytest.mark.parametrize("binary", [SAMPLES / "plc.bin",
                                    GOLDEN / "network" / "flat" / "out" / "drive.bin"],
                         ids=["container", "concise"])
def test_the_json_form_converts_as_the_bytes_it_records(binary, tmp_path):
    """``dump -f json`` is the lossless form of a container or a concise DCF: bin2dcf of it
    is bin2dcf of the bytes, line for line but the name it was read from (the JSON form
    was refused: "use dcf2bin compile to turn it back")."""
    (tmp_path / "x.bin").write_bytes(binary.read_bytes())
    assert run("dump", "-f", "json", tmp_path / "x.bin", "-o", tmp_path / "x.json").exit_code == 0
    from_bin = run("bin2dcf", tmp_path / "x.bin", "-o", "-")
    from_json = run("bin2dcf", tmp_path / "x.json", "-o", "-")
    assert (from_json.exit_code, from_json.stderr) == (from_bin.exit_code, from_bin.stderr.replace(
        "x.bin", "x.json"))
    assert from_json.stdout == from_bin.stdout.replace(f"{tmp_path}/x.bin", f"{tmp_path}/x.json")
    assert f"from {tmp_path}/x.json (" in from_json.stdout.splitlines()[0]


# -- samples: compile -> bin2dcf -> compile is byte-identical; golden DCFs ----------------------

@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_sample_roundtrip(name, tmp_path):
    """A container compiled from each sample dumps, converts to DCF and compiles back."""
    binary = (SAMPLES / f"{name}.bin").read_bytes()
    r = run("compile", SAMPLES / f"{name}.dcf", "-o", tmp_path / "a.bin")
    assert r.exit_code == 0 and (tmp_path / "a.bin").read_bytes() == binary
    r = run("dump", "-f", "json", tmp_path / "a.bin", "-o", tmp_path / "a.json")
    assert r.exit_code == 0, r.stderr
    r = run("compile", tmp_path / "a.json", "-o", tmp_path / "b.bin")
    assert r.exit_code == 0 and (tmp_path / "b.bin").read_bytes() == binary
    r = run("bin2dcf", tmp_path / "a.bin", "-o", tmp_path / "a.dcf")
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("compile", tmp_path / "a.dcf", "-o", tmp_path / "c.bin")
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "c.bin").read_bytes() == binary


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_golden_bin2dcf(name, tmp_path):
    out = tmp_path / f"{name}.dcf"
    r = run("bin2dcf", SAMPLES / f"{name}.bin", "-o", out)
    assert (r.exit_code, r.stderr) == (0, "")
    text = out.read_text().replace(str(SAMPLES / f"{name}.bin"), f"{name}.bin")
    assert text == (GOLDEN / f"{name}.bin2dcf.dcf").read_text()


def test_golden_bin2dcf_with_eds(tmp_path):
    """--eds: names, exact types (INTEGER16, REAL32 ...) and access from the EDS."""
    r = run("bin2dcf", SAMPLES / "device.bin", "--eds", SAMPLES / "device.dcf", "-o",
            tmp_path / "device.dcf")
    assert (r.exit_code, r.stderr) == (0, "")
    text = (tmp_path / "device.dcf").read_text().replace(str(SAMPLES) + "/", "")
    assert text == (GOLDEN / "device.eds.bin2dcf.dcf").read_text()
    back = compile_path(str(tmp_path / "device.dcf"), CompileOptions())
    assert back.data == (SAMPLES / "device.bin").read_bytes()


def test_bin2dcf_is_deterministic(tmp_path):
    a = run("bin2dcf", SAMPLES / "plc.bin", "-o", "-").stdout_bytes
    time.sleep(0.01)
    b = run("bin2dcf", SAMPLES / "plc.bin", "-o", "-").stdout_bytes
    assert a == b
    assert not re.search(rb"(?i)creation(time|date)|modification(time|date)", a)


# -- the corpus: every DCF that compiles comes back -----------------------------------------------

# Only the files that compile (with node-ID 1 where $NODEID needs one); tests/test_corpus.py
# checks that the others fail with clean file:line errors.

@pytest.mark.parametrize("path", compiling_corpus_params(".dcf"))
def test_corpus_dcf_roundtrip(path):
    res = compile_corpus_file(path)
    out = convert(res.data, str(path))
    assert out.roundtrip and out.diagnostics == []
    assert roundtrip_ok(res.data, out)


@pytest.mark.parametrize("path", compiling_corpus_params(".eds"))
def test_corpus_eds_roundtrip(path):
    """EDS files compile too (network variables, DefaultValue-only objects)."""
    res = compile_corpus_file(path)
    out = convert(res.data, str(path))
    assert roundtrip_ok(res.data, out) == out.roundtrip
    assert out.roundtrip, [d.format() for d in out.diagnostics]


@pytest.mark.parametrize("path", compiling_corpus_params(".eds"))
def test_corpus_eds_as_eds_option(path):
    """With the device's own EDS, the DCF still compiles back to the same bytes."""
    res = compile_corpus_file(path)
    info, dev, _ = dump.load_eds(str(path))
    out = convert(res.data, str(path), eds=info, eds_device=dev)
    assert roundtrip_ok(res.data, out) == out.roundtrip
    assert out.roundtrip, [d.format() for d in out.diagnostics]


# -- generated DCFs: compile(bin2dcf(compile(dcf))) == compile(dcf) ------------------------------

FIXED = [t for t in dt.BY_CODE.values()]
ACCESS = ["ro", "wo", "rw", "rwr", "rww", "const"]


@st.composite
def value_text(draw, dtype: dt.DataType) -> str | None:
    if dtype.kind == dt.VSTRING:
        s = draw(st.text(st.characters(blacklist_categories=["Cs"], blacklist_characters="\r\n"),
                         max_size=8))
        return values.decode(dtype, s.encode("utf-8"))
    if dtype.kind == dt.USTRING:
        s = draw(st.text(st.characters(blacklist_categories=["Cs"], blacklist_characters="\r\n"),
                         max_size=4))
        return values.decode(dtype, s.encode("utf-16-le"))
    size = dtype.size if dtype.size is not None else draw(st.integers(0, 6))
    data = draw(st.binary(min_size=size, max_size=size))
    if dtype.kind == dt.BOOL:
        data = bytes([data[0] & 1])
    return values.decode(dtype, data)


@st.composite
def entry_keys(draw, dtype: dt.DataType | None = None, configured: bool | None = None,
               access: str | None = None) -> str:
    t = dtype or draw(st.sampled_from(FIXED))
    acc = access or draw(st.sampled_from(ACCESS))
    lines = [f"DataType=0x{t.code:04X}", f"AccessType={acc}",
             f"PDOMapping={draw(st.integers(0, 1))}"]
    v = draw(value_text(t))
    if v is not None:
        lines.append(f"DefaultValue={v}")
    if configured if configured is not None else draw(st.booleans()):
        v = draw(value_text(t))
        if v is not None:
            lines.append(f"ParameterValue={v}")
    return "\n".join(lines) + "\n"


@st.composite
def dcf_texts(draw) -> str:
    out = ["[FileInfo]\nFileName=gen.dcf\n"]
    # plain objects, VAR or RECORD
    for idx in draw(st.lists(st.integers(0x1000, 0x2FFF).filter(
            lambda i: not 0x1400 <= i <= 0x1BFF), unique=True, max_size=4)):
        if draw(st.booleans()):
            out.append(f"[{idx:04X}]\nParameterName=V\nObjectType=0x7\n" + draw(entry_keys()))
        else:
            subs = draw(st.lists(st.integers(0, 12), unique=True, min_size=1, max_size=4))
            out.append(f"[{idx:04X}]\nParameterName=R\nObjectType=0x9\n")
            for s in sorted(subs):
                out.append(f"[{idx:04X}sub{s:X}]\nParameterName=S\n" + draw(entry_keys()))
    # PDOs (CiA 301 block)
    for comm in draw(st.lists(st.sampled_from([0x1400, 0x1401, 0x1402, 0x1800, 0x1801, 0x1803]),
                              unique=True, max_size=3)):
        cob = draw(st.integers(1, 0x7FF)) | (draw(st.sampled_from([0, 0x80000000, 0x40000000])))
        out.append(f"[{comm:04X}]\nObjectType=0x9\n[{comm:04X}sub0]\nDataType=0x0005\n"
                   f"AccessType=ro\nDefaultValue=6\n"
                   f"[{comm:04X}sub1]\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x{cob:X}\n"
                   + (f"ParameterValue=0x{cob:X}\n" if draw(st.booleans()) else ""))
        for s, t in ((2, dt.UNSIGNED8), (3, dt.UNSIGNED16), (4, dt.UNSIGNED8),
                     (5, dt.UNSIGNED16), (6, dt.UNSIGNED8)):
            if draw(st.booleans()):
                out.append(f"[{comm:04X}sub{s}]\n" + draw(entry_keys(t, access="rw")))
        mapping = comm + 0x200
        default, n = draw(st.integers(0, 4)), draw(st.integers(0, 4))
        configured = draw(st.booleans())
        out.append(f"[{mapping:04X}]\nObjectType=0x9\n[{mapping:04X}sub0]\nDataType=0x0005\n"
                   f"AccessType=rw\nDefaultValue={default}\n"
                   + (f"ParameterValue={n}\n" if configured else ""))
        for k in range(1, max(n, default) + 1 + draw(st.integers(0, 1))):
            out.append(f"[{mapping:04X}sub{k}]\n" + draw(entry_keys(dt.UNSIGNED32, access="rw")))
    # network variables: CiA 405 ranges
    for idx in draw(st.lists(st.sampled_from([0xA000, 0xA041, 0xA080, 0xA0C0, 0xA140, 0xA240,
                                              0xA280, 0xA4C0, 0xA4C1, 0xA500, 0xA600, 0xA6C0,
                                              0xA8C0]), unique=True, max_size=4)):
        t = dcfwriter.table_type(idx)[0]
        subs = draw(st.lists(st.integers(1, 254), unique=True, max_size=4))
        out.append(f"[{idx:04X}]\nObjectType=0x8\n")
        if draw(st.booleans()):
            out.append(f"[{idx:04X}sub0]\nDataType=0x0005\nAccessType=ro\n"
                       f"DefaultValue={max(subs, default=0)}\n")
        for s in sorted(subs):
            out.append(f"[{idx:04X}sub{s:X}]\n" + draw(entry_keys(t, access="rw")))
    # a [DynamicChannels] segment beyond the table (A900-AFFF), away from offset 0
    if draw(st.booleans()):
        t = draw(st.sampled_from([x for x in FIXED if x.size]))
        first = draw(st.integers(0xA900, 0xAF00))
        pp = draw(st.integers(0, 50)) * 8 + 4096
        out.append(f"[DynamicChannels]\nNrOfSeg=1\nType1=0x{t.code:04X}\n"
                   f"Dir1={draw(st.sampled_from(['ro', 'rw']))}\n"
                   f"Range1=0x{first:04X}-0x{first + 3:04X}\nPPOffset1={pp}\n")
        for idx in draw(st.lists(st.integers(first, first + 3), unique=True, max_size=2)):
            subs = draw(st.lists(st.integers(1, 254), unique=True, max_size=3))
            out.append(f"[{idx:04X}]\nObjectType=0x8\n")
            for s in sorted(subs):
                out.append(f"[{idx:04X}sub{s:X}]\n" + draw(entry_keys(t, access="rw")))
    return "\n".join(out)


@PROPS
@given(dcf_texts())
def test_generated_dcf_roundtrip(text):
    first = compile_text(text.encode("utf-8"), "gen.dcf")
    assume(first.ok)
    out = convert(first.data)
    assert [d.format() for d in out.diagnostics] == []
    assert out.roundtrip
    back = compile_text(out.to_bytes())
    assert back.ok, [d.format() for d in back.diagnostics if d.severity.value == "error"]
    assert back.data == first.data


# -- arbitrary containers: the prediction is exact ---------------------------------------------

@PROPS
@given(containers(8))
def test_prediction_matches_the_compiler(data):
    c, _ = read(data)
    res = dcfwriter.convert(c, "x.bin", dcf_name="x.dcf")
    back = compile_text(res.to_bytes())
    assert (back.data == data) == res.roundtrip
    if not res.roundtrip:
        summary = [d for d in res.diagnostics if d.rule == dcfwriter.R_SUMMARY]
        assert len(summary) == 1
    if res.roundtrip:
        assert res.diagnostics == []


@PROPS
@given(models(6))
def test_prediction_with_options(c):
    """When only --container-version / --no-process-image are missing, bin2dcf says which."""
    data = c.to_bytes()
    res = convert(data)
    if res.options:
        opts = {}
        for o in res.options:
            if o.startswith("--container-version"):
                opts["container_version"] = int(o.split()[1])
            if o == "--no-process-image":
                opts["process_image"] = False
            if o == "--entries all":
                opts["select"] = "all"
        back = compile_text(res.to_bytes(), **opts)
        assert back.data == data


# -- what cannot round-trip is named -------------------------------------------------------------

def _warnings(c: BinContainer) -> list[str]:
    data = c.to_bytes()
    res = convert(data)
    assert roundtrip_ok(data, res) == res.roundtrip
    return [d.format() for d in res.diagnostics]


def test_repeated_writes_outside_a_pdo_block():
    c = BinContainer(entries=[(0x2200, 0, b"\x1a\x00"), (0x2214, 0, b"\x01\x00\x00\x00"),
                              (0x2200, 0, b"\x1b\x00"), (0x2214, 0, b"\x02\x00\x00\x00")],
                     attributes=b"\x70\x70\x70\x70")
    assert _warnings(c) == [
        "x.bin:0x2C: warning: 0x2200sub0 is written 2 times outside a PDO block; the DCF keeps "
        "the last value (earlier ones are comments) [B2D003]",
        "x.bin:0x35: warning: 0x2214sub0 is written 2 times outside a PDO block; the DCF keeps "
        "the last value (earlier ones are comments) [B2D003]",
        "x.bin:0x2C: warning: the DCF will not compile back to the same container: entry 1 is "
        "0x2200sub0 = 1A00 (attribute 0x70), compile writes 0x2200sub0 = 1B00 (attribute 0x70); "
        "for a lossless copy use 'dcf2bin dump --format json' [B2D010]",
    ]


def test_read_only_entries_and_undefined_bits():
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00"), (0x2000, 0, b"\x05")],
                     attributes=b"\x30\x76")
    assert _warnings(c) == [
        "x.bin:0x2C: warning: 0x1000sub0 is read-only (attribute 0x30); compile does not "
        "write ro entries outside the PDO objects [B2D004]",
        "x.bin:0x37: warning: 0x2000sub0 has undefined attribute bits 0x06 (0x76); no DCF "
        "entry produces them [B2D002]",
        "x.bin:0x2C: warning: the DCF will not compile back to the same container: entry 1 is "
        "0x1000sub0 = 95010000 (attribute 0x30), compile writes 0x2000sub0 = 05 (attribute "
        "0x70); for a lossless copy use 'dcf2bin dump --format json' [B2D010]",
    ]


def test_version_and_missing_pi_name_the_options():
    c = BinContainer(entries=[(0xA4C0, 0, b"\x01"), (0xA4C0, 1, b"\x07")],
                     attributes=b"\x30\xf0", version=7)
    assert _warnings(c) == [
        "x.bin: warning: compile gives the same bytes only with --container-version 7 "
        "--no-process-image [B2D010]"]


def test_select_all_is_suggested_when_it_reproduces_the_container():
    """Item 20: ro entries outside a PDO block come back only with --entries all (SPEC §3.2);
    B2D010 says so, and the options name it."""
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00"), (0x2000, 0, b"\x05")],
                     attributes=b"\x30\x70")
    assert _warnings(c) == [
        "x.bin:0x2C: warning: 0x1000sub0 is read-only (attribute 0x30); compile does not "
        "write ro entries outside the PDO objects [B2D004]",
        "x.bin:0x2C: warning: the DCF will not compile back to the same container: entry 1 is "
        "0x1000sub0 = 95010000 (attribute 0x30), compile writes 0x2000sub0 = 05 (attribute "
        "0x70); compile gives the same bytes only with --entries all [B2D010]",
    ]
    data = c.to_bytes()
    res = convert(data)
    assert res.options == ["--entries all"]
    assert compile_text(res.to_bytes(), select="all").data == data


def test_select_all_suggestion_on_the_command_line(tmp_path):
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00")], attributes=b"\x30")
    (tmp_path / "ro.bin").write_bytes(c.to_bytes())
    r = run("bin2dcf", tmp_path / "ro.bin", "-o", tmp_path / "ro.dcf")
    assert (r.exit_code, r.stderr) == (0, (
        f"{tmp_path / 'ro.bin'}:0x2C: warning: 0x1000sub0 is read-only (attribute 0x30); "
        "compile does not write ro entries outside the PDO objects [B2D004]\n"
        f"{tmp_path / 'ro.bin'}:0x2C: warning: the DCF will not compile back to the same "
        "container: entry 1 is 0x1000sub0 = 95010000 (attribute 0x30), compile writes "
        "nothing; compile gives the same bytes only with --entries all [B2D010]\n"))
    r = run("compile", tmp_path / "ro.dcf", "--entries", "all", "-o", tmp_path / "back.bin")
    assert r.exit_code == 0 and (tmp_path / "back.bin").read_bytes() == c.to_bytes()


def test_select_all_with_other_options():
    c = BinContainer(entries=[(0xA4C0, 0, b"\x01"), (0xA4C0, 1, b"\x07"),
                              (0x1000, 0, b"\x91\x01\x0f\x00")],
                     attributes=b"\x30\xf0\x30", version=3)
    data = c.to_bytes()
    res = convert(data)
    assert [d.format() for d in res.diagnostics if d.rule == dcfwriter.R_SUMMARY] == [
        "x.bin:0x3C: warning: the DCF will not compile back to the same container: entry 3 is "
        "0x1000sub0 = 91010F00 (attribute 0x30), compile writes nothing; compile gives the "
        "same bytes only with --entries all --container-version 3 --no-process-image [B2D010]"]
    back = compile_text(res.to_bytes(), select="all", container_version=3, process_image=False)
    assert back.data == data


def test_select_all_is_not_suggested_when_it_would_write_more():
    """--entries all would also write the implied sub 0 of 0x2000 (a DefaultValue): no hint."""
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00"), (0x2000, 1, b"\x05")],
                     attributes=b"\x30\x70")
    data = c.to_bytes()
    res = convert(data)
    assert res.options == []
    assert [d.format() for d in res.diagnostics if d.rule == dcfwriter.R_SUMMARY] == [
        "x.bin:0x2C: warning: the DCF will not compile back to the same container: entry 1 is "
        "0x1000sub0 = 95010000 (attribute 0x30), compile writes 0x2000sub1 = 05 (attribute "
        "0x70); for a lossless copy use 'dcf2bin dump --format json' [B2D010]"]
    assert compile_text(res.to_bytes(), select="all").data != data


@PROPS
@given(dcf_texts())
def test_containers_compiled_with_select_all(text):
    """Containers compiled with --entries all: bin2dcf's options are exactly what compiles
    them back, and the default-options prediction stays exact."""
    first = compile_text(text.encode("utf-8"), "gen.dcf", select="all")
    assume(first.ok)
    res = convert(first.data)
    back = compile_text(res.to_bytes())
    assert (back.data == first.data) == res.roundtrip
    if res.options:
        again = compile_text(res.to_bytes(), select="all" if "--entries all" in res.options
                             else "auto")
        assert again.data == first.data, [d.format() for d in res.diagnostics]


def test_string_with_a_line_break_becomes_octet_string():
    c = BinContainer(entries=[(0x2000, 0, b"a\nb")], attributes=b"\x68")
    res = convert(c.to_bytes())
    assert "DataType=0x000A\nAccessType=rw\nPDOMapping=0\nParameterValue=610A62\n" in res.text
    assert [d.format() for d in res.diagnostics][0] == (
        "x.bin:0x2C: warning: 0x2000sub0: 610A62 cannot be written as a VISIBLE_STRING value "
        "in a DCF; written as OCTET_STRING [B2D007]")


def test_latin1_strings_keep_their_bytes():
    c = BinContainer(entries=[(0x2000, 0, b"Gr\xfc\xdf"), (0x2001, 0, "Grüß".encode())],
                     attributes=b"\x68\x68")
    data = c.to_bytes()
    res = convert(data)
    assert res.encoding == "latin-1" and res.roundtrip and res.diagnostics == []
    assert roundtrip_ok(data, res)


def test_dynamic_channels_are_reconstructed():
    """Variables placed by [DynamicChannels] PPOffsets come back with the same addresses."""
    text = ("[DynamicChannels]\nNrOfSeg=2\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\n"
            "PPOffset1=100\nType2=0x0007\nDir2=rw\nRange2=0xAA00-0xAA0F\nPPOffset2=8\n"
            "[A040]\nObjectType=0x8\n[A040sub1]\nDataType=0x0005\nAccessType=ro\n"
            "[AA01]\nObjectType=0x8\n[AA01sub2]\nDataType=0x0007\nAccessType=rw\n"
            "ParameterValue=0x12345678\n")
    first = compile_text(text.encode())
    assert first.ok
    res = convert(first.data)
    assert res.roundtrip and res.diagnostics == []
    assert ("[DynamicChannels]\nNrOfSeg=2\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\n"
            "PPOffset1=100\nType2=0x0007\nDir2=rw\nRange2=0xAA01-0xAFFF\nPPOffset2=1024\n"
            ) in res.text
    assert compile_text(res.to_bytes()).data == first.data


# -- the command line -----------------------------------------------------------------------------

def test_default_output_name_and_file_info(tmp_path):
    src = tmp_path / "plc.bin"
    src.write_bytes((SAMPLES / "plc.bin").read_bytes())
    r = run("bin2dcf", src)
    assert r.exit_code == 0
    text = (tmp_path / "plc.dcf").read_text()
    assert "\n[FileInfo]\nFileName=plc.dcf\n" in text
    assert f"Description=Converted from the binary DCF segment container {src}\n" in text


def test_standalone_bin2dcf_command(tmp_path):
    r = CliRunner().invoke(bin2dcf_main, [str(SAMPLES / "bild8.bin"), "-o", "-"],
                           catch_exceptions=False)
    assert r.exit_code == 0
    assert r.stdout == run("bin2dcf", SAMPLES / "bild8.bin", "-o", "-").stdout
    assert "FileName=bild8.dcf\n" in r.stdout
    r = CliRunner().invoke(bin2dcf_main, ["--version"])
    assert r.stdout.startswith("bin2dcf, version ")


def test_stdin_needs_output():
    r = run("bin2dcf", "-", input=(SAMPLES / "bild8.bin").read_bytes())
    assert r.exit_code == 2
    r = run("bin2dcf", "-", "-o", "-", input=(SAMPLES / "bild8.bin").read_bytes())
    assert r.exit_code == 0 and "FileName=stdin.dcf\n" in r.stdout


def test_strict_writes_nothing(tmp_path):
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00")], attributes=b"\x30")
    (tmp_path / "ro.bin").write_bytes(c.to_bytes())
    r = run("bin2dcf", tmp_path / "ro.bin", "--strict")
    assert r.exit_code == 1
    assert not (tmp_path / "ro.dcf").exists()
    lines = r.stderr.splitlines()
    assert lines[-2].startswith(f"{tmp_path / 'ro.bin'}:0x2C: error: the DCF will not compile")
    assert lines[-1] == (f"{tmp_path / 'ro.bin'}: the DCF would not compile back to the same "
                         "container (--strict), nothing written")
    r = run("bin2dcf", tmp_path / "ro.bin", "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "ro.dcf").exists()


def test_large_container_is_fast_enough():
    n = 20000
    entries = [(0xA040 + i // 254, i % 254 + 1, b"\x00") for i in range(n)]
    c = BinContainer(entries=entries, attributes=b"\xf0" * n, addresses=list(range(n)),
                     pi=(n, 0, n, 0, 0))
    data = c.to_bytes()
    t = time.perf_counter()
    res = convert(data)
    assert time.perf_counter() - t < 10      # generous: catches quadratic behaviour only
    assert "PI addresses" not in " ".join(d.message for d in res.diagnostics)


@st.composite
def edited_compiled(draw) -> bytes:
    """A container compiled from a generated DCF, then edited a little (near misses)."""
    first = compile_text(draw(dcf_texts()).encode("utf-8"), "gen.dcf")
    assume(first.ok)
    c, _ = read(first.data)
    entries, attrs = list(c.entries), bytearray(c.attributes or b"")
    for _ in range(draw(st.integers(0, 2))):
        kind = draw(st.sampled_from(["swap", "attr", "dup", "drop", "data", "addr", "pi"]))
        if kind in ("swap", "attr", "dup", "drop", "data") and not entries:
            continue
        i = draw(st.integers(0, len(entries) - 1)) if entries else 0
        if kind == "swap":
            j = draw(st.integers(0, len(entries) - 1))
            entries[i], entries[j] = entries[j], entries[i]
            attrs[i], attrs[j] = attrs[j], attrs[i]
        elif kind == "attr":
            attrs[i] = draw(st.integers(0, 255))
        elif kind == "dup":
            entries.insert(i, entries[i])
            attrs.insert(i, attrs[i])
        elif kind == "drop":
            del entries[i]
            del attrs[i]
        elif kind == "data":
            entries[i] = entries[i][:2] + (draw(st.binary(max_size=5)),)
        elif kind == "addr" and c.addresses:
            k = draw(st.integers(0, len(c.addresses) - 1))
            c.addresses[k] = draw(st.integers(0, 0xFFFF))
        elif kind == "pi" and c.pi:
            pi = list(c.pi)
            pi[draw(st.integers(0, 4))] = draw(st.integers(0, 300))
            c.pi = tuple(pi)
    c.entries, c.attributes = entries, bytes(attrs)
    return c.to_bytes()


@PROPS
@given(edited_compiled())
def test_prediction_on_near_misses(data):
    c, _ = read(data)
    res = dcfwriter.convert(c, "x.bin", dcf_name="x.dcf")
    back = compile_text(res.to_bytes())
    assert (back.data == data) == res.roundtrip, [d.format() for d in res.diagnostics]
    assert res.roundtrip == (res.diagnostics == [])


def test_default_output_never_clobbers_an_existing_dcf(tmp_path):
    """Beside plc.bin usually stands the plc.dcf it came from: bin2dcf must not overwrite it."""
    (tmp_path / "plc.bin").write_bytes((SAMPLES / "plc.bin").read_bytes())
    (tmp_path / "plc.dcf").write_text("; the user's own DCF\n")
    r = run("bin2dcf", tmp_path / "plc.bin")
    assert r.exit_code == 2
    assert r.stderr == (f"{tmp_path / 'plc.dcf'}: error: the file exists (often the DCF this "
                        "container was compiled from); name the output with -o to replace it, "
                        "or give --force\n")
    assert (tmp_path / "plc.dcf").read_text() == "; the user's own DCF\n"
    (tmp_path / "plc.dcf").unlink()
    assert run("bin2dcf", tmp_path / "plc.bin").exit_code == 0
    assert (tmp_path / "plc.dcf").read_text().startswith("; DCF written by dcf2bin bin2dcf")


# -- DIS-2 (D-12): the old-COB-ID write of a PDO block whose CAN-ID changes -------------------

def test_dis2_old_cob_id_block_comes_back_with_its_default_value(tmp_path):
    """samples/dis2_cobid.bin (compile --profile dis2) starts RPDO1's block with the COB-ID
    the drive has, | 0xC0000000. bin2dcf gives comm sub 1 that DefaultValue, says in an
    info and in the DCF that --profile dis2 gives the bytes back, and warns of nothing."""
    binary = (SAMPLES / "dis2_cobid.bin").read_bytes()
    r = run("bin2dcf", SAMPLES / "dis2_cobid.bin", "-o", tmp_path / "back.dcf")
    assert r.exit_code == 0
    assert r.stderr.splitlines() == [
        f"{SAMPLES / 'dis2_cobid.bin'}: info: compile gives the same bytes with --profile "
        "dis2: the PDO blocks first disable under the COB-ID the drive had (its "
        "DefaultValue), as Metronix DIS-2 drives need [B2D010]"]
    text = (tmp_path / "back.dcf").read_text()
    assert "; compile it with --profile dis2 to get the container's bytes back.\n" in text
    section = text[text.index("[1400sub1]"):text.index("[1600]")]
    assert "DefaultValue=0x00000205\n" in section and "ParameterValue=0x40000301\n" in section
    # TPDO1 keeps its CAN-ID (no old write): no DefaultValue of bin2dcf's making
    tpdo = text[text.index("[1800sub1]"):text.index("[1801]")]
    assert "DefaultValue" not in tpdo
    r = run("compile", "--profile", "dis2", tmp_path / "back.dcf", "-o", tmp_path / "c.bin")
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "c.bin").read_bytes() == binary
    res = dcfwriter.convert(read(binary)[0], "x.bin", dcf_name="x.dcf")
    assert (res.roundtrip, res.options) == (False, ["--profile dis2"])
    assert run("bin2dcf", "-q", SAMPLES / "dis2_cobid.bin", "-o", "-").stderr == ""


def test_dis2_sample_without_a_cob_id_change_round_trips_with_default_options(tmp_path):
    binary = (SAMPLES / "dis2.bin").read_bytes()
    res = dcfwriter.convert(read(binary)[0], "dis2.bin", dcf_name="dis2.dcf")
    assert (res.roundtrip, res.options, res.diagnostics) == (True, [], [])
    assert "DefaultValue=0x" not in res.text.split("[1400sub1]")[1].split("[")[0]
    assert compile_path("back.dcf", data=res.to_bytes()).data == binary


def test_an_old_cob_id_write_that_dis2_would_not_make_is_still_a_warning():
    """The same first write, but a mapping of 5 objects (DIS-2 allows 4): no profile
    gives these bytes, so the verdict stays a warning and no DefaultValue is invented."""
    c, _ = read((SAMPLES / "dis2_cobid.bin").read_bytes())
    entries = list(c.entries)
    i = next(k for k, e in enumerate(entries) if e[:2] == (0x1600, 0) and e[2] == b"\x01")
    extra = [(0x1600, s, (0x60400010).to_bytes(4, "little")) for s in (2, 3, 4, 5)]
    entries[i:i] = extra
    entries[i + 4] = (0x1600, 0, b"\x05")
    attrs = bytearray(c.attributes)
    attrs[i:i] = b"\x70" * 4
    c2 = BinContainer(entries=entries, attributes=bytes(attrs))
    res = dcfwriter.convert(c2, "x.bin", dcf_name="x.dcf")
    assert res.options == [] and not res.roundtrip
    assert [(d.severity.value, d.rule) for d in res.diagnostics] == [("warning", "B2D010")]
    assert "DefaultValue=0x00000205" not in res.text

"""The documented Python API (dcf2bin.api, docs/api.md; issue 10 item 21).

Each function against the samples' checked-in bytes and golden files, the command line's
output for the same input, warnings delivered through ``warnings.warn``, and errors raised
with their diagnostics.
"""
from __future__ import annotations

import doctest
import json
import pathlib
import re
import subprocess
import sys
import warnings

import pytest
from click.testing import CliRunner

import dcf2bin
from conftest import ROOT, SAMPLES
from dcf2bin import api
from dcf2bin.cli import main
from dcf2bin.compiler import CompileOptions
from dcf2bin.container import BinContainer

GOLDEN = ROOT / "tests" / "golden"
SAMPLE_NAMES = ["bild8", "plc", "device", "dis2"]


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def caught(fn, *args, **kw):
    """(return value, the one-line texts of the DiagnosticWarnings it issued)."""
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        value = fn(*args, **kw)
    assert all(issubclass(w.category, api.DiagnosticWarning) for w in got)
    return value, [str(w.message) for w in got]


# -- the package ----------------------------------------------------------------------------------

def test_import_dcf2bin_stays_cheap():
    """The API loads on first use: importing the package pulls in neither canopen nor
    construct (nor the API itself)."""
    code = ("import sys, dcf2bin\n"
            "print(sorted({m.split('.')[0] for m in sys.modules} & "
            "{'canopen', 'construct', 'click'}), 'dcf2bin.api' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True)
    assert out.stdout == "[] False\n"


def test_package_exports_the_api():
    assert dcf2bin.__all__ == ["__version__", *api.__all__]
    for name in api.__all__:
        assert getattr(dcf2bin, name) is getattr(api, name)
    assert set(api.__all__) <= set(dir(dcf2bin))
    with pytest.raises(AttributeError, match="module 'dcf2bin' has no attribute 'nothing'"):
        dcf2bin.nothing


def test_every_api_name_has_a_docstring():
    for name in api.__all__:
        assert getattr(api, name).__doc__, name


def test_docstring_examples(monkeypatch):
    """The examples in the docstrings run as written (from the repository root)."""
    monkeypatch.chdir(ROOT)
    for module in (api, dcf2bin, dcf2bin.dcfwriter):
        res = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert (module.__name__, res.failed) == (module.__name__, 0)
        assert res.attempted > 0


def test_docs_api_md_examples(monkeypatch):
    """The >>> examples of docs/api.md give what the page shows (code fences end a block)."""
    monkeypatch.chdir(ROOT)
    text = re.sub(r"(?m)^```.*$", "", (ROOT / "docs" / "api.md").read_text())
    test = doctest.DocTestParser().get_doctest(text, {"dcf2bin": dcf2bin}, "api.md",
                                              "docs/api.md", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.summarize(verbose=False) == doctest.TestResults(0, 24)


# -- compile_path / compile_file ------------------------------------------------------------------

@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_compile_path_gives_the_sample_bytes(name):
    res = dcf2bin.compile_path(str(SAMPLES / f"{name}.dcf"))
    assert res.ok and res.diagnostics == []
    assert res.data == (SAMPLES / f"{name}.bin").read_bytes()


def test_compile_path_options_as_keywords_or_object():
    src = str(SAMPLES / "dis2.dcf")
    golden = (SAMPLES / "dis2.bin").read_bytes()
    assert dcf2bin.compile_path(src, profile="dis2").data == golden
    assert dcf2bin.compile_path(src, CompileOptions(profile="dis2")).data == golden
    # keywords win over the object; the object is not changed
    opts = CompileOptions(container_version=7)
    res = dcf2bin.compile_path(src, opts, container_version=1)
    assert res.data == golden and opts.container_version == 7
    assert dcf2bin.compile_path(src, container_version=7).data[4:6] == b"\x07\x00"
    with pytest.raises(TypeError, match="nodeid"):
        dcf2bin.compile_path(src, nodeid=5)


def test_compile_path_keeps_its_positional_form():
    """compile_path(name, opts, data=...) as the command line and the tests call it."""
    data = (SAMPLES / "plc.dcf").read_bytes()
    res = dcf2bin.compile_path("in-memory.dcf", CompileOptions(), data=data)
    assert res.data == (SAMPLES / "plc.bin").read_bytes()
    assert dcf2bin.compile_path("in-memory.dcf", None, data).data == res.data


def test_compile_path_reports_errors_in_the_result():
    res = dcf2bin.compile_path("bad.dcf", data=b"[2000]\nDataType=0x0005\nAccessType=rw\n"
                                                b"ParameterValue=300\n")
    assert (res.ok, res.data) == (False, None)
    assert [d.format() for d in res.diagnostics] == [
        "bad.dcf:4: error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) [DCF200]"]


def test_unreadable_file_raises_oserror(tmp_path):
    with pytest.raises(FileNotFoundError):
        dcf2bin.compile_path(str(tmp_path / "missing.dcf"))
    with pytest.raises(FileNotFoundError):
        dcf2bin.read_container(tmp_path / "missing.bin")


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_compile_file_gives_the_sample_bytes(name):
    data, issued = caught(dcf2bin.compile_file, str(SAMPLES / f"{name}.dcf"))
    assert data == (SAMPLES / f"{name}.bin").read_bytes() and issued == []


def test_compile_file_delivers_warnings(tmp_path):
    """Problems in entries compile does not write are warnings: compile_file returns the
    bytes and issues each one as a DiagnosticWarning pointing at the caller."""
    src = tmp_path / "dup.dcf"
    src.write_text("[2000]\nDataType=0x0005\nAccessType=rw\nDefaultValue=1\nDefaultValue=2\n")
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        data = dcf2bin.compile_file(str(src))
    assert data == BinContainer().to_bytes()
    assert [str(w.message) for w in got] == [
        f"{src}:5: warning: key 'DefaultValue' repeated in [2000] (first at line 4) "
        "(not written by compile) [DCF010]",
        f"{src}: warning: nothing is configured (no ParameterValue or DownloadFile, no "
        "network variable): the container holds no entries [DCF009]"]
    w = got[0]
    assert w.category is dcf2bin.DiagnosticWarning and w.filename == __file__
    assert w.message.diagnostic == dcf2bin.Diagnostic(
        dcf2bin.Severity.WARNING, "key 'DefaultValue' repeated in [2000] (first at line 4) "
        "(not written by compile)", str(src), 5, rule="DCF010",
        hint="remove one of them; dcf2bin does not guess which is meant")
    with warnings.catch_warnings():
        warnings.simplefilter("error", dcf2bin.DiagnosticWarning)
        with pytest.raises(dcf2bin.DiagnosticWarning):
            dcf2bin.compile_file(str(src))


def test_compile_file_raises_with_every_diagnostic(tmp_path):
    src = tmp_path / "slave.dcf"
    src.write_text("[1800]\nObjectType=0x9\n[1800sub1]\nDataType=0x0007\nAccessType=rw\n"
                   "ParameterValue=$NODEID+0x180\n[1A00]\nObjectType=0x9\n[1A00sub0]\n"
                   "DataType=0x0005\nAccessType=rw\nParameterValue=0\n")
    with pytest.raises(dcf2bin.CompileError) as info:
        dcf2bin.compile_file(str(src))
    assert [d.format() for d in info.value.diagnostics] == [
        f"{src}:6: error: value '$NODEID+0x180' of 0x1800sub1 uses $NODEID but no node-ID "
        "is known [DCF201]"]
    assert str(info.value) == info.value.diagnostics[0].format()
    data, issued = caught(dcf2bin.compile_file, str(src), node_id=5)
    assert issued == [] and data == dcf2bin.compile_path(str(src), node_id=5).data
    assert (0x1800, 1, (0x185 | 0x80000000).to_bytes(4, "little")) in \
        dcf2bin.read_container(data).entries


# -- containers -----------------------------------------------------------------------------------

@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_read_container_from_bytes_path_or_container(name):
    path = SAMPLES / f"{name}.bin"
    data = path.read_bytes()
    for source in (data, str(path), path, bytearray(data)):
        c, issued = caught(dcf2bin.read_container, source)
        assert issued == [] and c.to_bytes() == data
    assert dcf2bin.read_container(c) is c


def test_read_container_raises_with_the_offset():
    with pytest.raises(dcf2bin.ReadError) as info:
        dcf2bin.read_container(b"\x01\x02", name="short.bin")
    assert [d.format() for d in info.value.diagnostics] == [
        "short.bin:0x0: error: 2 bytes: too short for the 40-byte header [CNT001]"]
    assert str(info.value) == "short.bin:0x0: error: 2 bytes: too short for the 40-byte " \
        "header [CNT001]"
    assert isinstance(info.value, ValueError)


def test_read_container_warns_about_odd_headers():
    data = bytearray(BinContainer(entries=[(0x2000, 0, b"\x05")], attributes=b"\x70")
                     .to_bytes())
    data[6] = 9                           # segment count
    c, issued = caught(dcf2bin.read_container, bytes(data))
    assert issued == ["<bytes>:0x6: warning: header counts 9 segments, 2 are present [CNT006]"]
    assert c.to_bytes() == bytes(data)    # kept as stored


@pytest.mark.parametrize("name", ["bild8", "plc", "device"])
def test_dump_json_and_text_match_the_golden_files(name):
    src = SAMPLES / f"{name}.bin"
    text = dcf2bin.dump_json(src.read_bytes(), name=f"{name}.bin")
    assert text == (GOLDEN / f"{name}.dump.json").read_text()
    assert dcf2bin.dump_text(src.read_bytes(), name=f"{name}.bin") == \
        (GOLDEN / f"{name}.dump.txt").read_text()
    assert dcf2bin.dump_text(src) == run("dump", src).stdout


def test_dump_text_with_eds_matches_the_command_line():
    src, eds = SAMPLES / "device.bin", SAMPLES / "device.dcf"
    assert dcf2bin.dump_text(src, eds=eds, full=True) == \
        run("dump", src, "--eds", eds, "--full").stdout


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_from_json_rebuilds_the_bytes(name):
    data = (SAMPLES / f"{name}.bin").read_bytes()
    text = dcf2bin.dump_json(data)
    assert dcf2bin.from_json(text) == data
    assert dcf2bin.from_json(text.encode()) == data
    assert dcf2bin.from_json(json.loads(text)) == data


def test_from_json_raises_with_the_line():
    with pytest.raises(dcf2bin.ReadError) as info:
        dcf2bin.from_json('{\n "format": "dcf2bin-container",\n "oops": 1\n}', name="x.json")
    assert [d.format() for d in info.value.diagnostics] == [
        "x.json:3: error: oops: unknown key 'oops' (expected one of format, version, "
        "layout, header, entries, extra_attributes, addresses, pi_parameters, gaps) [JSN002]"]


# -- bin2dcf --------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["bild8", "plc", "device"])
def test_to_dcf_matches_the_golden_dcf(name):
    src = SAMPLES / f"{name}.bin"
    res = dcf2bin.to_dcf(src.read_bytes(), name=f"{name}.bin", dcf_name=f"{name}.dcf")
    assert (res.roundtrip, res.options, res.diagnostics) == (True, [], [])
    assert res.text == (GOLDEN / f"{name}.bin2dcf.dcf").read_text()
    assert dcf2bin.to_dcf(src).to_bytes() == run("bin2dcf", src, "-o", "-").stdout_bytes
    back = dcf2bin.compile_path(f"{name}.dcf", data=res.to_bytes())
    assert back.data == src.read_bytes()


def test_to_dcf_with_eds():
    src, eds = SAMPLES / "device.bin", SAMPLES / "device.dcf"
    res = dcf2bin.to_dcf(src, eds=eds, name="device.bin")
    assert res.diagnostics == []
    text = res.text.replace(str(SAMPLES) + "/", "")
    assert text == (GOLDEN / "device.eds.bin2dcf.dcf").read_text()


def test_to_dcf_names_what_will_not_round_trip():
    c = BinContainer(entries=[(0x1000, 0, b"\x95\x01\x00\x00"), (0x2000, 0, b"\x05")],
                     attributes=b"\x30\x70")
    res = dcf2bin.to_dcf(c, name="ro.bin")
    assert (res.roundtrip, res.options) == (False, ["--entries all"])
    assert [d.rule for d in res.diagnostics] == ["B2D004", "B2D010"]
    assert "FileName=container.dcf\n" in res.text
    assert dcf2bin.compile_path("ro.dcf", data=res.to_bytes(), select="all").data == \
        c.to_bytes()


def test_to_dcf_keeps_the_container_warnings():
    data = bytearray((SAMPLES / "bild8.bin").read_bytes())
    data[6] = 9
    res = dcf2bin.to_dcf(bytes(data), name="odd.bin")
    assert [d.format() for d in res.diagnostics] == [
        "odd.bin:0x6: warning: header counts 9 segments, 4 are present [CNT006]",
        "odd.bin:0x0: warning: the header or segment layout is not the canonical one "
        "(segments back to back after the header in table order, an empty one at offset 0 "
        "and not counted); compile writes the canonical layout [B2D001]",
        "odd.bin: warning: the DCF will not compile back to the same container (header "
        "layout); for a lossless copy use 'dcf2bin dump --format json' [B2D010]"]


def test_to_dcf_raises_on_no_container():
    with pytest.raises(dcf2bin.ReadError) as info:
        dcf2bin.to_dcf(b"")
    assert [d.rule for d in info.value.diagnostics] == ["CNT001"]


# -- validate -------------------------------------------------------------------------------------

def test_validate_gives_the_command_lines_findings():
    src = str(SAMPLES / "plc.dcf")
    diags = dcf2bin.validate(src)
    doc = json.loads(run("validate", "--format", "json", src).stdout)
    assert [(d.rule, d.line) for d in diags] == \
        [(f["rule"], f["line"]) for f in doc["diagnostics"]]
    assert dcf2bin.validate([pathlib.Path(src)]) == diags


def test_validate_selects_rules_and_reads_directories(tmp_path):
    (tmp_path / "a.dcf").write_text("[2000]\nDataType=0x0005\nAccessType=rw\n"
                                    "ParameterValue=300\n")
    (tmp_path / "b.bin").write_bytes(b"\x00")
    diags = dcf2bin.validate(tmp_path, select=["DCF200", "CNT001"])
    assert [d.format() for d in diags] == [
        f"{tmp_path / 'a.dcf'}:4: error: 0x2000sub0: value 300 out of range "
        "for UNSIGNED8 (0..255) [DCF200]",
        f"{tmp_path / 'b.bin'}:0x0: error: 1 bytes: too short for the 40-byte header [CNT001]"]
    assert dcf2bin.validate(tmp_path, select="DCF200,CNT001") == diags
    assert dcf2bin.validate(tmp_path, select="DCF2,CNT", ignore="DCF200,CNT001") == []


def test_validate_unreadable_path_and_bad_selector(tmp_path):
    assert [(d.rule, d.message) for d in dcf2bin.validate(str(tmp_path / "none.dcf"))] == [
        ("IO001", "cannot read: No such file or directory")]
    with pytest.raises(ValueError):
        dcf2bin.validate(str(SAMPLES / "plc.dcf"), select="NOPE999")


# -- load -----------------------------------------------------------------------------------------

def test_load_gives_the_model_and_canopen():
    dev = dcf2bin.load(str(SAMPLES / "plc.dcf"))
    assert isinstance(dev, dcf2bin.Device) and dev.problems == []
    assert sorted(dev.objects)[:3] == [0x1000, 0x1001, 0x1017]
    od = dev.to_canopen()
    assert type(od).__name__ == "ObjectDictionary"
    assert od[0x1000].index == 0x1000

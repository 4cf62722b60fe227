"""Issue 26 item 16: a DCF that dcf2bin writes validates without errors.

bin2dcf and ``simulate --emit-od`` describe what they do not know from the container --
the objects every device has (0x1000, 0x1001, 0x1018: DCF101), the entries its PDOs map
(DCF404), the dummies they map (DCF410) -- read-only or as the mapping needs, without a
value and with ObjFlags=0x1, so that compiling bin2dcf's DCF still gives the container's
bytes, with ``--entries all`` too (SPEC §4; the round trips themselves are in
tests/test_bin2dcf.py)."""
from __future__ import annotations

import re

import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES, compile_corpus_file, compiling_corpus_params

from dcf2bin import dcfwriter, dump, model
from dcf2bin.cli import main
from dcf2bin.compiler import CompileOptions, compile_device
from dcf2bin.lint import Options, run as lint_run



def _containers():
    """Every .bin here that is a container (the CNT fixtures that are not, bin2dcf
    refuses: tests/test_bin2dcf.py)."""
    out = []
    for p in sorted([*SAMPLES.glob("*.bin"), *(ROOT / "tests").rglob("*.bin")]):
        if dump.read_bytes(p.read_bytes(), str(p))[0] is not None:
            out.append(p)
    return out


CONTAINERS = _containers()


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def errors_of(path) -> list[str]:
    return [d.format() for d in lint_run([str(path)], Options()).diagnostics
            if d.severity.value == "error"]


def converted(data: bytes, name: str, **kw):
    """bin2dcf's result, or None for bytes that are no container (CNTxxx fixtures)."""
    c, _ = dump.read_bytes(data, name)
    return None if c is None else dcfwriter.convert(c, name, dcf_name="x.dcf", **kw)


def without_added(text: str) -> str:
    """The DCF without the sections bin2dcf adds (those its comment marks), as it was
    before issue 26 item 16."""
    blocks = re.split(r"\n(?=\[)", text)
    dropped = set()
    kept = []
    for b in blocks:
        head = b.split("\n", 1)[0]
        index = re.fullmatch(r"\[([0-9A-F]{4})(?:sub[0-9A-F]+)?\]", head)
        if "\n; not in the container: " in b and "the sub 0 that compile implies" not in b:
            if index is not None and "sub" not in head:
                dropped.add(index.group(1))
            continue
        if index is not None and index.group(1) in dropped:
            continue
        kept.append(b)
    return "\n".join(kept)


def compile_text(text: str, **opts) -> bytes | None:
    dev = model.load("x.dcf", data=text.encode("utf-8"))
    return compile_device(dev, CompileOptions(**opts)).data


@pytest.mark.parametrize("path", CONTAINERS, ids=[str(p.relative_to(ROOT)) for p in CONTAINERS])
def test_bin2dcf_of_every_container_here_validates(path, tmp_path):
    res = converted(path.read_bytes(), str(path))
    out = tmp_path / "x.dcf"
    out.write_bytes(res.to_bytes())
    assert errors_of(out) == []
    # what compile gives is the same as without the added sections, --entries all too
    bare = without_added(res.text)
    assert bare != res.text
    for opts in ({}, {"select": "all"}):
        assert compile_text(res.text, **opts) == compile_text(bare, **opts), opts


@pytest.mark.parametrize("path", compiling_corpus_params(".dcf", ".eds"))
def test_bin2dcf_of_the_corpus_round_trip_validates(path, tmp_path):
    """The corpus round trip (compile, then bin2dcf, as tests/test_bin2dcf.py does), with
    and without the device's own EDS: no DCF404 for the device's mapped objects."""
    res = compile_corpus_file(path)
    info, dev, _ = dump.load_eds(str(path))
    for kw in ({}, {"eds": info, "eds_device": dev}):
        back = converted(res.data, str(path), **kw)
        out = tmp_path / "x.dcf"
        out.write_bytes(back.to_bytes())
        assert errors_of(out) == [], bool(kw)
        if back.roundtrip:
            assert compile_text(back.text) == res.data


def test_the_issue_commands(tmp_path):
    back = tmp_path / "back.dcf"
    r = run("bin2dcf", SAMPLES / "plc.bin", "-o", back)
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("validate", back)
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 1 file\n")
    assert run("compile", back, "-o", "-").stdout_bytes == (SAMPLES / "plc.bin").read_bytes()
    od = tmp_path / "od.dcf"
    r = run("simulate", "-q", SAMPLES / "plc.bin", "--emit-od", od)
    assert r.exit_code == 0
    r = run("validate", "-q", od)
    assert (r.exit_code, r.stdout) == (0, "")


def test_the_added_objects(tmp_path):
    """What bin2dcf adds, exactly: the three mandatory objects without values, and the
    device's mapped objects typed by the mapping's length (DIS-2 maps 0x6040, 16 bits)."""
    text = converted((SAMPLES / "dis2.bin").read_bytes(), "dis2.bin").text
    assert "[MandatoryObjects]\nSupportedObjects=3\n1=0x1000\n2=0x1001\n3=0x1018\n" in text
    assert ("[1000]\n; not in the container: an object every CANopen device has "
            "(ObjFlags=0x1: compile skips it)\nParameterName=Device type\nObjectType=0x7\n"
            "ObjFlags=0x1\nDataType=0x0007\nAccessType=ro\nPDOMapping=0\n\n") in text
    assert ("[1018]\n; not in the container: an object every CANopen device has "
            "(ObjFlags=0x1: compile skips it)\nParameterName=Identity object\n"
            "ObjectType=0x9\nObjFlags=0x1\nSubNumber=2\n\n[1018sub0]\n"
            "ParameterName=Highest sub-index supported\nObjectType=0x7\nDataType=0x0005\n"
            "AccessType=ro\nPDOMapping=0\n\n[1018sub1]\nParameterName=Vendor-ID\n"
            "ObjectType=0x7\nDataType=0x0007\nAccessType=ro\nPDOMapping=0\n\n") in text
    assert ("[6064]\n; not in the container: mapped by 0x1A00sub3 (32 bits); DataType and "
            "AccessType stand in for the device's (ObjFlags=0x1: compile skips it)\n"
            "ParameterName=Object 6064\nObjectType=0x7\nObjFlags=0x1\nDataType=0x0007\n"
            "AccessType=rw\nPDOMapping=1\n\n") in text


def test_with_the_eds_the_values_it_gives():
    """--eds: the mandatory objects' values from the EDS (those that are values of their
    CiA 301 type), the mapped entries as the EDS describes them."""
    info, dev, _ = dump.load_eds(str(SAMPLES / "device.dcf"))
    res = converted((SAMPLES / "device.bin").read_bytes(), "device.bin", eds=info,
                    eds_device=dev)
    assert "DataType=0x0007\nAccessType=ro\nDefaultValue=0x000F0191\nPDOMapping=0\n" in res.text
    assert "ParameterName=Vendor-ID\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\n" \
           "DefaultValue=0x000000AB\n" in res.text
    assert res.roundtrip and compile_text(res.text) == (SAMPLES / "device.bin").read_bytes()


@pytest.mark.parametrize("name", ["bild8.bin", "device.bin", "dis2.bin", "dis2_cobid.bin",
                                  "plc.bin", "plc.dcf", "device.dcf", "dis2.dcf"])
def test_simulate_emit_od_validates(name, tmp_path):
    od = tmp_path / "od.dcf"
    r = run("simulate", "-q", SAMPLES / name, "--emit-od", od)
    assert r.exit_code == 0, r.stderr
    assert errors_of(od) == []

"""Issue 28: CiA 311 XML (XDD/XDC) read into the model a DCF is read into -- the vendor-style
fixture against the DCF that says the same, the XDD0xx rules, hostile XML, and every
command that takes a device description taking an XDC."""
from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest
from click.testing import CliRunner
from conftest import ROOT

from dcf2bin import filekind, formats
from dcf2bin.cli import main
from dcf2bin.fileio import MAX_INPUT, InputTooLarge

FIX = ROOT / "tests" / "fixtures" / "xdd"
XDC, DCF = FIX / "vendor_v10.xdc", FIX / "vendor_v10.dcf"
FIELDS = ("name", "dtype", "access", "pdo_mapping", "obj_flags", "default", "param",
          "download_file", "low", "high", "denotation")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def entries(dev):
    return {(i, s): tuple(getattr(e, f) for f in FIELDS)
            for i, o in dev.objects.items() for s, e in o.entries.items()}


# -- the vendor-style fixture (v1.0: values as attributes, an XDC with actualValues) ---------

def test_the_xdc_and_the_dcf_that_says_the_same_compile_to_the_same_container(tmp_path):
    for src in (XDC, DCF):
        r = run("compile", src, "-o", tmp_path / f"{src.suffix[1:]}.bin")
        assert (r.exit_code, r.stderr) == (0, "")
    data = (tmp_path / "xdc.bin").read_bytes()
    assert data == (tmp_path / "dcf.bin").read_bytes()
    assert len(data) == 224             # 17 entries: both PDOs, 0x1017, 0x2401, 0x6083
    assert data[:4] == (224).to_bytes(4, "little")


def test_the_xdc_reads_into_the_model_the_dcf_reads_into():
    x, d = formats.load(str(XDC)), formats.load(str(DCF))
    assert entries(x) == entries(d)
    assert (x.node_id, d.node_id) == (5, 5)        # deviceCommissioning nodeID
    assert [p.diagnostic.format() for p in x.problems] == []
    assert x.dummy_usage == d.dummy_usage == {2, 5}
    e = x.entry(0x1A00, 2)       # an actualValue is a ParameterValue, on its parameter's line
    line = XDC.read_text().splitlines().index(
        '\t\t\t\t\t\t<actualValue value="0x60640020"/><defaultValue value="0x00000000"/>') + 1
    assert (e.default, e.param, e.value_where.line) == ("0x00000000", "0x60640020", line)
    assert x.entry(0x6083, 0).denotation == "Ramp up"
    assert x.entry(0x2401, 0).obj_flags == 2
    assert x.ini.section("devicecomissioning").get("baudrate") == "500"   # "500 Kbps"
    assert x.specifics[(0x6040, None)] == {"PDOmapping": "RPDO"}
    assert x.specifics[(0x6083, None)] == {"description": "Profile acceleration"}


def test_every_command_that_takes_a_description_takes_the_xdc(tmp_path):
    os.chdir(FIX)
    for args in (["map"], ["simulate"], ["export", "-f", "lenze-st", "-o", "-"],
                 ["download", "-n", "5", "--dry-run"]):
        got = [run(*args, name) for name in ("vendor_v10.xdc", "vendor_v10.dcf")]
        assert [r.exit_code for r in got] == [0, 0], args
        # the same output but for the file's name, and (download) the line of each value
        same = [re.sub(r"vendor_v10\.(xdc|dcf)(:\d+)? *", "F ", r.stdout) for r in got]
        assert same[0] == same[1], args
    container = tmp_path / "c.bin"
    assert run("compile", "vendor_v10.dcf", "-o", container).exit_code == 0
    for args in (["simulate", container, "--static-od", "vendor_v10.xdc"],
                 ["dump", container, "--eds", "vendor_v10.xdc"]):
        r = run(*args)
        assert (r.exit_code, r.stderr) == (0, ""), args
    from dcf2bin.bus import node
    assert node.from_file(str(XDC), None)[0].id == 5


def test_validate_reads_an_xdc_with_its_xml_lines():
    r = run("validate", XDC)
    assert r.exit_code == 0
    assert r.stdout == (
        f"{XDC}:31: info: 0x1018sub4 is ro; its ParameterValue is not written [DCF213]\n"
        f"{XDC}:92: info: 0x1000sub0 is const; its ParameterValue is not written [DCF213]\n"
        "0 errors, 0 warnings, 2 infos in 1 file\n")


def test_the_text_of_an_xdc_for_the_network_configurator_reads_back_to_the_same_model(tmp_path):
    dev, text = formats.load_with_text(str(XDC))
    back = tmp_path / "back.dcf"
    back.write_text(text)
    assert entries(formats.load(str(back))) == entries(dev)
    assert "[DeviceComissioning]\nNodeID=5\n" in text


# -- what only XML can get wrong: XDD0xx ------------------------------------------------------

HEAD = ('<?xml version="1.0"?>\n<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.1">'
        '\n<ISO15745Profile><ProfileBody>\n<ApplicationProcess><parameterList>\n')
MID = '</parameterList></ApplicationProcess>\n<dataTypeList>{types}</dataTypeList>\n' \
      '</ProfileBody></ISO15745Profile>\n<ISO15745Profile><ProfileBody>\n<CANopenObjectList>\n'
TAIL = '</CANopenObjectList>\n</ProfileBody></ISO15745Profile>\n</ISO15745ProfileContainer>\n'


def xdd(params: str, objects: str, types: str = "") -> bytes:
    """A small CANopenEditor-style file: the parameters start at line 5, the objects at line
    10 + the lines of the parameters."""
    return (HEAD + params + MID.format(types=types) + objects + TAIL).encode()


def findings(data: bytes, name: str = "t.xdd") -> list[str]:
    dev = formats.build(formats.read(data, name))
    return [p.diagnostic.format() for p in dev.problems]


VAR = '<CANopenObject index="2000" name="x" objectType="7" uniqueIDRef="{ref}"{more}/>\n'
PARAM = '<parameter uniqueID="P1" access="readWrite"><UINT/><defaultValue value="5"/></parameter>\n'


def test_a_parameter_gives_type_access_and_default_at_its_own_lines():
    dev = formats.load("t.xdd", data=xdd(PARAM, VAR.format(ref="P1", more="")))
    e = dev.entry(0x2000, 0)
    assert (e.dtype.name, e.access, e.default, e.where.line) == ("UNSIGNED16", "rw", "5", 11)
    assert (e.key_where("datatype").line, e.key_where("defaultvalue").line) == (5, 5)


def test_xdd010_a_reference_to_nothing():
    assert findings(xdd(PARAM, VAR.format(ref="P2", more=""))) == [
        't.xdd:11: error: 0x2000: uniqueIDRef="P2" names no parameter of the parameterList '
        '[XDD010]']
    ref = '<parameter uniqueID="P1"><dataTypeIDRef uniqueIDRef="T9"/></parameter>\n'
    assert findings(xdd(ref, VAR.format(ref="P1", more=""))) == [
        't.xdd:5: error: 0x2000: dataTypeIDRef uniqueIDRef="T9" names no type of the '
        'dataTypeList [XDD010]']


def test_xdd011_an_unknown_type_is_one_finding_not_two():
    timed = '<parameter uniqueID="P1"><TIME/></parameter>\n'
    assert findings(xdd(timed, VAR.format(ref="P1", more=""))) == [
        "t.xdd:5: error: 0x2000: <TIME> is not a data type dcf2bin knows [XDD011]"]
    bad = '<CANopenObject index="2000" name="x" objectType="7" dataType="7" accessType="rw"/>\n'
    assert findings(xdd("", bad)) == [
        't.xdd:10: error: 0x2000: dataType="7" is not 4 hex digits [XDD011]']


def test_xdd012_the_objects_attribute_wins_over_its_parameter_and_both_lines_are_named():
    data = xdd(PARAM, VAR.format(ref="P1", more=' dataType="0007" defaultValue="0x05"'))
    assert findings(data) == [
        't.xdd:11: warning: 0x2000: the CANopenObject says dataType="0007" and its parameter '
        "P1 (line 5) says <UINT> (0x0006); the CANopenObject's attribute is read [XDD012]"]
    assert formats.load("t.xdd", data=data).entry(0x2000, 0).dtype.name == "UNSIGNED32"


def test_xdd013_and_xdd014_bad_and_repeated_objects():
    objs = ('<CANopenObject index="20" name="a" objectType="7"/>\n'
            '<CANopenObject index="2000" name="b" objectType="7" dataType="0005" '
            'accessType="rw" PDOmapping="sometimes"/>\n'
            '<CANopenObject index="2000" name="c" objectType="7" dataType="0005" '
            'accessType="rw"/>\n')
    assert findings(xdd("", objs)) == [
        't.xdd:10: error: CANopenObject index="20" is not 4 hex digits; it is not read '
        "[XDD013]",
        't.xdd:11: error: 0x2000: PDOmapping="sometimes" is none of no, default, optional, '
        "TPDO, RPDO [XDD013]",
        "t.xdd:12: error: 0x2000 is given twice (first at line 11); the first is read "
        "[XDD014]"]


@pytest.mark.parametrize("data, line", [
    (b'<?xml version="1.0"?>\n<note>hello</note>\n',
     "t.xdd:2: error: the root element is <note>, not the ISO15745ProfileContainer of a CiA "
     "311 device description [XDD003]"),
    (b"<ISO15745ProfileContainer>\n<x>\n</ISO15745ProfileContainer>\n",
     "t.xdd:3: error: not well-formed XML: Opening and ending tag mismatch: x line 2 and "
     "ISO15745ProfileContainer [XDD001]"),
    (b"", "t.xdd:1: error: not well-formed XML: Document is empty [XDD001]"),
])
def test_a_file_that_is_not_cia311_is_one_line(data, line):
    assert findings(data) == [line]


# -- hostile XML: one line each, bounded --------------------------------------------------------

BOMB = (b'<?xml version="1.0"?>\n<!DOCTYPE lolz [\n <!ENTITY lol "lol">\n'
        + b"".join(b' <!ENTITY lol%d "%s">\n' % (i, b"".join(b"&lol%s;" % (b"" if i == 1 else
                                                                            b"%d" % (i - 1))
                                                               for _ in range(10)))
                   for i in range(1, 10))
        + b"]>\n<ISO15745ProfileContainer>&lol9;</ISO15745ProfileContainer>\n")
DOCTYPE = ("t.xdd:2: error: the file {}; a CiA 311 description has no DOCTYPE, and dcf2bin "
           "expands no entity and fetches no DTD [XDD002]")


@pytest.mark.parametrize("data, line", [
    (BOMB, DOCTYPE.format("declares XML entities")),
    (b'<?xml version="1.0"?>\n<!DOCTYPE x [<!ENTITY e SYSTEM "file:///etc/passwd">]>\n'
     b"<ISO15745ProfileContainer>&e;</ISO15745ProfileContainer>\n",
     DOCTYPE.format("declares XML entities")),
    (b'<?xml version="1.0"?>\n<!DOCTYPE ISO15745ProfileContainer SYSTEM '
     b'"http://192.0.2.1/x.dtd">\n<ISO15745ProfileContainer/>\n',
     DOCTYPE.format("names a DTD (http://192.0.2.1/x.dtd)")),
    (b"<a>" * 100_000 + b"</a>" * 100_000,
     "t.xdd:1: error: not well-formed XML: elements are nested more than 256 deep [XDD001]"),
])
def test_hostile_xml_is_one_line(data, line):
    assert findings(data) == [line]


def test_an_input_over_64_mib_is_refused_before_it_is_read(tmp_path):
    big = tmp_path / "big.xdd"
    with open(big, "wb") as f:
        f.write(b'<?xml version="1.0"?>\n')
        f.truncate(MAX_INPUT + 1)            # sparse: refused by its size
    with pytest.raises(InputTooLarge):       # formats.load reads through fileio.read_file
        formats.load(str(big))
    # (the commands read their inputs through cli.common.read_input, bounded by issue 26)


# -- the registry and filekind ---------------------------------------------------------------

def test_the_registry_names_the_formats_and_filekind_asks_it():
    assert [f.name for f in formats.FORMATS] == ["xdd", "ini"]
    assert formats.by_suffix(".XDC").name == "xdd"
    assert filekind.detect(XDC.read_bytes(), "x.bin") == filekind.XDD      # content first
    assert filekind.detect(DCF.read_bytes(), "x.xdd") == filekind.DCF
    assert filekind.detect(b"", "x.xpd") == filekind.XDD                    # else the name
    assert filekind.detect("<?xml version='1.0'?><a/>".encode("utf-16")) == filekind.XDD
    assert filekind.misnamed("x.xdd", filekind.DCF) == (
        "x.xdd is DCF/EDS text, not CiA 311 XML (XDD/XDC) as its name says; read as DCF/EDS "
        "text")
    assert filekind.mismatch("x.xdc", filekind.XDD, (filekind.CONTAINER,)) == (
        "x.xdc is CiA 311 XML (XDD/XDC), not a binary container; use dcf2bin compile to make "
        "a container of it (dcf2bin validate checks it)")


def test_an_xdc_given_where_a_dcf_text_is_edited_says_what_it_is(tmp_path):
    # allocate --into merges variables into a DCF's text: an XDC is not taken there
    csv = tmp_path / "vars.csv"
    csv.write_text("name,type,direction\nspeed,UNSIGNED16,input\n")
    r = run("allocate", csv, "--into", XDC, "-o", tmp_path / "x.dcf")
    assert (r.exit_code, r.stderr) == (1, f"{XDC}: error: {XDC} is CiA 311 XML (XDD/XDC), "
                                          "not DCF/EDS text; --into takes the DCF to merge the "
                                          "variables into\n")


def test_help_does_not_import_lxml():
    code = ("import sys; from dcf2bin.cli import main\ntry:\n    main(['--help'])\n"
            "except SystemExit:\n    pass\nprint('lxml' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip().splitlines()[-1] == "False"

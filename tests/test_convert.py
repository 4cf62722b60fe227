"""Issue 28 item 2: dcf2bin convert between EDS, DCF, XDD and XDC -- golden files of a small
sample (reviewed by hand), every warning's exact text, the round trips the issue names,
and the command's options and exit codes."""
from __future__ import annotations

import shutil

import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES
from convert_compare import differences

from dcf2bin import formats
from dcf2bin.cli import main
from dcf2bin.cli.convert import TARGETS
from dcf2bin.diagnostics import Severity

FIX = ROOT / "tests" / "fixtures" / "convert"
XDD_FIX = ROOT / "tests" / "fixtures" / "xdd"
SMALL = FIX / "small.eds"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def convert(path, target, name=None, node_id=None):
    data = path.read_bytes()
    return formats.convert(data, str(path), target, name=name, node_id=node_id)


def load(data: bytes, suffix: str):
    return formats.load(f"x.{suffix}", data=data)


def lines(res) -> list[str]:
    return [d.format() for d in res.diagnostics]


def errors(dev) -> list[str]:
    return [p.diagnostic.format() for p in dev.problems
            if p.diagnostic.severity is Severity.ERROR]


# -- golden files (tests/fixtures/convert, reviewed by hand) -------------------------------------

@pytest.mark.parametrize("source, golden", [
    (FIX / "small.eds", FIX / "small.xdd"),
    (FIX / "small.xdd", FIX / "small-back.eds"),
    (XDD_FIX / "vendor_v10.xdc", FIX / "vendor_v10.dcf"),
])
def test_golden(tmp_path, source, golden):
    out = tmp_path / golden.name
    r = run("convert", source, "-o", out, "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    assert out.read_bytes() == golden.read_bytes()


def test_the_output_is_the_same_bytes_each_run_and_names_no_time(tmp_path):
    first = convert(SMALL, "xdd", name="a.xdd").data
    assert convert(SMALL, "xdd", name="a.xdd").data == first
    assert b"2024-03-11" in first and b"14:07:00" in first      # [FileInfo]'s own
    dev = formats.load(str(SAMPLES / "plc.dcf"))
    dev.ini.sections.pop("fileinfo")
    assert b"fileCreationDate" not in formats.dump(dev, "xdc").data   # none given: none


# -- every warning, word for word -------------------------------------------------------------

def test_what_an_xdd_cannot_say_of_the_small_eds():
    f = str(SMALL)
    assert lines(convert(SMALL, "xdd")) == [
        f"{f}:1: warning: 2 comment lines (;...) left out: no reader keeps comments [CNV008]",
        f"{f}:3: warning: [FileInfo] FileRevision=2 and Description=Small test device left "
        "out: CiA 311 has no place for them [CNV005]",
        f"{f}:67: warning: 0x1016: CompactSubObj=2 has no CiA 311 form; its 2 sub-objects "
        "are written one by one [CNV001]",
        f"{f}:85: warning: 0x2000: [2000] StorageLocation=RAM left out: CiA 311 has no place "
        "for it [CNV005]",
        f"{f}:85: warning: 0x2000: AccessType=rww written as the access of its parameter "
        "(rwr as readWriteInput, rww as readWriteOutput): the accessType attribute says only "
        "const, ro, wo, rw [CNV006]",
        f"{f}:97: warning: 0x2100: sub1 AccessType=rwr written as the access of its "
        "parameter (rwr as readWriteInput, rww as readWriteOutput): the accessType attribute "
        "says only const, ro, wo, rw [CNV006]",
        f"{f}:126: warning: [Tools] left out: CiA 311 has no place for it [CNV005]"]


def test_what_an_eds_cannot_say_of_a_dcf_and_of_an_xdc():
    dcf = XDD_FIX / "vendor_v10.dcf"
    tail = "left out: an EDS holds no configured values [CNV002]"
    assert lines(convert(dcf, "eds")) == [
        f"{dcf}:1: warning: 2 comment lines (;...) left out: no reader keeps comments "
        "[CNV008]",
        f"{dcf}:38: warning: [DeviceComissioning] NodeID=5, NodeName=Axis X, Baudrate=500 "
        f"and 3 more {tail}",
        f"{dcf}:52: warning: 0x1000: ParameterValue=0x00020192 {tail}",
        f"{dcf}:69: warning: 0x1018: sub4 ParameterValue=31400222 {tail}",
        f"{dcf}:126: warning: 0x1017: ParameterValue=100 {tail}",
        f"{dcf}:137: warning: 0x1400: sub1 ParameterValue=$NODEID+0x200 and sub2 "
        f"ParameterValue=255 {tail}",
        f"{dcf}:170: warning: 0x1600: sub0 ParameterValue=1 and sub1 ParameterValue="
        f"0x60400010 {tail}",
        f"{dcf}:195: warning: 0x1800: sub1 ParameterValue=$NODEID+0x180, sub2 "
        f"ParameterValue=1 and sub3 ParameterValue=50 {tail}",
        f"{dcf}:235: warning: 0x1A00: sub0 ParameterValue=2, sub1 ParameterValue=0x60410010 "
        f"and sub2 ParameterValue=0x60640020 {tail}",
        f"{dcf}:293: warning: 0x6083: ParameterValue=2500 and Denotation=Ramp up {tail}",
        f"{dcf}:307: warning: 0x2401: ParameterValue=0x0004 {tail}"]
    xdc = XDD_FIX / "vendor_v10.xdc"
    got = lines(convert(xdc, "eds"))
    assert got[8:11] == [
        f"{xdc}:123: warning: 0x6040: PDOmapping=\"RPDO\" left out: an EDS has no key for it "
        "[CNV003]",
        f"{xdc}:124: warning: 0x6041: PDOmapping=\"TPDO\" left out: an EDS has no key for it "
        "[CNV003]",
        f"{xdc}:125: warning: 0x6064: PDOmapping=\"TPDO\" left out: an EDS has no key for it "
        "[CNV003]"]
    assert (len(got), got[-1]) == (13, f"{xdc}:147: warning: [DeviceComissioning] NodeID=5, "
                                       f"NodeName=Axis X, Baudrate=500 and 3 more {tail}")
    assert all(d.rule == "CNV002" for d in convert(dcf, "xdd").diagnostics[1:])
    assert lines(convert(dcf, "xdc")) == [
        f"{dcf}:1: warning: 2 comment lines (;...) left out: no reader keeps comments "
        "[CNV008]"]


def test_a_value_xml_cannot_hold_is_named():
    text = SMALL.read_text().replace("DefaultValue=XS-1 <prototype>", "DefaultValue=XS-1\x01")
    res = formats.convert(text.encode(), "s.eds", "xdd")
    assert "s.eds:97: warning: 0x2100: sub2 defaultValue left out: XML cannot hold its " \
           "control characters [CNV007]" in lines(res)
    assert load(res.data, "xdd").entry(0x2100, 2).default is None


def test_an_input_with_errors_is_not_converted(tmp_path):
    bad = tmp_path / "bad.eds"
    bad.write_text(SMALL.read_text().replace("DataType=0x0005\nAccessType=ro\nDefaultValue=0\n"
                                             "PDOMapping=1", "DataType=0x0099\nAccessType=ro"))
    out = tmp_path / "out.xdd"
    r = run("convert", bad, "-o", out)
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] == (f"{bad}:58: error: [1001] unknown or unsupported "
                                        "DataType 0x0099 [DCF030]")
    assert r.stderr.splitlines()[-1] == f"{bad}: 1 error, nothing written"
    assert not out.exists()


# -- round trips ---------------------------------------------------------------------------------

WARNED_XDD = ("compact", "compactpdo", "edsversion", "filename", "filerevision",
              "description")


def test_eds_to_xdd_to_eds_gives_the_same_model():
    for path in (SMALL, SAMPLES / "device.eds"):
        dev = formats.load(str(path))
        xdd = load(formats.dump(dev, "xdd").data, "xdd")
        back = load(formats.dump(xdd, "eds").data, "eds")
        skip = WARNED_XDD + ("implicit",)     # CompactSubObj's, CompactPDO's: written out
        assert errors(xdd) == errors(back) == []
        assert differences(dev, xdd, skip_fields=skip, specifics=False) == [], path
        assert differences(dev, back, skip_fields=skip) == [], path


def test_dcf_to_xdc_to_dcf_keeps_values_denotations_and_the_commissioning():
    for path in (XDD_FIX / "vendor_v10.dcf", SAMPLES / "plc.dcf", SAMPLES / "device.dcf"):
        dev = formats.load(str(path))
        xdc = load(formats.dump(dev, "xdc").data, "xdc")
        back = load(formats.dump(xdc, "dcf").data, "dcf")
        skip = WARNED_XDD + ("implicit",)
        assert differences(dev, xdc, skip_fields=skip, specifics=False) == [], path
        assert differences(dev, back, skip_fields=skip) == [], path
        assert back.node_id == dev.node_id


def test_the_vendor_xdc_to_dcf_to_xdc_to_dcf():
    xdc = formats.load(str(XDD_FIX / "vendor_v10.xdc"))
    dcf = load(formats.dump(xdc, "dcf").data, "dcf")
    xdc2 = load(formats.dump(dcf, "xdc").data, "xdc")
    dcf2 = load(formats.dump(xdc2, "dcf").data, "dcf")
    # the kind of PDO mapping (TPDO, RPDO) is CiA 311's only: a DCF says PDOMapping=1
    assert differences(xdc, dcf, specifics=False, skip_fields=("filename", "edsversion")) == []
    assert differences(dcf, dcf2, skip_fields=("filename", "edsversion")) == []
    assert differences(xdc, xdc2, specifics=False, skip_fields=("filename", "edsversion")) == []
    assert (dcf2.node_id, dcf2.entry(0x6083, 0).denotation) == (5, "Ramp up")
    assert dcf2.ini.section("devicecomissioning").values == \
        dcf.ini.section("devicecomissioning").values


def test_an_xdd_written_of_an_xdd_keeps_the_specifics(tmp_path):
    dev = formats.load(str(XDD_FIX / "vendor_v10.xdc"))
    again = load(formats.dump(dev, "xdc").data, "xdc")
    assert differences(dev, again, skip_fields=("filename", "edsversion")) == []
    assert again.specifics[(0x6040, None)] == {"PDOmapping": "RPDO"}
    assert again.specifics[(0x6083, None)] == {"description": "Profile acceleration"}


def test_a_written_eds_validates_and_a_written_xdd_reads_without_a_finding(tmp_path):
    for target in TARGETS:
        out = tmp_path / f"small.{target}"
        assert run("convert", SMALL, "-o", out, "-q").exit_code == 0
        r = run("validate", out, "--select", "DCF0,XDD", "--ignore", "DCF050")
        assert r.stdout == "0 errors, 0 warnings, 0 infos in 1 file\n", (target, r.stdout)
    # the whole rule set: what the source has (no 0x1018, two keys of its own), no more
    for target in ("eds", "dcf"):
        r = run("validate", tmp_path / f"small.{target}")
        assert r.stdout.splitlines()[-1] == run("validate", SMALL).stdout.splitlines()[-1] \
            == "1 error, 2 warnings, 0 infos in 1 file"


# -- the command -----------------------------------------------------------------------------

def test_targets_match_the_library():
    assert TARGETS == tuple(formats.TARGETS)


def test_the_format_from_the_suffix_or_f(tmp_path):
    r = run("convert", SMALL, "-o", "-", "-f", "xdd", "-q")
    assert r.exit_code == 0 and r.stdout.startswith('<?xml version="1.0" encoding="UTF-8"?>')
    assert 'fileName="small.eds"' in r.stdout         # stdout: the source's name is kept
    r = run("convert", SMALL, "-o", tmp_path / "x.xpd", "-q")
    assert r.exit_code == 0 and (tmp_path / "x.xpd").read_bytes().startswith(b"<?xml")
    r = run("convert", SMALL, "-o", tmp_path / "x.txt", "--to", "dcf", "-q")
    assert r.exit_code == 0 and (tmp_path / "x.txt").read_text().startswith("[FileInfo]\n")


@pytest.mark.parametrize("args, message", [
    (["-o", "x.bin"], "Invalid value for '-o' / '--output': cannot tell the format of 'x.bin' "
                      "from its suffix; give -f eds|dcf|xdd|xdc"),
    (["-o", "t.txt"], "Invalid value for '-o' / '--output': cannot tell the format of 't.txt' "
                      "from its suffix; give -f eds|dcf|xdd|xdc"),
    ([], "Missing option '-o' / '--output'. Its suffix, or -f, names the format (-o - for "
         "standard output)."),
    (["-o", "x.eds", "-n", "3"], "-n applies to a DCF or an XDC only (the output is EDS: it "
                                 "holds no configured values)"),
])
def test_usage_errors(args, message):
    """In click's form, as every other usage error: Usage, Try, Error."""
    r = run("convert", SMALL, *args)
    assert r.exit_code == 2
    assert r.stderr.splitlines() == ["Usage: main convert [OPTIONS] INPUT",
                                     "Try 'main convert --help' for help.", "",
                                     f"Error: {message}"]


def test_node_id_is_the_commissioned_one(tmp_path):
    out = tmp_path / "x.xdc"
    assert run("convert", SMALL, "-o", out, "-n", "0x21", "-q").exit_code == 0
    assert '<deviceCommissioning nodeID="33"/>' in out.read_text()
    assert formats.load(str(out)).node_id == 33


def test_a_container_is_not_converted(tmp_path):
    r = run("convert", SAMPLES / "plc.bin", "-o", tmp_path / "x.xdd")
    assert r.exit_code == 1
    assert "not DCF/EDS text" in r.stderr or "binary container" in r.stderr


def test_the_input_is_never_overwritten(tmp_path):
    src = tmp_path / "small.eds"
    shutil.copy(SMALL, src)
    r = run("convert", src, "-o", src, "-f", "eds")
    assert r.exit_code == 2 and "is the input file" in r.stderr
    assert src.read_bytes() == SMALL.read_bytes()


OLD_PROFILE = ROOT.parent / "shared" / "corpus" / "xdd" / "canopeneditor" / "DS301_profile_old.xpd"


@pytest.mark.skipif(not OLD_PROFILE.is_file(), reason=f"corpus file not found: {OLD_PROFILE}")
def test_validates_findings_beyond_reading_do_not_stop_it(tmp_path):
    """The help's words: only reading errors stop convert. CANopenEditor's old DS301
    profile reads cleanly but has 4 DCF404 errors (a PDO mapping's sub 0 counts entries
    that map nothing): it is converted as written, and validate says the same of both."""
    src = OLD_PROFILE
    out = tmp_path / "x.eds"
    assert run("convert", src, "-o", out, "-q").exit_code == 0
    for path in (src, out):
        r = run("validate", path, "--select", "DCF404")
        assert r.exit_code == 1
        assert r.stdout.splitlines()[-1] == "4 errors, 0 warnings, 0 infos in 1 file"


def test_a_value_out_of_range_is_carried_as_written_and_validate_says_it_of_both(tmp_path):
    src = tmp_path / "bad.dcf"
    src.write_text("[2000]\nParameterName=x\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\n"
                   "ParameterValue=300\n")
    out = tmp_path / "bad.xdc"
    assert run("convert", src, "-o", out, "-q").exit_code == 0   # never truncated or guessed
    assert 'actualValue="300"' in out.read_text()
    for path in (src, out):
        r = run("validate", path, "--select", "DCF200")
        assert r.stdout.splitlines()[0].endswith(
            "error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) [DCF200]"), \
            r.stdout


UNREADABLE_FLAGS = """\
[1017]
ParameterName=Producer heartbeat time
ObjectType=0x7
DataType=0x0006
AccessType=rw
ObjFlags=none
DefaultValue=0

[2100]
ParameterName=Rec
ObjectType=0x9
SubNumber=2
ObjFlags=some

[2100sub0]
ParameterName=Count
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=1

[2100sub1]
ParameterName=V
ObjectType=0x7
DataType=0x0005
AccessType=rw
ObjFlags=x2
DefaultValue=0
"""


def test_an_objflags_that_is_no_number_is_written_as_it_is_never_as_0(tmp_path):
    """convert refuses such a file (DCF020, a reading error); the writers, called on its
    Device, keep each ObjFlags text as written -- before, the XDD writer wrote the
    object's as objFlags="0000" and dropped the VAR's, the EDS writer wrote the VAR's as
    ObjFlags=0x0: a number made up for a text that is none."""
    src = tmp_path / "flags.dcf"
    src.write_text(UNREADABLE_FLAGS)
    dev = formats.load(str(src))
    assert sorted({p.diagnostic.rule for p in dev.problems}) == ["DCF020"]
    xdd = formats.dump(dev, "xdd").data.decode()
    assert ('<CANopenObject index="1017" name="Producer heartbeat time" objectType="7" '
            'dataType="0006" accessType="rw" defaultValue="0" PDOmapping="no" '
            'objFlags="none"/>') in xdd
    assert '<CANopenObject index="2100" name="Rec" objectType="9" objFlags="some" ' \
           'subNumber="2">' in xdd
    assert ('<CANopenSubObject subIndex="01" name="V" objectType="7" dataType="0005" '
            'accessType="rw" defaultValue="0" PDOmapping="no" objFlags="x2"/>') in xdd
    eds = formats.dump(dev, "eds").data.decode()
    assert "\nAccessType=rw\nDefaultValue=0\nPDOMapping=0\nObjFlags=none\n" in eds
    assert "\nSubNumber=0x2\nObjFlags=some\n" in eds
    assert "[2100sub1]\nParameterName=V\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\n" \
           "DefaultValue=0\nPDOMapping=0\nObjFlags=x2\n" in eds
    assert "ObjFlags=0x" not in eds


NODE_0 = ("[DeviceComissioning]\nNodeID=0\n\n[2000]\nParameterName=x\nObjectType=0x7\n"
          "DataType=0x0005\nAccessType=rw\nDefaultValue=$NODEID+1\nParameterValue=7\n")


@pytest.mark.parametrize("suffix, written", [
    ("xdc", '<deviceCommissioning nodeID="5"/>'),
    ("dcf", "[DeviceComissioning]\nNodeID=5\n"),
])
def test_n_overrides_the_files_nodeid_as_compile_does(tmp_path, suffix, written):
    """The reviewer's repro 6: oresat's DCF says NodeID=0; compile -n 5 compiles it, and
    convert -n 5 stopped at DCF012 ("nothing written"). -n stands in for the file's NodeID
    in both; without -n both refuse the file alike."""
    src = tmp_path / "n0.dcf"
    src.write_text(NODE_0)
    out = tmp_path / f"x.{suffix}"
    assert run("compile", src, "-n", "5", "-o", tmp_path / "x.bin", "-q").exit_code == 0
    r = run("convert", src, "-n", "5", "-o", out)
    assert (r.exit_code, r.stderr) == (0, "")
    assert written in out.read_text()
    assert formats.load(str(out)).node_id == 5
    r = run("convert", src, "-o", tmp_path / "y.dcf")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}:2: error: NodeID 0 is outside 1..127 [DCF012]", f"{src}: 1 error, nothing written"]


SAMPLE_XDD = ROOT / "tests" / "fixtures" / "canopennode" / "sample.xdd"
LEFT_OUT = ("warning: 1 object marked CO_disabled left out (CANopenNode builds it into no "
            "object dictionary, and an EDS has no way to say so): 0x2002 [CNV004]")


@pytest.mark.parametrize("target, said", [("xdd", []), ("xdc", []),
                                          ("eds", [LEFT_OUT]), ("dcf", [LEFT_OUT])])
def test_the_co_disabled_objects_are_called_left_out_only_where_they_are(tmp_path, target,
                                                                          said):
    """The reviewer's finding: XDD -> XDD printed the reader's "... are left out" (XDD020)
    while every object was written. CiA 311 keeps them with their property: no word; CiA
    306 text leaves them out: its one warning, no second note."""
    out = tmp_path / f"x.{target}"
    r = run("convert", SAMPLE_XDD, "-o", out)
    assert r.exit_code == 0
    notes = [line.split(": ", 1)[1] for line in r.stderr.splitlines()
             if "CO_disabled" in line and not line.startswith("    hint")]
    assert notes == said
    disabled = 'index="2002"' in out.read_text()
    assert disabled == (target in ("xdd", "xdc"))
    if disabled:
        assert '<property name="CO_disabled" value="true"/>' in out.read_text()
    else:
        assert "[2002]" not in out.read_text()


def test_validate_still_says_the_reader_leaves_them_out():
    r = run("validate", SAMPLE_XDD, "--select", "XDD020")
    assert r.stdout.splitlines()[0] == (
        f"{SAMPLE_XDD}: info: 1 object marked CO_disabled (CANopenNode builds it into no "
        "object dictionary) is left out: 0x2002 [XDD020]")


# -- a string's bytes through DCF -> XDC -> DCF (issue 28: the values are kept) -----------------

STRING_DCF = ("[DeviceComissioning]\r\nNodeID=5\r\n[1000]\r\nParameterName=Device type\r\n"
              "DataType=0x0007\r\nAccessType=ro\r\nDefaultValue=0\r\n[2002]\r\n"
              "ParameterName=str\r\nDataType=0x0009\r\nAccessType=rw\r\nDefaultValue=x\r\n"
              "ParameterValue=caf\u00e9\r\n")


@pytest.mark.parametrize("encoding, declared, value", [
    ("latin-1", b'<?xml version="1.0" encoding="ISO-8859-1"?>', b"caf\xe9"),
    ("utf-8", b'<?xml version="1.0" encoding="UTF-8"?>', b"caf\xc3\xa9"),
])
def test_a_strings_bytes_survive_dcf_to_xdc_to_dcf(tmp_path, encoding, declared, value):
    """The reviewer's repro 3: a Latin-1 DCF's "caf\\xE9" (4 bytes) came back from an XDC
    as UTF-8's 5 bytes, without a word. A string's bytes are those that stood in the
    file: the XDC is written in the source's encoding and says so in its declaration, its
    reader takes the declared encoding, and the DCF written of it is in it again."""
    src, xdc, back = tmp_path / "t.dcf", tmp_path / "t.xdc", tmp_path / "rt.dcf"
    src.write_bytes(STRING_DCF.encode(encoding))
    for a, b in ((src, xdc), (xdc, back)):
        r = run("convert", a, "-o", b, "-q")
        assert (r.exit_code, r.stderr) == (0, "")
    assert xdc.read_bytes().startswith(declared + b"\n")
    assert b'actualValue="' + value + b'"' in xdc.read_bytes()
    assert b"\nParameterValue=" + value + b"\n" in back.read_bytes()
    bins = []
    for path in (src, xdc, back):
        out = tmp_path / f"{path.name}.bin"
        assert run("compile", path, "-o", out, "-q").exit_code == 0
        bins.append(out.read_bytes())
    assert bins[0] == bins[1] == bins[2]
    assert bins[0].count(value) == 1


def test_a_cia311_files_declared_encoding_is_its_strings_encoding():
    latin = (b'<?xml version="1.0" encoding="windows-1252"?>'
             + (XDD_FIX / "vendor_v10.xdc").read_bytes().split(b"?>", 1)[1])
    dev = load(latin, "xdc")
    assert dev.encoding == "cp1252"
    assert formats.dump(dev, "xdc").data.startswith(
        b'<?xml version="1.0" encoding="windows-1252"?>\n')
    for head, encoding in ((b'<?xml version="1.0" encoding="iso-8859-1"?>', "latin-1"),
                           (b"<?xml version='1.0' encoding='US-ASCII' ?>", "utf-8"),
                           (b'<?xml version="1.0"?>', "utf-8")):
        assert load(head + latin.split(b"?>", 1)[1], "xdc").encoding == encoding, head

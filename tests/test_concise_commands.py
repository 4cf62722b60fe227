"""Issue 27 item 4: the build's own files are readable by dcf2bin. A concise DCF (CiA 302-3,
SPEC §3.2: what ``network build`` writes for each slave) is a kind every command knows by
its content: dump shows it (text and lossless JSON), validate checks it (CON0xx), download
writes it in its order, bin2dcf turns it into a DCF, and the others name the command that
reads it. Every network fixture's build output validates without an error."""
from __future__ import annotations

import json
import pathlib

import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES

from dcf2bin import concise, filekind
from dcf2bin.cli import main


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def _u32(v: int) -> bytes:
    return v.to_bytes(4, "little")


# TPDO1's event timer changed as CiA 301 does it, the heartbeat, and a manufacturer entry of
# 3 bytes whose type only the device knows
IO = [(0x1800, 1, _u32(0x80000185)), (0x1800, 5, b"\x64\x00"), (0x1800, 1, _u32(0x185)),
      (0x1017, 0, b"\xC8\x00"), (0x2000, 1, b"\x01\x02\x03")]
IO_BYTES = bytes.fromhex(
    "05000000"                          # 5 entries
    "0018" "01" "04000000" "85010080"   # 0x1800sub1 = 0x80000185 (TPDO1 invalid)
    "0018" "05" "02000000" "6400"       # 0x1800sub5 = 100 ms
    "0018" "01" "04000000" "85010000"   # 0x1800sub1 = 0x185 (valid again)
    "1710" "00" "02000000" "C800"       # 0x1017sub0 = 200 ms
    "0020" "01" "03000000" "010203")    # 0x2000sub1, 3 bytes


@pytest.fixture
def io_bin(tmp_path):
    path = tmp_path / "io.bin"
    path.write_bytes(concise.to_bytes(IO))
    return path


def test_the_example_is_what_the_writer_writes():
    assert concise.to_bytes(IO) == IO_BYTES


# -- what it is ----------------------------------------------------------------------------------

GOLDEN = ROOT / "tests" / "golden" / "network" / "flat" / "out"


@pytest.mark.parametrize("name", ["drive.bin", "drive.dcf", "drive.eds", "drive", ""])
def test_known_by_its_content_whatever_its_name(name):
    data = (GOLDEN / "drive.bin").read_bytes()
    assert filekind.detect(data, name) == filekind.CONCISE
    assert filekind.detect(IO_BYTES, name) == filekind.CONCISE


@pytest.mark.parametrize("data,kind", [
    (b"\0\0\0\0", filekind.CONCISE),                    # an empty concise DCF
    (IO_BYTES[:-1], filekind.CONCISE),                  # cut short: CON002 names the byte
    (IO_BYTES + b"\0", filekind.CONCISE),               # a trailing byte: CON003
    (b"\x09" + IO_BYTES[1:], filekind.CONCISE),         # a count that disagrees: CON004
    (b"\x0C\0\0\0\x01\0\x01\0\x28\0\0\0", filekind.CONTAINER),   # a container cut short
    (b"\0\0\0", filekind.CONTAINER),                    # no count: by the name
    (b"\x01\0\0\0" + bytes(8), filekind.CONTAINER),     # index 0 is no object: by the name
])
def test_the_files_that_could_be_either(data, kind):
    """A container's first DWORD is its size, a concise DCF's the number of its entries
    (each 7 bytes or more): a whole one of each is never the other. The damaged ones go by
    their first entry, else by the name (.bin: a container)."""
    assert filekind.detect(data, "x.bin") == kind


def test_the_json_form_is_its_own_kind():
    text = run("dump", "-f", "json", GOLDEN / "drive.bin").stdout_bytes
    assert filekind.detect(text, "x.json") == filekind.CONCISE_JSON
    assert filekind.detect(text, "x.bin") == filekind.CONCISE_JSON


def test_bin_is_its_name_and_another_name_is_a_warning(io_bin, tmp_path):
    assert filekind.misnamed(str(io_bin), filekind.CONCISE) is None
    named = tmp_path / "io.dcf"
    named.write_bytes(IO_BYTES)
    r = run("dump", named)
    assert r.exit_code == 0
    assert r.stderr == (f"{named}: warning: {named} is a concise DCF (CiA 302-3), not DCF/EDS "
                        "text as its name says; read as a concise DCF (CiA 302-3)\n")


WORDS = ("use dcf2bin dump to read it (dcf2bin validate checks it, download writes it to a "
         "node, bin2dcf turns it into a DCF)")


@pytest.mark.parametrize("args,wanted", [
    (["simulate"], "a binary container or DCF/EDS text or its JSON form"),
    (["map"], "DCF/EDS text or a binary container or its JSON form"),
    (["compile", "-o", "-"], "DCF/EDS text or its JSON form"),
    (["export", "-f", "lenze-st", "-n", "2"], "DCF/EDS text"),
    (["node", "-n", "3", "-i", "virtual", "--duration", "0"], "DCF/EDS text"),
])
def test_every_other_command_names_the_ones_that_read_it(io_bin, args, wanted):
    r = run(*args[:1], io_bin, *args[1:])
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == f"{io_bin}: error: {io_bin} is a concise DCF (CiA 302-3), not {wanted}; " \
                       f"{WORDS}\n"


# -- dump ----------------------------------------------------------------------------------------

IO_REPORT = """\
{name}: concise DCF (CiA 302-3), 54 bytes, 5 entries
A type ending in ? is guessed from the size alone (--eds gives the device's types).

  #  offset  index   sub  size  data      type         value                               write
  1  0x4     0x1800    1     4  85010080  UNSIGNED32   0x80000185 = COB-ID 0x185, invalid  1/2
  2  0xF     0x1800    5     2  6400      UNSIGNED16   100
  3  0x18    0x1800    1     4  85010000  UNSIGNED32   0x00000185 = COB-ID 0x185           2/2
  4  0x23    0x1017    0     2  C800      UNSIGNED16   200
  5  0x2C    0x2000    1     3  010203    UNSIGNED24?  0x030201
"""


def test_dump_shows_every_entry_in_its_order(io_bin):
    r = run("dump", io_bin)
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == IO_REPORT.format(name=io_bin)


def _eds(tmp_path, body: str) -> pathlib.Path:
    path = tmp_path / "device.eds"
    path.write_text("[1017]\nParameterName=Producer heartbeat time\nObjectType=0x7\n"
                    "DataType=0x0006\nAccessType=rw\nDefaultValue=0\n\n" + body)
    return path


INTEGER24 = ("[2000]\nParameterName=Position\nObjectType=0x9\nSubNumber=2\n\n"
             "[2000sub0]\nParameterName=Count\nObjectType=0x7\nDataType=0x0005\n"
             "AccessType=ro\nDefaultValue=1\n\n"
             "[2000sub1]\nParameterName=Offset\nObjectType=0x7\nDataType=0x0010\n"
             "AccessType=rw\nDefaultValue=0\n")


def test_dump_with_the_eds_decodes_its_types_and_names(io_bin, tmp_path):
    eds = _eds(tmp_path, INTEGER24)
    r = run("dump", io_bin, "--eds", eds)
    assert r.exit_code == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[1] == (f"Types and names from {eds}; a type ending in ? is guessed from the "
                        "size alone.")
    assert lines[3].split() == ["#", "offset", "index", "sub", "size", "data", "type", "value",
                                "write", "name"]
    # INTEGER24 0x030201 = 197121; the heartbeat's name from the EDS
    assert lines[7].split() == ["4", "0x23", "0x1017", "0", "2", "C800", "UNSIGNED16", "200",
                                "Producer", "heartbeat", "time"]
    assert lines[8].split() == ["5", "0x2C", "0x2000", "1", "3", "010203", "INTEGER24",
                                "197121", "Offset"]
    # the EDS has no TPDO1: said once an entry, below the table
    assert lines[9:] == ["", f"  ! 0x1800sub1: {eds} has no such entry",
                         f"  ! 0x1800sub5: {eds} has no such entry"]


def test_dump_says_where_the_eds_disagrees(io_bin, tmp_path):
    eds = _eds(tmp_path, INTEGER24.replace("DataType=0x0010", "DataType=0x0007"))
    r = run("dump", io_bin, "--eds", eds)
    assert r.stdout.splitlines()[-1] == (f"  ! 0x2000sub1: 3 data bytes, {eds} gives UNSIGNED32 "
                                         "(4 bytes)")
    assert "UNSIGNED24?" in r.stdout


def test_dump_of_an_empty_one(tmp_path):
    path = tmp_path / "none.bin"
    path.write_bytes(b"\0\0\0\0")
    r = run("dump", path)
    assert r.stdout == (f"{path}: concise DCF (CiA 302-3), 4 bytes, 0 entries\n"
                        "A type ending in ? is guessed from the size alone (--eds gives the "
                        "device's types).\n\nNo entries: the file configures nothing.\n")
    assert run("dump", "-f", "json", path).stdout == (
        '{\n  "format": "dcf2bin-concise",\n  "version": 1,\n  "entries": []\n}\n')


@pytest.mark.parametrize("data,message", [
    (IO_BYTES[:-1], "0x2F: error: entry 5 of 5 (0x2000sub1) claims 3 data bytes, 2 remain "
                    "[CON002]"),
    (IO_BYTES + b"\0", "0x36: error: 1 byte after the last of 5 entries [CON003]"),
    (b"\x09" + IO_BYTES[1:], "0x0: error: the count says 9 entries, but 5 entries fill the "
                             "file exactly [CON004]"),
])
def test_a_damaged_one_is_one_line_naming_its_byte(tmp_path, data, message):
    path = tmp_path / "s.bin"
    path.write_bytes(data)
    for args in (["dump"], ["dump", "-f", "json"], ["bin2dcf", "-o", "-"],
                 ["download", "-n", "5", "--dry-run"]):
        r = run(*args[:1], path, *args[1:])
        assert (r.exit_code, r.stdout, r.stderr) == (1, "", f"{path}:{message}\n"), args


IO_JSON = """\
{
  "format": "dcf2bin-concise",
  "version": 1,
  "entries": [
    {"index": "0x1800", "subindex": 1, "data": "85010080"},
    {"index": "0x1800", "subindex": 5, "data": "6400"},
    {"index": "0x1800", "subindex": 1, "data": "85010000"},
    {"index": "0x1017", "subindex": 0, "data": "C800"},
    {"index": "0x2000", "subindex": 1, "data": "010203"}
  ]
}
"""


def test_the_json_form_is_lossless(io_bin, tmp_path):
    r = run("dump", "-f", "json", io_bin)
    assert (r.exit_code, r.stdout, r.stderr) == (0, IO_JSON, "")
    back = tmp_path / "back.json"
    back.write_text(r.stdout)
    r = run("compile", back, "-o", tmp_path / "again.bin")
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "again.bin").read_bytes() == IO_BYTES


@pytest.mark.parametrize("name", sorted(p.name for p in GOLDEN.glob("*.bin")))
def test_every_built_file_goes_through_its_json_form(tmp_path, name):
    data = (GOLDEN / name).read_bytes()
    back = tmp_path / "x.json"
    back.write_text(run("dump", "-f", "json", GOLDEN / name).stdout)
    assert run("compile", back, "-o", "-").stdout_bytes == data


def test_the_json_form_matches_its_schema(io_bin):
    jsonschema = pytest.importorskip("jsonschema")
    from dcf2bin import schemas
    doc = json.loads(run("dump", "-f", "json", io_bin).stdout)
    jsonschema.validate(doc, schemas.load("dump-concise"))
    doc["entries"][0]["attribute"] = "0x70"         # a container's key: not this form
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(doc, schemas.load("dump-concise"))


@pytest.mark.parametrize("edit,line,message", [
    (lambda t: t.replace('"version": 1', '"version": 2'), 3,
     "version: schema version 2 is not supported; this dcf2bin reads version 1 (written by a "
     "newer dcf2bin?)"),
    (lambda t: t.replace('"data": "C800"', '"data": "C80"'), 8,
     "entries[3].data: odd number of hex digits (3)"),
    (lambda t: t.replace('"subindex": 5', '"subindex": 256'), 6,
     "entries[1].subindex: 256 is outside 0..255"),
    (lambda t: t.replace('"data": "6400"}', '"data": "6400", "attribute": "0x70"}'), 6,
     "entries[1].attribute: unknown key 'attribute' (expected one of index, subindex, data)"),
])
def test_a_wrong_json_form_names_its_line(tmp_path, edit, line, message):
    path = tmp_path / "x.json"
    path.write_text(edit(IO_JSON))
    r = run("compile", path, "-o", tmp_path / "x.bin")
    assert (r.exit_code, r.stderr) == (1, f"{path}:{line}: error: {message} [JSN002]\n")
    assert not (tmp_path / "x.bin").exists()


# -- validate ------------------------------------------------------------------------------------

def _concise(tmp_path, name: str, entries) -> pathlib.Path:
    path = tmp_path / name
    path.write_bytes(concise.to_bytes(entries))
    return path


def test_validate_a_clean_one(io_bin):
    r = run("validate", io_bin)
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 1 file\n")


def test_validate_replays_the_pdo_reconfiguration(tmp_path):
    """CiA 301: a mapping, inhibit time or CAN-ID changes only while the PDO is invalid,
    mapping entries only while sub 0 is 0. After the file made the PDO valid: errors;
    before it made it invalid: warnings (the node's state decides)."""
    path = _concise(tmp_path, "s.bin", [
        (0x1A00, 0, b"\x00"),                   # 1: before any COB-ID: warning
        (0x1800, 1, _u32(0x181)),               # 2: valid, never invalid: warning
        (0x1A00, 1, _u32(0x60410010)),          # 3: the mapping of a valid TPDO: error
        (0x1800, 3, b"\x0A\x00"),               # 4: its inhibit time too: error
        (0x1800, 1, _u32(0x182)),               # 5: another CAN-ID while valid: error
        (0x1801, 1, _u32(0x80000281)),          # 6: TPDO2 invalid: fine
        (0x1A01, 0, b"\x02"),                   # 7: sub 0 = 2 ...
        (0x1A01, 1, _u32(0x60640020)),          # 8: ... then an entry: error
    ])
    at = concise.offsets(concise.parse(path.read_bytes()))
    r = run("validate", path)
    assert r.exit_code == 1
    assert r.stdout == (
        f"{path}:0x{at[0]:X}: warning: 0x1A00sub0 changes TPDO1's mapping, but the file has "
        "not made TPDO1 invalid before (0x1800sub1 with bit 31 set): a node whose TPDO1 is "
        "valid refuses it [CON011]\n"
        f"{path}:0x{at[1]:X}: warning: 0x1800sub1 = 0x00000181 sets TPDO1's COB-ID, but the "
        "file has not made TPDO1 invalid before (0x1800sub1 with bit 31 set): a node whose "
        "TPDO1 is valid with another one refuses it [CON011]\n"
        f"{path}:0x{at[2]:X}: error: 0x1A00sub1 changes TPDO1's mapping while TPDO1 is valid "
        "(entry 2, 0x1800sub1 = 0x00000181) [CON010]\n"
        f"{path}:0x{at[3]:X}: error: 0x1800sub3 changes TPDO1's inhibit time while TPDO1 is "
        "valid (entry 2, 0x1800sub1 = 0x00000181) [CON010]\n"
        f"{path}:0x{at[4]:X}: error: 0x1800sub1 = 0x00000182 changes TPDO1's COB-ID while "
        "TPDO1 is valid (entry 2, 0x1800sub1 = 0x00000181) [CON010]\n"
        f"{path}:0x{at[7]:X}: error: 0x1A01sub1 is written while 0x1A01sub0 is 2 (entry 7); "
        "CiA 301 writes a mapping's entries while its sub 0 is 0 [CON012]\n"
        "4 errors, 2 warnings, 0 infos in 1 file\n")


def test_validate_compares_with_the_dcf_beside_it_or_eds(io_bin, tmp_path):
    """drive.bin is checked against drive.dcf beside it, as network build writes them;
    --eds names the description for every concise DCF given."""
    wrong = [(0x1017, 0, b"\xC8\x00\x00\x00"), (0x1018, 1, _u32(7)), (0x2001, 0, b"\x01"),
             (0x2000, 2, b"\x01")]
    path = _concise(tmp_path, "drive.bin", wrong)
    at = concise.offsets(wrong)
    eds = _eds(tmp_path, INTEGER24 + "\n[1018]\nParameterName=Identity\nObjectType=0x9\n"
               "SubNumber=2\n\n[1018sub0]\nParameterName=n\nObjectType=0x7\nDataType=0x0005\n"
               "AccessType=ro\nDefaultValue=1\n\n[1018sub1]\nParameterName=Vendor-ID\n"
               "ObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=1\n")
    findings = (
        f"{path}:0x{at[0]:X}: error: 0x1017sub0: 4 bytes, {{eds}} gives UNSIGNED16 (2 bytes) "
        "[CON020]\n"
        f"{path}:0x{at[1]:X}: error: 0x1018sub1: {{eds}} gives AccessType=ro [CON022]\n"
        f"{path}:0x{at[2]:X}: warning: 0x2001sub0: {{eds}} has no object 0x2001 [CON021]\n"
        f"{path}:0x{at[3]:X}: warning: 0x2000sub2: {{eds}} has no such sub-index [CON021]\n"
        "2 errors, 2 warnings, 0 infos in 1 file\n")
    r = run("validate", path, "--eds", eds)
    assert (r.exit_code, r.stdout) == (1, findings.format(eds=eds))
    r = run("validate", path)           # no description: only the structure and the PDOs
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 1 file\n")
    eds.rename(tmp_path / "drive.dcf")
    r = run("validate", path)
    assert (r.exit_code, r.stdout) == (1, findings.format(eds="drive.dcf"))


def test_validate_eds_must_be_a_description(io_bin):
    r = run("validate", io_bin, "--eds", io_bin)
    assert r.exit_code == 1
    assert r.stderr == (f"{io_bin}: error: {io_bin} is a concise DCF (CiA 302-3), not DCF/EDS "
                        f"text; --eds takes the device's EDS or DCF\n")


def test_validate_infos(tmp_path):
    twice = _concise(tmp_path, "twice.bin", [(0x1017, 0, b"\x64\x00"), (0x6060, 0, b"\x08"),
                                             (0x1017, 0, b"\xC8\x00")])
    empty = _concise(tmp_path, "empty.bin", [])
    r = run("validate", twice, empty)
    assert (r.exit_code, r.stdout) == (0, (
        f"{twice}:0x4: info: 0x1017sub0 is written 2 times (entries 1, 3); the node keeps the "
        "last, C800 [CON030]\n"
        f"{empty}:0x0: info: no entries: the file configures nothing [CON031]\n"
        "0 errors, 0 warnings, 2 infos in 2 files\n"))


def test_validate_the_json_form_names_compile(tmp_path, io_bin):
    path = tmp_path / "io.json"
    path.write_text(run("dump", "-f", "json", io_bin).stdout)
    r = run("validate", path)
    assert (r.exit_code, r.stdout.splitlines()[0]) == (1, (
        f"{path}: error: {path} is the JSON form of a concise DCF, not DCF/EDS text or a "
        "binary container; dcf2bin compile turns it back into the concise DCF, which validate "
        "checks [DCF008]"))


# every network of the tests, in the mode its master asks for and, for a PLC, as a lely master
NETWORKS = sorted({*ROOT.glob("tests/fixtures/network/lely/*.yml"),
                   *ROOT.glob("tests/fixtures/network/*.yml"),
                   *ROOT.glob("tests/fixtures/network/check/*.yml"),
                   *ROOT.glob("tests/fixtures/network_show/*.yml"),
                   *ROOT.glob("tests/fixtures/network_corpus/*.yml"),
                   *ROOT.glob("tests/golden/network/*/bus.yml")})
CORPUS = ROOT.parent / "shared" / "corpus"
# networks whose own input files have errors, which the built .dcf files carry
INPUT_ERRORS = {
    "flat_controlword.yml": "its PLC DCF maps RTR-only RPDOs (DCF414), a vendor EDS maps an "
                            "object it does not call mappable (DCF405, TGT078) and has a "
                            "LowLimit above its HighLimit (DCF211)",
    "vendor_zero_entry.yml": "the C20 EDS gives 0x1600/0x1A00 no DataType and AccessType "
                             "(DCF031, DCF033)",
    "dcfgen_wrong.yml": "node_canopen's test.eds declares 0x201C-0x201F with DataTypes "
                        "0x0020-0x0023, which CiA 301 does not define (DCF030)",
}


def _networks():
    out = []
    for path in NETWORKS:
        needs_corpus = "shared/corpus" in path.read_text() or "network_corpus" in str(path)
        marks = pytest.mark.skip(reason=f"corpus not found at {CORPUS}") \
            if needs_corpus and not CORPUS.is_dir() else ()
        rel = path.relative_to(ROOT)
        out.append(pytest.param(path, None, id=str(rel), marks=marks))
        if "dcf:" in path.read_text().split("master:", 1)[-1].split("\n\n", 1)[0]:
            out.append(pytest.param(path, "lely", id=f"{rel}-as-lely", marks=marks))
    return out


@pytest.mark.parametrize("network,master", _networks())
def test_every_network_build_validates(tmp_path, network, master):
    from dcf2bin.lint import Options, run as lint
    from dcf2bin.network.build import build_network
    res = build_network(str(network), str(tmp_path), master=master)
    assert res.ok, [str(d) for d in res.diagnostics]
    bins = sorted(tmp_path.glob("*.bin"))
    assert bins and all(filekind.detect(p.read_bytes(), p.name) == filekind.CONCISE
                        for p in bins)
    if res.mode == "lely" and (tmp_path / "master.bin").exists():
        assert "master.bin" in [p.name for p in bins]
    result = lint([str(tmp_path)], Options())
    concise_findings = [d.format() for d in result.diagnostics if d.file.endswith(".bin")
                        and d.rule != "CON031"]     # a slave the build configures nothing on
    assert concise_findings == []
    errors = [d.format() for d in result.diagnostics if d.severity.value == "error"]
    if network.name in INPUT_ERRORS:
        # the slaves' DCFs (written for a PLC and for a lely master alike) carry their
        # files' errors; nothing else may be left
        assert errors and all(e.split(":")[0].endswith(".dcf") for e in errors)
    else:
        assert errors == []
    # the PLC mode's slaves are checked against the .dcf written beside each
    for p in bins:
        if (tmp_path / (p.stem + ".dcf")).exists() and p.stem != "master":
            from dcf2bin.lint.context import ConciseContext
            ctx = ConciseContext(str(p), p.read_bytes(), Options())
            assert ctx.eds is not None and ctx.eds_name == p.stem + ".dcf"


# -- download ------------------------------------------------------------------------------------

def test_download_dry_run_in_its_order(io_bin):
    r = run("download", io_bin, "-n", "5", "--dry-run")
    assert (r.exit_code, r.stderr) == (0, "")
    w = len(f"{io_bin}:0x18")
    assert r.stdout == (
        f"{io_bin}: 5 SDO writes to node 5 (dry run, nothing sent)\n"
        f"   #  entry       size  {'source':<{w}}  data\n"
        f"   1  0x1800sub1     4  {f'{io_bin}:0x4':<{w}}  85 01 00 80\n"
        f"   2  0x1800sub5     2  {f'{io_bin}:0xF':<{w}}  64 00\n"
        f"   3  0x1800sub1     4  {f'{io_bin}:0x18':<{w}}  85 01 00 00\n"
        f"   4  0x1017sub0     2  {f'{io_bin}:0x23':<{w}}  C8 00\n"
        f"   5  0x2000sub1     3  {f'{io_bin}:0x2C':<{w}}  01 02 03\n")


def test_download_the_json_form_names_its_lines(io_bin, tmp_path):
    path = tmp_path / "io.json"
    path.write_text(run("dump", "-f", "json", io_bin).stdout)
    lines = run("download", path, "-n", "5", "--dry-run").stdout.splitlines()
    assert [line.split()[3] for line in lines[2:]] == [f"{path}:{n}" for n in range(5, 10)]


def test_download_to_the_configuration_manager_sends_the_file(io_bin):
    r = run("download", io_bin, "-n", "5", "--concise-dcf-to", "1", "--dry-run")
    assert r.stdout.splitlines()[2] == (f"   1  0x1F22sub5    54  {io_bin}  "
                                        + IO_BYTES[:32].hex(" ").upper() + " ... (54 bytes)")


def test_download_forced_reads_a_short_file_as_one(tmp_path):
    path = tmp_path / "s.bin"
    path.write_bytes(b"\x01\0")
    r = run("download", path, "-n", "5", "--dry-run", "--from", "concise")
    assert (r.exit_code, r.stderr) == (1, f"{path}:0x0: error: 2 bytes: too short for the "
                                          "entry count (a DWORD) [CON001]\n")


pytest_plugins = ["bus_fixtures"]


def test_download_writes_each_entry_in_order_and_reads_back(bench, tmp_path, at_root):
    """The index segment of the device's container as a concise DCF: the node sees every
    write in the file's order (the PDO sequence included) and reads back each value."""
    from bus_helpers import bus_args
    from dcf2bin.compiler import CompileOptions, compile_path
    entries = compile_path(str(SAMPLES / "device.dcf"), CompileOptions(node_id=3)).container.entries
    path = _concise(tmp_path, "device.bin", entries)
    node = bench.device()
    seen = []
    node.add_write_callback(lambda index, subindex, od, data: seen.append(
        (index, subindex, bytes(data))))
    r = run("download", path, "-n", "3", "--verify", *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == f"{path}: 15 entries written to node 3, read back equal\n"
    assert seen == entries


# -- bin2dcf -------------------------------------------------------------------------------------

def test_bin2dcf_writes_the_last_values_and_the_earlier_as_comments(io_bin, tmp_path):
    r = run("bin2dcf", io_bin)
    assert (r.exit_code, r.stderr) == (0, "")
    text = (tmp_path / "io.dcf").read_text()
    assert text.startswith(
        f"; DCF written by dcf2bin bin2dcf from {io_bin} (a concise DCF, 54 bytes, 5 entries).\n"
        "; ParameterValue is the last value written to each entry; comments list earlier "
        "writes.\n"
        "; A DCF keeps no order of writes: dcf2bin dump lists the concise DCF's, and types "
        "without --eds are CiA 301's or guessed from the size.\n")
    assert f"Description=Converted from the concise DCF {io_bin}\n" in text
    assert ("[1800sub1]\nParameterName=COB-ID\nObjectType=0x7\n"
            "; entry 1 (offset 0x4) wrote 0x80000185\n"
            "; entry 3 (offset 0x18) wrote the ParameterValue below\n"
            "DataType=0x0007\nAccessType=rw\nPDOMapping=0\nParameterValue=0x00000185\n") in text
    assert ("[1800sub5]\nParameterName=Event timer\nObjectType=0x7\nDataType=0x0006\n"
            "AccessType=rw\nPDOMapping=0\nParameterValue=0x0064\n") in text
    assert ("[1017]\nParameterName=Producer heartbeat time\nObjectType=0x7\nDataType=0x0006\n"
            "AccessType=rw\nPDOMapping=0\nParameterValue=0x00C8\n") in text
    assert ("[2000sub1]\nParameterName=Sub-index 1\nObjectType=0x7\n"
            "; DataType guessed from the size alone (--eds gives the device's)\n"
            "DataType=0x0016\nAccessType=rw\nPDOMapping=0\nParameterValue=0x030201\n") in text
    # TPDO1's mapping object, which the file does not write, is there without a value
    assert ("[1A00]\n; not in the concise DCF: the mapping object of the PDO that 0x1800 "
            "configures (ObjFlags=0x1: compile skips it)\nParameterName=TPDO1 mapping "
            "parameter\nObjectType=0x9\nObjFlags=0x1\nSubNumber=1\n\n[1A00sub0]\n"
            "ParameterName=Number of mapped objects\nObjectType=0x7\nDataType=0x0005\n"
            "AccessType=rw\nPDOMapping=0\n") in text
    r = run("validate", tmp_path / "io.dcf")
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 1 file\n")


def test_bin2dcf_takes_the_types_from_the_eds(io_bin, tmp_path):
    eds = _eds(tmp_path, INTEGER24)
    r = run("bin2dcf", io_bin, "--eds", eds, "-o", "-")
    assert r.exit_code == 0, r.stderr
    assert ("[2000sub1]\nParameterName=Offset\nObjectType=0x7\nDataType=0x0010\n"
            "AccessType=rw\nPDOMapping=0\nParameterValue=197121\n") in r.stdout


def test_bin2dcf_strict_is_for_containers(io_bin):
    r = run("bin2dcf", io_bin, "--strict", "-o", "-")
    assert (r.exit_code, r.stdout) == (2, "")
    assert r.stderr == (f"{io_bin}: error: {io_bin} is a concise DCF: --strict checks that "
                        "compile gives a container's bytes back, and a DCF keeps no order of a "
                        "concise DCF's writes; convert it without --strict\n")


@pytest.mark.parametrize("name", sorted(p.name for p in GOLDEN.glob("*.bin")))
def test_bin2dcf_of_every_built_file_validates(tmp_path, name):
    out = tmp_path / "x.dcf"
    r = run("bin2dcf", GOLDEN / name, "-o", out, "--eds", GOLDEN / (name[:-4] + ".dcf"))
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("validate", out)
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 1 file\n")

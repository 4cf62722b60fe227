"""Issue 28 item 4: CANopenNode v4's object dictionary, ``export --format canopennode``
(OD.h and OD.c; docs/export.md).

No code of CANopenNode is in this project: the generated files are compiled with the C
compiler (``-Wall -Wextra -pedantic -Werror``) against tests/fixtures/canopennode/301/
CO_ODinterface.h, a stand-in written from CANopenNode's documentation of the interface,
and linked with walk.c there, which reads every entry of ``OD->list`` as the interface
does and prints each sub-object's attribute bits, length and data bytes. That listing is
compared with one derived here again from the model (attributes, lengths and values worked
out in this file, not taken from dcf2bin.export.canopennode). The goldens under
tests/fixtures/canopennode/golden/ were read line by line against sample.eds/sample.xdd.
"""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest
from click.testing import CliRunner
from conftest import ROOT
from test_export_markdown import EXAMPLE, needs_example, parse_canopeneditor

from dcf2bin import datatypes as dt, formats, values
from dcf2bin.cli import main
from dcf2bin.export import canopennode, run

FIX = ROOT / "tests" / "fixtures" / "canopennode"
GOLDEN = FIX / "golden"
CC = shutil.which("gcc") or shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (gcc or cc) found on PATH")
FLAGS = ["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror"]


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def export(path, **options) -> dict:
    r = run("canopennode", str(path), **options)
    assert r.ok, [d.format() for d in r.diagnostics]
    return r.output


# -- goldens and the command ------------------------------------------------------------------

@pytest.mark.parametrize("sample", ["eds", "xdd"])
def test_golden_files(sample, tmp_path):
    r = cli("export", "-q", "-f", "canopennode", FIX / f"sample.{sample}", "-o", tmp_path / "od")
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    assert sorted(p.name for p in (tmp_path / "od").iterdir()) == ["OD.c", "OD.h"]
    for name in ("OD.h", "OD.c"):
        assert (tmp_path / "od" / name).read_text() == (GOLDEN / sample / name).read_text()


def test_two_runs_write_the_same_bytes():
    assert export(FIX / "sample.eds") == export(FIX / "sample.eds")


def test_without_a_folder_it_is_a_usage_error_before_anything_is_read(tmp_path):
    r = cli("export", "-f", "canopennode", tmp_path / "missing.eds")
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == ("Error: --format canopennode writes two files, OD.h "
                                         "and OD.c: give the folder with -o FOLDER")


def test_a_file_where_the_folder_should_be_is_exit_3(tmp_path):
    f = tmp_path / "od"
    f.write_text("x")
    r = cli("export", "-f", "canopennode", FIX / "sample.eds", "-o", f)
    assert r.exit_code == 3
    assert r.stderr == f"{f}: error: cannot write: Not a directory\n"
    assert f.read_text() == "x"


def test_od_name_names_the_files_and_every_c_name(tmp_path):
    r = cli("export", "-q", "-f", "canopennode", FIX / "sample.xdd", "-o", tmp_path,
            "--od-name", "ODdrive")
    assert r.exit_code == 0, r.stderr
    h = (tmp_path / "ODdrive.h").read_text()
    c = (tmp_path / "ODdrive.c").read_text()
    assert "#define ODdrive_CNT_NMT 1" in h and "extern ODdrive_ATTR_OD OD_t *ODdrive;" in h
    assert "#define ODdrive_ENTRY_H1018_identity (&ODdrive->list[3])" in h
    assert '#include "ODdrive.h"' in c and "OD_t *ODdrive = &ODdriveDictionary;" in c
    assert re.findall(r"\bOD_(?:RAM|PERSIST|ENTRY|CNT)", h + c) == []


@pytest.mark.parametrize("value", ["1OD", "O-D", ""])
def test_od_name_is_a_c_name(value):
    r = cli("export", "-f", "canopennode", FIX / "sample.eds", "-o", "x", "--od-name", value)
    assert r.exit_code == 2
    assert f"'{value}' is not a C identifier" in r.stderr


@pytest.mark.parametrize("opt", [["-n", "5"], ["--allow-external-files"], ["--symbol", "x"]])
def test_options_of_other_formats_are_refused(opt, tmp_path):
    r = cli("export", "-f", "canopennode", FIX / "sample.eds", "-o", tmp_path / "o", *opt)
    assert r.exit_code == 2
    assert not (tmp_path / "o").exists()


# -- names ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("name, c", [
    ("Device type", "deviceType"), ("COB-ID SYNC message", "COB_ID_SYNCMessage"),
    ("Highest sub-index supported", "highestSub_indexSupported"), ("Vendor-ID", "vendor_ID"),
    ("Pre-defined error field", "pre_definedErrorField"),
    ("Node-ID of the SDO server", "node_IDOfTheSDOServer"), ("SYNC start value", "SYNCStartValue"),
    ("COB-ID client to server (tx)", "COB_IDClientToServerTx"),
    ("Application object 1", "applicationObject1"), ("Read input 8-bit", "readInput8_bit"),
    ("1st value", "_1stValue"), ("x", "x"), ("A", "a"), ("", ""), ("--", "__"),
    ("Temperatur Kühler", "temperaturKHler")])
def test_c_names_follow_canopennodes_rule(name, c):
    assert canopennode.cname(name) == c


# -- the files compile and hold what the description says -------------------------------------

def build(files: dict, tmp_path, *more: str) -> list[str]:
    """Compile the files (-c, the flags above) and link them with walk.c; walk's lines."""
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    objs = []
    for src in [n for n in files if n.endswith(".c")]:
        obj = tmp_path / (src + ".o")
        done = subprocess.run([CC, *FLAGS, *more, "-I", str(FIX), "-I", str(tmp_path), "-c",
                               str(tmp_path / src), "-o", str(obj)], capture_output=True,
                              text=True)
        assert done.returncode == 0, done.stderr[:3000]
        objs.append(str(obj))
    exe = tmp_path / "walk"
    done = subprocess.run([CC, *FLAGS, "-I", str(FIX), "-I", str(tmp_path), "-o", str(exe),
                           str(FIX / "walk.c"), *objs], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[:3000]
    walked = subprocess.run([str(exe)], capture_output=True, text=True, timeout=20)
    assert walked.returncode == 0
    return walked.stdout.splitlines()


def stated(path, dev) -> dict:
    """CANopenNode's settings as the file states them, read here again: (index, sub or
    None) -> {name: value}."""
    if path.suffix != ".eds":
        return dev.specifics
    out: dict = {}
    key = None
    for line in path.read_text().splitlines():
        m = re.fullmatch(r"\[([0-9A-Fa-f]{4})(?:sub([0-9A-Fa-f]+))?\]", line.strip())
        if m:
            key = (int(m.group(1), 16), int(m.group(2), 16) if m.group(2) else None)
        elif key and (m := re.fullmatch(r";(CO_\w+)=(.*)", line.strip())):
            out.setdefault(key, {})[m.group(1)] = m.group(2)
    return out


def expected_walk(path, dev) -> list[str]:
    """What walk prints, worked out from the model: SDO bits 1/2/3 by access, PDO bits
    4 (into a TPDO), 8 (from an RPDO) by PDOmapping TPDO/RPDO or by access, SRDO 0x10/0x20, 0x40
    for numbers of 2 bytes and more, 0x80 for strings; the value's bytes ($NODEID as 0),
    '-' where the description gives none."""
    says = stated(path, dev)
    objs = [o for o in dev.sorted_objects() if o.index >= 0x1000]
    lines = [f"size={len(objs)}"]
    for o in objs:
        kind = "VAR" if not o.complex else ("ARR" if o.object_type == dt.OT_ARRAY else "REC")
        entries = o.sorted_entries()
        lines.append(f"{o.index:04X} n={len(entries)} {kind}")
        elements_given = kind == "ARR" and bool(_text(entries[1]))
        for e in entries:
            s = says.get((o.index, e.sub if o.complex else None), {})
            attr = {"ro": 1, "const": 1, "wo": 2, "rw": 3, "rwr": 3, "rww": 3}[e.access]
            word = s.get("PDOmapping")
            if word in ("TPDO", "RPDO"):
                attr |= {"TPDO": 4, "RPDO": 8}[word]
            elif e.pdo_mapping:         # PDOMapping=1, optional, default: by the access
                attr |= {"ro": 4, "const": 4, "rwr": 4, "wo": 8, "rww": 8, "rw": 12}[e.access]
            attr |= {"tx": 0x10, "rx": 0x20, "trx": 0x30}.get(s.get("CO_accessSRDO"), 0)
            t = e.dtype
            if t.is_numeric and t.size >= 2 and t.size in (2, 4, 8) and "TIME" not in t.name:
                attr |= 0x40
            if t.name in ("VISIBLE_STRING", "UNICODE_STRING"):
                attr |= 0x80
            text = _text(e)
            data = values.encode(t, text, node_id=0) if text else b""
            least = int(s.get("CO_stringLengthMin", 0))
            if t.name == "UNICODE_STRING":
                length = 2 * max(len(data) // 2, least)
            elif t.size is None:
                length = 0 if t.name == "DOMAIN" else max(len(data), least)
            else:
                length = t.size
            if kind == "ARR" and e.sub:
                given = elements_given
            elif t.name == "DOMAIN":
                given = False
            else:
                given = length > 0 if t.size is None else bool(text)
            shown = (data + bytes(length)).hex().upper()[:2 * length] if given else "-"
            lines.append(f"  {e.sub:02X} attr=0x{attr:02X} len={length} data={shown}")
    lines.append("0000 n=0 ?")
    return lines


def _text(e) -> str:
    if e.param is not None:
        return e.param
    return e.section.values.get("defaultvalue", "") if e.section is not None else e.default or ""


@needs_cc
@pytest.mark.parametrize("sample", ["sample.eds", "sample.xdd"])
def test_the_walked_od_is_the_description(sample, tmp_path):
    path = FIX / sample
    assert build(export(path), tmp_path) == expected_walk(path, formats.load(str(path)))


@needs_cc
def test_two_object_dictionaries_link_into_one_program_with_their_configuration(tmp_path):
    """--od-name keeps every C name apart; OD_INIT_CONFIG fills CANopenNode's CO_config_t
    (the stand-in's) for a CO_MULTIPLE_OD build."""
    files = {**export(FIX / "sample.eds"), **export(FIX / "sample.xdd", od_name="ODdrive")}
    files["config.c"] = (
        '#include "301/CO_ODinterface.h"\n#include "OD.h"\n#include "ODdrive.h"\n'
        "int configure(CO_config_t *a, CO_config_t *b);\n"
        "int configure(CO_config_t *a, CO_config_t *b)\n"
        "{\n    OD_INIT_CONFIG(*a);\n    ODdrive_INIT_CONFIG(*b);\n"
        "    return a->CNT_RPDO + 10 * b->CNT_NMT + 100 * a->CNT_ARR_1003"
        " + (b->ENTRY_H1200 == NULL ? 1000 : 0);\n}\n")
    lines = build(files, tmp_path, "-DCO_MULTIPLE_OD")
    assert lines[0] == "size=21"          # walk.c walks OD, the one named by OD.h


@needs_cc
def test_the_header_alone_compiles_in_a_program_that_uses_it(tmp_path):
    files = export(FIX / "sample.eds")
    files["app.c"] = ('#include "301/CO_ODinterface.h"\n#include "OD.h"\n'
                      "uint32_t app(void);\nuint32_t app(void)\n{\n"
                      "    OD_RAM.x2000_setPoint = 5;\n"
                      "    return OD_PERSIST_COMM.x1018_identity.vendor_ID + "
                      "OD_ENTRY_H1017_producerHeartbeatTime->index + OD_CNT_ARR_1003;\n}\n")
    assert build(files, tmp_path)[0] == "size=21"


# -- what is refused, and what is said ------------------------------------------------------------

def _with(tmp_path, old: str, new: str):
    src = tmp_path / "dev.eds"
    text = (FIX / "sample.eds").read_text()
    assert old in text
    src.write_text(text.replace(old, new))
    return src


def _said(src) -> list[str]:
    return [d.format() for d in run("canopennode", str(src)).diagnostics]


def test_an_array_whose_elements_differ_is_written_as_a_record(tmp_path):
    src = _with(tmp_path, "[2002sub2]\nParameterName=Output 2\nObjectType=0x7\n"
                ";CO_accessSRDO=tx\nDataType=0x0003",
                "[2002sub2]\nParameterName=Output 2\nObjectType=0x7\n"
                ";CO_accessSRDO=tx\nDataType=0x0004")
    r = run("canopennode", str(src))
    line = src.read_text().splitlines().index("[2002]") + 1
    assert [d.format() for d in r.diagnostics] == [
        f"{src}:{line}: warning: 0x2002 is written as a RECORD: it cannot be a CANopenNode "
        "ARRAY (sub-index 0x02 differs from sub-index 0x01 in data type, length or access); "
        "the stack serves it the same, the application reaches its elements as struct "
        "members [EXP317]"]
    h, c = r.output["OD.h"], r.output["OD.c"]
    assert ("    struct {\n        uint8_t numberOfOutputs;\n        int16_t output1;\n"
            "        int32_t output2;\n    } x2002_outputs;\n") in h
    assert "OD_CNT_ARR_2002" not in h
    assert "    {0x2002, 0x03, ODT_REC, &ODObjs.o_2002_outputs, NULL},\n" in c
    assert ("    .x2002_outputs = {\n        .numberOfOutputs = 0x02,\n        .output1 = -1,\n"
            "        .output2 = 32767\n    }\n") in c


def test_an_array_with_a_gap_is_written_as_a_record(tmp_path):
    src = _with(tmp_path, "[2002sub2]", "[2002sub3]")
    assert [m for m in _said(src) if "EXP317" in m][0].endswith(
        "warning: 0x2002 is written as a RECORD: it cannot be a CANopenNode ARRAY (its "
        "sub-indexes are not 0, 1, 2, ... without a gap); the stack serves it the same, the "
        "application reaches its elements as struct members [EXP317]")
    c = run("canopennode", str(src)).output["OD.c"]
    assert "            .subIndex = 3,\n" in c


def test_an_array_whose_sub0_is_no_unsigned8_is_refused(tmp_path):
    src = _with(tmp_path, "[2002sub0]\nParameterName=Number of outputs\nObjectType=0x7\n"
                "DataType=0x0005", "[2002sub0]\nParameterName=Number of outputs\n"
                "ObjectType=0x7\nDataType=0x0006")
    r = run("canopennode", str(src))
    assert r.output is None
    assert [d.format() for d in r.errors][0].endswith(
        "error: 0x2002: sub-index 0 of an ARRAY is UNSIGNED8 in CANopenNode [EXP316]")


def test_a_storage_group_that_is_no_c_name_is_an_error_at_its_line(tmp_path):
    src = _with(tmp_path, ";CO_storageGroup=PERSIST_APP", ";CO_storageGroup=PERSIST APP")
    line = src.read_text().splitlines().index(";CO_storageGroup=PERSIST APP") + 1
    assert f"{src}:{line}: error: 0x2002: storage group 'PERSIST APP' cannot be part of a C " \
           "name [EXP310]" in _said(src)


def test_a_standard_object_with_another_count_label_gets_the_standard_one(tmp_path):
    src = _with(tmp_path, "[1001]\nParameterName=Error register\nObjectType=0x7\n",
                "[1001]\nParameterName=Error register\nObjectType=0x7\n;CO_countLabel=ERR\n")
    line = src.read_text().splitlines().index(";CO_countLabel=ERR") + 1
    r = run("canopennode", str(src))
    assert [d.format() for d in r.diagnostics] == [
        f"{src}:{line}: warning: 0x1001 states count label 'ERR'; CANopenNode's stack needs "
        "EM there, which is used [EXP311]"]
    assert "#define OD_CNT_EM 1" in r.output["OD.h"] and "ERR" not in r.output["OD.h"]


def test_nodeid_outside_the_cob_ids_canopennode_completes_is_a_warning(tmp_path):
    src = _with(tmp_path, "DefaultValue=0x123456789ABCDEF0", "DefaultValue=$NODEID+0x10")
    line = src.read_text().splitlines().index("DefaultValue=$NODEID+0x10") + 1
    r = run("canopennode", str(src))
    assert [d.format() for d in r.diagnostics] == [
        f"{src}:{line}: warning: 0x2008sub0: '$NODEID+0x10' is written without $NODEID; "
        "CANopenNode adds the node-ID only to the pre-defined COB-IDs of EMCY, SDO servers, "
        "SRDOs and PDOs [EXP312]"]
    assert ".x2008_counter = 0x0000000000000010," in r.output["OD.c"]


def test_a_domain_value_is_not_put_into_the_od(tmp_path):
    src = _with(tmp_path, "DataType=0x000F\nAccessType=wo\n",
                "DataType=0x000F\nAccessType=wo\nDefaultValue=0102\n")
    assert [m.split(": ", 1)[1] for m in _said(src)] == [
        "warning: 0x2005sub0: a DOMAIN holds no data in CANopenNode's object dictionary; "
        "its value is left out [EXP313]"]


def test_sub_entries_with_one_c_name_are_told_apart(tmp_path):
    src = _with(tmp_path, "ParameterName=Product code", "ParameterName=Vendor-ID")
    line = src.read_text().splitlines().index("[1018sub2]") + 1
    r = run("canopennode", str(src))
    assert [d.format() for d in r.diagnostics] == [
        f"{src}:{line}: warning: 0x1018sub2: its C name 'vendor_ID' is taken by sub-index "
        "0x01; it is named 'vendor_ID_sub2' [EXP315]"]
    assert "        uint32_t vendor_ID;\n        uint32_t vendor_ID_sub2;\n" in r.output["OD.h"]


def test_a_record_member_named_like_a_c_keyword_gets_its_sub_index(tmp_path):
    src = _with(tmp_path, "ParameterName=Product code", "ParameterName=int")
    assert "        uint32_t int_sub2;" in run("canopennode", str(src)).output["OD.h"]


def test_a_real_that_is_not_finite_has_no_c_initializer(tmp_path):
    src = _with(tmp_path, "DefaultValue=1.5", "DefaultValue=0x7F800000")
    msgs = _said(src)
    assert any(m.endswith("error: 0x2001sub0: REAL32 value '0x7F800000' is not finite and "
                          "has no C initializer [EXP314]") for m in msgs), msgs


def test_nothing_is_written_on_an_error(tmp_path):
    src = _with(tmp_path, "[2002sub0]\nParameterName=Number of outputs\nObjectType=0x7\n"
                "DataType=0x0005", "[2002sub0]\nParameterName=Number of outputs\n"
                "ObjectType=0x7\nDataType=0x0006")
    out = tmp_path / "od"
    r = cli("export", "-f", "canopennode", src, "-o", out)
    assert r.exit_code == 1 and not out.exists()


def test_an_xdd_that_leaves_out_a_standard_count_label_is_told(tmp_path):
    src = tmp_path / "dev.xdd"
    src.write_text((FIX / "sample.xdd").read_text().replace(
        '<q1:property name="CO_countLabel" value="EM" />', ""))
    r = run("canopennode", str(src))
    obj_line = next(n for n, ln in enumerate(src.read_text().splitlines(), 1)
                    if '<CANopenObject index="1001"' in ln)
    assert [d.format() for d in r.diagnostics if d.rule == "EXP311"] == [
        f"{src}:{obj_line}: warning: 0x1001 states no count label; CANopenNode's stack needs "
        "EM there, which is used [EXP311]"]


# -- CANopenNode's example ----------------------------------------------------------------------

# Facts of CANopenNode's own example/OD.h (CANopenNode/CANopenNode at 01887f26, generated
# by CANopenEditor v4.0 from an earlier revision of the same DS301_profile.xpd): its
# counts, array sizes and the names of its 33 entries. (Its record members of PDO mappings
# are "applicationObject_1"; CANopenEditor's later rule, and ours, give
# "applicationObject1": no entry name changes.)
EXAMPLE_COUNTS = {"NMT": 1, "EM": 1, "SYNC": 1, "SYNC_PROD": 1, "STORAGE": 1, "TIME": 1,
                  "EM_PROD": 1, "HB_CONS": 1, "HB_PROD": 1, "SDO_SRV": 1, "SDO_CLI": 1,
                  "RPDO": 4, "TPDO": 4}
EXAMPLE_ARRAYS = {"1003": 16, "1010": 4, "1011": 4, "1016": 8}
EXAMPLE_ENTRIES = (
    "1000_deviceType 1001_errorRegister 1003_pre_definedErrorField 1005_COB_ID_SYNCMessage "
    "1006_communicationCyclePeriod 1007_synchronousWindowLength 1010_storeParameters "
    "1011_restoreDefaultParameters 1012_COB_IDTimeStampObject 1014_COB_ID_EMCY "
    "1015_inhibitTimeEMCY 1016_consumerHeartbeatTime 1017_producerHeartbeatTime "
    "1018_identity 1019_synchronousCounterOverflowValue 1200_SDOServerParameter "
    "1280_SDOClientParameter 1400_RPDOCommunicationParameter "
    "1401_RPDOCommunicationParameter 1402_RPDOCommunicationParameter "
    "1403_RPDOCommunicationParameter 1600_RPDOMappingParameter 1601_RPDOMappingParameter "
    "1602_RPDOMappingParameter 1603_RPDOMappingParameter 1800_TPDOCommunicationParameter "
    "1801_TPDOCommunicationParameter 1802_TPDOCommunicationParameter "
    "1803_TPDOCommunicationParameter 1A00_TPDOMappingParameter 1A01_TPDOMappingParameter "
    "1A02_TPDOMappingParameter 1A03_TPDOMappingParameter").split()


@needs_example
def test_the_example_od_has_canopennodes_counts_and_names():
    h = export(EXAMPLE / "DS301_profile.xpd")["OD.h"]
    assert dict(re.findall(r"#define OD_CNT_([A-Z_]+) (\d+)\n", h)) == \
        {k: str(v) for k, v in EXAMPLE_COUNTS.items()}
    assert dict(re.findall(r"#define OD_CNT_ARR_([0-9A-F]{4}) (\d+)\n", h)) == \
        {k: str(v) for k, v in EXAMPLE_ARRAYS.items()}
    assert re.findall(r"#define OD_ENTRY_H(\w+) \(&OD->list\[(\d+)\]\)", h)[33:] == \
        [(name, str(k)) for k, name in enumerate(EXAMPLE_ENTRIES)]


@needs_example
def test_the_eds_canopeneditor_exported_gives_the_same_od_as_its_project():
    """The EDS keeps the storage groups as ;StorageLocation lines, and the count labels
    are the standard ones: the files differ only in the banner naming the source."""
    a = export(EXAMPLE / "DS301_profile.xpd")
    b = export(EXAMPLE / "DS301_profile.eds")
    for name in ("OD.h", "OD.c"):
        diff = [(x, y) for x, y in zip(a[name].splitlines(), b[name].splitlines()) if x != y]
        assert diff == [("    of DS301_profile.xpd", "    of DS301_profile.eds"),
                        ("    Modified: 09-05-2023", "    Modified: 03-17-2023")]


@needs_cc
@needs_example
def test_the_example_od_holds_what_canopeneditors_page_says(tmp_path):
    """Every object of CANopenEditor's page of the example, walked in our OD: the same
    entries, SDO and PDO attributes as its SDO/PDO columns, the storage group its data is
    in, and its default value's bytes (no data where the page gives no default)."""
    path = EXAMPLE / "DS301_profile.xpd"
    files = export(path)
    walked = build(files, tmp_path)
    assert walked == expected_walk(path, formats.load(str(path)))
    page = parse_canopeneditor((EXAMPLE / "DS301_profile.md").read_text())
    listing: dict = {}
    for line in walked[1:]:
        if not line.startswith(" "):
            idx = int(line[:4], 16)
            listing[idx] = {}
        else:
            sub, attr, length, data = re.fullmatch(
                r"  (\w\w) attr=0x(\w\w) len=(\d+) data=(\S+)", line).groups()
            listing[idx][int(sub, 16)] = (int(attr, 16), int(length), data)
    listing.pop(0)
    assert sorted(listing) == sorted(page)
    groups = {g: body for body, g in re.findall(r"typedef struct \{\n(.*?)\n\} OD_(\w+)_t;",
                                                 files["OD.h"], re.S)}
    assert sorted(groups) == ["PERSIST_COMM", "RAM"]
    sdo = {"ro": 1, "wo": 2, "rw": 3}
    pdo = {"no": 0, "t": 4, "r": 8, "tr": 12}
    for idx, obj in page.items():
        assert sorted(listing[idx]) == sorted(obj["subs"]), hex(idx)
        for sub, row in obj["subs"].items():
            attr, length, data = listing[idx][sub]
            assert attr & 0x0F == sdo[row["sdo"]] | pdo[row["pdo"]], (hex(idx), sub)
            t = dt.BY_NAME[row["dtype"]]
            if row["default"]:
                want = values.encode(t, row["default"], node_id=0).hex().upper()
                assert data == want, (hex(idx), sub)
            else:
                assert data == "-", (hex(idx), sub)
        var = f"x{idx:04X}_{canopennode.cname(obj['name'])}"
        has_data = any(row["default"] for row in obj["subs"].values())
        holding = [g for g, body in groups.items() if re.search(r"\b" + var + r"\b", body)]
        assert holding == ([obj["group"]] if has_data else []), hex(idx)


@pytest.mark.parametrize("old, new, said", [
    (";CO_accessSRDO=tx\nDataType=0x0003\nAccessType=rw\nDefaultValue=-1",
     ";CO_accessSRDO=both\nDataType=0x0003\nAccessType=rw\nDefaultValue=-1",
     "0x2002sub1: CO_accessSRDO 'both' is none of tx, rx, trx, no [EXP310]"),
    (";CO_stringLengthMin=4", ";CO_stringLengthMin=-1",
     "0x2004sub0: CO_stringLengthMin '-1' is not a length from 0 to 65535 [EXP310]")])
def test_a_setting_that_is_none_of_its_values_is_an_error_at_its_line(tmp_path, old, new, said):
    src = _with(tmp_path, old, new)
    line = src.read_text().splitlines().index(new.split("\n")[0]) + 1
    r = run("canopennode", str(src))
    assert r.output is None
    assert [d.format() for d in r.errors] == [f"{src}:{line}: error: {said}"]


def test_a_description_without_objects_from_0x1000_exports_nothing(tmp_path):
    src = tmp_path / "types.eds"
    src.write_text("[FileInfo]\nFileName=types.eds\n\n[DeviceInfo]\nProductName=x\n\n"
                   "[0005]\nParameterName=UNSIGNED8\nObjectType=0x7\nDataType=0x0007\n"
                   "AccessType=ro\nDefaultValue=8\nPDOMapping=0\n")
    r = run("canopennode", str(src))
    assert r.output is None
    assert [d.format() for d in r.errors] == [
        f"{src}: error: no objects from 0x1000 up: nothing to export [EXP100]"]


@pytest.mark.parametrize("name, other", [("OD.h", "OD.c"), ("OD.c", "OD.h")])
def test_neither_file_is_written_when_one_would_be_the_input(tmp_path, name, other):
    src = tmp_path / name
    src.write_text((FIX / "sample.eds").read_text())
    r = cli("export", "-q", "-f", "canopennode", src, "-o", tmp_path)
    assert r.exit_code == 2
    assert r.stderr == (f"{tmp_path / name}: error: the output is the input file; refusing "
                        "to overwrite it\n")
    assert src.read_text() == (FIX / "sample.eds").read_text()
    assert not (tmp_path / other).exists()

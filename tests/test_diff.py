"""dcf2bin diff (issue 29 item 3, docs/diff.md): two configurations compared by meaning.

Small DCFs written here (``dcf``) pin the rules one by one with exact outputs; the samples
and fixtures check the pairs of kinds (a DCF and the XDC of the same device, a container and
the DCF it was compiled from, its JSON form, a concise DCF and the build's DCF)."""
from __future__ import annotations

import json
import os
import pty
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES, compile_corpus_file, corpus_files, needs_corpus
from dcf2bin import schemas
from dcf2bin.cli import main

XDD = ROOT / "tests" / "fixtures" / "xdd"
FLAT = ROOT / "tests" / "golden" / "network" / "flat" / "out"

# A small device: every rule below changes one line of it.
BASE = """\
[DeviceInfo]
VendorName=Test
VendorNumber=0x000000AB
ProductName=T-1

[DeviceComissioning]
NodeID=5

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00000191

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=0

[1017]
ParameterName=Producer heartbeat time
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0x10

[1800]
ParameterName=TPDO1 communication parameter
ObjectType=0x9
SubNumber=3

[1800sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[1800sub1]
ParameterName=COB-ID used by TPDO
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180

[1800sub2]
ParameterName=Transmission type
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=255

[1A00]
ParameterName=TPDO1 mapping parameter
ObjectType=0x9
SubNumber=2

[1A00sub0]
ParameterName=Number of mapped objects
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=1

[1A00sub1]
ParameterName=Mapped object 1
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0x60410010

[2000]
ParameterName=Tool name
ObjectType=0x7
DataType=0x0009
AccessType=const
DefaultValue=T-1

[6000]
ParameterName=Read inputs
ObjectType=0x8
SubNumber=2

[6000sub0]
ParameterName=Number of inputs
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=1

[6000sub1]
ParameterName=Inputs 1-8
ObjectType=0x7
DataType=0x0005
AccessType=ro
PDOMapping=1
DefaultValue=0

[6040]
ParameterName=Controlword
ObjectType=0x7
DataType=0x0006
AccessType=rww
PDOMapping=1
DefaultValue=0

[6041]
ParameterName=Statusword
ObjectType=0x7
DataType=0x0006
AccessType=ro
PDOMapping=1
DefaultValue=0
"""


def run(*args, input=None):
    return CliRunner().invoke(main, ["diff", *map(str, args)], input=input,
                              catch_exceptions=False)


def dcf(tmp_path, name: str, *edits: tuple[str, str], text: str = BASE):
    """BASE with each (old, new) replaced once (each must be there), written as ``name``."""
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture
def cd(tmp_path, monkeypatch):
    """Run in tmp_path, so that the outputs name a.dcf and b.dcf."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


# -- values by meaning ----------------------------------------------------------------------

@pytest.mark.parametrize("value", ["16", "020", "0X10", "+16"])
def test_a_value_written_another_way_is_equal(cd, value):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", f"DefaultValue={value}"))
    r = run("a.dcf", "b.dcf")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("a.dcf, b.dcf: equal; 10 entries compared, 3 of the node's state "
                        "left out (--all compares them)\n")


def test_one_changed_value_is_two_lines_under_its_object(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "ParameterValue=100"))
    r = run("a.dcf", "b.dcf")
    assert r.exit_code == 1
    assert r.stdout == ("--- a.dcf\n"
                        "+++ b.dcf\n"
                        "@@ 0x1017 Producer heartbeat time @@\n"
                        "-0x1017sub0 Producer heartbeat time: 16\n"
                        "+0x1017sub0 Producer heartbeat time: 100\n")
    assert r.stderr == ("a.dcf, b.dcf: 1 entry differs; 10 entries compared, 3 of the "
                        "node's state left out (--all compares them)\n")


def test_the_effective_value_parametervalue_over_defaultvalue(cd):
    """A DCF against its EDS: the DCF's ParameterValue against the EDS's DefaultValue."""
    dcf(cd, "a.eds")
    dcf(cd, "b.dcf", ("DefaultValue=255", "DefaultValue=255\nParameterValue=0xFF"))
    assert run("a.eds", "b.dcf").exit_code == 0
    dcf(cd, "c.dcf", ("DefaultValue=255", "DefaultValue=255\nParameterValue=1"))
    r = run("a.eds", "c.dcf", "-q")
    assert r.stdout.splitlines()[2:] == ["@@ 0x1800 TPDO1 communication parameter @@",
                                         "-0x1800sub2 Transmission type: 255",
                                         "+0x1800sub2 Transmission type: 1"]
    assert r.stderr == ""


def test_nodeid_is_worked_out_with_each_files_node_id(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=$NODEID+0x180", "DefaultValue=0x185"))
    assert run("a.dcf", "b.dcf").exit_code == 0
    dcf(cd, "c.dcf", ("DefaultValue=$NODEID+0x180", "DefaultValue=0x185"),
        ("NodeID=5", "NodeID=6"))
    assert run("a.dcf", "c.dcf").exit_code == 0      # each file with its own node-ID
    dcf(cd, "d.dcf", ("NodeID=5", "NodeID=6"))
    r = run("a.dcf", "d.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1800 TPDO1 communication parameter @@",
        "-0x1800sub1 COB-ID used by TPDO: 0x00000185 = COB-ID 0x185",
        "+0x1800sub1 COB-ID used by TPDO: 0x00000186 = COB-ID 0x186"]


def test_a_file_without_node_id_takes_the_other_files(cd):
    """An EDS (no NodeID) against its DCF (NodeID=5, ParameterValue 0x185): equal."""
    dcf(cd, "a.eds", ("[DeviceComissioning]\nNodeID=5\n", ""))
    dcf(cd, "b.dcf", ("DefaultValue=$NODEID+0x180",
                      "DefaultValue=$NODEID+0x180\nParameterValue=0x80000185"))
    r = run("a.eds", "b.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1800 TPDO1 communication parameter @@",
        "-0x1800sub1 COB-ID used by TPDO: 0x00000185 = COB-ID 0x185",
        "+0x1800sub1 COB-ID used by TPDO: 0x80000185 = COB-ID 0x185, invalid"]
    dcf(cd, "c.dcf", ("DefaultValue=$NODEID+0x180",
                      "DefaultValue=$NODEID+0x180\nParameterValue=0x185"))
    assert run("a.eds", "c.dcf").exit_code == 0


def test_n_gives_both_files_the_node_id(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=$NODEID+0x180", "DefaultValue=0x187"))
    assert run("a.dcf", "b.dcf").exit_code == 1
    assert run("a.dcf", "b.dcf", "-n", "7").exit_code == 0
    assert run("a.dcf", "b.dcf", "--node-id", "0x7").exit_code == 0


def test_without_any_node_id_formulas_equal_for_every_node_id(cd):
    """$NODEID+0x180 equals 0x180+$NODEID (for every node-ID), not 0x185."""
    plain = BASE.replace("[DeviceComissioning]\nNodeID=5\n", "")
    dcf(cd, "a.eds", text=plain)
    dcf(cd, "b.eds", ("$NODEID+0x180", "0x180 + $nodeid"), text=plain)
    assert run("a.eds", "b.eds").exit_code == 0
    dcf(cd, "c.eds", ("$NODEID+0x180", "0x185"), text=plain)
    r = run("a.eds", "c.eds", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1800 TPDO1 communication parameter @@",
        "-0x1800sub1 COB-ID used by TPDO: $NODEID+0x180",
        "+0x1800sub1 COB-ID used by TPDO: 0x00000185 = COB-ID 0x185"]


def test_a_value_that_cannot_be_encoded_is_compared_as_written_with_an_error(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=255", "DefaultValue=300"))
    r = run("a.dcf", "b.dcf")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1800 TPDO1 communication parameter @@",
        "-0x1800sub2 Transmission type: 255",
        "+0x1800sub2 Transmission type: 300 (invalid: value 300 out of range for UNSIGNED8 "
        "(0..255))"]
    assert r.stderr.splitlines()[0] == (
        "b.dcf:54: error: 0x1800sub2: value 300 out of range for UNSIGNED8 (0..255); "
        "compared as written [DCF200]")


def test_the_same_bad_value_on_both_sides_is_not_equal(cd):
    """Exit 0 means both inputs read cleanly and are equal: the same value out of range in
    both files is compared as written (no entry differs), and the run still exits 1."""
    dcf(cd, "a.dcf", ("DefaultValue=255", "DefaultValue=300"))
    dcf(cd, "b.dcf", ("DefaultValue=255", "DefaultValue=300"))
    r = run("a.dcf", "b.dcf")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        "a.dcf:54: error: 0x1800sub2: value 300 out of range for UNSIGNED8 (0..255); "
        "compared as written [DCF200]",
        "b.dcf:54: error: 0x1800sub2: value 300 out of range for UNSIGNED8 (0..255); "
        "compared as written [DCF200]",
        "a.dcf, b.dcf: no entry differs as read, but a.dcf has 1 error and b.dcf has 1 "
        "error; 10 entries compared, 3 of the node's state left out (--all compares them)"]


def test_a_file_with_conflict_markers_is_never_equal(cd):
    """A DCF left with git's conflict markers (both sides of the conflict the same line)
    reads as the other file does; its reading errors are findings, each on its own line,
    and the run exits 1 -- a CI drift check does not pass on a broken file."""
    dcf(cd, "good.dcf")
    dcf(cd, "conflict.dcf", ("DefaultValue=0x10", "<<<<<<< HEAD\nDefaultValue=0x10\n"
                             "=======\nDefaultValue=0x10\n>>>>>>> other"))
    r = run("conflict.dcf", "good.dcf")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        "conflict.dcf:28: error: line without '=': '<<<<<<< HEAD' [DCF002]",
        "conflict.dcf:30: error: key missing before '=': '=======' [DCF002]",
        "conflict.dcf:32: error: line without '=': '>>>>>>> other' [DCF002]",
        "conflict.dcf:31: error: key 'DefaultValue' repeated in [1017] (first at line 29) "
        "[DCF010]",
        "    hint: remove one of them; dcf2bin does not guess which is meant",
        "conflict.dcf, good.dcf: no entry differs as read, but conflict.dcf has 4 errors; "
        "10 entries compared, 3 of the node's state left out (--all compares them)"]
    doc = json.loads(run("conflict.dcf", "good.dcf", "-f", "json", "-q").stdout)
    assert doc["equal"] is False
    assert [doc["files"][0][s]["errors"] for s in "ab"] == [4, 0]
    assert doc["files"][0]["differences"] == []


def test_an_error_of_an_entry_counts_where_the_entry_is_compared(cd):
    """An error the reader ties to an entry (an unknown AccessType) is an error where that
    entry is compared -- two descriptions compare every entry -- and a warning where it is
    not: a container written from the DCF leaves the device's defaults out, as compile
    itself says of an entry it does not write."""
    dcf(cd, "a.dcf", ("DefaultValue=0x10", "ParameterValue=100"))
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "ParameterValue=100"),
        ("Controlword\nObjectType=0x7\nDataType=0x0006\nAccessType=rww",
         "Controlword\nObjectType=0x7\nDataType=0x0006\nAccessType=rx"))
    r = run("a.dcf", "b.dcf", "--values-only")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        "b.dcf:106: error: [6040] unknown AccessType 'rx' [DCF032]",
        "a.dcf, b.dcf: no entry differs as read, but b.dcf has 1 error; 10 entries "
        "compared, 3 of the node's state left out (--all compares them)"]
    assert CliRunner().invoke(main, ["compile", "b.dcf", "-o", "b.bin"]).exit_code == 0
    r = run("b.dcf", "b.bin")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr.splitlines() == [
        "b.dcf:106: warning: [6040] unknown AccessType 'rx' (not compared) [DCF032]",
        "b.dcf, b.bin: equal; 1 entry compared"]


def test_long_values_are_shown_bounded(cd):
    """A huge literal and a long string are shown as every message quotes a user's value:
    the first 40 and last 12 characters and the count (issue 26 item 3); the JSON form's
    value is the same text, its data the whole bytes."""
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "DefaultValue=" + "9" * 4000),
        ("DefaultValue=T-1", "DefaultValue=" + "x" * 99 + "y"))
    r = run("a.dcf", "b.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1017 Producer heartbeat time @@",
        "-0x1017sub0 Producer heartbeat time: 16",
        f"+0x1017sub0 Producer heartbeat time: {'9' * 40}...{'9' * 12} (4000 characters) "
        "(invalid: integer literal too long (4000 digits, at most 64))",
        "@@ 0x2000 Tool name @@",
        '-0x2000sub0 Tool name: "T-1"',
        f'+0x2000sub0 Tool name: "{"x" * 39}...{"x" * 10}y" (102 characters)']
    doc = json.loads(run("a.dcf", "b.dcf", "-f", "json", "-q").stdout)
    tool = doc["files"][0]["differences"][1]["b"]
    assert tool["value"] == f'"{"x" * 39}...{"x" * 10}y" (102 characters)'
    assert tool["data"] == "78" * 99 + "79"


def test_pdo_mapping_entries_name_the_objects_they_map(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x60410010", "DefaultValue=0x60400010"))
    r = run("a.dcf", "b.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1A00 TPDO1 mapping parameter @@",
        "-0x1A00sub1 Mapped object 1: 0x60410010 = 0x6041sub0 Statusword, 16 bits",
        "+0x1A00sub1 Mapped object 1: 0x60400010 = 0x6040sub0 Controlword, 16 bits"]


STRING_DCF = ("[DeviceComissioning]\r\nNodeID=5\r\n[2002]\r\nParameterName=str\r\n"
              "ObjectType=0x7\r\nDataType=0x0009\r\nAccessType=rw\r\nParameterValue=")


def test_values_that_read_alike_show_their_bytes(cd):
    """A Latin-1 "café" (E9) against a UTF-8 one (C3 A9): the same text, other bytes. Each
    line shows its bytes, or the two would differ in nothing a reader sees; in the JSON
    form too, whose ``value`` is the text's (``data`` holds the bytes as ever)."""
    (cd / "a.dcf").write_bytes(STRING_DCF.encode() + "café\r\n".encode("latin-1"))
    (cd / "b.dcf").write_bytes(STRING_DCF.encode() + "café\r\n".encode("utf-8"))
    r = run("a.dcf", "b.dcf", "-q")
    assert (r.exit_code, r.stdout) == (1, "--- a.dcf\n+++ b.dcf\n@@ 0x2002 str @@\n"
                                          '-0x2002sub0 str: "café" (63 61 66 E9)\n'
                                          '+0x2002sub0 str: "café" (63 61 66 C3 A9)\n')
    doc = json.loads(run("a.dcf", "b.dcf", "-f", "json").stdout)
    d = doc["files"][0]["differences"][0]
    assert [(d[s]["value"], d[s]["data"]) for s in "ab"] == [
        ('"café" (63 61 66 E9)', "636166E9"), ('"café" (63 61 66 C3 A9)', "636166C3A9")]
    # values that read differently show no bytes
    (cd / "b.dcf").write_bytes(STRING_DCF.encode() + b"cafe\r\n")
    assert run("a.dcf", "b.dcf", "-q").stdout.splitlines()[3:] == [
        '-0x2002sub0 str: "café"', '+0x2002sub0 str: "cafe"']


IDENTITY = """\
[DeviceInfo]
VendorNumber=0x000000AB
ProductNumber=0x1234
RevisionNumber=0x00010002

[DeviceComissioning]
NodeID=5
LSS_SerialNumber=1234

[1018]
ParameterName=Identity Object
ObjectType=0x9
SubNumber=5

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=4

[1018sub1]
ParameterName=Vendor ID
ObjectType=0x7
DataType=0x0007
AccessType=ro

[1018sub2]
ParameterName=Product Code
ObjectType=0x7
DataType=0x0007
AccessType=ro

[1018sub3]
ParameterName=Revision number
ObjectType=0x7
DataType=0x0007
AccessType=ro

[1018sub4]
ParameterName=Serial number
ObjectType=0x7
DataType=0x0007
AccessType=ro
"""


def test_an_identity_entry_without_a_value_is_the_one_the_file_states_elsewhere(cd):
    """Issue 29: 0x1018 sub 1-4 without a value hold what [DeviceInfo] VendorNumber,
    ProductNumber, RevisionNumber and [DeviceComissioning] LSS_SerialNumber say, as the
    node made of the file answers them (model.identity): the EDS equals the DCF an upload
    writes of that node, which states them (it differed: "0x00000000 (no value given)")."""
    dcf(cd, "a.eds", text=IDENTITY)
    values = ("0x000000AB", "0x00001234", "0x00010002", "0x000004D2")
    up = dcf(cd, "up.dcf", *((f"[1018sub{sub}]\nParameterName={name}\nObjectType=0x7\n"
                               "DataType=0x0007\nAccessType=ro\n",
                               f"[1018sub{sub}]\nParameterName={name}\nObjectType=0x7\n"
                               f"DataType=0x0007\nAccessType=ro\nParameterValue={v}\n")
                              for sub, name, v in zip((1, 2, 3, 4), (
                                  "Vendor ID", "Product Code", "Revision number",
                                  "Serial number"), values)), text=IDENTITY)
    r = run("a.eds", "up.dcf")
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "a.eds, up.dcf: equal; 5 entries "
                                                        "compared\n")
    up.write_text(up.read_text().replace("ParameterValue=0x00001234", "ParameterValue=0x1235")
                  .replace("ParameterValue=0x000004D2", "ParameterValue=0x4D3"))
    r = run("a.eds", "up.dcf", "-q")
    assert (r.exit_code, r.stdout) == (1, "--- a.eds\n+++ up.dcf\n"
                                          "@@ 0x1018 Identity Object @@\n"
                                          "-0x1018sub2 Product Code: 0x00001234 (from "
                                          "[DeviceInfo] ProductNumber)\n"
                                          "+0x1018sub2 Product Code: 0x00001235\n"
                                          "-0x1018sub4 Serial number: 0x000004D2 (from "
                                          "[DeviceComissioning] LSS_SerialNumber)\n"
                                          "+0x1018sub4 Serial number: 0x000004D3\n")
    d = json.loads(run("a.eds", "up.dcf", "-f", "json").stdout)["files"][0]["differences"]
    assert [(x["a"]["value"], x["a"]["data"], x["a"]["where"]) for x in d] == [
        ("0x00001234 (from [DeviceInfo] ProductNumber)", "34120000", "a.eds:3"),
        ("0x000004D2 (from [DeviceComissioning] LSS_SerialNumber)", "D2040000", "a.eds:8")]
    # a key that is no UNSIGNED32 states nothing: the entry has no value (never guessed)
    dcf(cd, "b.eds", ("ProductNumber=0x1234", "ProductNumber=0x1FFFFFFFF"), text=IDENTITY)
    r = run("b.eds", "a.eds", "-q")
    assert (r.exit_code, r.stdout) == (0, "")
    assert run("b.eds", "a.eds").stderr == ("b.eds, a.eds: equal; 5 entries compared, "
                                            "1 value only one file states not compared\n")


def test_a_value_only_one_description_states_is_not_compared(cd):
    """Between two descriptions, an entry one gives no value says nothing of what the
    node holds there (as such an entry is not read from a node): its value is not
    compared, and the last line counts it; its type, access and PDO mapping flag are.
    Against a write list the type's zero stands (compile writes it)."""
    dcf(cd, "a.dcf", ("DefaultValue=0x10\n", "\n"))
    dcf(cd, "b.dcf", ("DefaultValue=0x10\n", "ParameterValue=500\n"))
    r = run("a.dcf", "b.dcf")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("a.dcf, b.dcf: equal; 10 entries compared, 3 of the node's state "
                        "left out (--all compares them), 1 value only one file states not "
                        "compared\n")
    doc = json.loads(run("a.dcf", "b.dcf", "-f", "json").stdout)
    check_schema(doc)
    assert doc["files"][0]["left_out"] == {"state": 3, "ignored": 0, "no_value": 1}
    dcf(cd, "c.dcf", ("DataType=0x0006\nAccessType=rw\nDefaultValue=0x10\n",
                      "DataType=0x0007\nAccessType=rw\nParameterValue=500\n"))
    r = run("a.dcf", "c.dcf", "-q")
    assert (r.exit_code, r.stdout) == (1, "--- a.dcf\n+++ c.dcf\n"
                                          "@@ 0x1017 Producer heartbeat time @@\n"
                                          "-0x1017sub0 Producer heartbeat time: 0 (no value "
                                          "given) (UNSIGNED16)\n"
                                          "+0x1017sub0 Producer heartbeat time: 0x000001F4 "
                                          "(UNSIGNED32)\n")
    # a container compiled from b.dcf writes 500 where a.dcf's compile would write the zero
    assert CliRunner().invoke(main, ["compile", "b.dcf", "-o", "b.bin", "-q"]).exit_code == 0
    r = run("a.dcf", "b.bin", "-q")
    assert (r.exit_code, r.stdout.splitlines()[2:]) == (1, [
        "@@ 0x1017 Producer heartbeat time @@",
        "-0x1017sub0 Producer heartbeat time: 0 (no value given)",
        "+0x1017sub0 Producer heartbeat time: 500"])


# -- the other facts of an entry -----------------------------------------------------------

def test_data_type_access_and_mapping_flag_differences_are_shown(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DataType=0x0006\nAccessType=rw\nDefaultValue=0x10",
                      "DataType=0x0007\nAccessType=rw\nDefaultValue=0x10"),
        ("AccessType=rww\nPDOMapping=1", "AccessType=rw\nPDOMapping=0"))
    r = run("a.dcf", "b.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1017 Producer heartbeat time @@",
        "-0x1017sub0 Producer heartbeat time: 16 (UNSIGNED16)",
        "+0x1017sub0 Producer heartbeat time: 0x00000010 (UNSIGNED32)",
        "@@ 0x6040 Controlword @@",
        "-0x6040sub0 Controlword: 0 (rww, mappable)",
        "+0x6040sub0 Controlword: 0 (rw, not mappable)"]
    # the number 16 is the same in both types: only the type differs
    doc = json.loads(run("a.dcf", "b.dcf", "-f", "json").stdout)
    assert [d["differs_in"] for d in doc["files"][0]["differences"]] == [
        ["datatype"], ["access", "pdo_mapping"]]
    r = run("a.dcf", "b.dcf", "--values-only")
    assert (r.exit_code, r.stdout) == (0, "")


def test_objects_only_in_one_file(cd):
    dcf(cd, "a.dcf")
    extra = ("[2001]\nParameterName=Gain\nObjectType=0x7\nDataType=0x0008\nAccessType=rw\n"
             "DefaultValue=1.5\n\n[6000]")
    dcf(cd, "b.dcf", ("[6000]", extra), ("[1017]\nParameterName", "[1F17]\nParameterName"))
    r = run("a.dcf", "b.dcf", "-q")
    assert r.exit_code == 1
    assert r.stdout == (
        "--- a.dcf\n+++ b.dcf\n"
        "@@ 0x1017 Producer heartbeat time: only in a.dcf @@\n"
        "-0x1017sub0 Producer heartbeat time: 16 (UNSIGNED16, rw, not mappable)\n"
        "@@ 0x1F17 Producer heartbeat time: only in b.dcf @@\n"
        "+0x1F17sub0 Producer heartbeat time: 16 (UNSIGNED16, rw, not mappable)\n"
        "@@ 0x2001 Gain: only in b.dcf @@\n"
        "+0x2001sub0 Gain: 1.5 (REAL32, rw, not mappable)\n")


# -- the node's state and --ignore ----------------------------------------------------------

def test_the_nodes_state_is_left_out_unless_all(cd):
    """0x1001 (a state object) and 0x6041/0x6000sub1 (ro from 0x2000 on) are left out;
    the count of entries of 0x6000 (its ro sub 0), a const entry and ro entries below
    0x2000 (0x1000) are compared."""
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf",
        ("AccessType=ro\nDefaultValue=0\n\n[1017]", "AccessType=ro\nDefaultValue=1\n\n[1017]"),
        ("PDOMapping=1\nDefaultValue=0\n\n[6040]", "PDOMapping=1\nDefaultValue=8\n\n[6040]"),
        ("AccessType=ro\nPDOMapping=1\nDefaultValue=0\n", "AccessType=ro\nPDOMapping=1\n"
         "DefaultValue=7\n"))
    r = run("a.dcf", "b.dcf")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("a.dcf, b.dcf: equal; 10 entries compared, 3 of the node's state "
                        "left out (--all compares them)\n")
    r = run("a.dcf", "b.dcf", "--all", "-q")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1001 Error register @@",
        "-0x1001sub0 Error register: 0", "+0x1001sub0 Error register: 1",
        "@@ 0x6000 Read inputs @@",
        "-0x6000sub1 Inputs 1-8: 0", "+0x6000sub1 Inputs 1-8: 8",
        "@@ 0x6041 Statusword @@",
        "-0x6041sub0 Statusword: 0", "+0x6041sub0 Statusword: 7"]
    dcf(cd, "c.dcf", ("DefaultValue=T-1", "DefaultValue=T-2"), ("DefaultValue=1\n\n[6000sub1]",
                                                               "DefaultValue=2\n\n[6000sub1]"),
        ("DefaultValue=0x00000191", "DefaultValue=0x00000192"))
    r = run("a.dcf", "c.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1000 Device type @@",
        "-0x1000sub0 Device type: 0x00000191", "+0x1000sub0 Device type: 0x00000192",
        "@@ 0x2000 Tool name @@",
        '-0x2000sub0 Tool name: "T-1"', '+0x2000sub0 Tool name: "T-2"',
        "@@ 0x6000 Read inputs @@",
        "-0x6000sub0 Number of inputs: 1", "+0x6000sub0 Number of inputs: 2"]


@pytest.mark.parametrize("ignore, shown", [
    (["0x1017"], ["0x1800sub2"]),
    (["0x1800sub2"], ["0x1017sub0"]),
    (["0x1000-0x17FF"], ["0x1800sub2"]),
    (["0x1017,0x1800sub2"], []),
    (["0x1017", "6144sub2"], []),                       # decimal 6144 = 0x1800
    (["0x1800sub1-0x1800sub2"], ["0x1017sub0"]),
    (["0x1800sub3-0xFFFF"], ["0x1017sub0", "0x1800sub2"]),
])
def test_ignore_entries_and_ranges(cd, ignore, shown):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "DefaultValue=17"),
        ("DefaultValue=255", "DefaultValue=254"))
    args = [a for i in ignore for a in ("--ignore", i)]
    r = run("a.dcf", "b.dcf", *args)
    assert r.exit_code == (1 if shown else 0)
    assert [line[1:].split()[0] for line in r.stdout.splitlines()
            if line[:1] == "-" and not line.startswith("---")] == shown
    doc = json.loads(run("a.dcf", "b.dcf", "-f", "json", *args).stdout)
    assert doc["scope"]["ignore"] == [p for i in ignore for p in i.split(",")]
    f = doc["files"][0]
    assert f["compared"] + f["left_out"]["ignored"] + f["left_out"]["state"] == 13


@pytest.mark.parametrize("value, message", [
    ("0x1018sub", "'0x1018sub' is not an entry or range (an index such as 0x1017, an entry "
                  "such as 0x1018sub4, or a range such as 0x2000-0x2FFF)"),
    ("0x2FFF-0x2000", "'0x2FFF-0x2000': the range ends before it starts"),
    ("0x10000", "'0x10000': index 0x10000 is not in 0x0000-0xFFFF"),
    ("0x1018sub100", "'0x1018sub100': sub-index 100 is not in 0x00-0xFF"),
    ("08", "'08': invalid octal literal '08'"),
    (",", "',' names no entry (an index such as 0x1017, an entry such as 0x1018sub4, or a "
          "range such as 0x2000-0x2FFF)"),
])
def test_a_bad_ignore_is_a_usage_error(cd, value, message):
    dcf(cd, "a.dcf")
    r = run("a.dcf", "a.dcf", "--ignore", value)
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: Invalid value for '--ignore': {message}"


# -- pairs of kinds -------------------------------------------------------------------------

def test_a_dcf_and_the_xdc_of_the_same_device_are_equal():
    r = run(XDD / "vendor_v10.dcf", XDD / "vendor_v10.xdc", "--all")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr.endswith(": equal; 25 entries compared\n")


@pytest.mark.parametrize("sample", ["plc", "device", "bild8", "dis2", "dis2_cobid"])
def test_a_container_and_the_dcf_it_was_compiled_from_are_equal(sample):
    r = run(SAMPLES / f"{sample}.dcf", SAMPLES / f"{sample}.bin", "--all")
    assert (r.exit_code, r.stdout) == (0, ""), r.stdout
    r = run(SAMPLES / f"{sample}.bin", SAMPLES / f"{sample}.dcf", "--all")
    assert (r.exit_code, r.stdout) == (0, ""), r.stdout


@needs_corpus
def test_every_compiling_corpus_file_equals_its_container():
    """Every corpus DCF/EDS that compiles (node-ID 1 where it needs one, as
    compile_corpus_file does) is equal to its container, the node's state included."""
    from dcf2bin import compare
    checked = 0
    for p in corpus_files(".dcf", ".eds"):
        res = compile_corpus_file(p)
        if not res.ok:
            continue
        a = compare.load(p.read_bytes(), str(p), "dcf")
        if a.node_id is None:
            a = compare.load(p.read_bytes(), str(p), "dcf", node_id=1)
        b = compare.load(res.data, "x.bin", "bin")
        diff, _ = compare.compare_sources(a, b, compare.Scope(state=False))
        assert diff.equal, (p, [(hex(c.key[0]), c.key[1], c.kind) for c in diff.changes])
        checked += 1
    assert checked > 50


def test_a_container_its_json_form_and_stdin(tmp_path):
    dumped = CliRunner().invoke(main, ["dump", "-f", "json", str(SAMPLES / "plc.bin")]).stdout
    (tmp_path / "plc.json").write_text(dumped)
    assert run(SAMPLES / "plc.bin", tmp_path / "plc.json", "--all").exit_code == 0
    assert run(tmp_path / "plc.json", SAMPLES / "plc.dcf", "--all").exit_code == 0
    r = run("-", SAMPLES / "plc.dcf", input=(SAMPLES / "plc.bin").read_bytes())
    assert (r.exit_code, r.stderr) == (0, f"<stdin>, {SAMPLES}/plc.dcf: equal; 24 entries "
                                          "compared, 6 of the node's state left out (--all "
                                          "compares them)\n")


def test_a_container_against_a_dcf_it_was_not_compiled_from(tmp_path):
    """The DCF's configured entries the container lacks, the container's writes the DCF
    does not configure, and a written value that differs; entries the DCF only
    describes (DefaultValue) are what the node holds already and are not compared."""
    text = (SAMPLES / "device.dcf").read_text()
    assert "[1017]" in text and "ParameterValue=500" in text
    changed = tmp_path / "device.dcf"
    changed.write_text(text.replace("ParameterValue=500", "ParameterValue=400"))
    r = run(changed, SAMPLES / "device.bin")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1017 Producer heartbeat time @@",
        "-0x1017sub0 Producer heartbeat time: 400",
        "+0x1017sub0 Producer heartbeat time: 500"]
    r = run(SAMPLES / "device.eds", SAMPLES / "device.bin", "-q")
    removed = [line for line in r.stdout.splitlines() if line.startswith("+")][1:4]
    assert removed == ["+0x1016sub1 Consumer heartbeat time1: 0x00010064",
                       "+0x1016sub2 Consumer heartbeat time2: 0x000200C8",
                       "+0x1017sub0 Producer heartbeat time: 500"]


def test_a_write_list_against_a_description_assumes_a_node_at_its_defaults(cd):
    """Entries the container does not write hold their DefaultValue on a node at its
    defaults: a ParameterValue equal to it, one on a ro entry (a record of what was read)
    or under ObjFlags=1 (not to be written) needs no write; one that changes a writable
    entry does ("only in" the DCF when the container lacks it)."""
    configured = ("DefaultValue=255", "DefaultValue=255\nParameterValue=1")
    dcf(cd, "a.dcf", configured)
    r = CliRunner().invoke(main, ["compile", "a.dcf", "-o", "a.bin"])
    assert r.exit_code == 0, r.stderr
    dcf(cd, "b.dcf", configured,
        ("DefaultValue=0x60410010", "DefaultValue=0x60410010\nParameterValue=0x60410010"),
        ("DefaultValue=0x00000191", "DefaultValue=0x00000191\nParameterValue=0x192"),
        ("AccessType=rw\nDefaultValue=0x10", "AccessType=rw\nObjFlags=1\nDefaultValue=0x10\n"
         "ParameterValue=99"))
    r = run("a.bin", "b.dcf")
    assert (r.exit_code, r.stdout) == (0, ""), r.stdout
    dcf(cd, "c.dcf", configured, ("PDOMapping=1\nDefaultValue=0\n\n[6041]",
                                  "PDOMapping=1\nDefaultValue=0\nParameterValue=0x1234\n\n"
                                  "[6041]"))
    r = run("a.bin", "c.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x6040 Controlword: only in c.dcf @@",
        "+0x6040sub0 Controlword: 4660 (UNSIGNED16, rww, mappable)"]
    # a mapping's sub above its count (sub 0 = 1) is unused: no PDO block writes it
    unused = ("[2000]", "[1A00sub2]\nParameterName=Mapped object 2\nDataType=0x0007\n"
              "AccessType=rw\nDefaultValue=0\nParameterValue=0x60400010\n\n[2000]")
    dcf(cd, "d.dcf", configured, unused)
    assert run("a.bin", "d.dcf").exit_code == 0
    dcf(cd, "e.dcf", configured, unused, ("DefaultValue=1\n\n[1A00sub1]",
                                          "DefaultValue=1\nParameterValue=2\n\n[1A00sub1]"))
    r = run("a.bin", "e.dcf", "-q")
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1A00 TPDO1 mapping parameter @@",
        "-0x1A00sub0 Number of mapped objects: 1",
        "+0x1A00sub0 Number of mapped objects: 2",
        "+0x1A00sub2 Mapped object 2: 0x60400010 = 0x6040sub0 Controlword, 16 bits "
        "(UNSIGNED32, rw, not mappable)"]


def test_two_containers_compare_attribute_bytes_too():
    r = run(SAMPLES / "dis2.bin", SAMPLES / "dis2_cobid.bin", "-q")
    assert r.exit_code == 1
    doc = json.loads(run(SAMPLES / "dis2.bin", SAMPLES / "dis2_cobid.bin", "-f", "json").stdout)
    check_schema(doc)
    assert all(d["a"] is None or d["a"]["attribute"] is not None
               for d in doc["files"][0]["differences"])


def test_a_concise_dcf_and_the_builds_dcf_are_equal():
    for name in ("drive", "io"):
        r = run(FLAT / f"{name}.bin", FLAT / f"{name}.dcf")
        assert (r.exit_code, r.stdout) == (0, ""), (name, r.stdout)
    r = run(FLAT / "drive.bin", FLAT / "io.bin", "-q")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[:8] == [
        f"--- {FLAT}/drive.bin", f"+++ {FLAT}/io.bin",
        "@@ 0x1017 @@",                          # no names: two concise DCFs
        "-0x1017sub0: 50",                       # CiA 301's UNSIGNED16
        "+0x1017sub0: 200",
        f"@@ 0x1400: only in {FLAT}/drive.bin @@",
        "-0x1400sub1: 0x00000202 = COB-ID 0x202",
        "-0x1400sub2: 1"]
    r = run(FLAT / "drive.bin", FLAT / "io.bin", "-q", "--ignore", "0x1017,0x1400-0x1BFF")
    assert r.stdout.splitlines()[2:] == [f"@@ 0x6060: only in {FLAT}/drive.bin @@",
                                         "-0x6060sub0: 08 (1 byte)"]


def test_a_concise_dcf_of_no_entry(tmp_path):
    """Four zero bytes: network build's <slave>.bin for a slave without writes. Against a
    DCF it is every entry the DCF configures, missing."""
    empty = tmp_path / "x.bin"
    empty.write_bytes(bytes(4))
    r = run(empty, SAMPLES / "device.eds")
    assert (r.exit_code, r.stdout) == (0, "")
    r = run(empty, SAMPLES / "device.dcf", "--ignore", "0x1016,0x1800-0x2FFF", "-q")
    assert r.stdout == (f"--- {empty}\n+++ {SAMPLES}/device.dcf\n"
                        f"@@ 0x1017 Producer heartbeat time: only in {SAMPLES}/device.dcf @@\n"
                        "+0x1017sub0 Producer heartbeat time: 500 (UNSIGNED16, rw, not "
                        "mappable)\n")


def test_a_misnamed_file_is_read_by_its_content_with_a_warning(tmp_path):
    fake = tmp_path / "plc.dcf"
    fake.write_bytes((SAMPLES / "plc.bin").read_bytes())
    r = run(fake, SAMPLES / "plc.dcf")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr.splitlines()[0] == (f"{fake}: warning: {fake} is a binary container, not "
                                        "DCF/EDS text as its name says; read as a binary "
                                        "container")
    assert run(fake, SAMPLES / "plc.dcf", "-q").stderr == ""


def test_a_truncated_concise_dcf_is_unreadable(tmp_path):
    """A concise DCF cut short is still told by its content (a count smaller than the file,
    a first entry that writes an object: filekind) and read by the one concise reader,
    whose error names the entry that runs past the end at the byte offset of its size, as
    dump and validate print it; diff cannot compare it: exit 3."""
    bad = tmp_path / "x.bin"
    bad.write_bytes((FLAT / "drive.bin").read_bytes()[:-1])
    r = run(bad, FLAT / "drive.dcf")
    assert (r.exit_code, r.stdout) == (3, "")
    assert r.stderr == (f"{bad}:0xDA: error: entry 22 of 22 (0x6060sub0) claims 1 data "
                        "byte, 0 remain [CON002]\n")
    dumped = CliRunner().invoke(main, ["dump", str(bad)])
    assert (dumped.exit_code, dumped.stderr) == (1, r.stderr)


def test_the_json_form_of_a_concise_dcf_is_compared(tmp_path):
    """``dump -f json`` of a network build's <slave>.bin is the concise DCF's lossless form:
    diff reads it as the concise DCF it records (it was refused, exit 3, in words that
    named the kinds diff takes as the ones it did not)."""
    form = tmp_path / "drive.json"
    dumped = CliRunner().invoke(main, ["dump", "-f", "json", str(FLAT / "drive.bin"),
                                       "-o", str(form)])
    assert dumped.exit_code == 0, dumped.output
    r = run(form, FLAT / "drive.bin")
    assert (r.exit_code, r.stdout, r.stderr) == (
        0, "", f"{form}, {FLAT}/drive.bin: equal; 18 entries compared\n")
    assert run(form, FLAT / "drive.dcf").exit_code == 0
    r = run(form, FLAT / "io.bin", "-q", "--ignore", "0x1400-0x1BFF,0x6060")
    assert (r.exit_code, r.stdout) == (1, f"--- {form}\n+++ {FLAT}/io.bin\n"
                                          "@@ 0x1017 @@\n-0x1017sub0: 50\n+0x1017sub0: 200\n")
    doc = json.loads(run(form, FLAT / "drive.bin", "-f", "json").stdout)
    check_schema(doc)
    assert [doc["files"][0][s]["kind"] for s in "ab"] == ["concise-json", "concise"]
    assert doc["files"][0]["a"]["file"] == str(form)


# -- what cannot be compared ----------------------------------------------------------------

def test_unreadable_inputs_are_exit_3_with_one_line(cd):
    dcf(cd, "a.dcf")
    (cd / "vars.csv").write_text("name,type,direction\nA,UNSIGNED8,input\n")
    (cd / "bad.bin").write_bytes(b"\x30\x00\x00\x00" + b"\x01\x00" * 10)
    (cd / "empty.dcf").write_text("")
    cases = {
        "missing.dcf": "missing.dcf: error: cannot read: No such file or directory [IO001]",
        "vars.csv": "vars.csv: error: vars.csv is not DCF/EDS text (it looks like CSV: "
                    "dcf2bin allocate reads it); dcf2bin diff compares DCF/EDS text, CiA "
                    "311 XML, containers, concise DCFs and the JSON form of either "
                    "[DCF008]",
        "bad.bin": "bad.bin:0x0: error: 24 bytes: too short for the 40-byte header "
                   "[CNT001]",
        "empty.dcf": "empty.dcf: error: the file is empty [DCF056]",
    }
    for name, line in cases.items():
        r = run(name, "a.dcf")
        assert (r.exit_code, r.stdout) == (3, ""), name
        assert r.stderr.splitlines()[0] == line, name


@pytest.mark.parametrize("args, message", [
    (["a.dcf"], "give two inputs to compare, or one and -n N to compare it with that node "
                "on the bus"),
    (["a.dcf", "a.dcf", "-i", "virtual"], "-i/--interface, --channel and --bitrate are for "
                                          "a node: give one input and -n N"),
    (["a.dcf", "."], ". is a folder and a.dcf is not: diff compares a folder with a folder, "
                     "a file with a file"),
    ([".", ".", "-n", "3"], "-n names one node: with two folders each file's own node-ID is "
                            "taken"),
    ([".", "-n", "7"], ". is a folder: with -n, diff compares one file (a DCF, EDS, XDD/XDC, "
                       "container or concise DCF) with that node on the bus; two folders are "
                       "compared with each other"),
])
def test_usage_errors(cd, args, message):
    dcf(cd, "a.dcf")
    r = run(*args)
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: {message}"


# -- output ---------------------------------------------------------------------------------

def check_schema(doc: dict) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.Draft202012Validator.check_schema(schemas.load("diff"))
    jsonschema.validate(doc, schemas.load("diff"))


def test_json_form_exactly(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x60410010", "DefaultValue=0x60400010"),
        ("[6000]", "[6100]\nParameterName=X\nDataType=0x0005\nAccessType=rw\n\n[6000]"))
    r = run("a.dcf", "b.dcf", "-f", "json")
    assert r.exit_code == 1
    doc = json.loads(r.stdout)
    check_schema(doc)
    assert {k: doc[k] for k in ("format", "version", "a", "b", "equal", "scope")} == {
        "format": "dcf2bin-diff", "version": 1, "a": "a.dcf", "b": "b.dcf", "equal": False,
        "scope": {"state_left_out": True, "ignore": [], "values_only": False}}
    f = doc["files"][0]
    assert {k: v for k, v in f.items() if k != "differences"} == {
        "a": {"file": "a.dcf", "kind": "dcf", "node_id": 5, "errors": 0},
        "b": {"file": "b.dcf", "kind": "dcf", "node_id": 5, "errors": 0},
        "equal": False, "compared": 11, "left_out": {"state": 3, "ignored": 0, "no_value": 0},
        "objects_only_in_a": [], "objects_only_in_b": ["0x6100"]}
    assert f["differences"] == [
        {"index": "0x1A00", "subindex": 1, "change": "changed",
         "object": "TPDO1 mapping parameter", "name": "Mapped object 1",
         "differs_in": ["value"],
         "a": {"value": "0x60410010", "data": "10004160",
               "meaning": "0x6041sub0 Statusword, 16 bits", "datatype": "UNSIGNED32",
               "access": "rw", "pdo_mapping": False, "attribute": None,
               "where": "a.dcf:73"},
         "b": {"value": "0x60400010", "data": "10004060",
               "meaning": "0x6040sub0 Controlword, 16 bits", "datatype": "UNSIGNED32",
               "access": "rw", "pdo_mapping": False, "attribute": None,
               "where": "b.dcf:73"}},
        {"index": "0x6100", "subindex": 0, "change": "added", "object": "X", "name": "X",
         "differs_in": [], "a": None,
         "b": {"value": "0 (no value given)", "data": "00", "meaning": None,
               "datatype": "UNSIGNED8", "access": "rw", "pdo_mapping": False,
               "attribute": None, "where": "b.dcf:82"}}]


def test_json_of_equal_inputs_and_of_a_container(tmp_path):
    doc = json.loads(run(SAMPLES / "plc.dcf", SAMPLES / "plc.bin", "-f", "json").stdout)
    check_schema(doc)
    assert doc["equal"] is True and doc["files"][0]["differences"] == []
    assert doc["files"][0]["b"] == {"file": f"{SAMPLES}/plc.bin", "kind": "bin",
                                    "node_id": None, "errors": 0}


def test_output_file_and_quiet(cd):
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "DefaultValue=17"))
    r = run("a.dcf", "b.dcf", "-o", "out.txt", "-q")
    assert (r.exit_code, r.stdout, r.stderr) == (1, "", "")
    assert (cd / "out.txt").read_text().splitlines()[-1] == \
        "+0x1017sub0 Producer heartbeat time: 17"
    r = run("a.dcf", "a.dcf", "-o", "out.txt", "-q")
    assert r.exit_code == 0 and (cd / "out.txt").read_text() == ""
    r = run("a.dcf", "b.dcf", "-o", "a.dcf")
    assert r.exit_code == 2 and (cd / "a.dcf").read_text() == BASE


def test_colour_only_on_a_terminal(cd):
    """In a pseudo-terminal the lines are coloured; piped, or with NO_COLOR, never."""
    dcf(cd, "a.dcf")
    dcf(cd, "b.dcf", ("DefaultValue=0x10", "DefaultValue=17"))
    cmd = [sys.executable, "-m", "dcf2bin", "diff", "a.dcf", "b.dcf", "-q"]
    env = {k: v for k, v in os.environ.items() if k != "NO_COLOR"}

    def on_terminal(env) -> str:
        master, slave = pty.openpty()
        try:
            p = subprocess.run(cmd, stdout=slave, stderr=subprocess.DEVNULL, env=env,
                               timeout=60, cwd=cd)
            os.close(slave)
            slave = None
            out = b""
            while True:
                try:
                    chunk = os.read(master, 4096)
                except OSError:
                    break
                if not chunk:
                    break
                out += chunk
        finally:
            if slave is not None:
                os.close(slave)
            os.close(master)
        assert p.returncode == 1
        return out.decode().replace("\r\n", "\n")
    assert on_terminal(env) == (
        "\x1b[1m--- a.dcf\x1b[0m\n\x1b[1m+++ b.dcf\x1b[0m\n"
        "\x1b[36m@@ 0x1017 Producer heartbeat time @@\x1b[0m\n"
        "\x1b[31m-0x1017sub0 Producer heartbeat time: 16\x1b[0m\n"
        "\x1b[32m+0x1017sub0 Producer heartbeat time: 17\x1b[0m\n")
    assert "\x1b" not in on_terminal({**env, "NO_COLOR": "1"})
    piped = subprocess.run(cmd, capture_output=True, env=env, timeout=60, cwd=cd)
    assert piped.returncode == 1 and b"\x1b" not in piped.stdout

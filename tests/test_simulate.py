"""compile, validate and simulate with the DynBuildOd emulation (SPEC §8, D-11), through the
command line: the three one-line edits of issue 9, exact diagnostics and reports."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from click.testing import CliRunner
from conftest import SAMPLES

from dcf2bin.cli import main

PLC = (SAMPLES / "plc.dcf").read_text()


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


def edited(tmp_path, line: int, text: str):
    """plc.dcf with one line replaced."""
    lines = PLC.split("\n")
    lines[line - 1] = text
    p = tmp_path / "plc.dcf"
    p.write_text("\n".join(lines))
    return p


HINT = "    hint: the target's DynBuildOd() would refuse this container; see dcf2bin-simulate(1)"

# The three one-line edits of issue 9: line, new text, the error compile prints.
EDITS = [
    (293, "ParameterValue=0xA4C00110",
     "293: error: 0x1A00sub1 = 0xA4C00110: 0xA4C0sub1 has 8 bits, the mapping says 16; would "
     "make DynBuildOd return 0x78 kCopPdoErrorMapp [TGT078]"),
    (293, "ParameterValue=0x30000120",
     "293: error: 0x1A00sub1 = 0x30000120: the mapped object 0x3000 does not exist; would make "
     "DynBuildOd return 0x31 kCopObdIndexNotExist [TGT031]"),
    (236, "ParameterValue=$NODEID+0x700",
     "236: error: 0x1800sub1 = 0x00000710: TPDO1 (0x1800): CAN-ID 0x710 is restricted by CiA "
     "301 (0x701-0x77F); would make DynBuildOd return 0x23 kCopCobIllegalCanId [TGT023]"),
]


def test_plc_sample_lines_are_the_ones_edited():
    lines = PLC.split("\n")
    assert lines[292] == "ParameterValue=0xA4C00108" and lines[290 - 1].startswith("AccessType")
    assert lines[235] == "ParameterValue=0x180 + $NODEID"


@pytest.mark.parametrize("line, text, error", EDITS)
def test_compile_refuses_the_three_edits(tmp_path, line, text, error):
    src = edited(tmp_path, line, text)
    out = tmp_path / "plc.bin"
    r = run("compile", src)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [f"{src}:{error}", HINT, f"{src}: 1 error, nothing written"]
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".dcf2bin-")] == []


@pytest.mark.parametrize("line, text, error", EDITS)
def test_no_target_check_writes_with_a_warning(tmp_path, line, text, error):
    src = edited(tmp_path, line, text)
    r = run("compile", src, "--no-target-check", "-o", tmp_path / "x.bin")
    assert r.exit_code == 0
    assert r.stderr.splitlines() == [f"{src}:{error.replace(': error: ', ': warning: ', 1)}",
                                     HINT]
    assert (tmp_path / "x.bin").stat().st_size > 40


@pytest.mark.parametrize("line, text, error", EDITS)
def test_validate_reports_the_same_finding(tmp_path, line, text, error):
    src = edited(tmp_path, line, text)
    r = run("validate", src)
    assert r.exit_code == 1
    assert f"{src}:{error}" in r.stdout.splitlines()


@pytest.mark.parametrize("line, text, error", EDITS)
def test_simulate_the_edited_dcf(tmp_path, line, text, error):
    src = edited(tmp_path, line, text)
    r = run("simulate", src, "-f", "json")
    assert r.exit_code == 1
    doc = json.loads(r.stdout)
    code = error.split("return ")[1][:4]
    assert (doc["code"], doc["where"], doc["rule"]) == (code, f"{src}:{line}", f"TGT0{code[2:]}")
    assert doc["index"] == "0x" + error.split(": 0x")[1][:4]


def test_a_dcf_that_does_not_compile_has_nothing_to_simulate(tmp_path):
    lines = PLC.split("\n")
    line = next(n for n, text in enumerate(lines, 1) if text.startswith("DefaultValue=")
                and n > lines.index("[A040sub1]"))
    src = edited(tmp_path, line, "DefaultValue=0x1FF")
    r = run("simulate", src)
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr == (f"{src}:{line}: error: 0xA040sub1: value 0x1FF (= 511) out of range "
                        "for UNSIGNED8 (0..255) [DCF200]\n"
                        f"{src}: 1 error, no container to simulate\n")


@pytest.mark.parametrize("name", ["plc", "device", "bild8", "dis2"])
def test_samples_still_compile_byte_identically(tmp_path, name):
    r = run("compile", SAMPLES / f"{name}.dcf", "-o", tmp_path / "x.bin")
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "x.bin").read_bytes() == (SAMPLES / f"{name}.bin").read_bytes()


def test_compile_cob_table_option(tmp_path):
    r = run("compile", SAMPLES / "plc.dcf", "--tx-cobs", "0", "-o", tmp_path / "x.bin")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] == (
        f"{SAMPLES / 'plc.dcf'}:236: error: 0x1800sub1 = 0x00000190: TPDO1 (0x1800) would be "
        "valid TX PDO number 1; the target's TX COB table holds 0; would make DynBuildOd "
        "return 0x20 kCopCobNoFreeEntry [TGT020]")
    assert run("compile", SAMPLES / "plc.dcf", "--tx-cobs", "1", "--rx-cobs", "1",
               "--granularity", "8", "--no-bit-mapping", "-o", tmp_path / "x.bin").exit_code == 0


PLC_TEXT = """\
0x00 kCopSuccessful: {name}: 34 entries applied
process image: 16 bytes (input 8 @ 0, output 8 @ 8); target memory unlimited
created: 9 objects, 30 entries, 70 bytes

PDO           COB-ID      bits    object      len  PI address
RPDO1 0x1400  0x00000210  0..7    0xA040sub1  8    0 (0x0000)
                          8..15   0xA040sub2  8    1 (0x0001)
                          16..23  0xA040sub3  8    2 (0x0002)
                          24..31  0xA040sub4  8    3 (0x0003)
                          32..47  0xA0C0sub3  16   4 (0x0004)
                          48..63  0xA0C0sub4  16   6 (0x0006)
TPDO1 0x1800  0x00000190  0..7    0xA4C0sub1  8    8 (0x0008)
                          8..15   0xA4C0sub2  8    9 (0x0009)
                          16..47  0xA680sub2  32   12 (0x000C)
"""


def test_simulate_container_text():
    r = run("simulate", SAMPLES / "plc.bin")
    assert r.exit_code == 0
    assert r.stdout == PLC_TEXT.format(name=SAMPLES / "plc.bin")
    assert r.stderr == ""


def test_simulate_dcf_uses_its_own_objects_as_static_od():
    r = run("simulate", SAMPLES / "plc.dcf")
    assert r.exit_code == 0
    lines = r.stdout.splitlines()
    assert lines[2] == "created: 4 objects, 13 entries, 18 bytes"   # only the A0xx/A4xx objects
    assert lines[4:] == PLC_TEXT.splitlines()[4:]


def test_simulate_json_form_of_a_container(tmp_path):
    js = tmp_path / "plc.json"
    assert run("dump", SAMPLES / "plc.bin", "-f", "json", "-o", js).exit_code == 0
    r = run("simulate", js, "--format", "json")
    assert r.exit_code == 0
    doc = json.loads(r.stdout)
    assert {k: doc[k] for k in ("code", "name", "ok", "entry", "index", "subindex", "offset",
                                "reason")} == {"code": "0x00", "name": "kCopSuccessful", "ok": True,
                                               "entry": None, "index": None, "subindex": None,
                                               "offset": None, "reason": None}
    assert doc["descriptor"] == {"memory": None, "pi_size": 16, "input_offset": 0,
                                 "input_size": 8, "output_offset": 8, "output_size": 8}
    assert (doc["format"], doc["version"]) == ("dcf2bin-simulate", 1)
    assert doc["pdos"][1] == {"direction": "tx", "comm_index": "0x1800", "cob_id": "0x00000190",
                              "can_id": "0x00000190", "bits": 48, "mapped": [
                                  {"index": "0xA4C0", "subindex": 1, "bits": 8, "pi_address": 8},
                                  {"index": "0xA4C0", "subindex": 2, "bits": 8, "pi_address": 9},
                                  {"index": "0xA680", "subindex": 2, "bits": 32,
                                   "pi_address": 12}]}
    assert doc["created"]["objects"][:2] == ["0x1017", "0x1400"]


def test_simulate_pi_memory_failure_exit_1():
    r = run("simulate", SAMPLES / "plc.bin", "--pi-size", "15")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[0] == (f"0xA0 kCopDynNoMemory: {SAMPLES / 'plc.bin'}: the "
                                        "process image needs 16 bytes, the target gives 15")
    doc = json.loads(run("simulate", SAMPLES / "plc.bin", "--pi-size", "15", "-f",
                         "json").stdout)
    assert (doc["code"], doc["name"], doc["entry"], doc["step"]) == ("0xA0", "kCopDynNoMemory",
                                                                     None, "memory")


def test_validate_container_runs_the_emulation():
    r = run("validate", "--pi-size", "4", SAMPLES / "plc.bin")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[0] == (
        f"{SAMPLES / 'plc.bin'}: error: the process image needs 16 bytes, the target gives 4; "
        "would make DynBuildOd return 0xA0 kCopDynNoMemory [TGT0A0]")
    assert run("validate", "--pi-size", "4", "--no-target-check",
               SAMPLES / "plc.bin").exit_code == 0
    assert run("validate", "--pi-size", "4", "--ignore", "TGT", SAMPLES / "plc.bin").exit_code == 0


def test_simulate_failing_entry_in_a_container(tmp_path):
    src = edited(tmp_path, 293, "ParameterValue=0xA4C00110")
    assert run("compile", src, "--no-target-check", "-o", tmp_path / "x.bin").exit_code == 0
    r = run("simulate", tmp_path / "x.bin")
    assert r.exit_code == 1
    assert r.stdout.splitlines() == [
        f"0x78 kCopPdoErrorMapp: {tmp_path / 'x.bin'}: entry 30 0x1A00sub1 = 0xA4C00110 "
        "(byte 0x136): 0xA4C0sub1 has 8 bits, the mapping says 16",
        "process image: 16 bytes (input 8 @ 0, output 8 @ 8); target memory unlimited",
        "created: 9 objects, 27 entries, 58 bytes (before entry 30)"]
    data = (tmp_path / "x.bin").read_bytes()
    assert data[0x136:0x139] == b"\x00\x1a\x01"        # the entry's WORD index and sub


def test_simulate_static_od_for_a_container():
    r = run("simulate", SAMPLES / "dis2.bin")
    assert r.exit_code == 0
    assert r.stderr.splitlines()[0] == (
        f"{SAMPLES / 'dis2.bin'}: warning: mapped object 0x6040sub0 is not in the container and "
        "the static OD is unknown: its existence, access and length were not checked "
        "(give --static-od) [TGT103]")
    r = run("simulate", SAMPLES / "dis2.bin", "--static-od", SAMPLES / "dis2.dcf")
    assert r.exit_code == 0 and r.stderr == ""


def test_simulate_unreadable_input_exit_3(tmp_path):
    r = run("simulate", tmp_path / "nope.bin")
    assert r.exit_code == 3
    assert r.stderr == f"{tmp_path / 'nope.bin'}: error: cannot read: No such file or directory [IO001]\n"


def test_simulate_broken_container_is_0xA1():
    r = run("simulate", "-", "--from", "bin", input=b"\x00" * 12)
    assert r.exit_code == 1
    assert r.stdout.splitlines()[0] == ("0xA1 kCopDynInvalidConfig: <stdin>: byte 0x0: "
                                        "12 bytes: too short for the 40-byte header")


def test_emit_od_reads_back_in_validate_and_canopen(tmp_path):
    canopen = pytest.importorskip("canopen", reason="canopen is optional")
    od_path = tmp_path / "od.dcf"
    r = run("simulate", SAMPLES / "plc.dcf", "--emit-od", od_path, "-q")
    assert r.exit_code == 0
    v = run("validate", od_path)
    assert v.exit_code == 0, v.stdout
    od = canopen.import_od(str(od_path))
    assert od[0x1800][1].default == 0x190
    assert od[0x1A00][3].default == 0xA6800220
    assert od[0xA0C0][3].data_type == 0x03            # INTEGER16, from the CiA 405 range
    # a container alone: no mandatory objects, but readable by both
    od2 = tmp_path / "od2.dcf"
    assert run("simulate", SAMPLES / "plc.bin", "--emit-od", od2, "-q").exit_code == 0
    v = run("validate", od2, "-f", "json")
    rules = {d["rule"] for d in json.loads(v.stdout)["diagnostics"]}
    assert rules <= {"DCF101", "DCF323"}
    assert canopen.import_od(str(od2))[0xA040][1].data_type == 0x05


def test_emit_od_never_overwrites_the_input(tmp_path):
    src = tmp_path / "plc.dcf"
    src.write_text(PLC)
    r = run("simulate", src, "--emit-od", src)
    assert r.exit_code == 2
    assert src.read_text() == PLC


def test_simulate_help_does_not_import_heavy_modules():
    code = ("import sys; from dcf2bin.cli import main\n"
            "try:\n    main(['simulate', '--help'])\nexcept SystemExit:\n    pass\n"
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('construct', 'canopen')"
            " or m.startswith('dcf2bin.dynod'))\nprint(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "NO_COLOR": "1"})
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_bin2dcf_output_compiles_back_with_the_check_on(tmp_path):
    """A DCF that bin2dcf wrote holds the container, not the device: what it lacks (a mapped
    object of the device's static OD) is not checked, so SPEC §4's round trip holds."""
    src = tmp_path / "m.dcf"
    src.write_text("[DeviceComissioning]\nNodeID=1\n\n"
                   "[1800]\nObjectType=0x9\n[1800sub0]\nDataType=0x0005\nAccessType=ro\n"
                   "DefaultValue=2\n[1800sub1]\nDataType=0x0007\nAccessType=rw\n"
                   "ParameterValue=$NODEID+0x180\n[1800sub2]\nDataType=0x0005\nAccessType=rw\n"
                   "DefaultValue=255\n[1A00]\nObjectType=0x9\n[1A00sub0]\nDataType=0x0005\n"
                   "AccessType=rw\nParameterValue=1\n[1A00sub1]\nDataType=0x0007\n"
                   "AccessType=rw\nParameterValue=0x60000108\n")
    r = run("compile", src, "-o", tmp_path / "a.bin")
    assert r.exit_code == 1
    assert "the mapped object 0x6000 does not exist" in r.stderr
    assert run("compile", src, "--no-target-check", "-o", tmp_path / "a.bin").exit_code == 0
    assert run("bin2dcf", tmp_path / "a.bin", "-o", tmp_path / "b.dcf").exit_code == 0
    r = run("compile", tmp_path / "b.dcf", "-o", tmp_path / "b.bin")
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "b.bin").read_bytes() == (tmp_path / "a.bin").read_bytes()


def test_pdo_sequence_none_that_writes_a_valid_pdos_mapping_is_refused():
    """--pdo-sequence none writes the COB-ID before the mapping: CiA 301 forbids changing
    the mapping of a valid PDO, so the target would return 0x78."""
    r = run("compile", SAMPLES / "plc.dcf", "--pdo-sequence", "none", "-o", "-")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] == (
        f"{SAMPLES / 'plc.dcf'}:160: error: 0x1600sub0 = 0x06: the mapping of RPDO1 (0x1400) "
        "is changed while the PDO is valid (set COB-ID bit 31 first); would make DynBuildOd "
        "return 0x78 kCopPdoErrorMapp [TGT078]")

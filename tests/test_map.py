"""dcf2bin map: the variable map of SPEC.md §9.1 in every format (D-14 for IEC and C).

The goldens under tests/golden/plc/ were checked by hand against SPEC §2.2 and seed 000
Bild 8: A4C0 sub1..3 (UNSIGNED8 outputs) -> output bytes 0, 1, 2; A580 sub3 (UNSIGNED16)
-> element 2 -> byte 4; byte 3 unused. samples/plc.dcf: A040 sub1..4 -> input 0..3,
A0C0 sub3/4 (INTEGER16) -> input 4, 6; output area at 8; A4C0 sub1/2 -> output 0, 1
(image 8, 9); A680 sub2 (UNSIGNED32) -> element 1 -> output 4 (image 12); PI 16 bytes.
"""
from __future__ import annotations

import json
import shutil
import subprocess

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin.plc.idents import identifiers
from dcf2bin.plc.varmap import VarMap, make_row
from dcf2bin import datatypes as dt

GOLDEN = ROOT / "tests" / "golden" / "plc"
FORMATS = {"text": "txt", "csv": "csv", "json": "json", "iec": "st", "c": "h", "svg": "svg",
           "html": "html"}
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) here")


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


@pytest.mark.parametrize("sample", ["bild8", "plc"])
@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_golden(sample, fmt):
    r = run("map", SAMPLES / f"{sample}.dcf", "--format", fmt)
    assert r.exit_code == 0, r.stderr
    assert r.stdout == (GOLDEN / f"{sample}.map.{FORMATS[fmt]}").read_text()


def test_bild8_numbers_in_json():
    """Seed Bild 8 as numbers (SPEC §2.2's required worked example)."""
    doc = json.loads(run("map", SAMPLES / "bild8.dcf", "-f", "json").stdout)
    rows = [(v["index"], v["subindex"], v["type"], v["direction"], v["offset"], v["address"],
             v["size"]) for v in doc["variables"]]
    assert (doc["format"], doc["version"], doc["file"]) == ("dcf2bin-map", 1, "bild8.dcf")
    assert rows == [("0xA4C0", 1, "UNSIGNED8", "output", 0, 0, 1),
                    ("0xA4C0", 2, "UNSIGNED8", "output", 1, 1, 1),
                    ("0xA4C0", 3, "UNSIGNED8", "output", 2, 2, 1),
                    ("0xA580", 3, "UNSIGNED16", "output", 4, 4, 2)]
    assert doc["areas"] == {"pi_size": 6, "input_offset": 0, "input_size": 0,
                            "output_offset": 0, "output_size": 6}


def test_container_without_eds_uses_generated_names(tmp_path):
    r = run("map", SAMPLES / "bild8.bin", "-f", "csv")
    assert r.exit_code == 0, r.stderr
    assert r.stdout.splitlines() == [
        "name,index,subindex,type,direction,offset,address,size",
        "out_UNSIGNED8_A4C0_1,0xA4C0,1,UNSIGNED8,output,0,0,1",
        "out_UNSIGNED8_A4C0_2,0xA4C0,2,UNSIGNED8,output,1,1,1",
        "out_UNSIGNED8_A4C0_3,0xA4C0,3,UNSIGNED8,output,2,2,1",
        "out_UNSIGNED16_A580_3,0xA580,3,UNSIGNED16,output,4,4,2"]


@pytest.mark.parametrize("fmt", ["csv", "json", "iec", "c"])
def test_container_with_eds_equals_the_dcf_map(fmt):
    """The map of plc.bin with --eds plc.dcf is the map of plc.dcf (but for the source name)."""
    from_dcf = run("map", SAMPLES / "plc.dcf", "-f", fmt).stdout
    from_bin = run("map", SAMPLES / "plc.bin", "--eds", SAMPLES / "plc.dcf", "-f", fmt).stdout
    assert from_bin.replace("plc.bin", "plc.dcf") == from_dcf


def test_json_dump_input(tmp_path):
    dump = tmp_path / "plc.json"
    assert run("dump", SAMPLES / "plc.bin", "-f", "json", "-o", dump).exit_code == 0
    assert run("map", dump, "-f", "csv").stdout == run("map", SAMPLES / "plc.bin", "-f",
                                                          "csv").stdout


def test_address_base_area_container(tmp_path):
    """A container built with --address-base area: the map still gives image addresses."""
    out = tmp_path / "area.bin"
    assert run("compile", SAMPLES / "plc.dcf", "--address-base", "area", "-o", out).exit_code == 0
    want = run("map", SAMPLES / "plc.bin", "-f", "csv").stdout
    assert run("map", out, "--address-base", "area", "-f", "csv").stdout == want
    r = run("map", out, "-f", "csv")   # read as image addresses: outputs fall outside
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] == (
        f"{out}: error: 0xA4C0sub1: PI address 0x0000 (1 bytes) lies outside the output area "
        "(image bytes 8..15, 8 bytes); was the container built with --address-base area? "
        "[MAP001]")


def test_dcf_with_errors_gives_no_map(tmp_path):
    src = tmp_path / "bad.dcf"
    src.write_text("[A4C0]\nObjectType=0x8\nSubNumber=2\n[A4C0sub1]\nParameterName=x\n"
                   "DataType=0x0006\n")
    r = run("map", src)
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr.splitlines()[-1] == f"{src}: 1 error, no map"


def test_denotation_wins_over_parametername(tmp_path):
    src = tmp_path / "d.dcf"
    src.write_text("[A040]\nObjectType=0x8\nSubNumber=3\n[A040sub1]\nParameterName=Plain\n"
                   "Denotation=Pump running\n[A040sub2]\nParameterName=Other\n")
    assert run("map", src, "-f", "csv").stdout.splitlines()[1:] == [
        "Pump running,0xA040,1,UNSIGNED8,input,0,0,1", "Other,0xA040,2,UNSIGNED8,input,1,1,1"]


def test_compact_sub_obj_names(tmp_path):
    src = tmp_path / "c.dcf"
    src.write_text("[A0C0]\nParameterName=Temp\nObjectType=0x8\nCompactSubObj=2\n"
                   "DataType=0x0003\nAccessType=ro\nPDOMapping=1\n")
    assert run("map", src, "-f", "csv").stdout.splitlines()[1:] == [
        "Temp1,0xA0C0,1,INTEGER16,input,0,0,2", "Temp2,0xA0C0,2,INTEGER16,input,2,2,2"]


# -- IEC 61131-3 (D-14) ------------------------------------------------------------------------

def _vm(*rows):
    return VarMap("t.dcf", [make_row(name, idx, sub, dt.BY_NAME[t], d, off, off)
                            for name, idx, sub, t, d, off in rows], (0, 0, 0, 0, 0))


def test_identifiers_d14():
    vm = _vm(("Speed set-point", 0xA100, 1, "UNSIGNED16", "input", 0),
             ("2nd value", 0xA100, 2, "UNSIGNED16", "input", 2),
             ("STEP", 0xA100, 3, "UNSIGNED16", "input", 4),
             ("time", 0xA100, 4, "UNSIGNED16", "input", 6),
             ("__x__", 0xA100, 5, "UNSIGNED16", "input", 8),
             ("", 0xA100, 6, "UNSIGNED16", "input", 10),
             ("***", 0xA100, 0x1F, "UNSIGNED16", "input", 12),
             ("speed SET point", 0xA100, 8, "UNSIGNED16", "input", 14),
             ("Speed_set_point_2", 0xA100, 9, "UNSIGNED16", "input", 16),
             ("Ölstand", 0xA100, 10, "UNSIGNED16", "input", 18))
    assert identifiers(vm.rows) == [
        "Speed_set_point", "_2nd_value", "nv_STEP", "nv_time", "x", "nv_A100_6", "nv_A100_1F",
        "speed_SET_point_2", "Speed_set_point_2_2", "lstand"]


def test_iec_all_kinds_and_comment_breaking():
    from dcf2bin.plc import iec
    vm = _vm(("a(*b*)c", 0xA080, 1, "BOOLEAN", "input", 0),
             ("i8", 0xA000, 1, "INTEGER8", "input", 1),
             ("u24", 0xA180, 1, "UNSIGNED24", "input", 3),
             ("r", 0xA6C0, 2, "REAL32", "output", 4),
             ("l", 0xA880, 1, "INTEGER64", "output", 8),
             ("u48", 0xA780, 3, "UNSIGNED48", "output", 18))
    text, diags = iec.render(vm)
    assert diags == []
    assert text.splitlines()[4:-1] == [
        "    a_b_c AT %IX0.0 : BOOL; (* a( *b* )c 0xA080sub1 *)",
        "    i8 AT %IB1 : SINT; (* i8 0xA000sub1 *)",
        "    u24 AT %IB3 : ARRAY[0..2] OF BYTE; (* u24 0xA180sub1 *)",
        "    nv_r AT %QD4 : REAL; (* r 0xA6C0sub2 *)",  # R is an IL operator
        "    l AT %QL8 : LINT; (* l 0xA880sub1 *)",
        "    u48 AT %QB18 : ARRAY[0..5] OF BYTE; (* u48 0xA780sub3 *)"]
    text, diags = iec.render(vm, "element")
    assert diags == []
    assert [line.split(" : ")[0].split(" AT ")[1] for line in text.splitlines()[4:-1]] == [
        "%IX0.0", "%IB1", "%IB3", "%QD1", "%QL1", "%QB18"]


def test_iec_element_addressing_cli():
    r = run("map", SAMPLES / "plc.dcf", "-f", "iec", "--iec-addressing", "element")
    assert r.exit_code == 0
    assert [ln for ln in r.stdout.splitlines() if " AT " in ln][4:] == [
        "    AnaIn_3 AT %IW2 : INT; (* AnaIn_3 0xA0C0sub3 *)",
        "    AnaIn_4 AT %IW3 : INT; (* AnaIn_4 0xA0C0sub4 *)",
        "    DigOut_1 AT %QB0 : USINT; (* DigOut_1 0xA4C0sub1 *)",
        "    DigOut_2 AT %QB1 : USINT; (* DigOut_2 0xA4C0sub2 *)",
        "    Setpoint_2 AT %QD1 : UDINT; (* Setpoint_2 0xA680sub2 *)"]


def test_iec_element_addressing_alignment_error(tmp_path):
    """A PPOffset of 1 puts an UNSIGNED16 at byte 1: %IW cannot address it."""
    src = tmp_path / "odd.dcf"
    src.write_text("[DynamicChannels]\nNrOfSeg=1\nType1=0x0006\nDir1=ro\nRange1=0xA100-0xA13F\n"
                   "PPOffset1=1\n\n[A100]\nObjectType=0x8\nSubNumber=2\n\n[A100sub1]\n"
                   "ParameterName=w\nDataType=0x0006\n")
    assert run("map", src, "-f", "iec").exit_code == 0
    r = run("map", src, "-f", "iec", "--iec-addressing", "element")
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr.splitlines() == [
        f"{src}:12: error: 0xA100sub1 (UNSIGNED16) lies at byte 1 of the input area, not a "
        "multiple of 2: %IW cannot address it in element addressing [MAP002]"]


# -- C header ------------------------------------------------------------------------------------

@needs_cc
@pytest.mark.parametrize("sample", ["bild8", "plc"])
def test_c_header_compiles_and_holds_the_map(tmp_path, sample):
    doc = json.loads(run("map", SAMPLES / f"{sample}.dcf", "-f", "json").stdout)
    header = tmp_path / "map.h"
    header.write_text(run("map", SAMPLES / f"{sample}.dcf", "-f", "c", "--prefix", "NV_").stdout)
    idents = [f"NV_{v['name'].upper()}_ADDR" for v in doc["variables"]]
    areas = ["NV_PI_SIZE", "NV_IN_OFFSET", "NV_IN_SIZE", "NV_OUT_OFFSET", "NV_OUT_SIZE"]
    prints = "".join(f'    printf("%u\\n", (unsigned){m});\n' for m in areas + idents)
    (tmp_path / "main.c").write_text(f'#include <stdio.h>\n#include "map.h"\n#include "map.h"\n'
                                     f"int main(void) {{\n{prints}    return 0;\n}}\n")
    exe = tmp_path / "main"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", "-o", str(exe),
                    str(tmp_path / "main.c")], check=True, cwd=tmp_path)
    got = [int(x) for x in subprocess.run([str(exe)], capture_output=True, text=True,
                                           check=True).stdout.split()]
    a = doc["areas"]
    assert got == [a["pi_size"], a["input_offset"], a["input_size"], a["output_offset"],
                   a["output_size"]] + [v["address"] for v in doc["variables"]]


def test_c_header_avoids_reserved_names():
    from dcf2bin.plc import cheader
    vm = _vm(("1st", 0xA040, 1, "UNSIGNED8", "input", 0),
             ("x__y", 0xA040, 2, "UNSIGNED8", "input", 1))
    lines = [ln.split()[1] for ln in cheader.render(vm).splitlines()
             if ln.startswith("#define") and ln.endswith("*/")]
    assert lines == ["DCF_1ST_ADDR", "DCF_X_Y_ADDR"]


@pytest.mark.parametrize("prefix", ["_X", "X__", "1X", "a-b", ""])
def test_bad_prefix_is_a_usage_error(prefix):
    r = run("map", SAMPLES / "bild8.dcf", "-f", "c", "--prefix", prefix)
    assert r.exit_code == 2
    assert r.stderr.startswith(f"dcf2bin: error: --prefix: prefix '{prefix}' must start with")


# -- the container as C source ------------------------------------------------------------------

@pytest.mark.parametrize("sample,args", [("bild8", []),
                                         ("plc", ["--c-name", "plc_dcf", "--c-decl",
                                                  "static CONST BYTE ROM"])])
def test_compile_format_c_golden(sample, args):
    r = run("compile", SAMPLES / f"{sample}.dcf", "--format", "c", "-o", "-", *args)
    assert r.exit_code == 0, r.stderr
    assert r.stdout == (GOLDEN / f"{sample}.c").read_text()


@needs_cc
@pytest.mark.parametrize("sample", ["bild8", "plc", "device", "dis2"])
def test_compile_format_c_builds_the_same_bytes(tmp_path, sample):
    src = tmp_path / "container.c"
    r = run("compile", SAMPLES / f"{sample}.dcf", "--format", "c", "--c-name", "dcf_data",
            "-o", src)
    assert r.exit_code == 0, r.stderr
    (tmp_path / "main.c").write_text(
        '#include <stdio.h>\n#include "container.c"\nint main(void) {\n'
        '    fwrite(dcf_data, 1, sizeof dcf_data, stdout);\n'
        '    fprintf(stderr, "%u", (unsigned)DCF_DATA_PI_SIZE);\n    return 0;\n}\n')
    exe = tmp_path / "main"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", "-o", str(exe),
                    str(tmp_path / "main.c")], check=True)
    done = subprocess.run([str(exe)], capture_output=True, check=True)
    data = (SAMPLES / f"{sample}.bin").read_bytes()
    assert done.stdout == data
    from dcf2bin.container import read
    c, _ = read(data)
    assert int(done.stderr) == (c.pi[0] if c.pi is not None else 0)


def test_compile_format_c_default_name_and_output(tmp_path):
    src = tmp_path / "9-plc.dcf"
    src.write_bytes((SAMPLES / "bild8.dcf").read_bytes())
    assert run("compile", src, "--format", "c").exit_code == 0
    text = (tmp_path / "9-plc.c").read_text()
    assert "#define DCF_9_PLC_PI_SIZE 6\n" in text
    assert "const unsigned char dcf_9_plc[127] = {\n" in text


@pytest.mark.parametrize("args,msg", [
    (["--c-name", "_x"], "C name '_x' must start with a letter"),
    (["--c-name", "a__b"], "C name 'a__b' must start with a letter"),
    (["--c-decl", "int x; char"], "declaration 'int x; char' must be one line")])
def test_compile_format_c_bad_names(args, msg):
    r = run("compile", SAMPLES / "bild8.dcf", "--format", "c", "-o", "-", *args)
    assert r.exit_code == 2 and r.stdout == ""
    assert r.stderr.startswith(f"dcf2bin: error: {msg}")


# -- containers: what they cannot say ------------------------------------------------------------

DYN = ("[DynamicChannels]\nNrOfSeg=1\nType1=0x0007\nDir1=rww\nRange1=0xA900-0xA93F\n"
       "PPOffset1=8\n\n[A900]\nObjectType=0x8\nSubNumber=2\n\n[A900sub1]\n"
       "ParameterName=Counter\nDataType=0x0007\n\n[A4C0]\nObjectType=0x8\nSubNumber=2\n\n"
       "[A4C0sub1]\nParameterName=Lamp\n")


def test_container_outside_the_405_ranges_needs_the_eds(tmp_path):
    src = tmp_path / "dyn.dcf"
    src.write_text(DYN)
    out = tmp_path / "dyn.bin"
    assert run("compile", src, "-o", out).exit_code == 0
    want = ["Lamp,0xA4C0,1,UNSIGNED8,output,0,0,1", "Counter,0xA900,1,UNSIGNED32,output,8,8,4"]
    assert run("map", src, "-f", "csv").stdout.splitlines()[1:] == want
    r = run("map", out, "-f", "csv")
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr.splitlines() == [
        f"{out}: error: 0xA900sub1: data type unknown (4 bytes, no CiA 405 range of that "
        "size); give the device's EDS/DCF with --eds [MAP001]"]
    r = run("map", out, "--eds", src, "-f", "csv")
    assert r.exit_code == 0
    assert r.stdout.splitlines()[1:] == want


def test_container_without_pi_segments(tmp_path):
    out = tmp_path / "nopi.bin"
    assert run("compile", SAMPLES / "plc.dcf", "--no-process-image", "-o", out).exit_code == 0
    r = run("map", out)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{out}: error: the container has network variables but no PI address or PI "
        "parameter segment (built with --no-process-image?), so their addresses are unknown "
        "[MAP001]"]


def test_container_on_stdin_and_eds_with_a_dcf_is_usage():
    r = run("map", "-", "-f", "csv", input=(SAMPLES / "bild8.bin").read_bytes())
    assert r.exit_code == 0
    assert r.stdout.splitlines()[4] == "out_UNSIGNED16_A580_3,0xA580,3,UNSIGNED16,output,4,4,2"
    r = run("map", SAMPLES / "plc.dcf", "--eds", SAMPLES / "plc.dcf")
    assert r.exit_code == 2
    assert r.stderr == ("dcf2bin: error: --eds is for a container input; a DCF names its "
                        "own variables\n")


def test_compile_json_dump_as_c(tmp_path):
    dump = tmp_path / "plc.json"
    assert run("dump", SAMPLES / "plc.bin", "-f", "json", "-o", dump).exit_code == 0
    r = run("compile", dump, "--format", "c", "--c-name", "plc_dcf", "--c-decl",
            "static CONST BYTE ROM", "-o", "-")
    assert r.exit_code == 0
    assert r.stdout == (GOLDEN / "plc.c").read_text().replace("from plc.dcf", "from plc.json")

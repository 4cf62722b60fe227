"""compile's checks of values beyond encoding them: 0x-prefixed OCTET_STRING/DOMAIN hex
(DCF218: accepted, the bytes after the prefix, a warning) and LowLimit/HighLimit
(DCF210-DCF212: as validate words them; DCF212 an error for a written value, a warning
"(not written by compile)" for the others).
"""
from __future__ import annotations

import re

import pytest
from click.testing import CliRunner

from conftest import CORPUS
from dcf2bin import model, to_dcf
from dcf2bin.cli import main
from dcf2bin.compiler import CompileOptions, compile_path
from dcf2bin.lint import Options, run as lint_run

HEAD = "[DeviceComissioning]\nNodeID=5\n\n"   # lines 1-3


def run(*args):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def write(tmp_path, text, name="v.dcf"):
    path = tmp_path / name
    path.write_text(HEAD + text)
    return path


def lines(text: str, path) -> list[str]:
    """The diagnostic lines of a CLI run, the path made relative."""
    return [ln.replace(str(path), "F") for ln in text.splitlines()]


def validate(path, *rules):
    res = lint_run([str(path)], Options(active=set(rules)))
    return [(d.rule, d.line, d.severity.value, d.message) for d in res.diagnostics]


# ---------------------------------------------------------------------------------------
# DCF218: 0x-prefixed hex (Sevcon DriveWizard)

HEX = """[2000]
ParameterName=Data
DataType=0x000F
AccessType=rw
DefaultValue={default}
ParameterValue={param}

[2001]
ParameterName=Key
DataType=0x000A
AccessType=rw
ParameterValue={octets}

[2002]
ParameterName=Unwritten key
DataType=0x000A
AccessType=ro
ParameterValue={octets}
"""


def test_0x_hex_compiles_to_the_bytes_without_the_prefix_with_a_warning(tmp_path):
    with_prefix = write(tmp_path, HEX.format(default="0x00", param="0x0102A0FF",
                                             octets="0XBEEF"), "with.dcf")
    without = write(tmp_path, HEX.format(default="00", param="0102A0FF", octets="BEEF"),
                    "without.dcf")
    plain = run("compile", str(without), "-o", str(tmp_path / "without.bin"))
    assert plain.exit_code == 0 and plain.output == ""
    res = run("compile", str(with_prefix), "-o", str(tmp_path / "with.bin"))
    assert res.exit_code == 0
    assert lines(res.output, with_prefix) == [
        "F:8: warning: 0x2000sub0 DefaultValue: DOMAIN value starts with 0x; hex byte pairs "
        "are written without it (the bytes after it are used) (not written by compile) "
        "[DCF218]",
        "F:9: warning: 0x2000sub0 ParameterValue: DOMAIN value starts with 0x; hex byte "
        "pairs are written without it (the bytes after it are used) [DCF218]",
        "F:15: warning: 0x2001sub0 ParameterValue: OCTET_STRING value starts with 0x; hex "
        "byte pairs are written without it (the bytes after it are used) [DCF218]",
        "F:21: warning: 0x2002sub0 ParameterValue: OCTET_STRING value starts with 0x; hex "
        "byte pairs are written without it (the bytes after it are used) (not written by "
        "compile) [DCF218]",
    ]
    data = (tmp_path / "with.bin").read_bytes()
    assert data == (tmp_path / "without.bin").read_bytes()
    assert b"\x01\x02\xa0\xff" in data and b"\xbe\xef" in data


def test_validate_words_0x_hex_as_compile_does(tmp_path):
    path = write(tmp_path, HEX.format(default="0x00", param="0x0102A0FF", octets="0XBEEF"))
    words = "starts with 0x; hex byte pairs are written without it (the bytes after it are used)"
    assert validate(path, "DCF218", "DCF200") == [
        ("DCF218", 8, "warning", f"0x2000sub0 DefaultValue: DOMAIN value {words}"),
        ("DCF218", 9, "warning", f"0x2000sub0 ParameterValue: DOMAIN value {words}"),
        ("DCF218", 15, "warning", f"0x2001sub0 ParameterValue: OCTET_STRING value {words}"),
        ("DCF218", 21, "warning", f"0x2002sub0 ParameterValue: OCTET_STRING value {words}"),
    ]


def test_0x_hex_round_trips_through_bin2dcf(tmp_path):
    path = write(tmp_path, HEX.format(default="0x00", param="0x0102A0FF", octets="0XBEEF"))
    first = compile_path(str(path))
    assert first.ok
    back = to_dcf(first.data)
    assert back.roundtrip and back.diagnostics == []
    again = compile_path(str(tmp_path / "back.dcf"), data=back.to_bytes())
    assert again.ok and again.data == first.data
    assert "0x0102A0FF" not in back.text and "0102A0FF" in back.text


def test_a_bad_0x_hex_value_is_still_dcf200(tmp_path):
    path = write(tmp_path, HEX.format(default="00", param="0x012", octets="BEEF"))
    res = run("compile", str(path), "-o", str(tmp_path / "v.bin"))
    assert res.exit_code == 1
    assert lines(res.output, path) == [
        "F:9: error: 0x2000sub0: odd number of hex digits in DOMAIN value '0x012' [DCF200]",
        "F: 1 error, nothing written",
    ]


SEVCON = CORPUS / "sevcon" / ("2019-06-13-ME0913-0705-0013-GEN4-110V-300A-PARINAUTES-"
                              "Ok-a-vide-19h39.dcf")


@pytest.mark.skipif(not SEVCON.is_file(), reason=f"Sevcon corpus DCF not found at {SEVCON}")
def test_sevcon_drivewizard_dcf_compiles_and_round_trips(tmp_path):
    """Sevcon's DriveWizard writes its DOMAINs (0x4617sub1, 0x5600subN) with 0x. The file
    also has written values outside their limits (DCF212) and a TPDO on CAN-ID 0x178,
    which CiA 301 restricts (TGT023): both are turned into warnings here, as a user of
    such a file does with --no-limit-check --no-target-check."""
    opts = CompileOptions(target_check="warning", limit_check="warning")
    res = compile_path(str(SEVCON), opts)
    assert res.ok, [d.format() for d in res.diagnostics if d.severity.value == "error"]
    prefixed = sorted(d.line for d in res.diagnostics if d.rule == "DCF218")
    assert len(prefixed) == 10   # 0x4617sub1 (value and default), 0x5600sub1..7, subA
    assert not [d for d in res.diagnostics if d.rule == "DCF200"]
    # the same bytes as the file with the prefixes taken out
    text = SEVCON.read_bytes().decode("latin-1").split("\n")
    for line in prefixed:
        text[line - 1] = re.sub(r"=(\s*)0[xX]", r"=\1", text[line - 1], count=1)
    stripped = compile_path(str(SEVCON), opts, data="\n".join(text).encode("latin-1"))
    assert stripped.ok and stripped.data == res.data
    assert not [d for d in stripped.diagnostics if d.rule == "DCF218"]
    dev = model.load(str(SEVCON))
    domain = dev.encode(dev.entry(0x4617, 1))
    assert len(domain) == 9488 and domain == b"\xff" * 9488
    assert domain in res.data
    # compile -> bin2dcf -> compile gives the same bytes
    back = to_dcf(res.data)
    again = compile_path(str(tmp_path / "back.dcf"), CompileOptions(target_check="warning"),
                         data=back.to_bytes())
    assert again.ok and again.data == res.data


# ---------------------------------------------------------------------------------------
# DCF210-DCF212: LowLimit/HighLimit

LIMITS = """[2000]
ParameterName=Speed
DataType=0x0006
AccessType=rw
LowLimit=10
HighLimit=0x64
ParameterValue={param}
DefaultValue={default}

[2001]
ParameterName=Read-only speed
DataType=0x0006
AccessType=ro
LowLimit=10
HighLimit=100
ParameterValue=200

[2002]
ParameterName=Broken limits
DataType=0x0002
AccessType=rw
LowLimit=200
HighLimit=5
ParameterValue=1

[2003]
ParameterName=Inverted limits
DataType=0x0005
AccessType=rw
LowLimit=9
HighLimit=5
ParameterValue=7
"""


def test_compile_reports_limits_as_validate_does(tmp_path):
    """A written value outside its limits is a warning by default (issue 26 item 17: values
    read back from a device, vendors' junk limits), an error with --limit-check error;
    validate says the same words, every one an error."""
    path = write(tmp_path, LIMITS.format(param="5", default="101"))
    later = [
        "F:11: warning: 0x2000sub0 DefaultValue 101 is above HighLimit 0x64 (= 100) "
        "(not written by compile) [DCF212]",
        "F:19: warning: 0x2001sub0 ParameterValue 200 is above HighLimit 100 "
        "(not written by compile) [DCF212]",
        "F:25: warning: 0x2002sub0 LowLimit: value 200 out of range for INTEGER8 (-128..127) "
        "[DCF210]",
        "F:33: warning: 0x2003sub0 LowLimit 9 is greater than HighLimit 5 [DCF211]",
    ]
    res = run("compile", str(path), "-o", str(tmp_path / "v.bin"))
    assert res.exit_code == 0
    assert lines(res.output, path) == [
        "F:10: warning: 0x2000sub0 ParameterValue 5 is below LowLimit 10 [DCF212]",
        "    hint: the value is written as it is; --limit-check error refuses it",
    ] + later
    assert (tmp_path / "v.bin").read_bytes() == compile_path(str(path)).data
    res = run("compile", "--limit-check", "error", str(path), "-o", str(tmp_path / "e.bin"))
    assert res.exit_code == 1 and not (tmp_path / "e.bin").exists()
    assert lines(res.output, path) == [
        "F:10: error: 0x2000sub0 ParameterValue 5 is below LowLimit 10 [DCF212]",
        "    hint: change the value or the limits; without --limit-check error this is a "
        "warning",
    ] + later + ["F: 1 error, nothing written"]
    # validate: the same words, at its own severities
    assert validate(path, "DCF210", "DCF211", "DCF212") == [
        ("DCF212", 10, "error", "0x2000sub0 ParameterValue 5 is below LowLimit 10"),
        ("DCF212", 11, "error", "0x2000sub0 DefaultValue 101 is above HighLimit 0x64 (= 100)"),
        ("DCF212", 19, "error", "0x2001sub0 ParameterValue 200 is above HighLimit 100"),
        ("DCF210", 25, "error",
         "0x2002sub0 LowLimit: value 200 out of range for INTEGER8 (-128..127)"),
        ("DCF211", 33, "error", "0x2003sub0 LowLimit 9 is greater than HighLimit 5"),
    ]


@pytest.mark.parametrize("args", [[], ["--no-limit-check"], ["--limit-check", "warning"]])
def test_no_limit_check_is_the_default_a_written_value_outside_its_limits_a_warning(
        tmp_path, args):
    path = write(tmp_path, LIMITS.format(param="5", default="50"))
    res = run("compile", "-q", *args, str(path), "-o", str(tmp_path / "v.bin"))
    assert res.exit_code == 0 and res.output == ""
    full = compile_path(str(path), limit_check="warning")
    assert [(d.rule, d.line, d.severity.value) for d in full.diagnostics
            if d.rule == "DCF212"] == [("DCF212", 10, "warning"), ("DCF212", 19, "warning")]
    assert (tmp_path / "v.bin").read_bytes() == full.data == compile_path(str(path)).data
    assert compile_path(str(path), limit_check="error").data is None


def test_no_limit_check_with_limit_check_error_is_a_usage_error(tmp_path):
    path = write(tmp_path, LIMITS.format(param="5", default="50"))
    res = run("compile", "--no-limit-check", "--limit-check", "error", str(path), "-o",
              str(tmp_path / "v.bin"))
    assert res.exit_code == 2 and not (tmp_path / "v.bin").exists()
    assert res.output.splitlines()[-1] == ("Error: --no-limit-check and --limit-check error "
                                           "contradict each other; give one")


def test_values_within_limits_compile_silently(tmp_path):
    text = LIMITS.format(param="100", default="10").split("\n\n[2001]")[0] + "\n"
    path = write(tmp_path, text)
    res = run("compile", str(path), "-o", str(tmp_path / "v.bin"))
    assert res.exit_code == 0 and res.output == ""


def test_limits_with_nodeid_and_compact_sub_objects(tmp_path):
    text = """[2000]
ParameterName=COB
DataType=0x0007
AccessType=rw
LowLimit=$NODEID+0x180
ParameterValue=0x180

[2100]
ParameterName=Array
ObjectType=0x8
CompactSubObj=3
DataType=0x0005
AccessType=rw
HighLimit=4
DefaultValue=5

[2100Value]
NrOfEntries=1
2=3
"""
    path = write(tmp_path, text)
    res = run("compile", "--limit-check", "error", str(path), "-o", str(tmp_path / "v.bin"))
    assert res.exit_code == 1
    assert lines(res.output, path) == [
        "F:9: error: 0x2000sub0 ParameterValue 0x180 (= 384) is below LowLimit "
        "$NODEID+0x180 (= 389) [DCF212]",
        "    hint: change the value or the limits; without --limit-check error this is a "
        "warning",
        "F:18: warning: 0x2100sub1 DefaultValue 5 is above HighLimit 4 (not written by "
        "compile) [DCF212]",
        "F: 1 error, nothing written",
    ]

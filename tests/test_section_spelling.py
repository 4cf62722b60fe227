"""Section and key spellings the reader accepts but a user should hear about: a subindex
of more than 2 hex digits (DCF061, and it is the same section as the canonical one), and
[DeviceInfo] numbers that are no integers (DCF040, at the key's line)."""
from __future__ import annotations

from click.testing import CliRunner

from dcf2bin import ini
from dcf2bin.cli import main
from dcf2bin.compiler import compile_path

OBJ = """[DeviceComissioning]
NodeID=5

[2000]
ParameterName=Pair
ObjectType=0x9
SubNumber=2

[2000sub0]
ParameterName=Count
DataType=0x0005
AccessType=ro
DefaultValue=1

[2000{sub}]
ParameterName=Value
DataType=0x0005
AccessType=rw
ParameterValue=7
"""


def run(*args):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def test_three_digit_subindex_is_the_canonical_section_with_a_warning(tmp_path):
    odd, plain = tmp_path / "odd.dcf", tmp_path / "plain.dcf"
    odd.write_text(OBJ.format(sub="SUB001"))
    plain.write_text(OBJ.format(sub="sub1"))
    res = run("validate", "--select", "DCF061,DCF010,DCF005", str(odd))
    assert res.output.splitlines() == [
        f"{odd}:15: warning: [2000SUB001] has a subindex of 3 digits; it is read as "
        "[2000sub1], the canonical spelling [DCF061]",
        "0 errors, 1 warning, 0 infos in 1 file"]
    assert res.exit_code == 0
    assert compile_path(str(odd)).data == compile_path(str(plain)).data is not None
    assert run("validate", "--select", "DCF061", str(plain)).output.splitlines() == [
        "0 errors, 0 warnings, 0 infos in 1 file"]


def test_three_digit_subindex_and_the_canonical_one_are_a_duplicate(tmp_path):
    path = tmp_path / "dup.dcf"
    path.write_text(OBJ.format(sub="sub001") + "\n" + OBJ.split("\n\n")[-1].format(sub="sub1"))
    f = ini.read(str(path))
    assert [(d.section, d.key, d.first_line, d.line) for d in f.duplicates] == [
        ("2000sub1", None, 15, 21)]
    res = run("compile", str(path), "-o", str(tmp_path / "dup.bin"))
    assert res.exit_code == 1
    assert res.output.splitlines()[0] == (
        f"{path}:21: error: section [2000sub001] repeated (first at line 15) [DCF010]")


def test_a_subindex_above_0xff_in_three_digits_is_dcf005_not_dcf061(tmp_path):
    path = tmp_path / "big.dcf"
    path.write_text(OBJ.format(sub="sub100"))
    res = run("validate", "--select", "DCF061,DCF005", str(path))
    assert res.output.splitlines() == [
        f"{path}:15: error: subindex 0x100 of [2000sub100] is above 0xFF [DCF005]",
        "1 error, 0 warnings, 0 infos in 1 file"]


def test_canonical_section_names():
    assert ini.canonical_section("1018sub001") == "1018sub1"
    assert ini.canonical_section("1018SUB0A") == "1018suba"
    assert ini.canonical_section("1018sub100") == "1018sub100"   # above 0xFF: DCF005
    assert ini.canonical_section("1018sub") == "1018sub"


def test_bad_deviceinfo_pdo_number_points_at_its_key(tmp_path):
    path = tmp_path / "info.dcf"
    path.write_text("[DeviceInfo]\nVendorName=x\nNrOfRXPDO=1\nCompactPDO=zz\n\n"
                    + OBJ.format(sub="sub1"))
    res = run("compile", str(path), "-o", str(tmp_path / "info.bin"))
    assert res.exit_code == 1
    assert res.output.splitlines() == [
        f"{path}:4: error: [DeviceInfo] CompactPDO: invalid integer 'zz' [DCF040]",
        f"{path}: 1 error, nothing written"]

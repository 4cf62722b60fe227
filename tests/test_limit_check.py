"""Issue 26 item 17: real Sevcon files compile although their values lie outside their own
LowLimit/HighLimit (values read back from the drive; limits such as LowLimit=0x65766173,
"save" in ASCII). A written value outside its limits is a warning by default; the errors
left are those the target itself would refuse, or values no container can hold."""
from __future__ import annotations

from collections import Counter

import pytest
from click.testing import CliRunner
from conftest import CORPUS

from dcf2bin.cli import main
from dcf2bin.compiler import compile_path

SEVCON = CORPUS / "sevcon"
GEN4 = "2019-06-13-ME0913-0705-0013-GEN4-110V-300A-PARINAUTES-Ok-a-vide-19h39.dcf"

# file -> (errors with default options, errors with --entries all -n 1, DCF212 warnings)
# as Counter({rule: n}), and the number of DCF212 findings (all warnings now)
EXPECTED = {
    # its TPDO1 on CAN-ID 0x178, which CiA 301 restricts: DynBuildOd returns 0x23
    GEN4: ({"TGT023": 1}, {"TGT023": 1}, 14),
    # 325 values that do not fit their own DataType (0x1017 UNSIGNED8 = 500, ...) and 18
    # PDO COB-IDs typed other than UNSIGNED32: no container can hold them as typed
    "High Power espAC_pc0x0502f050_rev0x00030001.eds": ({}, {"DCF200": 325, "DCF403": 18}, 1),
    "Nano_pc0x04013019_rev0x0001000b.eds": ({}, {}, 4),
    "espAC_pc0x00000000_rev0x00000000.eds": ({}, {}, 0),
    "espAC_pc0x01FF0000_rev0x00020000.eds": ({}, {}, 0),
    "espac_pc0x0502f014_rev0x00020002.eds": ({}, {}, 1),
    # line 726 'Direction referecne' has no '=': the file is broken text
    "pst_pc0x02011806_rev0x00010000.eds": ({"DCF002": 1}, {"DCF002": 1}, 2),
    "sevcon_gen4.eds": ({}, {}, 0),
}


def _present(name: str):
    return pytest.param(name, marks=pytest.mark.skipif(
        not (SEVCON / name).is_file(), reason=f"corpus file sevcon/{name} not found under "
        f"{CORPUS} (a fresh clone without ../shared)"))


@pytest.mark.parametrize("name", [_present(n) for n in EXPECTED])
def test_sevcon_files_are_refused_only_for_what_the_target_refuses(name):
    path = str(SEVCON / name)
    default, every, limits = EXPECTED[name]
    for options, wanted in (({}, default), ({"select": "all", "node_id": 1}, every)):
        res = compile_path(path, **options)
        errors = Counter(d.rule for d in res.diagnostics if d.severity.value == "error")
        assert errors == Counter(wanted), (name, options)
        assert res.ok == (not wanted)
        found = [d for d in res.diagnostics if d.rule == "DCF212"]
        assert len(found) == limits and all(d.severity.value == "warning" for d in found)


@pytest.mark.skipif(not (SEVCON / GEN4).is_file(), reason=f"Sevcon DCF not found under {CORPUS}")
def test_the_gen4_dcf_on_the_command_line(tmp_path):
    """The DCF of the issue: compile stops only on the restricted CAN-ID; with
    --no-target-check it writes the container, values outside limits as the file gives
    them; validate still reports every limit violation as an error."""
    path = SEVCON / GEN4
    r = CliRunner().invoke(main, ["compile", "-q", str(path), "-o", str(tmp_path / "g.bin")])
    assert r.exit_code == 1 and not (tmp_path / "g.bin").exists()
    assert r.stderr.splitlines() == [
        f"{path}:2453: error: 0x1800sub1 = 0x00000178: TPDO1 (0x1800): CAN-ID 0x178 is "
        "restricted by CiA 301 (0x101-0x180); would make DynBuildOd return 0x23 "
        "kCopCobIllegalCanId [TGT023]",
        "    hint: the target's DynBuildOd() would refuse this container; see "
        "dcf2bin-simulate(1)",
        f"{path}: 1 error, nothing written"]
    r = CliRunner().invoke(main, ["compile", "-q", "--no-target-check", str(path), "-o",
                                  str(tmp_path / "g.bin")])
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "g.bin").read_bytes() == compile_path(
        str(path), target_check="warning").data
    r = CliRunner().invoke(main, ["validate", "--select", "DCF212", str(path)])
    assert r.exit_code == 1
    assert r.stdout.splitlines()[-1] == "14 errors, 0 warnings, 0 infos in 1 file"

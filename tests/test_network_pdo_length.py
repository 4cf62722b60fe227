"""SPEC §5: a PDO maps at most 64 bits (one classic CAN frame). A YAML mapping: longer than
that is NET125 in every network command, and the PDO is linked to nothing (one cause, one
finding). Before: a 144-bit TPDO passed network check with 0 errors, and show -f dbc
described an 18-byte frame."""
from __future__ import annotations

from click.testing import CliRunner

from dcf2bin.cli import main
from test_network_build import SLAVE, build, mini_eds

# mini.eds (TPDO1 maps two objects at most; 0x2000 is a REAL64) and two UNSIGNED32 inputs
EDS = mini_eds("".join(f"[{i}]\nParameterName=u{i}\nObjectType=0x7\nDataType=0x0007\n"
                       "AccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n"
                       for i in ("2002", "2003")))
MAPPING = "  tpdo:\n    1:\n      mapping:\n        - {index: 0x2002}\n        - {index: 0x2003}\n"
LONG = SLAVE + "  tpdo:\n    1:\n      mapping:\n        - {index: 0x2000}\n" \
    "        - {index: 0x2002}\n"


def test_a_mapping_longer_than_64_bits_is_an_error(tmp_path):
    got, res = build(tmp_path, LONG, eds=EDS)
    assert got == ["bus.yml:10: error: io TPDO1 maps 96 bits, more than 64: a PDO is one "
                   "CAN frame of at most 8 bytes [NET125]"]
    assert not res.ok


def test_64_bits_are_a_frame(tmp_path):
    got, res = build(tmp_path, SLAVE + MAPPING, eds=EDS)
    assert got == [] and res.ok


def test_check_and_show_say_it_and_exit_1(tmp_path):
    build(tmp_path, LONG, eds=EDS)               # writes mini.eds, plc.dcf and bus.yml
    line = (f"{tmp_path}/bus.yml:10: error: io TPDO1 maps 96 bits, more than 64: a PDO is "
            "one CAN frame of at most 8 bytes [NET125]")
    for args in (["network", "check"], ["network", "show", "-f", "dbc"]):
        r = CliRunner().invoke(main, args + [str(tmp_path / "bus.yml")])
        assert r.exit_code == 1, args
        assert line in r.output.splitlines(), args

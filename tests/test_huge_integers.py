"""Issue 26 item 3: an integer of thousands of digits, in any input dcf2bin reads, is
refused with the rule and line of the key that holds it, and no message prints an
unbounded number or text (``diagnostics.shorten``).

Before, ``heartbeat_producer: 0x`` and 4,000 ``F`` ended in exit 70: the number was read,
then printing it in decimal inside a message failed (Python refuses to turn an int of more
than 4300 digits into text). One test per input kind, each with the exact message.
"""
from __future__ import annotations

import pytest
from click.testing import CliRunner

from dcf2bin.cli import main
from dcf2bin.diagnostics import shorten
from dcf2bin.network import load_network
from dcf2bin.network.cpj import read as read_cpj

HEX = "0x" + "F" * 4000          # 4000 digits
TOO_LONG = "integer literal too long ({} digits, at most 64)"


def messages(diags, tmp_path) -> list[str]:
    return [d.format().replace(str(tmp_path) + "/", "") for d in diags]


# -- the helper --------------------------------------------------------------------------------

def test_shorten_keeps_a_short_text_and_cuts_a_long_one_in_the_middle():
    assert shorten("0x1017") == "0x1017"
    assert shorten("x" * 60) == "x" * 60
    assert shorten(HEX) == "0x" + "F" * 38 + "..." + "F" * 12 + " (4002 characters)"


def test_shorten_never_prints_a_huge_int_in_decimal():
    # str() of this int raises ValueError (more than 4300 decimal digits)
    assert shorten(int("F" * 4000, 16)) == "0x" + "F" * 38 + "..." + "F" * 12 + \
        " (4002 characters)"
    assert shorten(-(1 << 300)) == "-0x1" + "0" * 36 + "..." + "0" * 12 + " (79 characters)"
    assert shorten(12345) == "12345"


# -- YAML: every integer form PyYAML converts, and a quoted one --------------------------------

@pytest.mark.parametrize("literal,digits", [
    (HEX, 4000),                                  # hexadecimal, converted by PyYAML
    ("0b" + "1" * 5000, 5000),                    # binary
    ("9" * 5000, 5000),                           # decimal: PyYAML's int() itself fails
    ("0" + "7" * 4000, 4001),                     # YAML 1.1 octal
    ("1" + ":30" * 3000, 6001),                   # sexagesimal 1:30:30:...
    ("-" + HEX, 4000),                            # signed
    ("!!int " + "9" * 5000, 5000),                # an explicit tag
    (f'"{HEX}"', 4000),                           # a string: SPEC §1 syntax, values.parse_int
], ids=["hex", "binary", "decimal", "octal", "sexagesimal", "signed", "tagged", "quoted"])
def test_yaml_integer_key_refuses_a_huge_integer_with_its_own_rule_and_line(
        tmp_path, literal, digits):
    p = tmp_path / "bus.yml"
    p.write_text(f"master:\n  node_id: 1\n  heartbeat_producer: {literal}\n"
                 f"  sync_period: {literal}\nio:\n  dcf: io.eds\n  node_id: 5\n  sdo:\n"
                 f"    - {{index: 0x1017, sub_index: {literal}, value: 1}}\n")
    net = load_network(str(p))
    assert messages(net.diagnostics, tmp_path) == [
        f"bus.yml:3: error: heartbeat_producer: {TOO_LONG.format(digits)} [NET004]",
        f"bus.yml:4: error: sync_period: {TOO_LONG.format(digits)} [NET004]",
        f"bus.yml:9: error: sub_index: {TOO_LONG.format(digits)} [NET004]"]


def test_yaml_huge_integer_where_a_text_a_flag_a_number_or_a_pdo_number_stands(tmp_path):
    p = tmp_path / "bus.yml"
    p.write_text(f"master:\n  node_id: 1\n  name: {HEX}\n  heartbeat_multiplier: {HEX}\n"
                 f"io:\n  dcf: io.eds\n  node_id: 5\n  boot: {HEX}\n  tpdo:\n    ? {HEX}\n"
                 # (a plain key is at most 1024 characters: an explicit one)
                 f"    : {{enabled: true}}\n  sdo:\n    - {{index: 0x1017, value: {HEX}}}\n")
    net = load_network(str(p))
    cut = shorten(HEX)
    assert messages(net.diagnostics, tmp_path) == [
        "bus.yml:3: error: name: expected a text, found an integer of 4000 digits [NET004]",
        f"bus.yml:4: error: heartbeat_multiplier: {TOO_LONG.format(4000)} [NET004]",
        "bus.yml:8: error: boot: expected true or false, found an integer of 4000 digits "
        "[NET004]",
        f"bus.yml:10: error: tpdo: PDO number '{cut}' is not an integer 1..512 [NET004]",
        f"bus.yml:13: error: value: {TOO_LONG.format(4000)} [NET004]"]


def test_yaml_long_keys_and_texts_are_cut_in_messages(tmp_path):
    key = "k" * 100_000
    p = tmp_path / "bus.yml"
    # (a plain key is at most 1024 characters: explicit ones)
    p.write_text(f"master:\n  node_id: 1\n  ? {key}\n  : 1\n  ? {key}\n  : 2\n"
                 "io:\n  dcf: io.eds\n"
                 f"  node_id: '$NODEID{'+1' * 50_000}'\n")
    net = load_network(str(p))
    cut = shorten(key)
    assert messages(net.diagnostics, tmp_path) == [
        f"bus.yml:5: error: key '{cut}' repeated (first at line 3) [NET002]",
        f"bus.yml:3: info: key '{cut}' is not used by dcf2bin; ignored [NET007]",
        "bus.yml:9: error: node_id: $NODEID is not allowed in the network file: "
        f"'{shorten('$NODEID' + '+1' * 50_000)}' [NET004]"]


def test_network_check_of_a_huge_heartbeat_is_exit_1_not_70(tmp_path):
    p = tmp_path / "bus.yml"
    p.write_text(f"master:\n  node_id: 1\n  heartbeat_producer: {HEX}\n")
    r = CliRunner().invoke(main, ["network", "check", str(p)])
    assert r.exit_code == 1, r.output
    assert f"{p}:3: error: heartbeat_producer: {TOO_LONG.format(4000)} [NET004]" in r.output


# -- .cpj ----------------------------------------------------------------------------------------

def test_cpj_huge_node_number_and_values(tmp_path):
    p = tmp_path / "net.cpj"
    key = f"Node{'9' * 5000}Present"
    p.write_text(f"[Topology]\nNetName=x\nNodes={HEX}\n{key}=1\nNode2Present={HEX}\n")
    net = read_cpj(str(p))
    assert messages(net.diagnostics, tmp_path) == [
        f"net.cpj:4: error: [Topology] {shorten(key)}: node-ID {TOO_LONG.format(5000)} "
        "[NET053]",
        f"net.cpj:5: error: [Topology] Node2Present: {TOO_LONG.format(4000)} [NET052]",
        f"net.cpj:3: error: [Topology] Nodes: {TOO_LONG.format(4000)} [NET052]",
        "net.cpj:1: error: [Topology] marks no node present [NET057]"]


# -- DCF: a CompactSubObj name key (the values themselves: test_hostile_input.py) ----------------

def test_dcf_compact_name_key_of_thousands_of_digits(tmp_path):
    from dcf2bin import model
    key = "9" * 5000
    p = tmp_path / "c.eds"
    p.write_text("[2000]\nParameterName=x\nObjectType=0x8\nDataType=0x0007\nAccessType=rw\n"
                 f"CompactSubObj=3\n[2000Name]\nNrOfEntries=1\n{key}=abc\n")
    dev = model.load(str(p))
    assert [p.diagnostic.format().replace(str(tmp_path) + "/", "") for p in dev.problems
            if p.diagnostic.rule == "DCF026"] == [
        f"c.eds:9: warning: [2000Name] key '{shorten(key)}' is not a decimal subindex "
        "[DCF026]"]


# -- CSV (allocate) ------------------------------------------------------------------------------

def test_csv_type_code_of_thousands_of_digits(tmp_path):
    from dcf2bin.plc.allocate import AllocationError, read_vars
    name = "v" * 10_000
    data = (f"name,type,direction\na,{HEX},input\n{name},UNSIGNED8,{'x' * 5000}\n"
            "b,0x_6,input\n").encode()
    with pytest.raises(AllocationError) as info:
        read_vars(data, "vars.csv")
    assert [d.format() for d in info.value.diagnostics] == [
        f"vars.csv:2: error: unknown data type '{shorten(HEX)}' (a CiA 306 name such as "
        "UNSIGNED16, or a code such as 0x0006) [ALC006]",
        f"vars.csv:3: error: direction '{shorten('x' * 5000)}' must be input or output "
        "(in, out) [ALC008]",
        # int("0x_6", 16) is 6; the DCF syntax has no '_'
        "vars.csv:4: error: unknown data type '0x_6' (a CiA 306 name such as UNSIGNED16, "
        "or a code such as 0x0006) [ALC006]"]


# -- a command-line option -----------------------------------------------------------------------

def test_option_integer_of_thousands_of_digits(tmp_path):
    r = CliRunner().invoke(main, ["compile", "-n", HEX, "samples/plc.dcf", "-o",
                                  str(tmp_path / "x.bin")])
    assert r.exit_code == 2
    assert r.output.splitlines()[-1] == (
        f"Error: Invalid value for '-n' / '--node-id': '{shorten(HEX)}' is not an integer "
        f"({TOO_LONG.format(4000)}; decimal, 0x hex or 0 octal as in a DCF)")


# -- a user's long text in the messages of validate, diff and export -------------------------

LONG_KEY = "K" * 300
CUT_KEY = "K" * 40 + "..." + "K" * 12 + " (300 characters)"
COMMENT = "; " + "c" * 300
CUT_COMMENT = "; " + "c" * 38 + "..." + "c" * 12 + " (302 characters)"


def _long_device(tmp_path):
    from conftest import SAMPLES
    text = (SAMPLES / "device.dcf").read_text()
    text = text.replace("ParameterValue=500", f"ParameterValue=500 {COMMENT}", 1)
    text = text.replace("[DeviceInfo]", f"[DeviceInfo]\n{LONG_KEY}=1", 1)
    path = tmp_path / "long.dcf"
    path.write_text(text)
    return path


def test_validate_quotes_a_long_key_cut(tmp_path):
    path = _long_device(tmp_path)
    r = CliRunner().invoke(main, ["validate", str(path)])
    assert f"{path}:13: warning: key '{CUT_KEY}' is not defined by CiA 306 for [DeviceInfo] " \
           "[DCF050]" in r.stdout.splitlines()


def test_export_quotes_a_long_comment_cut(tmp_path):
    path = _long_device(tmp_path)
    r = CliRunner().invoke(main, ["export", "-f", "canopennode", str(path), "-o",
                                  str(tmp_path / "od")])
    assert (r.exit_code, r.stderr) == (0, (
        f"{path}:95: warning: 0x1017sub0: comment '{CUT_COMMENT}' after the number is "
        "ignored [DCF203]\n"))


@pytest.mark.parametrize("args, message", [
    (["validate", "--select", "Z" * 300, "{device}"], "Invalid value for '--select' / "
     f"'--ignore': '{'Z' * 40}...{'Z' * 12} (300 characters)' matches no rule id, id prefix "
     "or rule name (see --list-rules)"),
    (["diff", "--ignore", "0x2000-" + "z" * 300, "{device}", "{device}"], "Invalid value for "
     f"'--ignore': '0x2000-{'z' * 33}...{'z' * 12} (307 characters)' is not an entry or range "
     "(an index such as 0x1017, an entry such as 0x1018sub4, or a range such as "
     "0x2000-0x2FFF)"),
    (["export", "-f", "port-c", "--prefix", "-" * 300, "{device}", "-o", "x.c"], "Invalid "
     f"value for '--prefix': '{'-' * 40}...{'-' * 12} (300 characters)' is not a C "
     "identifier"),
])
def test_option_texts_are_cut_in_usage_errors(tmp_path, monkeypatch, args, message):
    from conftest import SAMPLES
    monkeypatch.chdir(tmp_path)
    r = CliRunner().invoke(main, [a.format(device=SAMPLES / "device.dcf") for a in args])
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: {message}"

"""Issue 26 item 13: every argument of every public API function (docs/api.md) is checked as
the command line checks its option, in the same words: a value the command would refuse
raises ValueError, one of the wrong type TypeError -- never a compile that silently uses
node-ID 200, nor a misleading finding (TGT023 for node-ID 0).

The ranges and choices are declared once (dcf2bin/argspec.py) and used by the click
options and the API alike; the last tests check that every option of that meaning in every
command takes its type from there."""
from __future__ import annotations

import dataclasses

import click
import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES

import dcf2bin
from dcf2bin import argspec, compiler
from dcf2bin.cli import main
from dcf2bin.cli.common import Choice, Integer, Number

PLC_DCF = str(SAMPLES / "plc.dcf")
PLC_BIN = str(SAMPLES / "plc.bin")
BUS = str(ROOT / "tests" / "golden" / "network" / "flat" / "bus.yml")


def _compile_options(kw):
    return lambda: dcf2bin.compile_path(PLC_DCF, **kw)


# (id, call, exception, message): one or more cases for every argument of every function
CASES = [
    # compile_path / compile_file: the call's own arguments ...
    ("compile_path-path", lambda: dcf2bin.compile_path(3), TypeError,
     "path must be a path (str or os.PathLike), not int"),
    ("compile_path-opts", lambda: dcf2bin.compile_path(PLC_DCF, "all"), TypeError,
     "opts must be a CompileOptions or None, not str"),
    ("compile_path-data", lambda: dcf2bin.compile_path("x.dcf", data="[1000]"), TypeError,
     "data must be bytes or None, not str"),
    ("compile_path-unknown", lambda: dcf2bin.compile_path(PLC_DCF, nodeid=5), TypeError,
     "CompileOptions.__init__() got an unexpected keyword argument 'nodeid'"),
    ("compile_file-path", lambda: dcf2bin.compile_file(None), TypeError,
     "path must be a path (str or os.PathLike), not NoneType"),
    ("compile_file-node_id", lambda: dcf2bin.compile_file(PLC_DCF, node_id=128), ValueError,
     "node_id: 128 is not in the range 1<=x<=127"),
    # ... and every CompileOptions field
    ("node_id-200", _compile_options({"node_id": 200}), ValueError,
     "node_id: 200 is not in the range 1<=x<=127"),
    ("node_id-0", _compile_options({"node_id": 0}), ValueError,
     "node_id: 0 is not in the range 1<=x<=127"),
    ("node_id--1", _compile_options({"node_id": -1}), ValueError,
     "node_id: -1 is not in the range 1<=x<=127"),
    ("node_id-str", _compile_options({"node_id": "5"}), TypeError,
     "node_id must be an int or None, not str"),
    ("node_id-bool", _compile_options({"node_id": True}), TypeError,
     "node_id must be an int or None, not bool"),
    ("select", _compile_options({"select": "some"}), ValueError,
     "select: 'some' is not one of 'auto', 'all'."),
    ("pdo_sequence", _compile_options({"pdo_sequence": "dis2"}), ValueError,
     "pdo_sequence: 'dis2' is not one of 'cia301', 'none'."),
    ("static_od", _compile_options({"static_od": 7}), TypeError,
     "static_od must be a path (str or os.PathLike) or None, not int"),
    ("process_image", _compile_options({"process_image": "no"}), TypeError,
     "process_image must be a bool, not str"),
    ("pi_align-3", _compile_options({"pi_align": 3}), ValueError,
     "pi_align: 3 is not one of 1, 2, 4, 8."),
    ("pi_align-str", _compile_options({"pi_align": "8"}), TypeError,
     "pi_align must be an int, not str"),
    ("pi_size", _compile_options({"pi_size": -1}), ValueError,
     "pi_size: -1 is not in the range x>=0"),
    ("address_base", _compile_options({"address_base": "Image"}), ValueError,
     "address_base: 'Image' is not one of 'image', 'area'."),
    ("container_version", _compile_options({"container_version": 0x10000}), ValueError,
     "container_version: 65536 is not in the range 0<=x<=65535"),
    ("allow_external_files", _compile_options({"allow_external_files": 1}), TypeError,
     "allow_external_files must be a bool, not int"),
    ("profile", _compile_options({"profile": "dis3"}), ValueError,
     "profile: 'dis3' is not one of 'cia301', 'dis2'."),
    ("append-str", _compile_options({"append": "extra.writes"}), TypeError,
     "append must be a list or tuple of paths, not str"),
    ("append-item", _compile_options({"append": (3,)}), TypeError,
     "append must be a list or tuple of paths, not tuple"),
    ("target_check", _compile_options({"target_check": "strict"}), ValueError,
     "target_check: 'strict' is not one of 'error', 'warning', 'off'."),
    ("tx_cobs", _compile_options({"tx_cobs": -2}), ValueError,
     "tx_cobs: -2 is not in the range x>=0"),
    ("rx_cobs", _compile_options({"rx_cobs": 1.5}), TypeError,
     "rx_cobs must be an int or None, not float"),
    ("granularity", _compile_options({"granularity": 16}), ValueError,
     "granularity: 16 is not one of 8, 64."),
    ("bit_mapping", _compile_options({"bit_mapping": None}), TypeError,
     "bit_mapping must be a bool, not NoneType"),
    ("limit_check", _compile_options({"limit_check": "off"}), ValueError,
     "limit_check: 'off' is not one of 'error', 'warning'."),
    # the container functions
    ("read_container-source", lambda: dcf2bin.read_container(3), TypeError,
     "source must be bytes, a path (str or os.PathLike) or a BinContainer, not int"),
    ("read_container-name", lambda: dcf2bin.read_container(PLC_BIN, name=1), TypeError,
     "name must be a str or None, not int"),
    ("dump_json-source", lambda: dcf2bin.dump_json([1, 2]), TypeError,
     "source must be bytes, a path (str or os.PathLike) or a BinContainer, not list"),
    ("dump_json-name", lambda: dcf2bin.dump_json(PLC_BIN, name=b"x"), TypeError,
     "name must be a str or None, not bytes"),
    ("dump_text-source", lambda: dcf2bin.dump_text(None), TypeError,
     "source must be bytes, a path (str or os.PathLike) or a BinContainer, not NoneType"),
    ("dump_text-eds", lambda: dcf2bin.dump_text(PLC_BIN, eds=5), TypeError,
     "eds must be a path (str or os.PathLike), not int"),
    ("dump_text-full", lambda: dcf2bin.dump_text(PLC_BIN, full="yes"), TypeError,
     "full must be a bool, not str"),
    ("dump_text-name", lambda: dcf2bin.dump_text(PLC_BIN, name=2), TypeError,
     "name must be a str or None, not int"),
    ("from_json-doc", lambda: dcf2bin.from_json(3), TypeError,
     "doc must be a str, bytes or a dict, not int"),
    ("from_json-name", lambda: dcf2bin.from_json("{}", name=None), TypeError,
     "name must be a str, not NoneType"),
    ("to_dcf-source", lambda: dcf2bin.to_dcf(1.0), TypeError,
     "source must be bytes, a path (str or os.PathLike) or a BinContainer, not float"),
    ("to_dcf-eds", lambda: dcf2bin.to_dcf(PLC_BIN, eds=["x.eds"]), TypeError,
     "eds must be a path (str or os.PathLike), not list"),
    ("to_dcf-dcf_name", lambda: dcf2bin.to_dcf(PLC_BIN, dcf_name=3), TypeError,
     "dcf_name must be a str or None, not int"),
    ("to_dcf-name", lambda: dcf2bin.to_dcf(PLC_BIN, name=3), TypeError,
     "name must be a str or None, not int"),
    # validate
    ("validate-paths", lambda: dcf2bin.validate(3), TypeError,
     "paths must be a path (str or os.PathLike) or an iterable of paths, not int"),
    ("validate-paths-item", lambda: dcf2bin.validate([PLC_DCF, None]), TypeError,
     "paths must be a path (str or os.PathLike) or an iterable of paths, not list"),
    ("validate-select-type", lambda: dcf2bin.validate(PLC_DCF, select=4), TypeError,
     "select must be a str, an iterable of str or None, not int"),
    ("validate-select", lambda: dcf2bin.validate(PLC_DCF, select="DCF9999"), ValueError,
     "'DCF9999' matches no rule id, id prefix or rule name (see --list-rules)"),
    ("validate-ignore", lambda: dcf2bin.validate(PLC_DCF, ignore=[1]), TypeError,
     "ignore must be a str, an iterable of str or None, not list"),
    ("validate-profile", lambda: dcf2bin.validate(PLC_DCF, profile="DIS2"), ValueError,
     "profile: 'DIS2' is not one of 'cia301', 'dis2'."),
    ("validate-node_id", lambda: dcf2bin.validate(PLC_DCF, node_id=0), ValueError,
     "node_id: 0 is not in the range 1<=x<=127"),
    ("validate-pi_size", lambda: dcf2bin.validate(PLC_DCF, pi_size=-8), ValueError,
     "pi_size: -8 is not in the range x>=0"),
    ("validate-pi_align", lambda: dcf2bin.validate(PLC_DCF, pi_align=16), ValueError,
     "pi_align: 16 is not one of 1, 2, 4, 8."),
    ("validate-address_base", lambda: dcf2bin.validate(PLC_DCF, address_base=""), ValueError,
     "address_base: '' is not one of 'image', 'area'."),
    ("validate-allow_external_files",
     lambda: dcf2bin.validate(PLC_DCF, allow_external_files="yes"), TypeError,
     "allow_external_files must be a bool, not str"),
    # networks
    ("load_network-path", lambda: dcf2bin.load_network(3), TypeError,
     "path must be a path (str or os.PathLike), not int"),
    ("load_network-data", lambda: dcf2bin.load_network(BUS, data="x: 1"), TypeError,
     "data must be bytes or None, not str"),
    ("configure_network", lambda: dcf2bin.configure_network(BUS), TypeError,
     "network must be a Network (from load_network), not str"),
    ("build_network-path", lambda: dcf2bin.build_network(b"bus.yml"), TypeError,
     "path must be a path (str or os.PathLike), not bytes"),
    ("build_network-outdir", lambda: dcf2bin.build_network(BUS, 3), TypeError,
     "outdir must be a path (str or os.PathLike) or None, not int"),
    ("build_network-data", lambda: dcf2bin.build_network(BUS, data=[]), TypeError,
     "data must be bytes or None, not list"),
    ("check_network-path", lambda: dcf2bin.check_network(None), TypeError,
     "path must be a path (str or os.PathLike), not NoneType"),
    ("check_network-select", lambda: dcf2bin.check_network(BUS, select=5), TypeError,
     "select must be a str, an iterable of str or None, not int"),
    ("check_network-ignore", lambda: dcf2bin.check_network(BUS, ignore=[None]), TypeError,
     "ignore must be a str, an iterable of str or None, not list"),
    ("check_network-max_load", lambda: dcf2bin.check_network(BUS, max_load=101), ValueError,
     "max_load: 101.0 is not in the range 0<=x<=100."),
    ("check_network-max_load-type", lambda: dcf2bin.check_network(BUS, max_load="80"),
     TypeError, "max_load must be a number, not str"),
    ("check_network-net", lambda: dcf2bin.check_network(BUS, net=0), ValueError,
     "net: 0 is not in the range x>=1"),
    # the model
    ("load-path", lambda: dcf2bin.load(3), TypeError,
     "path must be a path (str or os.PathLike), not int"),
    ("load-node_id", lambda: dcf2bin.load(PLC_DCF, node_id=200), ValueError,
     "node_id: 200 is not in the range 1<=x<=127"),
    ("load-allow_external_files", lambda: dcf2bin.load(PLC_DCF, allow_external_files=None),
     TypeError, "allow_external_files must be a bool, not NoneType"),
    ("load-data", lambda: dcf2bin.load("x.dcf", data="[1000]"), TypeError,
     "data must be bytes or None, not str"),
]


@pytest.mark.parametrize("call,exc,message", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_a_wrong_argument_raises_in_the_commands_words(call, exc, message):
    with pytest.raises(exc) as info:
        call()
    assert str(info.value) == message
    assert type(info.value) is exc or type(info.value).__name__ == "SelectorError"


def test_every_api_function_has_its_arguments_checked():
    """Each public function of docs/api.md, and each of its parameters, has a case above."""
    import inspect
    seen = {c[0].split("-")[0] for c in CASES}
    fields = {f.name for f in dataclasses.fields(compiler.CompileOptions)}
    assert fields <= seen
    for name in dcf2bin.api.__all__:
        fn = getattr(dcf2bin.api, name)
        if not inspect.isfunction(fn):
            continue
        params = set(inspect.signature(fn).parameters) - {"options"}
        covered = {c[0].split("-")[1] for c in CASES if c[0].startswith(name + "-")}
        if name in ("compile_path", "compile_file"):
            covered |= fields | {"path", "opts", "data"}
        elif name == "configure_network":
            covered.add("network")
        assert params <= covered, (name, params - covered)


def test_the_issue_calls():
    """node_id=200 returned ok with RPDO COB-ID 0x2C8; node_id=0 gave TGT023; pi_align=3
    was taken. Valid values at the ends of each range still compile."""
    with pytest.raises(ValueError, match=r"^node_id: 200 is not in the range 1<=x<=127$"):
        dcf2bin.compile_path(PLC_DCF, node_id=200)
    for node_id in (1, 127):
        assert dcf2bin.compile_path(PLC_DCF, node_id=node_id).ok
    for align in (1, 2, 4, 8):
        assert dcf2bin.compile_path(PLC_DCF, pi_align=align).ok
    res = dcf2bin.compile_path(PLC_DCF, container_version=0xFFFF, pi_size=0x1000, append=[],
                               granularity=8, limit_check="error", target_check="off")
    assert res.ok and dcf2bin.read_container(res.data).version == 0xFFFF


def test_compile_options_check_on_construction_and_replace():
    with pytest.raises(ValueError, match=r"^pi_align: 3 is not one of 1, 2, 4, 8\.$"):
        compiler.CompileOptions(pi_align=3)
    opts = compiler.CompileOptions(append=[SAMPLES / "dis2_identification.writes"],
                                   static_od=SAMPLES / "device.eds")
    assert opts.append == (str(SAMPLES / "dis2_identification.writes"),)
    assert opts.static_od == str(SAMPLES / "device.eds")
    with pytest.raises(ValueError, match=r"^granularity: 7 is not one of 8, 64\.$"):
        dataclasses.replace(opts, granularity=7)


def test_data_may_be_any_bytes_like():
    text = (SAMPLES / "plc.dcf").read_bytes()
    want = (SAMPLES / "plc.bin").read_bytes()
    for data in (text, bytearray(text), memoryview(text)):
        assert dcf2bin.compile_path("plc.dcf", data=data).data == want
        assert dcf2bin.load("plc.dcf", data=data).node_id == 16


# -- the same words on the command line ----------------------------------------------------

# (command line, the API call that means the same)
SAME = [
    (["compile", PLC_DCF, "-o", "-", "-n", "200"], _compile_options({"node_id": 200})),
    (["compile", PLC_DCF, "-o", "-", "--pi-align", "3"], _compile_options({"pi_align": 3})),
    (["compile", PLC_DCF, "-o", "-", "--pi-size", "-1"], _compile_options({"pi_size": -1})),
    (["compile", PLC_DCF, "-o", "-", "--entries", "some"],
     _compile_options({"select": "some"})),
    (["compile", PLC_DCF, "-o", "-", "--pdo-sequence", "dis2"],
     _compile_options({"pdo_sequence": "dis2"})),
    (["compile", PLC_DCF, "-o", "-", "--address-base", "Image"],
     _compile_options({"address_base": "Image"})),
    (["compile", PLC_DCF, "-o", "-", "--container-version", "65536"],
     _compile_options({"container_version": 65536})),
    (["compile", PLC_DCF, "-o", "-", "--profile", "dis3"], _compile_options({"profile": "dis3"})),
    (["compile", PLC_DCF, "-o", "-", "--limit-check", "off"],
     _compile_options({"limit_check": "off"})),
    (["compile", PLC_DCF, "-o", "-", "--granularity", "16"],
     _compile_options({"granularity": 16})),
    (["compile", PLC_DCF, "-o", "-", "--tx-cobs", "-2"], _compile_options({"tx_cobs": -2})),
    (["validate", PLC_DCF, "--pi-align", "16"], lambda: dcf2bin.validate(PLC_DCF, pi_align=16)),
    (["validate", PLC_DCF, "-n", "0"], lambda: dcf2bin.validate(PLC_DCF, node_id=0)),
    (["network", "check", BUS, "--max-load", "101"],
     lambda: dcf2bin.check_network(BUS, max_load=101)),
    (["network", "check", BUS, "--net", "0"], lambda: dcf2bin.check_network(BUS, net=0)),
]


@pytest.mark.parametrize("args,call", SAME, ids=[" ".join(a[:1] + a[-2:]) for a, _ in SAME])
def test_the_command_line_says_the_same_words(args, call):
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 2
    cli = r.stderr.splitlines()[-1]
    with pytest.raises(ValueError) as info:
        call()
    name, _, words = str(info.value).partition(": ")
    assert cli.startswith("Error: Invalid value for '") and cli.endswith("': " + words), \
        (cli, str(info.value))


# -- one table: every option of these meanings takes its type from argspec ----------------

SPEC_OF = {"node_id": argspec.NODE_ID, "manager": argspec.NODE_ID, "pi_size": argspec.COUNT,
           "tx_cobs": argspec.COUNT, "rx_cobs": argspec.COUNT, "pi_align": argspec.PI_ALIGN,
           "address_base": argspec.ADDRESS_BASE, "profile": argspec.PROFILE,
           "entries": argspec.ENTRIES, "pdo_sequence": argspec.PDO_SEQUENCE,
           "granularity": argspec.GRANULARITY, "container_version": argspec.CONTAINER_VERSION,
           "limit_check": argspec.LIMIT_CHECK, "max_load": argspec.MAX_LOAD,
           "net": argspec.NET}


def _commands(group=main, prefix=()):
    for name, cmd in sorted(group.commands.items()):
        if isinstance(cmd, click.Group):
            yield from _commands(cmd, prefix + (name,))
        else:
            yield " ".join(prefix + (name,)), cmd


def test_every_such_option_uses_the_one_table():
    seen = set()
    for name, cmd in _commands():
        for p in cmd.params:
            if not isinstance(p, click.Option) or p.name not in SPEC_OF:
                continue
            assert isinstance(p.type, (Integer, Choice, Number)), (name, p.name, p.type)
            assert p.type.spec is SPEC_OF[p.name], (name, p.name)
            seen.add(p.name)
    assert seen == set(SPEC_OF)


def test_the_table_agrees_with_the_library():
    from dcf2bin import profiles, select
    assert argspec.PROFILE.values == profiles.NAMES
    assert argspec.ENTRIES.values == (select.AUTO, select.ALL)
    assert argspec.PDO_SEQUENCE.values == (select.CIA301, select.NONE)
    assert set(compiler.ARGS) == {f.name for f in dataclasses.fields(compiler.CompileOptions)}

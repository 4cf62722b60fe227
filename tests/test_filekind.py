"""Issue 19: one rule for a file's kind in every command (dcf2bin/filekind.py), and a
sentence that names the right command when the kind is wrong."""
from __future__ import annotations

import uuid

import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES, corpus_files

from dcf2bin import filekind
from dcf2bin.cli import main

PLC_DCF = (SAMPLES / "plc.dcf").read_bytes()
PLC_BIN = (SAMPLES / "plc.bin").read_bytes()


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def _json():
    return run("dump", "-f", "json", SAMPLES / "plc.bin").stdout_bytes


# -- the rule ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["x.bin", "x.dcf", "x.json", "x", ""])
def test_clear_content_wins_over_the_name(name):
    assert filekind.detect(PLC_DCF, name) == filekind.DCF
    assert filekind.detect(PLC_BIN, name) == filekind.CONTAINER
    assert filekind.detect(_json(), name) == filekind.JSON


@pytest.mark.parametrize("data", [b"", b"  \n", b"\x1a", b"\x30\x00\x00\x00\x01\x00",
                                  b"junk without sections\n", b"{", b"\x00" * 64])
def test_unclear_content_goes_by_the_name(data):
    assert filekind.detect(data, "x.bin") == filekind.CONTAINER
    assert filekind.detect(data, "x.DCF") == filekind.DCF
    assert filekind.detect(data, "x.eds") == filekind.DCF
    assert filekind.detect(data, "x.json") == filekind.JSON


def test_without_a_name_binary_is_a_container_and_text_is_dcf():
    assert filekind.detect(b"\x00" * 64) == filekind.CONTAINER
    assert filekind.detect(b"junk\n") == filekind.DCF
    assert filekind.detect(b"{") == filekind.JSON
    # UTF-16 text is text in the wrong encoding: the DCF reader says so (DCF008)
    assert filekind.detect("[FileInfo]\r\n".encode("utf-16")) == filekind.DCF


def test_the_sentences():
    assert filekind.mismatch("fake.bin", filekind.DCF, filekind.CONTAINER) == (
        "fake.bin is DCF/EDS text, not a binary container; use dcf2bin compile to make a "
        "container of it (dcf2bin validate checks it)")
    assert filekind.mismatch("fake.bin", filekind.DCF, (filekind.DCF,)) is None
    assert filekind.misnamed("fake.dcf", filekind.CONTAINER) == (
        "fake.dcf is a binary container, not DCF/EDS text as its name says; read as a "
        "binary container")
    assert filekind.misnamed("x", filekind.CONTAINER) is None
    assert filekind.misnamed("x.bin", filekind.CONTAINER) is None


# -- every command, given the wrong kind ------------------------------------------------------

DCF_IS_NOT = ("is DCF/EDS text, not a binary container{}; use dcf2bin compile to make a "
              "container of it (dcf2bin validate checks it)")
BIN_IS_NOT = ("is a binary container, not DCF/EDS text{}; use dcf2bin dump to read it "
              "(dcf2bin bin2dcf turns it into a DCF)")
JSON_IS_NOT = ("is the JSON form of a container, not {}; use dcf2bin compile to turn it back "
               "into the container")

CONCISE_TOO = " or a concise DCF (CiA 302-3)"     # dump and bin2dcf read both

# (command, arguments before the file, the file's kind, the sentence after "<file> ")
WRONG = [
    ("dump", [], "dcf", DCF_IS_NOT.format(CONCISE_TOO)),
    ("dump", [], "json", JSON_IS_NOT.format("a binary container" + CONCISE_TOO)),
    ("bin2dcf", ["-o", "-"], "dcf", "is DCF/EDS text, not a binary container" + CONCISE_TOO +
     " or the JSON form of either; it is a DCF already (dcf2bin compile makes a container "
     "of it)"),
    ("compile", ["-o", "-"], "bin", BIN_IS_NOT.format(" or its JSON form")),
    ("export", ["-f", "lenze-st"], "bin", BIN_IS_NOT.format("")),
    ("export", ["-f", "lenze-st"], "json", JSON_IS_NOT.format("DCF/EDS text")),
    ("node", ["-n", "3"], "bin", "is a binary container, not DCF/EDS text; run it with "
                                 "dcf2bin node --container {file} --node-id N"),
    ("node", ["-n", "3", "--container"], "dcf", DCF_IS_NOT.format(" or its JSON form")),
]


def _file(tmp_path, kind, name):
    path = tmp_path / name
    path.write_bytes({"dcf": PLC_DCF, "bin": PLC_BIN, "json": _json()}[kind])
    return path


@pytest.mark.parametrize("cmd,before,kind,sentence", WRONG,
                         ids=[f"{c}-{' '.join(b)}-{k}" for c, b, k, _ in WRONG])
@pytest.mark.parametrize("named", ["as its kind", "as the command wants"])
def test_the_wrong_kind_names_the_right_command(tmp_path, cmd, before, kind, sentence, named):
    """Whatever the file is called: its content decides, and the one line says what it is
    and which command reads it (exit 1)."""
    suffix = {"dcf": ".dcf", "bin": ".bin", "json": ".json"}[kind] if named == "as its kind" \
        else (".bin" if kind != "bin" else ".dcf")
    path = _file(tmp_path, kind, "fake" + suffix)
    extra = ["-i", "virtual", "--duration", "0"] if cmd == "node" else []
    r = run(cmd, *before, path, *extra)
    assert r.exit_code == 1
    assert r.stderr == f"{path}: error: {path} {sentence.format(file=path)}\n"


def test_the_issue_fake_bin_everywhere(tmp_path):
    """A DCF named fake.bin: no 'truncated container: header says 1834164283 bytes' from
    any command; those that read DCFs read it (with a warning), the others name compile."""
    fake = _file(tmp_path, "dcf", "fake.bin")
    warning = (f"{fake}: warning: {fake} is DCF/EDS text, not a binary container as its name "
               "says; read as DCF/EDS text\n")
    for args in (["map"], ["download", "-n", "3", "--dry-run"], ["simulate"]):
        r = run(*args, fake)
        assert (r.exit_code, r.stderr) == (0, warning), args
    r = run("validate", fake)
    assert r.exit_code == 0 and r.stdout.startswith(
        f"{fake}: warning: {fake} is DCF/EDS text, not a binary container as its name says; "
        "checked as DCF/EDS text [IO002]\n")
    said = (f"{fake}: error: {fake} is DCF/EDS text, not a binary container or a concise DCF "
            "(CiA 302-3)")
    for args, rest in ((["dump"], "; use dcf2bin compile to make a container of it (dcf2bin "
                        "validate checks it)"),
                       (["bin2dcf", "-o", "-"], " or the JSON form of either; it is a DCF "
                        "already (dcf2bin compile makes a container of it)")):
        r = run(*args, fake)
        assert (r.exit_code, r.stderr) == (1, said + rest + "\n"), args


def test_the_issue_fake_dcf_everywhere(tmp_path):
    """A container named fake.dcf: validate checks it as the container it is, like map."""
    fake = _file(tmp_path, "bin", "fake.dcf")
    r = run("validate", "-q", fake)
    assert (r.exit_code, r.stdout) == (0, "")
    for args in (["map"], ["simulate"], ["dump"], ["download", "-n", "3", "--dry-run"]):
        r = run(*args, fake)
        assert r.exit_code == 0 and "as its name says" in r.stderr, args
        assert run(*args, "-q", fake).stderr == "", args


def test_stdin_goes_by_content():
    r = CliRunner().invoke(main, ["dump", "-"], input=PLC_BIN)
    assert r.exit_code == 0 and r.stderr == ""
    r = CliRunner().invoke(main, ["dump", "-"], input=PLC_DCF)
    assert (r.exit_code, r.stderr) == (
        1, f"<stdin>: error: <stdin> {DCF_IS_NOT.format(CONCISE_TOO)}\n")


def test_validate_the_json_form_names_compile(tmp_path):
    path = _file(tmp_path, "json", "plc.json")
    r = run("validate", path)
    assert r.exit_code == 1
    assert r.stdout.splitlines()[0] == (
        f"{path}: error: {path} is the JSON form of a container, not DCF/EDS text or a binary "
        "container; dcf2bin compile turns it back into the container, which validate checks "
        "[DCF008]")


def test_allocate_refuses_a_container_and_merges_only_into_a_dcf(tmp_path):
    r = run("allocate", SAMPLES / "plc.bin")
    assert (r.exit_code, r.stderr) == (1, (
        f"{SAMPLES / 'plc.bin'}: error: {SAMPLES / 'plc.bin'} is a binary container, not a "
        "CSV list of variables; use dcf2bin dump to read it (dcf2bin bin2dcf turns it into a "
        "DCF)\n"))
    csv = tmp_path / "v.csv"
    csv.write_text("name,type,direction\nA,UNSIGNED8,input\n")
    r = run("allocate", csv, "--into", SAMPLES / "plc.bin")
    assert (r.exit_code, r.stderr) == (1, (
        f"{SAMPLES / 'plc.bin'}: error: {SAMPLES / 'plc.bin'} is a binary container, not "
        "DCF/EDS text; --into takes the DCF to merge the variables into\n"))


# -- --static-od: one rule in compile, simulate, node and validate ---------------------------

def _bus():
    return ["-i", "virtual", "--channel", f"kind-{uuid.uuid4().hex[:8]}", "--duration", "0"]


def test_static_od_must_be_an_eds_everywhere(tmp_path):
    static = SAMPLES / "bild8.bin"
    line = (f"{static}: error: {static} is a binary container, not DCF/EDS text; --static-od "
            "takes the EDS of the target's firmware\n")
    for args in (["compile", "-o", tmp_path / "x.bin", SAMPLES / "plc.dcf"],
                 ["simulate", SAMPLES / "plc.bin"], ["simulate", SAMPLES / "plc.dcf"],
                 ["validate", SAMPLES / "plc.dcf"],
                 ["node", "--container", SAMPLES / "plc.bin", "-n", "3", *_bus()]):
        r = run(*args, "--static-od", static)
        assert (r.exit_code, r.stderr, r.stdout) == (1, line, ""), args
    assert not (tmp_path / "x.bin").exists()


def test_a_broken_static_od_is_refused_everywhere(tmp_path):
    static = tmp_path / "broken.eds"
    static.write_text("[FileInfo]\nFileName=broken.eds\n[1000]\nParameterName=x\n[1000]\n")
    outcomes = {"compile": "nothing written", "simulate": "nothing simulated",
                "validate": "nothing checked", "node": "the node does not start"}
    for cmd, args in (("compile", ["-o", tmp_path / "x.bin", SAMPLES / "plc.dcf"]),
                      ("simulate", [SAMPLES / "plc.bin"]),
                      ("validate", [SAMPLES / "plc.dcf"]),
                      ("node", ["--container", SAMPLES / "plc.bin", "-n", "3", *_bus()])):
        r = run(cmd, *args, "--static-od", static)
        assert r.exit_code == 1, cmd
        lines = r.stderr.splitlines()
        assert lines[0].startswith(f"{static}:5: error: static OD: ") and "[DCF010]" in lines[0]
        assert lines[-1] == f"{static}: 1 error in the static OD, {outcomes[cmd]}", cmd


def test_the_issue_simulate_with_a_container_as_static_od_says_so():
    r = run("simulate", SAMPLES / "dis2.bin", "--static-od", SAMPLES / "bild8.bin")
    assert r.exit_code == 1 and "0x31" not in r.stdout + r.stderr
    assert "--static-od takes the EDS" in r.stderr


def test_node_container_without_static_od_warns_as_simulate_does():
    sim = run("simulate", SAMPLES / "dis2.bin")
    warnings = [x for x in sim.stderr.splitlines() if ": warning: " in x]
    assert warnings and all("(give --static-od)" in w for w in warnings)
    r = run("node", "--container", SAMPLES / "dis2.bin", "-n", "1", *_bus())
    assert r.exit_code == 0
    assert [x for x in r.stderr.splitlines() if ": warning: " in x] == warnings
    r = run("node", "--container", SAMPLES / "dis2.bin", "-n", "1", "-q", *_bus())
    assert r.stderr == ""


def test_validate_static_od_checks_what_a_container_never_writes():
    bare = run("validate", SAMPLES / "dis2.bin")
    assert bare.exit_code == 0
    r = run("validate", SAMPLES / "dis2.bin", "--static-od", SAMPLES / "device.eds")
    # device.eds has no 0x6040: the mapped object the container never writes is now checked
    assert r.exit_code == 1 and "0x6040" in r.stdout, r.stdout


# -- the other kinds dcf2bin reads or writes (issue 26 item 15) --------------------------------

NET = ROOT / "tests" / "golden" / "network" / "flat"

# kind -> (how to make a file of it, what it is called, who reads it)
OTHER = {
    "csv": (lambda d: _write(d, "v", b"name,type,direction\nA,UNSIGNED8,input\n"),
            "CSV", "dcf2bin allocate reads it"),
    "map-csv": (lambda d: _made(d, "map", "-f", "csv", SAMPLES / "plc.dcf"),
                "the CSV map of dcf2bin map", "dcf2bin writes this; it is not an input"),
    "yaml": (lambda d: _write(d, "n", (NET / "bus.yml").read_bytes()),
             "a YAML network file",
             "dcf2bin network check, show, build, download and scan read it"),
    "cpj": (lambda d: _write(d, "p", (ROOT / "tests" / "fixtures" / "network" / "check" /
                                      "network.cpj").read_bytes()),
            "a CiA 306-3 network project", "dcf2bin network check and network show read it"),
    "iec": (lambda d: _made(d, "map", "-f", "iec", SAMPLES / "plc.dcf"), "IEC 61131-3 text",
            "dcf2bin map and export write this; it is not an input"),
    "c": (lambda d: _made(d, "compile", "-f", "c", SAMPLES / "plc.dcf"), "C source",
          "dcf2bin compile, map and export write this; it is not an input"),
    "json-output": (lambda d: _made(d, "map", "-f", "json", SAMPLES / "plc.dcf"),
                    "a JSON report of dcf2bin", "dcf2bin writes this; it is not an input"),
    "svg": (lambda d: _made(d, "map", "-f", "svg", SAMPLES / "plc.dcf"), "an SVG picture",
            "dcf2bin map and network show write this; it is not an input"),
    "html": (lambda d: _made(d, "map", "-f", "html", SAMPLES / "plc.dcf"), "an HTML page",
             "dcf2bin map and network show write this; it is not an input"),
    "lenze-bin": (lambda d: _made(d, "export", "-f", "lenze-bin", "-n", "2",
                                  SAMPLES / "device.eds"),
                  "Lenze PLC Designer records",
                  "dcf2bin export --format lenze-bin writes this; it is not an input"),
}


def _write(folder, stem, data: bytes):
    path = folder / stem
    path.write_bytes(data)
    return path


def _made(folder, *args):
    out = folder / "made"
    r = run(*args, "-o", out)
    assert r.exit_code == 0, r.stderr
    return out


@pytest.mark.parametrize("kind", sorted(OTHER))
def test_each_kind_is_told_by_its_content(tmp_path, kind):
    """Content first: without a suffix, and under a name that says DCF."""
    data = OTHER[kind][0](tmp_path).read_bytes()
    for name in ("x", "x.dcf", "x.eds"):
        assert filekind.detect(data, name) == kind, name


@pytest.mark.parametrize("kind", sorted(OTHER))
def test_a_file_of_another_kind_is_one_sentence_in_every_reader(tmp_path, kind):
    """simulate, map, compile, export, download, node and dump say once what the file
    looks like and who reads it (exit 1), validate the same as its one DCF008 finding --
    never one DCF002 per line."""
    path = OTHER[kind][0](tmp_path)
    _, what, words = OTHER[kind]
    line = f"{path}: error: {path} is not DCF/EDS text (it looks like {what}: {words})\n"
    for args in (["simulate"], ["map"], ["compile", "-o", tmp_path / "out.bin"],
                 ["export", "-f", "lenze-st", "-n", "2"],
                 ["download", "-n", "3", "--dry-run"]):
        r = run(*args, path)
        assert (r.exit_code, r.stderr) == (1, line), args
    r = run("node", "-n", "3", path, *_bus())
    assert (r.exit_code, r.stderr) == (1, line)
    r = run("dump", path)
    assert (r.exit_code, r.stderr) == (1, line.replace("DCF/EDS text", "a binary container"))
    r = run("validate", path)
    assert r.exit_code == 1
    assert r.stdout == (line[:-1] + " [DCF008]\n"
                        "1 error, 0 warnings, 0 infos in 1 file\n")
    r = run("compile", SAMPLES / "plc.dcf", "-o", tmp_path / "o.bin", "--static-od", path)
    assert (r.exit_code, r.stderr) == (1, line[:-1] + "; --static-od takes the EDS of the "
                                       "target's firmware\n")
    assert not (tmp_path / "out.bin").exists() and not (tmp_path / "o.bin").exists()


def test_the_issue_commands(tmp_path):
    """simulate vars.csv and map nv.st printed one DCF002 per line and DCF056."""
    csv = tmp_path / "vars.csv"
    csv.write_text("name,type,direction\nDigIn_1,UNSIGNED8,input\nDigOut_1,UNSIGNED8,output\n")
    r = run("simulate", csv)
    assert (r.exit_code, r.stdout, r.stderr) == (1, "", (
        f"{csv}: error: {csv} is not DCF/EDS text (it looks like CSV: dcf2bin allocate "
        "reads it)\n"))
    st = tmp_path / "nv.st"
    assert run("map", "-f", "iec", SAMPLES / "plc.dcf", "-o", st).exit_code == 0
    r = run("map", st)
    assert (r.exit_code, r.stdout, r.stderr) == (1, "", (
        f"{st}: error: {st} is not DCF/EDS text (it looks like IEC 61131-3 text: dcf2bin map "
        "and export write this; it is not an input)\n"))


@pytest.mark.parametrize("name,kind", [("x.csv", "csv"), ("x.yml", "yaml"),
                                       ("x.yaml", "yaml"), ("x.cpj", "cpj"), ("x.st", "iec"),
                                       ("x.h", "c"), ("x.svg", "svg"), ("x.HTML", "html")])
def test_the_name_decides_where_the_content_does_not(name, kind):
    assert filekind.detect(b"", name) == kind
    assert filekind.detect(PLC_DCF, name) == filekind.DCF     # content first
    assert filekind.misnamed(name, filekind.DCF).startswith(f"{name} is DCF/EDS text, not ")


@pytest.mark.skipif(not corpus_files(".dcf", ".eds"),
                    reason="corpus not found (a fresh clone without ../shared)")
def test_no_dcf_or_eds_of_the_corpus_is_taken_for_another_kind():
    files = corpus_files(".dcf", ".eds")
    got = {str(p): filekind.detect(p.read_bytes(), p.name) for p in files}
    assert {p: k for p, k in got.items() if k != filekind.DCF} == {}


def test_a_registry_extends_the_table(monkeypatch):
    """Another module adds a kind: detected by its content before the description formats,
    worded with its reader, its suffix known; a kind of the same name is replaced."""
    monkeypatch.setattr(filekind, "KINDS", list(filekind.KINDS))
    dbc = filekind.Kind("dbc", "a CAN database (DBC)", "cantools reads it, dcf2bin does not",
                        lambda d: d.startswith(b'VERSION "'), (".dbc",))
    filekind.register(dbc, first=True)
    data = b'VERSION ""\n\n[not a section]\nBO_ 100 Msg: 8 Node\n'
    assert filekind.detect(data, "x.dcf") == "dbc" and filekind.by_name("d.DBC") == "dbc"
    assert filekind.mismatch("d.dbc", "dbc", ("bin",)) == (
        "d.dbc is not a binary container (it looks like a CAN database (DBC): cantools reads "
        "it, dcf2bin does not)")
    assert filekind.mismatch("d.dbc", "dbc", ("dcf", "dbc")) is None
    filekind.register(filekind.Kind("dbc", "DBC", "", lambda d: False))
    assert [k.name for k in filekind.KINDS].count("dbc") == 1
    assert filekind.detect(data, "x.dcf") == filekind.DCF

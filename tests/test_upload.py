"""dcf2bin upload (issue 29 item 2): a node read back by SDO into a DCF, on python-can's
virtual bus with software nodes. The values read are the values configured (both DCFs
compiled and their containers compared); a refused entry keeps its abort code, a value of
another size its raw bytes, as a comment and a warning; a node that stops answering
halfway writes nothing; without --eds the node's own EDS from 0x1021; every time bound
asserted by the harness (run_within), never by sleeping."""
from __future__ import annotations

import pytest
from bus_helpers import VIRTUAL, run, run_within
from conftest import ROOT

from dcf2bin.compiler import CompileOptions, compile_path

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

EDS, DCF = "samples/device.eds", "samples/device.dcf"
STORED = "tests/fixtures/upload/stored.eds"
GOLDEN = ROOT / "tests" / "golden" / "upload"
SLACK = 3.0                  # what a loaded machine may add to a command's own bound
TIMEOUT, RETRIES = 0.2, 0
# the infos of samples/device.eds: what the file only implies has no section to hold a value
IMPLIED = (
    f"{EDS}:68: info: 0x1016 sub 0: not read: the file only implies it (no section to state "
    "a value in)\n"
    f"{EDS}:24: info: 0x1400: not read: the file only implies its entries (no section to "
    "state a value in)\n"
    f"{EDS}:24: info: 0x1600: not read: the file only implies its entries (no section to "
    "state a value in)\n")


def bus(channel: str, timeout: float | str = "2", *more: str) -> list[str]:
    return ["-i", "virtual", "--channel", channel, "--timeout", str(timeout),
            "--retries", str(RETRIES), *more]


def configured(path: str, node_id: int, entries: str = "auto") -> dict:
    """The final value of each entry a DCF's container writes."""
    res = compile_path(str(path), CompileOptions(node_id=node_id, select=entries))
    assert res.ok, [d.format() for d in res.diagnostics]
    return {(index, sub): data for index, sub, data in res.container.entries}


def section(text: str, name: str) -> list[str]:
    """The lines of one section of a DCF's text, its header first."""
    lines = text.splitlines()
    start = lines.index(f"[{name}]")
    end = next((k for k in range(start + 1, len(lines)) if lines[k].startswith("[")),
               len(lines))
    return [line for line in lines[start:end] if line]


def _mux(frame: bytes) -> tuple[int, int]:
    return int.from_bytes(frame[1:3], "little"), frame[3]


def _is_upload(frame: bytes) -> bool:
    return frame[0] & 0xE0 == 0x40


def refusing(faulty, node, refused: dict):
    """``node`` answers an SDO abort (entry -> code) to an upload of these entries."""
    class Refuses(faulty.Misbehaving):
        def handle(self, request, serve, send):
            code = refused.get(_mux(request)) if _is_upload(request) else None
            if code is None:
                return serve()
            send(bytes([0x80]) + request[1:4] + code.to_bytes(4, "little"))
    return Refuses(node)


def answering(faulty, node, answers: dict):
    """``node`` answers these raw bytes (1-4, expedited, size given) to an upload of
    these entries."""
    class Answers(faulty.Misbehaving):
        def handle(self, request, serve, send):
            data = answers.get(_mux(request)) if _is_upload(request) else None
            if data is None:
                return serve()
            send(bytes([0x43 | (4 - len(data)) << 2]) + request[1:4] + data.ljust(4, b"\0"))
    return Answers(node)


def falling_silent(faulty, node, after: int):
    """``node`` answers its first ``after`` uploads, then nothing at all."""
    class FallsSilent(faulty.Misbehaving):
        answered = 0

        def handle(self, request, serve, send):
            if self.answered < after:
                self.answered += 1
                serve()
    return FallsSilent(node)


# -- what the node holds ----------------------------------------------------------------------

def test_an_upload_of_a_downloaded_node_gives_the_configured_values(bench, tmp_path):
    bench.device(3, EDS)
    assert run("download", DCF, "-n", "3", *bus(bench.channel)).exit_code == 0
    out = tmp_path / "io8.dcf"
    r = run("upload", "-n", "3", "--eds", EDS, "-o", str(out), "--node-name", "io8",
            "--bitrate", "250000", *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == IMPLIED + f"node 3: 19 entries read; written to {out}\n"
    # every other line of the EDS as it was (reviewed by hand: tests/golden/upload/README)
    assert out.read_bytes() == (GOLDEN / "device.dcf").read_bytes()
    # what was configured is what was read; the rest is what the EDS gave the node
    written, read = configured(DCF, 3), configured(str(out), 3)
    assert {k: read[k] for k in written} == written
    defaults = configured(EDS, 3, "all")
    assert {k: v for k, v in read.items() if k not in written} == {
        k: defaults[k] for k in read if k not in written}
    assert len(read) == 13


def test_the_dcf_goes_to_standard_output_by_default(bench):
    bench.device(3, EDS)
    r = run("upload", "-n", "3", "--eds", EDS, "-q", *bus(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout.encode() == (GOLDEN / "device.eds.dcf").read_bytes()


def test_the_values_of_a_dcf_given_as_eds_are_replaced_by_what_the_node_holds(bench, tmp_path):
    node = bench.device(3, EDS)                    # the EDS's values, not the DCF's
    node.sdo[0x1017].raw = 250
    out = tmp_path / "out.dcf"
    r = run("upload", "-n", "3", "--eds", DCF, "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    text = out.read_text()
    assert section(text, "1017")[-1] == "ParameterValue=0x00FA"        # DCF: 500
    assert section(text, "DeviceComissioning") == [
        "[DeviceComissioning]", "NodeID=3", "NodeName=io8", "Baudrate=250"]
    assert configured(str(out), 3)[(0x1017, 0)] == b"\xfa\x00"


# -- what the node will not give -------------------------------------------------------------

def test_a_refused_entry_keeps_its_abort_code_in_a_comment(bench, faulty, tmp_path):
    refusing(faulty, bench.device(3, EDS), {(0x2001, 0): 0x06020000, (0x1016, 2): 0x06090011})
    out = tmp_path / "out.dcf"
    r = run("upload", "-n", "3", "--eds", DCF, "-o", str(out), "-q", *bus(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    r = run("upload", "-n", "3", "--eds", DCF, "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0
    # the line of each one's ParameterValue in the DCF, which its comment replaces (the
    # bench node has no value for the string 0x2000: it refuses it too)
    assert r.stderr.splitlines()[-4:] == [
        f"{DCF}:85: warning: 0x1016 sub 2: the node refused the upload: SDO abort 0x06090011: "
        "Subindex does not exist",
        f"{DCF}:178: warning: 0x2000 sub 0: the node refused the upload: SDO abort "
        "0x060A0023: Resource not available",
        f"{DCF}:187: warning: 0x2001 sub 0: the node refused the upload: SDO abort "
        "0x06020000: Object does not exist",
        "node 3: 16 of 19 entries read, 3 refused; written to " + str(out)]
    text = out.read_text()
    # the DCF's own ParameterValue of the entry (-8388608) is not kept: the comment is
    assert section(text, "2001") == [
        "[2001]", "ParameterName=Position offset", "ObjectType=0x7", "DataType=0x0010",
        "AccessType=rw", "PDOMapping=1", "DefaultValue=0",
        "; 0x2001 sub 0: the node refused the upload: SDO abort 0x06020000: Object does not "
        "exist"]
    assert section(text, "1016Value") == [
        "[1016Value]", "NrOfEntries=2", "1=0x00000000",
        "; 0x1016 sub 2: the node refused the upload: SDO abort 0x06090011: Subindex does "
        "not exist"]
    assert (0x2001, 0) not in configured(str(out), 3)


def test_bytes_that_are_no_value_of_the_type_are_kept_raw(bench, faulty, tmp_path):
    answering(faulty, bench.device(3, EDS), {(0x1001, 0): b"\x01\0\0\0",
                                             (0x2004, 0): b"\x07\x08"})
    out = tmp_path / "out.dcf"
    r = run("upload", "-n", "3", "--eds", EDS, "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0
    assert r.stderr == IMPLIED + (
        f"{EDS}:60: warning: 0x1001 sub 0: the node answered 4 bytes for an UNSIGNED8 (1 "
        "byte): 01 00 00 00; no value stated, the bytes are kept as a comment\n"
        f"{EDS}:157: warning: 0x2000 sub 0: the node refused the upload: SDO abort "
        "0x060A0023: Resource not available\n"
        f"{EDS}:186: warning: 0x2004 sub 0: the node answered 2 bytes for an UNSIGNED48 (6 "
        "bytes): 07 08; no value stated, the bytes are kept as a comment\n"
        f"node 3: 16 of 19 entries read, 1 refused, 2 kept as raw bytes; written to {out}\n")
    assert section(out.read_text(), "1001")[-1] == (
        "; 0x1001 sub 0: the node answered 4 bytes for an UNSIGNED8 (1 byte): 01 00 00 00")


# -- a node that stops answering -------------------------------------------------------------

def node_bound(path: str, max_upload: int = 1 << 20) -> float:
    """The most an upload of a node described by ``path`` takes with TIMEOUT/RETRIES."""
    from dcf2bin import formats
    from dcf2bin.bus import upload as up
    todo, _ = up.targets(formats.load(path), max_upload=max_upload)
    return up.node_bound(todo, up.Options(TIMEOUT, RETRIES, max_upload))


STOPPED = (f"{EDS}:91: error: 0x1018 sub 0: node 3 did not answer (no SDO response within "
           f"0.2 s, 1 try{VIRTUAL})\n")


def test_a_node_that_stops_answering_halfway_writes_nothing(bench, faulty, tmp_path):
    falling_silent(faulty, bench.device(3, EDS), after=5)
    out = tmp_path / "out.dcf"
    r = run_within(node_bound(EDS) + SLACK, "upload", "-n", "3", "--eds", EDS, "-o",
                   str(out), "-q", *bus(bench.channel, TIMEOUT))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == STOPPED + "node 3: 5 of 19 entries read, 1 failed, 13 not read; " \
                                 "nothing written\n"
    assert not out.exists()


def test_keep_going_writes_what_was_read_and_comments_the_rest(bench, faulty, tmp_path):
    falling_silent(faulty, bench.device(3, EDS), after=5)
    out = tmp_path / "out.dcf"
    r = run_within(node_bound(EDS) + SLACK, "upload", "-n", "3", "--eds", EDS, "-o",
                   str(out), "-q", "--keep-going", *bus(bench.channel, TIMEOUT))
    assert (r.exit_code, r.stderr) == (1, STOPPED)
    text = out.read_text()
    assert section(text, "1017")[-1] == "ParameterValue=0x0000"
    assert section(text, "1018sub0")[-1] == (
        f"; 0x1018 sub 0: node 3 did not answer (no SDO response within 0.2 s, 1 try"
        f"{VIRTUAL})")
    assert section(text, "2005")[-1] == "; 0x2005 sub 0: not read: the upload stopped at " \
                                        "0x1018 sub 0"
    assert sum(line.startswith("; 0x") for line in text.splitlines()) == 14   # 1 + 13
    assert set(configured(str(out), 3)) == {(0x1016, 1), (0x1016, 2), (0x1017, 0)}


def test_a_node_that_is_not_there_did_not_answer(channel, tmp_path):
    out = tmp_path / "out.dcf"
    r = run_within(2 * TIMEOUT + SLACK, "upload", "-n", "9", "--eds", EDS, "-o", str(out),
                   "-q", *bus(channel, TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == (f"{EDS}:52: error: 0x1000 sub 0: node 9 did not answer (no SDO "
                        f"response within 0.2 s, 1 try{VIRTUAL})\n"
                        "node 9: did not answer; nothing written\n")
    assert not out.exists()


def test_an_entry_that_never_ends_is_bounded_by_max_upload(bench, faulty, tmp_path):
    liar = faulty.TogglesForever(bench.device(3, EDS), 0x2000, 0)
    out = tmp_path / "out.dcf"
    r = run_within(node_bound(EDS, 64) + SLACK, "upload", "-n", "3", "--eds", EDS, "-o",
                   str(out), "-q", "--max-upload", "64", *bus(bench.channel, TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{EDS}:157: error: 0x2000 sub 0: node 3 sent more than 64 bytes for an SDO upload of "
        "0x2000 sub 0 without ending it\n"
        "node 3: 13 of 19 entries read, 1 failed, 5 not read; nothing written\n")
    assert liar.segments == 10
    assert not out.exists()


def test_keep_going_reads_on_after_a_wrong_answer(bench, faulty, tmp_path):
    faulty.TogglesForever(bench.device(3, EDS), 0x2000, 0)
    out = tmp_path / "out.dcf"
    r = run("upload", "-n", "3", "--eds", EDS, "-o", str(out), "-q", "--max-upload", "64",
            "--keep-going", *bus(bench.channel, TIMEOUT))
    assert r.exit_code == 1
    # the liar answers every segment request with 7 more bytes: 0x2004 (6 bytes,
    # segmented) too; the entries after each are read all the same
    assert r.stderr == (f"{EDS}:157: error: 0x2000 sub 0: node 3 sent more than 64 bytes for "
                        "an SDO upload of 0x2000 sub 0 without ending it\n"
                        f"{EDS}:186: error: 0x2004 sub 0: node 3 sent more than the 6 bytes it "
                        "announced for an SDO upload of 0x2004 sub 0\n")
    read = configured(str(out), 3)
    assert (0x2000, 0) not in read and (0x2004, 0) not in read and (0x2003, 0) in read


def test_node_timeout_ends_the_upload_of_a_node(bench, faulty, tmp_path):
    faulty.TogglesForever(bench.device(3, EDS), 0x2000, 0)     # 1 MiB: 150,000 segments
    r = run_within(0.5 + SLACK, "upload", "-n", "3", "--eds", EDS, "-o",
                   str(tmp_path / "out.dcf"), "-q", "--node-timeout", "0.5",
                   *bus(bench.channel, TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == (f"{EDS}:157: error: 0x2000 sub 0: the upload of node 3 took longer "
                        "than the 0.5 s a node is given\n"
                        "node 3: 13 of 19 entries read, 1 failed, 5 not read; nothing "
                        "written\n")


def test_the_bound_of_a_node_is_the_sum_of_its_entries():
    from dcf2bin import formats
    from dcf2bin.bus import upload as up
    todo, _ = up.targets(formats.load(EDS), max_upload=64)
    # 17 entries of a fixed size (at most 8 bytes: 3 exchanges each), 2 strings of at most
    # 64 bytes (1 + 10 exchanges each)
    assert [t.most for t in todo].count(8) == 17 and [t.most for t in todo].count(64) == 2
    assert up.node_bound(todo, up.Options(0.2, 1, 64)) == pytest.approx(
        (17 * 3 + 2 * 11) * 2 * 0.2)
    assert up.node_bound(todo, up.Options(0.2, 1, 64, node_timeout=3)) == 3


# -- without --eds: the EDS the node stores ---------------------------------------------------

def stored_node(bench, node_id: int = 5, path: str = STORED):
    """A software node that keeps its EDS in 0x1021 (0x1022 = 0, plain text), configured
    with a string the EDS's encoding (latin-1) holds."""
    from dcf2bin.bus.node import from_file
    node, errors = from_file(path, node_id)
    assert errors == []
    node.set_data(0x1021, 0, (ROOT / path).read_bytes())
    node.set_data(0x2102, 0, "Halle B über Tor 3".encode("latin-1"))
    node.set_data(0x1F81, 2, b"\x01\x00\x00\x00")
    return bench.add(node)


def stored_infos(node_id: int = 5) -> str:
    name = f"<node {node_id} 0x1021>"
    return (f"{name}:75: info: 0x1010 sub 1: not read: write-only\n"
            f"{name}:111: info: 0x1021: not read: it holds the stored EDS, the description "
            "itself\n"
            f"{name}:126: info: 0x1F81 sub 0: not read: the file only implies it (no section "
            "to state a value in)\n")


def test_without_eds_the_node_s_stored_eds_is_read(bench, tmp_path):
    node = stored_node(bench)
    out = tmp_path / "drive.dcf"
    r = run("upload", "-n", "5", "-o", str(out), "--network-name", "line 2",
            *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == stored_infos() + f"node 5: 16 entries read; written to {out}\n"
    assert out.read_bytes() == (GOLDEN / "stored.dcf").read_bytes()
    # each value as the node holds it: a latin-1 string, a UNICODE_STRING, a REAL64, a
    # DOMAIN, a negative INTEGER16, a CompactSubObj sub-entry
    read = configured(str(out), 5)
    for (index, sub), data in read.items():
        assert node.get_data(index, sub) == data, f"0x{index:04X} sub {sub}"
    assert read[(0x2102, 0)] == "Halle B über Tor 3".encode("latin-1")
    assert read[(0x2103, 0)] == "Axé 1".encode("utf-16-le")
    assert read[(0x1F81, 2)] == b"\x01\0\0\0"
    assert len(read) == 10


def test_a_boolean_that_is_neither_0_nor_1_is_kept_raw(bench, tmp_path):
    stored_node(bench).set_data(0x2101, 0, b"\x02")
    out = tmp_path / "drive.dcf"
    r = run("upload", "-n", "5", "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0
    assert r.stderr.splitlines()[-2:] == [
        "<node 5 0x1021>:143: warning: 0x2101 sub 0: the node answered a BOOLEAN that is "
        "neither 0 nor 1: 02; no value stated, the bytes are kept as a comment",
        f"node 5: 15 of 16 entries read, 1 kept as raw bytes; written to {out}"]
    assert section(out.read_text(encoding="latin-1"), "2101")[-1] == (
        "; 0x2101 sub 0: the node answered a BOOLEAN that is neither 0 nor 1: 02")


def test_a_stored_eds_in_another_format_is_an_error(bench, tmp_path):
    stored_node(bench).set_data(0x1022, 0, b"\x90\x00")
    r = run("upload", "-n", "5", "-o", str(tmp_path / "out.dcf"), *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == ("dcf2bin: error: node 5 stores its EDS in format 0x90 (0x1022); only "
                        "0, plain text, can be read: give its EDS with --eds\n")


def test_a_node_without_a_stored_eds_needs_eds(bench, tmp_path):
    bench.device(3, EDS)
    r = run("upload", "-n", "3", "-o", str(tmp_path / "out.dcf"), *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == ("dcf2bin: error: node 3 has no stored EDS (0x1021: SDO abort "
                        "0x06020000: Object does not exist), and an SDO answer carries no "
                        "data type: give its EDS with --eds\n")
    assert not (tmp_path / "out.dcf").exists()


def test_a_node_without_0x1022_is_read_as_plain_text_with_a_warning(bench, tmp_path):
    eds = tmp_path / "no1022.eds"
    text = (ROOT / STORED).read_bytes()
    eds.write_bytes(text.replace(b"4=0x1022\r\n", b"").replace(b"4=0x1022\n", b"")
                    .replace(b"SupportedObjects=5\n1=0x1010", b"SupportedObjects=4\n1=0x1010")
                    .replace(b"5=0x1F81", b"4=0x1F81")
                    .split(b"[1022]")[0] + b"[1F81]" + text.split(b"[1F81]")[1])
    stored_node(bench, 6, str(eds))
    r = run("upload", "-n", "6", "-o", str(tmp_path / "out.dcf"), *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    assert r.stderr.splitlines()[0] == (
        "<node 6 0x1021>: warning: node 6 has no 0x1022 (storage format): its stored EDS "
        "(0x1021) is read as plain text")


def test_a_stored_eds_that_is_not_text_is_an_error(bench, tmp_path):
    stored_node(bench).set_data(0x1021, 0, b"PK\x03\x04" + bytes(60))
    r = run("upload", "-n", "5", "-o", str(tmp_path / "out.dcf"), *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == ("<node 5 0x1021>: error: node 5's 0x1021 holds 64 bytes that are no "
                        "EDS text\n")


# -- the command line -------------------------------------------------------------------------

class _TtyStderr:
    """The stderr click's test runner installs, claiming to be a terminal."""

    def __getattr__(self, name):
        import sys
        return getattr(sys.stderr, name)

    def isatty(self):
        return True


def test_progress_bar_on_a_terminal_only(bench, monkeypatch, tmp_path):
    import types

    import dcf2bin.cli.upload as cli_upload
    bench.device(3, EDS)
    out = str(tmp_path / "out.dcf")
    monkeypatch.setattr(cli_upload, "sys", types.SimpleNamespace(stderr=_TtyStderr()))
    r = run("upload", "-n", "3", "--eds", EDS, "-o", out, *bus(bench.channel))
    assert r.exit_code == 0
    steps = r.stderr.split("\r")
    assert steps[1] == "node 3  [------------------------------------]    0%"
    assert steps[-1].startswith("node 3  [####################################]  100%")
    r = run("upload", "-n", "3", "--eds", EDS, "-o", out, "-q", *bus(bench.channel))
    assert (r.exit_code, r.stderr, r.stdout) == (0, "", "")


def test_an_output_that_cannot_be_written_fails_before_the_bus(tmp_path):
    r = run("upload", "-n", "3", "--eds", EDS, "-o", str(tmp_path), "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (3, f"{tmp_path}: error: cannot write: Is a directory\n")
    missing = tmp_path / "no" / "out.dcf"
    r = run("upload", "-n", "3", "--eds", EDS, "-o", str(missing), "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (
        3, f"{missing}: error: cannot write: No such file or directory\n")
    r = run("upload", "-n", "3", "--eds", EDS, "-o", EDS, "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (
        2, f"{EDS}: error: the output is the input file; refusing to overwrite it\n")


def test_eds_of_another_kind_is_an_input_error():
    r = run("upload", "-n", "3", "--eds", "samples/device.bin", "-i", "no-such-interface")
    assert r.exit_code == 1
    assert r.stderr.startswith("samples/device.bin: error: ")


def test_a_name_must_be_one_line():
    r = run("upload", "-n", "3", "--eds", EDS, "--node-name", "a\nb")
    assert r.exit_code == 2
    assert "must be one line of printable text" in r.stderr


def test_a_name_the_eds_encoding_cannot_hold_fails_before_the_bus():
    r = run("upload", "-n", "5", "--eds", STORED, "--node-name", "Ω-axis", "-i",
            "no-such-interface")
    assert (r.exit_code, r.stderr) == (
        2, f"dcf2bin: error: NodeName 'Ω-axis' cannot be written in the latin-1 encoding of "
           f"{STORED}\n")

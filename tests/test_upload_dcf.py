"""The parts of `upload` that need no bus (dcf2bin/bus/upload.py): which bytes are a value
of a type, what a node's answers become (a channel that answers from a table), and the
DCF's comments and [DeviceComissioning] keys in files of every line end and encoding."""
from __future__ import annotations

import pytest
from conftest import ROOT

from dcf2bin import datatypes as dt
from dcf2bin.bus import sdo
from dcf2bin.bus import upload as up

EDS = ROOT / "samples" / "device.eds"


@pytest.mark.parametrize("dtype,data,said", [
    ("UNSIGNED8", b"\x05", None),
    ("UNSIGNED8", b"\x05\0\0\0", "answered 4 bytes for an UNSIGNED8 (1 byte)"),
    ("INTEGER24", b"\x01\x02", "answered 2 bytes for an INTEGER24 (3 bytes)"),
    ("BOOLEAN", b"\x02", "answered a BOOLEAN that is neither 0 nor 1"),
    ("REAL32", b"\0\0\xc0\x7f", None),                    # a NaN: stated as its bits
    ("VISIBLE_STRING", b"a\nb", "answered 3 bytes that are no VISIBLE_STRING this file can "
                                "hold (one line of latin-1 text)"),
    ("VISIBLE_STRING", "Ωmega".encode("utf-8"), None),     # latin-1 text: 'Î©mega'
    ("UNICODE_STRING", "Ω".encode("utf-16-le"), "answered 2 bytes that are no UNICODE_STRING "
                                               "this file can hold (one line of latin-1 "
                                               "text)"),
    ("UNICODE_STRING", b"A\0B", "answered 3 bytes that are no UNICODE_STRING this file can "
                                "hold (one line of latin-1 text)"),
    ("OCTET_STRING", b"", None),
    ("DOMAIN", bytes(range(256)), None),
    (None, b"\x01\x02", "answered 2 bytes for an entry whose data type is not known"),
])
def test_which_bytes_are_a_value_of_a_type(dtype, data, said):
    t = dt.BY_NAME[dtype] if dtype is not None else None
    assert up.unfit(t, data, "latin-1") == said


class Table:
    """An SDO channel whose node answers from a table: bytes, an abort code, or an
    ``SdoError`` to raise; ``watch`` is what watch_restarts raises, if anything."""

    def __init__(self, answers: dict, watch: Exception | None = None, node_id: int = 3):
        self.answers, self.watch, self.node_id = answers, watch, node_id
        self.asked: list[tuple[int, int, int]] = []

    def watch_restarts(self) -> None:
        if self.watch is not None:
            raise self.watch

    def upload(self, index, sub, *, max_size, deadline=None):
        self.asked.append((index, sub, max_size))
        a = self.answers.get((index, sub), b"\0")
        if isinstance(a, int):
            raise sdo.Aborted(a, self.node_id)
        if isinstance(a, Exception):
            raise a
        return a


def targets(*entries):
    return [up.Target(i, s, dt.BY_NAME[name] if name else None, None, 8)
            for i, s, name in entries]


TODO = targets((0x1000, 0, "UNSIGNED8"), (0x2000, 0, "UNSIGNED8"), (0x2001, 0, "UNSIGNED8"),
               (0x2002, 0, "UNSIGNED8"))


def kinds(result) -> list[tuple[int, str]]:
    return [(n.target.index, n.kind) for n in result.notes]


def test_an_abort_is_a_refusal_and_the_reading_goes_on():
    ch = Table({(0x2000, 0): 0x06020000})
    r = up.read_node(ch, TODO, up.Options())
    assert (r.status, kinds(r), sorted(r.values)) == (
        up.UPLOADED, [(0x2000, up.REFUSED)], [(0x1000, 0), (0x2001, 0), (0x2002, 0)])
    assert r.notes[0].text == ("0x2000 sub 0: the node refused the upload: SDO abort "
                               "0x06020000: Object does not exist")
    assert [a[2] for a in ch.asked] == [8, 8, 8, 8]


def test_a_wrong_answer_ends_the_upload_unless_keep_going():
    wrong = sdo.SdoError("answered a 3-byte frame to an SDO upload of 0x2000 sub 0", 3)
    r = up.read_node(Table({(0x2000, 0): wrong}), TODO, up.Options())
    assert (r.status, kinds(r)) == (up.FAILED, [(0x2000, up.FAILED), (0x2001, up.NOT_READ),
                                                (0x2002, up.NOT_READ)])
    assert r.notes[0].text == ("0x2000 sub 0: node 3 answered a 3-byte frame to an SDO "
                               "upload of 0x2000 sub 0")
    assert r.notes[2].text == "0x2002 sub 0: not read: the upload stopped at 0x2000 sub 0"
    r = up.read_node(Table({(0x2000, 0): wrong}), TODO, up.Options(keep_going=True))
    assert (r.status, kinds(r), len(r.values)) == (up.FAILED, [(0x2000, up.FAILED)], 3)


@pytest.mark.parametrize("keep_going", [False, True])
def test_silence_and_a_restart_end_it_even_with_keep_going(keep_going):
    silent = sdo.NoAnswer(1, 0.5, 3)
    r = up.read_node(Table({(0x2001, 0): silent}), TODO, up.Options(keep_going=keep_going))
    assert (r.status, kinds(r)) == (up.FAILED, [(0x2001, up.FAILED), (0x2002, up.NOT_READ)])
    restarted = sdo.Restarted("restarted (its boot-up message was heard)", 3)
    r = up.read_node(Table({(0x2001, 0): restarted}), TODO, up.Options(keep_going=keep_going))
    assert r.notes[0].text == "0x2001 sub 0: node 3 restarted (its boot-up message was heard)"


def test_a_node_silent_from_the_first_entry_did_not_answer():
    r = up.read_node(Table({(0x1000, 0): sdo.NoAnswer(1, 0.5, 3)}), TODO, up.Options())
    assert r.status == up.SILENT
    # a node that answered its stored EDS before is failed, not absent
    r = up.read_node(Table({(0x1000, 0): sdo.NoAnswer(1, 0.5, 3)}), TODO, up.Options(),
                     answered=True)
    assert r.status == up.FAILED


def test_a_deadline_already_passed_reads_nothing():
    import time
    ch = Table({})
    r = up.read_node(ch, TODO, up.Options(node_timeout=1), deadline=time.monotonic())
    assert ch.asked == []
    assert r.notes[0].text == ("0x1000 sub 0: the upload of node 3 took longer than the 1 s "
                               "a node is given")


def test_an_answer_nobody_asked_for_before_the_first_entry_fails_it():
    unasked = sdo.SdoError("sent an upload segment that was not asked for", 3)
    r = up.read_node(Table({}, watch=unasked), TODO, up.Options())
    assert kinds(r)[:2] == [(0x1000, up.FAILED), (0x2000, up.NOT_READ)]


def test_cancel_stops_at_the_next_entry():
    import threading
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(up.Cancelled):
        up.read_node(Table({}), TODO, up.Options(), cancel=cancel)


# -- the DCF ----------------------------------------------------------------------------------

def _desc(text: bytes, path: str = "dev.eds", node_id: int = 3):
    return up.description(text, path, node_id)


def zeros(todo) -> dict:
    """An answer of the right size for every target: zeros (a string: one 'x')."""
    return {(t.index, t.sub): bytes(t.dtype.size) if t.dtype.size else b"x" for t in todo}


def _result(desc, answers: dict):
    todo, _ = up.targets(desc.device)
    return up.read_node(Table({**zeros(todo), **answers}), todo, up.Options(),
                        encoding=desc.ini.encoding)


def test_crlf_lines_stay_crlf_and_every_insertion_is_crlf():
    text = EDS.read_bytes().replace(b"\n", b"\r\n")
    desc = _desc(text)
    r = _result(desc, {(0x2001, 0): 0x06020000, (0x1016, 2): 0x06090011,
                       (0x2000, 0): b"Hall 3"})
    out = up.dcf(desc, r, {"NodeName": "io8"})
    assert b"\n" not in out.replace(b"\r\n", b"")
    lines = out.decode().split("\r\n")
    k = lines.index("[2001]")
    assert lines[k + 7] == ("; 0x2001 sub 0: the node refused the upload: SDO abort "
                            "0x06020000: Object does not exist")
    assert lines[lines.index("[2000]") + 6] == "ParameterValue=Hall 3"
    assert lines[-9:] == ["[DeviceComissioning]", "NodeID=3", "NodeName=io8", "",
                          "[1016Value]", "NrOfEntries=1", "1=0x00000000",
                          "; 0x1016 sub 2: the node refused the upload: SDO abort 0x06090011: "
                          "Subindex does not exist", ""]


def test_commissioning_keys_of_a_dcf_are_replaced_where_they_stand():
    text = (ROOT / "samples" / "device.dcf").read_bytes()
    desc = _desc(text, "device.dcf")
    out = up.dcf(desc, _result(desc, {}), {"NodeName": "axis 1", "Baudrate": "500",
                                          "NetworkName": "cell"})
    lines = out.decode().splitlines()
    k = lines.index("[DeviceComissioning]")
    assert lines[k:k + 5] == ["[DeviceComissioning]", "NodeID=3", "NodeName=axis 1",
                              "Baudrate=500", "NetworkName=cell"]


def test_the_serial_number_read_is_lss_serial_number_in_device_comissioning():
    """CiA 306 [DeviceComissioning] LSS_SerialNumber: the serial number of the node's LSS
    address, which the upload reads as 0x1018 sub 4 (technosoft.eds: CRLF, no
    [DeviceComissioning] of its own)."""
    desc = _desc((ROOT / "tests" / "fixtures" / "network" / "technosoft.eds").read_bytes(),
                 "drive.eds")
    out = up.dcf(desc, _result(desc, {(0x1018, 4): (0x2001).to_bytes(4, "little")}),
                 {"NodeName": "axis1"})
    assert out.split(b"[DeviceComissioning]")[1] == (
        b"\r\nNodeID=3\r\nNodeName=axis1\r\nLSS_SerialNumber=0x00002001\r\n")
    refused = up.dcf(desc, _result(desc, {(0x1018, 4): 0x06090011}))
    assert refused.split(b"[DeviceComissioning]")[1] == b"\r\nNodeID=3\r\n"


def test_an_lss_serial_number_of_a_dcf_is_replaced_where_it_stands():
    text = (ROOT / "samples" / "device.dcf").read_bytes().replace(
        b"[DeviceComissioning]\n", b"[DeviceComissioning]\nLSS_SerialNumber=0x00000007\n")
    text = text.replace(b"[1018sub1]", b"[1018sub4]\nParameterName=Serial number\n"
                        b"ObjectType=0x7\nDataType=0x0007\nAccessType=ro\n\n[1018sub1]")
    desc = _desc(text, "device.dcf")
    out = up.dcf(desc, _result(desc, {(0x1018, 4): b"\x10\x20\x00\x00"}))
    lines = out.decode().splitlines()
    k = lines.index("[DeviceComissioning]")
    assert lines[k:k + 3] == ["[DeviceComissioning]", "LSS_SerialNumber=0x00002010",
                              "NodeID=3"]


def test_a_name_the_file_s_encoding_cannot_hold_is_an_error():
    desc = _desc((ROOT / "tests" / "fixtures" / "upload" / "stored.eds").read_bytes())
    with pytest.raises(up.UploadError) as e:
        up.dcf(desc, _result(desc, {}), {"NodeName": "Ω-axis"})
    assert str(e.value) == "'Ω' cannot be written in the latin-1 encoding of dev.eds"


def test_an_xdd_is_stated_in_its_cia_306_text():
    from dcf2bin import formats
    xdc = next((ROOT / "tests" / "fixtures" / "xdd").glob("*.xdc"))
    data = xdc.read_bytes()
    desc = _desc(data, str(xdc), 5)
    assert formats.format_of(data).name != "ini"
    todo, _ = up.targets(desc.device)
    out = up.dcf(desc, up.read_node(Table(zeros(todo)), todo, up.Options()), {})
    dev = formats.load("up.dcf", data=out, node_id=5)
    assert dev.ini.format == "ini"
    stated = {(e.index, e.sub) for o in dev.objects.values() for e in o.entries.values()
              if e.param is not None}
    assert stated == {(t.index, t.sub) for t in todo}

"""plc.merge.splice: the one writer of an edited DCF's bytes (allocate --into, a network's
configured DCFs, an uploaded DCF). Exact bytes: every line not changed is copied as it is
(its line end too); a text inserted after a line without a line end gets one; a section
added at the end is one blank line away from the file's last line, whatever that line
was (before, the network writer put two blank lines there when the last edit was on the
file's last line: tests/golden/upload)."""
from __future__ import annotations

from dcf2bin.plc.merge import _lines, splice

DATA = b"[1017]\r\nDefaultValue=0\r\n\r\n[2000]\r\nDefaultValue=1"


def _splice(replace=None, after=None, tail=()):
    return splice(DATA, _lines(DATA), replace or {}, after or {}, tail, nl=b"\r\n",
                  end=b"\r\n", encode=lambda text: text.encode("ascii"))


def test_nothing_to_change_is_the_same_bytes():
    assert _splice() == DATA


def test_a_line_replaced_and_texts_inserted_keep_every_other_line():
    assert _splice({1: b"DefaultValue=5\r\n"}, {1: ["ParameterValue=6"]}) == (
        b"[1017]\r\nDefaultValue=5\r\nParameterValue=6\r\n\r\n[2000]\r\nDefaultValue=1")


def test_an_insertion_after_the_last_line_gives_it_a_line_end():
    assert _splice(after={4: ["ParameterValue=2"]}) == (
        b"[1017]\r\nDefaultValue=0\r\n\r\n[2000]\r\nDefaultValue=1\r\nParameterValue=2\r\n")


def test_a_section_at_the_end_is_one_blank_line_away():
    tail = ["[DeviceComissioning]\r\nNodeID=3"]
    assert _splice(after={4: ["ParameterValue=2"]}, tail=tail) == (
        b"[1017]\r\nDefaultValue=0\r\n\r\n[2000]\r\nDefaultValue=1\r\nParameterValue=2\r\n"
        b"\r\n[DeviceComissioning]\r\nNodeID=3")
    assert _splice(tail=tail) == DATA + b"\r\n\r\n[DeviceComissioning]\r\nNodeID=3"

"""A YAML list keeps its items' lines only once one stands on another line than the list
(issue 26: 250,000 nested one-item flow lists held a list of lines each, 84 MiB for a
3 MB file against its bound of 72); ``lines`` answers the same either way."""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics
from dcf2bin.network.yamltree import YSeq, read_tree

TEXT = """\
block:
  - 1
  - [2, 3]
  - {a: 4}
flow: [5, 6,
  7, [8,
  9]]
deep: [[[10]]]
"""


def test_every_item_has_its_line():
    root = read_tree(TEXT, "t.yml", Diagnostics())
    assert root["block"].lines == [2, 3, 4]
    assert root["block"][1].lines == [3, 3]
    assert root["flow"].lines == [5, 5, 6, 6]
    assert root["flow"][3].lines == [6, 7]
    assert root["deep"].lines == [8] and root["deep"][0][0].lines == [8]


def test_a_list_on_one_line_keeps_no_lines_of_its_own():
    root = read_tree(TEXT, "t.yml", Diagnostics())
    assert root["deep"]._lines is None and root["deep"][0][0]._lines is None
    assert root["block"][1]._lines is None and root["flow"]._lines is not None
    seq = YSeq(3)
    seq.put("a", 3)
    seq.put("b", 4)
    seq.put("c", 4)
    assert seq == ["a", "b", "c"] and seq.lines == [3, 4, 4]

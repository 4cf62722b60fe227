"""Process-image offsets (SPEC §2, D-1...D-4, D-10): hand-computed cases."""
from __future__ import annotations

import pytest

from dcf2bin import layout
from helpers import compile_text, load_text, messages, nv_objects


def place(text: str, **kw) -> layout.Layout:
    dev = load_text(text)
    lay = layout.compute(dev, **kw)
    assert [p.diagnostic.format() for p in dev.problems] == []
    return lay


def addresses(lay: layout.Layout) -> dict[tuple[int, int], int]:
    return {k: lay.address(*k) for k in lay.variables}


def test_bild8_seed_example():
    """Seed 000 Bild 8 (required): A4C0 sub1..3 -> 0, 1, 2; A580 sub3 -> element 2 -> 4."""
    text = """
[A4C0]
SubNumber=4
[A4C0sub0]
ParameterName=NrOfElements
[A4C0sub1]
ParameterName=IN0_IN7
[A4C0sub2]
ParameterName=IN8_IN15
[A4C0sub3]
ParameterName=IN16_IN23
[A580]
SubNumber=2
[A580sub0]
ParameterName=NrOfElements
[A580sub3]
ParameterName=AIN0
"""
    lay = place(text)
    assert addresses(lay) == {(0xA4C0, 1): 0, (0xA4C0, 2): 1, (0xA4C0, 3): 2, (0xA580, 3): 4}
    # output area only: it starts at 0 (D-4); size = 4 + 2
    assert lay.pi_parameters == (6, 0, 0, 0, 6)


def test_inputs_and_outputs_together_alignment_and_address_base():
    text = nv_objects({0xA040: [1, 2, 3], 0xA4C0: [1, 2]})
    lay = place(text)
    # input size 3, output area starts at 3 rounded up to 8 (D-4), addresses from image start (D-10)
    assert addresses(lay) == {(0xA040, 1): 0, (0xA040, 2): 1, (0xA040, 3): 2,
                              (0xA4C0, 1): 8, (0xA4C0, 2): 9}
    assert lay.pi_parameters == (10, 0, 3, 8, 2)
    assert place(text, align=1).pi_parameters == (5, 0, 3, 3, 2)
    assert place(text, align=4).pi_parameters == (6, 0, 3, 4, 2)
    area = place(text, address_base="area")
    assert addresses(area)[(0xA4C0, 2)] == 1
    assert area.pi_parameters == (10, 0, 3, 8, 2)


def test_only_inputs_output_offset_zero():
    lay = place(nv_objects({0xA200: [2]}))      # UNSIGNED32 input element 1 -> 4
    assert addresses(lay) == {(0xA200, 2): 4}
    assert lay.pi_parameters == (8, 0, 8, 0, 0)


def test_24_40_56_bit_sizes():
    text = nv_objects({0xA180: [1, 2], 0xA280: [3], 0xA3C0: [4]})
    lay = place(text)
    # UNSIGNED24: 0, 3; UNSIGNED40 element 2: 10..14; INTEGER56 element 3: 21..27
    assert addresses(lay) == {(0xA180, 1): 0, (0xA180, 2): 3, (0xA280, 3): 10, (0xA3C0, 4): 21}
    assert lay.pi_parameters == (28, 0, 28, 0, 0)


def test_255th_variable_uses_next_index():
    lay = place(nv_objects({0xA4C0: [254], 0xA4C1: [1]}))
    assert addresses(lay) == {(0xA4C0, 254): 253, (0xA4C1, 1): 254}


def test_dynamic_channels_ppoffset_and_a900():
    text = """
[DynamicChannels]
NrOfSeg=2
Type1=0x0006
Dir1=rww
Range1=0xA580-0xA5BF
PPOffset1=0x10
Type2=0x0007
Dir2=ro
Range2=0xA900-0xA93F
PPOffset2=4
""" + nv_objects({0xA580: [1, 2], 0xA4C0: [1], 0xA900: [1, 2]})
    lay = place(text)
    # input: A900 (UNSIGNED32, own range start) 4, 8 -> size 12; output starts at 16
    # output: A4C0 sub1 -> 0; A580 (PPOffset 16) -> 16, 18 -> size 20
    assert addresses(lay) == {(0xA900, 1): 4, (0xA900, 2): 8, (0xA4C0, 1): 16,
                              (0xA580, 1): 32, (0xA580, 2): 34}
    assert lay.pi_parameters == (36, 0, 12, 16, 20)


def test_pioffset_synonym_and_maxcnt_capacity():
    text = """
[DynamicChannels]
NrOfSeg=1
Type1=0x0005
Dir1=ro
Range1=0xA040-0xA07F
PIOffset1=2
MaxCnt1=10
""" + nv_objects({0xA040: [1]})
    lay = place(text)
    assert addresses(lay) == {(0xA040, 1): 2}
    assert lay.pi_parameters == (12, 0, 12, 0, 0)   # D-3: capacity counts: 2 + 10*1


def test_boolean_step_one_accepted():
    text = """
[DynamicChannels]
NrOfSeg=1
Type1=0x0001
Dir1=ro
Range1=0xA080-0xA0BF
PPOffset1=0, 1
""" + nv_objects({0xA080: [1, 2]})
    assert addresses(place(text)) == {(0xA080, 1): 0, (0xA080, 2): 1}  # D-1: a byte each


@pytest.mark.parametrize("text, expected", [
    (nv_objects({0xA040: [1, 2], 0xA0C0: [1]}),
     ["test.dcf:15: error: 0xA0C0sub1 [bytes 0..1] (line 15) overlaps 0xA040sub1 [bytes 0..0] "
      "(line 5) in the input area [DCF307]",
      "test.dcf:8: error: 0xA040sub2 [bytes 1..1] (line 8) overlaps 0xA0C0sub1 [bytes 0..1] "
      "(line 15) in the input area [DCF307]"]),
    (nv_objects({0xA900: [1]}),
     ["test.dcf:1: error: [A900] lies in 0xA900-0xAFFF, which needs a [DynamicChannels] "
      "segment covering it [DCF301]"]),
    (nv_objects({0xA040: [1]}, {0xA040: "0x0006"}),
     ["test.dcf:7: error: 0xA040sub1: DataType UNSIGNED16 does not match range "
      "0xA040-0xA07F (UNSIGNED8) [DCF303]"]),
    (nv_objects({0xA040: [0xFF]}),
     ["test.dcf:5: error: 0xA040subFF: subindex 255 is above 254, the last network variable "
      "of an index [DCF302]"]),
    (nv_objects({0xA8BF: [254]}),
     ["test.dcf:5: error: 0xA8BFsubFE: address 0x1FBF8 does not fit the WORD of the PI "
      "address segment [DCF306]"]),
    # an area with an overlap is checked variable by variable, the WORD check too
    (nv_objects({0xA480: [1], 0xA4C0: [1], 0xA8BF: [254]}),
     ["test.dcf:12: error: 0xA4C0sub1 [bytes 0..0] (line 12) overlaps 0xA480sub1 [bytes 0..0] "
      "(line 5) in the output area [DCF307]",
      "test.dcf:19: error: 0xA8BFsubFE: address 0x1FBF8 does not fit the WORD of the PI "
      "address segment [DCF306]"]),
    ("[A040]\nDataType=0x0005\nAccessType=ro\n",
     ["test.dcf:1: error: [A040] is a VAR; objects in 0xA000-0xAFFF must be ARRAYs [DCF300]"]),
])
def test_layout_errors(text, expected):
    res = compile_text(text)
    assert not res.ok
    assert messages(res) == expected


def test_pi_size_limit():
    text = nv_objects({0xA040: [1, 2, 3, 4]})
    assert compile_text(text, pi_size=4).ok
    res = compile_text(text, pi_size=3)
    assert messages(res) == ["test.dcf: error: process image needs 4 bytes, more than "
                             "--pi-size 3 [DCF305]"]


@pytest.mark.parametrize("channels, expected", [
    ("NrOfSeg=1\nType1=0x0001\nDir1=ro\nRange1=0xA080-0xA0BF\nPPOffset1=0, 8\n",
     "test.dcf:6: error: [DynamicChannels] PPOffset1: step 8 is not supported (BOOLEANs are "
     "not bit-packed, the step must be 1) [DCF313]"),
    ("NrOfSeg=1\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\nPPOffset1=0\nPIOffset1=0\n",
     "test.dcf:7: error: [DynamicChannels] segment 1 gives both PPOffset1 and PIOffset1 [DCF314]"),
    ("NrOfSeg=1\nType1=0x0005\nRange1=0xA040-0xA07F\n",
     "test.dcf:1: error: [DynamicChannels] segment 1 lacks Dir1 [DCF312]"),
    ("NrOfSeg=2\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\n"
     "Type2=0x0005\nDir2=ro\nRange2=0xA070-0xA08F\n",
     "test.dcf:8: error: [DynamicChannels] Range2 overlaps Range1 (line 5) [DCF315]"),
    ("NrOfSeg=1\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\nMaxCnt1=1\n",
     "test.dcf:14: error: 0xA040sub2: variable 2 exceeds MaxCnt1=1 [DCF304]"),
])
def test_channel_errors(channels, expected):
    text = "[DynamicChannels]\n" + channels + nv_objects({0xA040: [1, 2]})
    res = compile_text(text)
    assert expected in messages(res)


def test_unnumbered_sys_tec_keys_warn():
    text = "[DynamicChannels]\nNrOfSeg=0\nPIOffset=4\n" + nv_objects({0xA040: [1]})
    res = compile_text(text)
    assert res.ok
    assert messages(res, "warning") == [
        "test.dcf:3: warning: [DynamicChannels] unnumbered 'PIOffset' is ignored (use the "
        "numbered form, e.g. PIOffset1) [DCF311]"]


def test_maxcnt_reservation_overlap_names_the_segment():
    """D-3: with MaxCnt a segment's whole capacity counts for the overlap check."""
    text = """
[DynamicChannels]
NrOfSeg=2
Type1=0x0005
Dir1=ro
Range1=0xA040-0xA07F
MaxCnt1=4
Type2=0x0005
Dir2=ro
Range2=0xA900-0xA93F
PPOffset2=2
""" + nv_objects({0xA040: [1], 0xA900: [1]})
    res = compile_text(text)
    assert messages(res) == [
        "test.dcf:22: error: 0xA900sub1 [bytes 2..2] (line 22) overlaps [DynamicChannels] "
        "segment 1 [bytes 0..3] in the input area [DCF307]"]


def test_channel_for_scan_and_table_agree():
    # up to layout._SCANNED segments a lookup scans them, beyond that one table paints each
    # index once: overlapping ranges (an error, DCF315) go to the lowest-numbered either way
    import random
    from types import SimpleNamespace

    from dcf2bin import datatypes as dt, layout
    rng = random.Random(5)
    for _ in range(50):
        channels = []
        for k in range(1, rng.randint(1, 12) + 1):
            first = rng.randint(0xA000, 0xA0FF)
            channels.append(layout.Channel(k, dt.UNSIGNED8, layout.INPUT, first,
                                           first + rng.randint(0, 40)))
        answers = []
        for scanned in (layout._SCANNED, 0):
            old, layout._SCANNED = layout._SCANNED, scanned
            try:
                dev = SimpleNamespace(channels=channels)
                answers.append([layout.channel_for(dev, i) for i in range(0xA000, 0xA140)])
            finally:
                layout._SCANNED = old
        assert answers[0] == answers[1]

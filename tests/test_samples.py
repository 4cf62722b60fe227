"""Golden samples: each samples/*.dcf recompiles to its checked-in .bin byte for byte.

The .bin files were checked by hand against SPEC.md (see the annotated Bild 8 below
and the comments in each sample); never regenerate them blindly.
"""
from __future__ import annotations

import pytest

from conftest import SAMPLES
from dcf2bin.compiler import CompileOptions, compile_file

# (sample, options) -> golden .bin beside it
CASES = [("bild8.dcf", {}), ("plc.dcf", {}), ("device.dcf", {}), ("dis2.dcf", {"profile": "dis2"}),
         ("dis2_cobid.dcf", {"profile": "dis2"})]


@pytest.mark.parametrize("name, opts", CASES, ids=[c[0] for c in CASES])
def test_sample_recompiles_byte_identically(name, opts):
    src = SAMPLES / name
    golden = src.with_suffix(".bin").read_bytes()
    assert compile_file(str(src), CompileOptions(**opts)) == golden


BILD8 = """
7f000000 0100 0400                 total 127, version 1 (D-5), 4 segments (D-6)
28000000 35000000                  index segment @40, 53 bytes
5d000000 08000000                  PI address segment @93, 8 bytes
65000000 06000000                  extended info @101, 6 bytes
6b000000 14000000                  PI parameters @107, 20 bytes
06000000                           6 entries, creation group (D-8 step 1)
c0a4 00 01000000 03                A4C0 sub0 = 3 (highest subindex present)
c0a4 01 01000000 00                A4C0 sub1 UNSIGNED8 = 0
c0a4 02 01000000 00                A4C0 sub2
c0a4 03 01000000 00                A4C0 sub3
80a5 00 01000000 03                A580 sub0 = 3
80a5 03 02000000 0000              A580 sub3 UNSIGNED16 = 0
0000 0100 0200 0400                addresses: A4C0 sub1..3 -> 0,1,2; A580 sub3 -> 4 (D-10)
30 f0 f0 f0 30 f0                  attributes: sub0 0x30, variables 0xF0 (D-9)
06000000 00000000 00000000         PI size 6, input @0 size 0
00000000 06000000                  output @0 size 6 (no inputs: starts at 0, D-4)
"""


def unhex(annotated: str) -> bytes:
    out = []
    for line in annotated.strip().splitlines():
        out.append(line[:35].replace(" ", ""))
    return bytes.fromhex("".join(out))


def test_bild8_golden_is_the_annotated_bytes():
    assert (SAMPLES / "bild8.bin").read_bytes() == unhex(BILD8)


def test_plc_sample_validates_clean():
    """samples/plc.dcf shows a clean DCF: no finding at all, not even an info (0x1000 is ro,
    so it carries no ParameterValue; its bytes are the same, see above)."""
    from dcf2bin.api import validate
    assert [d.format() for d in validate(str(SAMPLES / "plc.dcf"))] == []

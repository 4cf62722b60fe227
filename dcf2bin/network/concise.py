"""A slave's configuration as a CiA 302 concise DCF: the index-segment format of SPEC §3.2
(``DWORD count``, then per entry ``WORD index, BYTE sub, DWORD size, data``), which lely's
dcfgen writes too; and back.

Packed with ``struct`` as the index segment's schema (``dcf2bin.schema``) lays it out --
tests/test_network_build.py checks that ``BinContainer.index_bytes`` gives the same bytes
-- so that building a network does not import construct.
"""
from __future__ import annotations

import struct

from dcf2bin.network.model import Node

_COUNT = struct.Struct("<I")
_HEAD = struct.Struct("<HBI")


def concise_dcf(node: Node) -> bytes:
    parts = [_COUNT.pack(len(node.writes))]
    for w in node.writes:
        parts.append(_HEAD.pack(w.index, w.sub, len(w.data)))
        parts.append(w.data)
    return b"".join(parts)


def read_concise(data: bytes) -> list[tuple[int, int, bytes]]:
    """The entries of a concise DCF, in order (raises ContainerError when damaged)."""
    from dcf2bin.container import _read_index
    return _read_index(data, 0)

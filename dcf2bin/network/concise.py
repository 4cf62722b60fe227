"""A slave's configuration as a CiA 302 concise DCF: the index-segment format of SPEC §3.2
(``DWORD count``, then per entry ``WORD index, BYTE sub, DWORD size, data``), which lely's
dcfgen writes too; and back."""
from __future__ import annotations

from dcf2bin.network.model import Node


def concise_dcf(node: Node) -> bytes:
    from dcf2bin.container import BinContainer
    return BinContainer(entries=[(w.index, w.sub, w.data) for w in node.writes]).index_bytes()


def read_concise(data: bytes) -> list[tuple[int, int, bytes]]:
    """The entries of a concise DCF, in order (raises ContainerError when damaged)."""
    from dcf2bin.container import _read_index
    return _read_index(data, 0)

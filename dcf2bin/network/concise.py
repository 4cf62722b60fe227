"""A slave's configuration as a CiA 302 concise DCF: its ordered writes, written by the one
writer of the format (``dcf2bin.concise``, SPEC §3.2), which lely's dcfgen writes too; and
back.
"""
from __future__ import annotations

from dcf2bin import concise
from dcf2bin.network.model import Node


def concise_dcf(node: Node) -> bytes:
    """The node's writes as a concise DCF, in order."""
    return concise.to_bytes([(w.index, w.sub, w.data) for w in node.writes])


def read_concise(data: bytes) -> list[tuple[int, int, bytes]]:
    """The entries of a concise DCF, in order (raises concise.ConciseError when damaged)."""
    return concise.parse(data)

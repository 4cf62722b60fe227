"""A parsed document -> the container's bytes (``build``). In the ``canonical`` layout the
header is recomputed (a stale field is a warning); in the ``stored`` layout the header is
used as given and must describe the segments and gaps exactly (``_build_stored``).
"""
from __future__ import annotations

from dcf2bin import schema
from dcf2bin.container import BinContainer, ContainerError, read as read_container
from dcf2bin.dump.document import Parsed
from dcf2bin.dump.jsonform import _DWORD, CANONICAL, HEADER_FIELDS, JsonProblem


def build(parsed: Parsed) -> tuple[bytes, list[tuple[tuple, str]]]:
    """The container's bytes, and warnings as (path, message). Raises JsonProblem."""
    c = parsed.container
    warnings: list[tuple[tuple, str]] = []
    if parsed.layout == CANONICAL:
        if len(c.index_bytes()) > _DWORD - schema.HEADER_SIZE:
            raise JsonProblem(("entries",), "the entries do not fit a container (4 GiB)")
        canon = c.canonical_header()
        if parsed.header is not None:
            for k in HEADER_FIELDS:
                if parsed.header[k] != canon[k]:
                    warnings.append((("header", k), f"{parsed.header[k]} is recomputed as "
                                                    f"{canon[k]} (layout \"canonical\")"))
        data = c.to_bytes()
    else:
        data = _build_stored(c)
    return data, warnings


def _build_stored(c: BinContainer) -> bytes:
    h = c.header
    segs = c.segments()
    for name in schema.SEGMENTS:
        size = h[f"{name}_size"]
        if len(segs[name]) != size:
            what = {"index": "entries", "address": "addresses", "extinfo": "entries",
                    "piparam": "pi_parameters"}[name]
            raise JsonProblem(("header", f"{name}_size"),
                              f"{size}, but the {what} make {len(segs[name])} bytes of the "
                              f"{name} segment")
    covered = schema.HEADER_SIZE + sum(len(s) for s in segs.values()) + \
        sum(len(g) for _, g in c.gaps)
    if h["total_size"] != covered:
        # checked before anything is allocated from the document's total_size
        raise JsonProblem(("header", "total_size"),
                          f"{h['total_size']}, but the header, segments and gaps make "
                          f"{covered} bytes")
    spans = []
    for name in schema.SEGMENTS:
        off, size = h[f"{name}_offset"], h[f"{name}_size"]
        if size:
            spans.append((off, off + size, ("header", f"{name}_offset")))
    for i, (off, g) in enumerate(c.gaps):
        if g:
            spans.append((off, off + len(g), ("gaps", i, "offset")))
    spans.sort()
    pos = schema.HEADER_SIZE
    for start, end, path in spans:
        if start < pos:
            raise JsonProblem(path, f"{start}: bytes [{start}, {end}) overlap the header, a "
                                    f"segment or a gap ending at {pos}")
        if start > pos:
            raise JsonProblem(path, f"{start}: bytes [{pos}, {start}) are covered by no "
                                    "segment and no gap")
        pos = end
    try:
        data = c.to_bytes()
    except ContainerError as exc:  # defensive: the checks above should catch everything
        raise JsonProblem(("header",), str(exc)) from None
    try:
        back, _ = read_container(data)
    except ContainerError as exc:
        raise JsonProblem(("header",), f"the stored layout is not a readable container: "
                                       f"{exc} (at byte 0x{exc.offset:X})") from None
    if back.gaps != [g for g in c.gaps if g[1]]:
        raise JsonProblem(("gaps",), "the gaps do not match the bytes between the segments")
    return data

"""The variable map (SPEC.md §9.1): one row per network variable, in image-address order,
plus the five PI parameter numbers.

Two sources:

* ``from_result``: a compiled DCF (``compiler.compile_path``): the rows come from the
  layout's runs, the names from the model (``Denotation`` wins over ``ParameterName``).
* ``from_container``: a binary container (or its lossless JSON form), with an optional
  EDS/DCF for names, exact types and ``[DynamicChannels]``; without one the names are
  generated as ``<in|out>_<TYPE>_<index>_<sub>``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import Diagnostic, Severity, Where
from dcf2bin.layout import INPUT, OUTPUT, channel_for, table_channel

RULE_MAP = "MAP001"     # a container whose process image cannot be mapped


@dataclass(slots=True)
class Row:
    name: str
    index: int
    sub: int
    dtype: dt.DataType
    direction: str          # "input" / "output"
    offset: int             # within its area
    address: int            # from the start of the complete image (D-10 "image")
    size: int
    label: str              # 0xA580sub3, as the tool names entries everywhere
    # where the variable is declared: a Where, or the model's entry, whose file:line is
    # then made only when asked (a diagnostic), not for each of tens of thousands of rows
    origin: object = None

    @property
    def where(self) -> Where | None:
        origin = self.origin
        return origin if origin is None or isinstance(origin, Where) else origin.where


_SUB_HEX = [f"{s:X}" for s in range(256)]


def make_row(name: str, index: int, sub: int, dtype: dt.DataType, direction: str,
             offset: int, address: int, where: Where | None = None) -> Row:
    return Row(name, index, sub, dtype, direction, offset, address, dtype.size,
               f"0x{index:04X}sub{sub:X}", where)


@dataclass
class VarMap:
    source: str                                  # the file the map was made from
    rows: list[Row] = field(default_factory=list)
    # SPEC §3.5: complete size, input offset, input size, output offset, output size
    pi: tuple[int, int, int, int, int] = (0, 0, 0, 0, 0)

    @property
    def areas(self) -> dict[str, int]:
        total, in_off, in_size, out_off, out_size = self.pi
        return {"complete_size": total, "input_offset": in_off, "input_size": in_size,
                "output_offset": out_off, "output_size": out_size}

    def area(self, direction: str) -> tuple[int, int]:
        """(offset, size) of the input or output area in the image."""
        return (self.pi[1], self.pi[2]) if direction == INPUT else (self.pi[3], self.pi[4])


def generated_name(direction: str, dtype: dt.DataType, index: int, sub: int) -> str:
    """SPEC §9.1: the name of a variable read from a container without an EDS."""
    return f"{'in' if direction == INPUT else 'out'}_{dtype.name}_{index:04X}_{sub:X}"


def from_result(res, source: str) -> VarMap:
    """The map of a successful compile (``compiler.Result``): the layout's runs are
    already in area order, input area first."""
    lay = res.layout
    if lay is None:
        return VarMap(source)
    rows: list[Row] = []
    append = rows.append
    for start, _end, ch, idx, lo, hi, obj in lay.spans:
        if idx is None:          # a MaxCnt reservation
            continue
        dtype, direction = ch.dtype, ch.direction
        size = dtype.size
        shift = lay.output_offset if direction == OUTPUT else 0
        entries = obj.entries
        off = start
        prefix = f"0x{idx:04X}sub"
        for sub in range(lo, hi + 1):
            e = entries[sub]
            name = e.denotation or e.name or generated_name(direction, dtype, idx, sub)
            append(Row(name, idx, sub, dtype, direction, off, off + shift, size,
                       prefix + _SUB_HEX[sub], e))
            off += size
    total = lay.total_size
    pi = (total, 0, lay.input_size, lay.output_offset, lay.output_size)
    return VarMap(source, rows, pi)


def _eds_name(eds, index: int, sub: int) -> str:
    e = eds.entries.get((index, sub)) if eds is not None else None
    if e is None:
        return ""
    return e.denotation or e.name or ""


def from_container(c, source: str, *, eds=None, eds_device=None,
                   address_base: str = "image") -> tuple[VarMap | None, list[Diagnostic]]:
    """The map of a container. ``eds``: a ``dump.EdsInfo`` (names, exact types);
    ``eds_device``: its model (for ``[DynamicChannels]``). ``address_base`` says how the
    PI addresses were written (the container does not record it, D-10)."""
    from dcf2bin.dump import nv_keys, nv_type
    diags: list[Diagnostic] = []

    def error(message: str) -> None:
        diags.append(Diagnostic(Severity.ERROR, message, source, rule=RULE_MAP))

    keys = nv_keys(c)
    if not keys:
        pi = tuple(c.pi) if c.pi is not None else (0, 0, 0, 0, 0)
        return VarMap(source, [], pi), diags
    if c.addresses is None or c.pi is None:
        error("the container has network variables but no PI address or PI parameter "
              "segment (built with --no-process-image?), so their addresses are unknown")
        return None, diags
    if len(c.addresses) != len(keys):
        error(f"the PI address segment has {len(c.addresses)} addresses for {len(keys)} "
              "network variables")
        return None, diags
    sizes: dict[tuple[int, int], int] = {}
    for index, sub, data in c.entries:
        sizes.setdefault((index, sub), len(data))
    vm = VarMap(source, [], tuple(c.pi))
    channels: dict[int, object] = {}
    for (index, sub), stored in zip(keys, c.addresses):
        label = f"0x{index:04X}sub{sub:X}"
        size = sizes[(index, sub)]
        if index not in channels:
            channels[index] = (channel_for(eds_device, index) if eds_device is not None
                               else table_channel(index))
        ch = channels[index]
        dtype = nv_type(index, sub, size, eds)
        if dtype is None and ch is not None and ch.dtype.size == size:
            dtype = ch.dtype
        if dtype is None:
            error(f"{label}: data type unknown ({size} bytes, no CiA 405 range of that size); "
                  "give the device's EDS/DCF with --eds")
            continue
        direction = ch.direction if ch is not None else None
        if direction is None:
            if address_base == "area":
                error(f"{label}: direction unknown (outside the CiA 405 ranges); give the "
                      "device's EDS/DCF with --eds")
                continue
            direction = OUTPUT if vm.pi[4] and vm.pi[3] <= stored < vm.pi[3] + vm.pi[4] \
                else INPUT
        area_off, area_size = vm.area(direction)
        offset = stored - area_off if address_base == "image" else stored
        if offset < 0 or offset + size > area_size:
            hint = "" if address_base == "area" else \
                "; was the container built with --address-base area?"
            error(f"{label}: PI address 0x{stored:04X} ({size} bytes) lies outside the "
                  f"{direction} area (image bytes {area_off}..{area_off + area_size - 1}, "
                  f"{area_size} bytes){hint}")
            continue
        name = _eds_name(eds, index, sub) or generated_name(direction, dtype, index, sub)
        vm.rows.append(make_row(name, index, sub, dtype, direction, offset,
                                area_off + offset))
    if any(d.severity is Severity.ERROR for d in diags):
        return None, diags
    vm.rows.sort(key=lambda r: (r.address, r.index, r.sub))
    return vm, diags

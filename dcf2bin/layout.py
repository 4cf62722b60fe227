"""Network variables and the process image (SPEC.md §2, D-1...D-4).

``attach_channels`` runs while the model is built: it parses ``[DynamicChannels]``
and gives network variables their range's DataType. ``compute`` places every
variable in the input or output area and derives the PI parameters.
"""
from __future__ import annotations

import operator
import re
from itertools import repeat
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import Where, shorten
from dcf2bin.indexes import NV_FIRST, NV_LAST

INPUT, OUTPUT = "input", "output"
PER_INDEX = 254          # SPEC §2.2: subindex 1..254 per index
RANGE_LEN = 0x40
INPUT_FIRST, OUTPUT_FIRST, TABLE_END = 0xA000, 0xA480, 0xA900

# CiA 405 / seed Tabelle 2 (SPEC §2.1): the type of each 0x40-index range, in order.
# The 40/48/56-bit groups really list Unsigned before Integer.
_ORDER = ["INTEGER8", "UNSIGNED8", "BOOLEAN", "INTEGER16", "UNSIGNED16", "INTEGER24",
          "UNSIGNED24", "INTEGER32", "UNSIGNED32", "REAL32", "UNSIGNED40", "INTEGER40",
          "UNSIGNED48", "INTEGER48", "UNSIGNED56", "INTEGER56", "INTEGER64", "UNSIGNED64"]
TABLE_405: dict[int, tuple[dt.DataType, str]] = {}
for _i, _name in enumerate(_ORDER):
    TABLE_405[INPUT_FIRST + _i * RANGE_LEN] = (dt.BY_NAME[_name], INPUT)
    TABLE_405[OUTPUT_FIRST + _i * RANGE_LEN] = (dt.BY_NAME[_name], OUTPUT)
# OpenPCS supports only these (seed 000 Tabelle 2, "x"/"(x)"); lint reports the others as info.
OPENPCS_TYPES = frozenset({"INTEGER8", "UNSIGNED8", "INTEGER16", "UNSIGNED16", "INTEGER32",
                           "UNSIGNED32", "REAL32"})


@dataclass
class Channel:
    """One ``[DynamicChannels]`` segment (CiA 306-3), or a CiA 405 table range."""
    number: int                     # k of Type<k>; 0 for a table range
    dtype: dt.DataType
    direction: str
    first: int
    last: int
    pp_offset: int = 0
    max_count: int | None = None
    where: Where | None = None

    @property
    def label(self) -> str:
        if self.number:
            return f"[DynamicChannels] segment {self.number}"
        return f"range 0x{self.first:04X}-0x{self.last:04X}"


def table_channel(index: int) -> Channel | None:
    if not INPUT_FIRST <= index < TABLE_END:
        return None
    first = INPUT_FIRST + (index - INPUT_FIRST) // RANGE_LEN * RANGE_LEN
    dtype, direction = TABLE_405[first]
    return Channel(0, dtype, direction, first, first + RANGE_LEN - 1)


_SCANNED = 32      # up to this many segments, channel_for scans them


def channel_for(dev, index: int) -> Channel | None:
    """A [DynamicChannels] segment covering ``index`` wins over the 2.1 table (SPEC §2.3);
    of overlapping segments (an error) the lowest-numbered."""
    channels = dev.channels
    if len(channels) > _SCANNED:   # a file may hold thousands: one lookup table, not a scan
        # each (the table paints every index of every range: for the few segments of a
        # usual PLC file a scan per lookup is cheaper than painting, per compile)
        cached = dev.__dict__.get("_channel_owner")
        if cached is None or cached[0] is not channels:
            cached = dev.__dict__["_channel_owner"] = (channels, _owners(channels))
        ch = cached[1].get(index)
        return ch if ch is not None else table_channel(index)
    for ch in channels:
        if ch.first <= index <= ch.last:
            return ch
    return table_channel(index)


def _owners(channels: list[Channel]) -> dict[int, Channel]:
    """index -> the first channel (in list order) that covers it, each index painted once
    (a skip list over the 0x1000 indexes of 0xA000-0xAFFF), so overlapping ranges cost
    no more than disjoint ones."""
    owner: dict[int, Channel] = {}
    skip: dict[int, int] = {}                 # a painted index -> the next one to try

    def free(i: int) -> int:
        path = []
        while i in skip:
            path.append(i)
            i = skip[i]
        for p in path:
            skip[p] = i
        return i

    for ch in channels:
        i = free(ch.first)
        while i <= ch.last:
            owner[i] = ch
            skip[i] = i + 1
            i = free(i + 1)
    return owner


def _split_range(text: str) -> tuple[str, str] | None:
    """'0xSSSS-0xEEEE' (blanks around '-' allowed) -> the two texts, or None. The '-' is
    the first one after the first character that leaves two blank-free texts, as the
    pattern \\s*(\\S+?)\\s*-\\s*(\\S+)\\s* would split it -- a pattern that backtracks
    quadratically on a long value full of '-', so it is done by hand."""
    words = text.split()
    if len(words) == 1:
        w = words[0]
        i = w.find("-", 1)
        return (w[:i], w[i + 1:]) if 0 < i < len(w) - 1 else None
    if len(words) == 2:
        a, b = words
        if len(a) > 1 and a[-1] == "-":
            return a[:-1], b
        if len(b) > 1 and b[0] == "-":
            return a, b[1:]
        return None
    if len(words) == 3 and words[1] == "-":
        return words[0], words[2]
    return None


_NUMBERED = re.compile(r"(?:type|dir|range|ppoffset|pioffset|maxcnt)([0-9]+)")
_DIRS = {"ro": INPUT, "rww": OUTPUT, "rwr": OUTPUT, "rw": OUTPUT}


def parse_channels(dev) -> list[Channel]:
    """Parse ``[DynamicChannels]`` (SPEC §2.3 and D-2, D-3)."""
    sec = dev.ini.section("dynamicchannels") if dev.ini else None
    if sec is None:
        return []
    w = lambda key: Where(dev.path, sec.line_of(key))  # noqa: E731

    def num(key: str) -> int | None:
        text = sec.get(key)
        if text is None:
            return None
        try:
            return values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem as exc:
            dev.error(f"[DynamicChannels] {sec.keys[key].name}: {exc}", w(key), rule="DCF310")
            return None

    for key in ("pioffset", "maxcnt", "range"):
        if key in sec.keys:
            dev.warning(f"[DynamicChannels] unnumbered '{shorten(sec.keys[key].name)}' is ignored "
                        "(use the numbered form, e.g. PIOffset1)", w(key), rule="DCF311")
    n = num("nrofseg") or 0
    channels: list[Channel] = []
    segments = range(1, n + 1)
    if n > len(sec.values):
        # A segment takes three keys: a count above the number of keys cannot be met, and
        # it must not drive a loop of its own length. Report it once and look only at the
        # segments that the section does describe.
        described = sorted({int(m.group(1)) for m in map(_NUMBERED.fullmatch, sec.values)
                            if m is not None and len(m.group(1)) < 10})
        segments = [k for k in described if 1 <= k <= n]
        dev.error(f"[DynamicChannels] NrOfSeg={n} but the section describes "
                  f"{len(segments)} segment{'s' if len(segments) != 1 else ''}",
                  w("nrofseg"), rule="DCF312",
                  hint="NrOfSeg counts the segments Type<k>/Dir<k>/Range<k>, k = 1..NrOfSeg")
    keys = sec.keys
    for k in segments:
        tk, dk, rk = f"type{k}", f"dir{k}", f"range{k}"
        if tk not in keys or dk not in keys or rk not in keys:
            missing = [name for name in ("Type", "Dir", "Range") if f"{name.lower()}{k}" not in keys]
            dev.error(f"[DynamicChannels] segment {k} lacks {', '.join(m + str(k) for m in missing)}",
                      Where(dev.path, sec.line), rule="DCF312")
            continue
        code = num(tk)
        dtype = dt.BY_CODE.get(code) if code is not None else None
        if dtype is None or dtype.size is None:
            if code is not None:
                dev.error(f"[DynamicChannels] Type{k}=0x{code:04X} is not a fixed-size data type",
                          w(tk), rule="DCF313")
            continue
        dtext = (sec.get(dk) or "").strip().lower()
        direction = _DIRS.get(dtext)
        if direction is None:
            dev.error(f"[DynamicChannels] Dir{k}='{shorten(dtext)}' must be ro, rw, rwr or rww",
                      w(dk), rule="DCF313")
            continue
        m = _split_range(sec.get(rk) or "")
        try:
            if not m:
                raise values.ValueProblem("expected 0xSSSS-0xEEEE")
            first, last = values.parse_int(m[0]), values.parse_int(m[1])
            if not 0xA000 <= first <= last <= 0xAFFF:
                raise values.ValueProblem(f"0x{first:04X}-0x{last:04X} is not an ascending range "
                                          "inside 0xA000-0xAFFF")
        except values.ValueProblem as exc:
            dev.error(f"[DynamicChannels] Range{k}: {exc}", w(rk), rule="DCF313")
            continue
        pp_key, pi_key = f"ppoffset{k}", f"pioffset{k}"
        if pp_key in keys and pi_key in keys:
            dev.error(f"[DynamicChannels] segment {k} gives both PPOffset{k} and PIOffset{k}",
                      w(pi_key), rule="DCF314")
        off_key = pp_key if pp_key in keys else pi_key  # D-3: PIOffset<k> is a synonym
        offset = 0
        text = sec.get(off_key)
        if text is not None:
            parts = [p.strip() for p in values.split_numeric_comment(text)[0].split(",")]
            try:
                offset = values.parse_int(parts[0])
                if len(parts) > 2:
                    raise values.ValueProblem("expected 'offset' or 'offset, step'")
                if len(parts) == 2:
                    step = values.parse_int(parts[1])
                    if dtype.code != dt.BOOLEAN.code:
                        raise values.ValueProblem("a step is only allowed for BOOLEAN segments")
                    if step != 1:  # D-2
                        raise values.ValueProblem(f"step {step} is not supported (BOOLEANs are "
                                                  "not bit-packed, the step must be 1)")
                if offset < 0:
                    raise values.ValueProblem("offset must not be negative")
            except values.ValueProblem as exc:
                dev.error(f"[DynamicChannels] {sec.keys[off_key].name}: {exc}", w(off_key),
                          rule="DCF313")
                offset = 0
        max_count = num(f"maxcnt{k}")
        channels.append(Channel(k, dtype, direction, first, last, offset, max_count, w(rk)))
    # Overlaps in one sweep by first index: each segment that overlaps one before it is
    # named once, with the segment reaching furthest so far (not every pair: a file of
    # 2,000 equal ranges would otherwise make two million errors).
    pairs = []
    reach = None
    for ch in sorted(channels, key=lambda c: (c.first, c.number)):
        if reach is not None and ch.first <= reach.last:
            pairs.append((max(ch.number, reach.number), min(ch.number, reach.number)))
        if reach is None or ch.last > reach.last:
            reach = ch
    by_number = {ch.number: ch for ch in channels}
    for b, a in sorted(pairs):
        dev.error(f"[DynamicChannels] Range{b} overlaps Range{a} "
                  f"(line {by_number[a].where.line})", by_number[b].where, rule="DCF315")
    return channels


def attach_channels(dev) -> None:
    """Parse channels and give network variables their range's type and direction."""
    dev.channels = parse_channels(dev)
    for idx, obj in dev.objects.items():
        if not NV_FIRST <= idx <= NV_LAST:
            continue
        ch = channel_for(dev, idx)
        if ch is None:
            continue
        access = "ro" if ch.direction == INPUT else "rw"
        for sub, e in obj.entries.items():
            if e.dtype is None and sub:
                e.dtype = ch.dtype
            if e.access is None and sub:
                e.access = access


@dataclass(slots=True)
class Variable:
    """A network variable's place in the process image: its area and offset there."""
    index: int
    sub: int
    dtype: dt.DataType
    area: str
    offset: int          # within its area
    channel: Channel
    where: Where | None


_FIRST_SUB = operator.itemgetter(4)      # a run's first subindex


@dataclass
class Layout:
    """The process image: the areas' sizes and offsets, and where each variable lies."""
    input_size: int = 0
    output_offset: int = 0
    output_size: int = 0
    total_size: int = 0
    address_base: str = "image"
    # Runs of variables of one object with consecutive subindexes, which lie back to back
    # in their area: (start in area, end, channel, index, first sub, last sub, object);
    # index None = a MaxCnt reservation.
    spans: list[tuple] = field(default_factory=list, repr=False)
    _addresses: dict | None = field(default=None, repr=False)

    @property
    def pi_parameters(self) -> tuple[int, int, int, int, int]:
        """SPEC §3.5: complete size, input offset, input size, output offset, output size."""
        return (self.total_size, 0, self.input_size, self.output_offset, self.output_size)

    def shift(self, area: str) -> int:
        """D-10: what turns an offset in ``area`` into its address: offsets count from
        the image start (or, with ``--address-base area``, from the area's)."""
        if area == OUTPUT and self.address_base != "area":
            return self.output_offset
        return 0

    def addresses_of(self, indexes) -> list[int]:
        """The D-10 values of the placed variables of the objects ``indexes``, object by
        object in that order, each object's by subindex (what compile writes, SPEC §3.4)."""
        by_index: dict[int, list[tuple]] = {}
        for run in self.spans:
            if run[3] is not None:
                by_index.setdefault(run[3], []).append(run)
        out: list[int] = []
        for idx in indexes:
            for start, end, ch, _, _, _, _ in sorted(by_index.get(idx, ()), key=_FIRST_SUB):
                shift = self.shift(ch.direction)
                out.extend(range(start + shift, end + shift, ch.dtype.size))
        return out

    @property
    def addresses(self) -> dict[tuple[int, int], int]:
        """(index, sub) -> D-10 value of every placed variable (built on first use)."""
        if self._addresses is None:
            self._addresses = {}
            for start, end, ch, idx, lo, hi, _ in self.spans:
                if idx is not None:
                    shift = self.shift(ch.direction)
                    self._addresses.update(zip(zip(repeat(idx), range(lo, hi + 1)),
                                               range(start + shift, end + shift, ch.dtype.size)))
        return self._addresses

    @property
    def variables(self) -> dict[tuple[int, int], Variable]:
        """Every placed network variable (built on demand; compile needs only addresses)."""
        out = {}
        for start, _, ch, idx, lo, hi, obj in self.spans:
            if idx is None:
                continue
            size = ch.dtype.size
            for sub in range(lo, hi + 1):
                out[(idx, sub)] = Variable(idx, sub, ch.dtype, ch.direction,
                                           start + (sub - lo) * size, ch, obj.entries[sub].where)
        return out

    def address(self, index: int, sub: int) -> int:
        """D-10: offset from the start of the complete image (or within the area)."""
        return self.addresses[(index, sub)]


def compute(dev, *, align: int = 8, pi_size: int | None = None,
            address_base: str = "image") -> Layout:
    """Place every network variable (SPEC §2.2-2.4). Errors go to ``dev.problems``.

    A network-variable array is normally its subindexes 1..n, all of its range's type:
    such an object is one run of n variables back to back, placed, checked for overlaps
    and given its addresses as a whole. Anything else (a gap, a wrong DataType, a
    subindex above 254, MaxCnt, an overlap) is worked out variable by variable, so
    each problem names its own variable.
    """
    lay = Layout(address_base=address_base)
    areas: dict[str, list[tuple]] = {INPUT: [], OUTPUT: []}
    for idx in sorted(dev.objects):
        if not NV_FIRST <= idx <= NV_LAST:
            continue
        obj = dev.objects[idx]
        ch = channel_for(dev, idx)
        if ch is None:
            dev.error(f"[{idx:04X}] lies in 0xA900-0xAFFF, which needs a [DynamicChannels] "
                      "segment covering it", obj.where, idx, rule="DCF301")
            continue
        if not _place_run(obj, ch, areas[ch.direction]):
            _place_each(dev, obj, ch, areas[ch.direction])
    # MaxCnt capacities reserve their whole segment (D-3)
    for ch in dev.channels:
        if ch.max_count is not None:
            areas[ch.direction].append((ch.pp_offset, ch.pp_offset + ch.max_count * ch.dtype.size,
                                        ch, None, None, None, None))
    sizes, exact = {}, {}
    for area, runs in areas.items():
        ordered = sorted(runs, key=_START_END)
        if not _disjoint(ordered):
            exact[area] = _each_variable(runs)
            _check_overlaps(dev, exact[area], area)
        sizes[area] = max((run[1] for run in runs), default=0)
        areas[area] = ordered
    lay.input_size, lay.output_size = sizes[INPUT], sizes[OUTPUT]
    if lay.output_size:
        lay.output_offset = -(-lay.input_size // align) * align
        lay.total_size = lay.output_offset + lay.output_size
    else:
        lay.total_size = lay.input_size
    if pi_size is not None and lay.total_size > pi_size:
        dev.error(f"process image needs {lay.total_size} bytes, more than --pi-size {pi_size}",
                  Where(dev.path), rule="DCF305")
    # D-10 addresses are worked out from the runs when asked for; here only the check
    # that each fits its WORD (SPEC §2.2), in the order of the variables in their area
    for area in (INPUT, OUTPUT):
        shift = lay.shift(area)
        if area in exact:
            for start, _, _, idx, sub, e in exact[area]:
                if idx is not None and start + shift > 0xFFFF:
                    _address_too_big(dev, idx, sub, start + shift, e)
            continue
        for start, end, ch, idx, lo, hi, obj in areas[area]:
            size = ch.dtype.size
            if idx is not None and end - size + shift > 0xFFFF:
                for sub in range(lo, hi + 1):
                    addr = start + shift + (sub - lo) * size
                    if addr > 0xFFFF:
                        _address_too_big(dev, idx, sub, addr, obj.entries[sub])
    lay.spans = areas[INPUT] + areas[OUTPUT]
    return lay


def _address_too_big(dev, idx: int, sub: int, addr: int, e) -> None:
    dev.error(f"0x{idx:04X}sub{sub:X}: address 0x{addr:X} does not fit the WORD of the PI "
              "address segment", e.where, idx, sub, rule="DCF306")


def _place_run(obj, ch: Channel, target: list[tuple]) -> bool:
    """Place an object whose variables are subindexes lo..hi without a gap, all of the
    channel's type, inside 1..254 and MaxCnt, as one run; False when it is not one."""
    entries = obj.entries
    subs = sorted(entries)
    if subs and subs[0] == 0:
        del subs[0]
    if not subs:
        return True
    lo, hi = subs[0], subs[-1]
    if hi > PER_INDEX or hi - lo + 1 != len(subs):
        return False
    before = (obj.index - ch.first) * PER_INDEX - 1    # element = before + sub (SPEC §2.2)
    if ch.max_count is not None and before + hi >= ch.max_count:
        return False
    chdt = ch.dtype
    for sub in subs:
        dtype = entries[sub].dtype
        if dtype is not chdt and dtype is not None and dtype.code != chdt.code:
            return False
    size = chdt.size
    target.append((ch.pp_offset + (before + lo) * size, ch.pp_offset + (before + hi + 1) * size,
                   ch, obj.index, lo, hi, obj))
    return True


def _place_each(dev, obj, ch: Channel, target: list[tuple]) -> None:
    """Variable by variable, with a diagnostic for each one that cannot be placed."""
    idx = obj.index
    size, code, max_count = ch.dtype.size, ch.dtype.code, ch.max_count
    # SPEC §2.2: element = (index - range_start) * 254 + (subindex - 1)
    before = (idx - ch.first) * PER_INDEX - 1
    for sub, e in obj.entries.items():
        if sub == 0:
            continue
        if sub > PER_INDEX:
            dev.error(f"{e.label}: subindex {sub} is above 254, the last network "
                      "variable of an index", e.where, idx, sub, rule="DCF302")
            continue
        dtype = e.dtype
        if dtype is not None and dtype.code != code:
            dev.error(f"{e.label}: DataType {dtype.name} does not match {ch.label} "
                      f"({ch.dtype.name})", e.key_where("datatype"), idx, sub, rule="DCF303")
            continue
        element = before + sub
        if max_count is not None and element >= max_count:
            dev.error(f"{e.label}: variable {element + 1} exceeds MaxCnt{ch.number}="
                      f"{max_count}", e.where, idx, sub, rule="DCF304")
            continue
        start = ch.pp_offset + element * size
        target.append((start, start + size, ch, idx, sub, sub, obj))


_START_END = operator.itemgetter(0, 1)


def _disjoint(runs: list[tuple]) -> bool:
    """No two runs (sorted by start) share a byte, and no MaxCnt reservation is among
    them (a variable may lie inside its own segment's reservation: the exact check)."""
    reach_end = -1
    for run in runs:
        if run[3] is None or run[0] < reach_end:
            return False
        reach_end = max(reach_end, run[1])
    return True


def _each_variable(runs: list[tuple]) -> list[tuple]:
    """Runs (in the order they were placed) as (start, end, channel, index, sub, entry)
    per variable, sorted by start and end."""
    out = []
    for start, end, ch, idx, lo, hi, obj in runs:
        if idx is None:
            out.append((start, end, ch, None, None, None))
            continue
        size = ch.dtype.size
        for sub in range(lo, hi + 1):
            s = start + (sub - lo) * size
            out.append((s, s + size, ch, idx, sub, obj.entries[sub]))
    out.sort(key=_START_END)
    return out


def _check_overlaps(dev, spans: list[tuple], area: str) -> None:
    """Two variables (or reserved MaxCnt segments) of one area must not intersect."""
    reach_end, reach = -1, None
    for span in spans:
        start, end, ch, idx = span[0], span[1], span[2], span[3]
        # a variable inside the MaxCnt reservation of its own segment is no overlap
        if start < reach_end and not (ch is reach[2] and (idx is None or reach[3] is None)):
            e = span[5]
            where = e.where if e is not None else ch.where
            dev.error(f"{_describe(span)} overlaps {_describe(reach)} in the {area} area",
                      where, idx, span[4], rule="DCF307")
        if end > reach_end:
            reach_end, reach = end, span


def _describe(span: tuple) -> str:
    start, end, ch, idx, sub, e = span
    if idx is None:
        return f"{ch.label} [bytes {start}..{end - 1}]"
    line = f" (line {e.where.line})" if e.where and e.where.line else ""
    return f"0x{idx:04X}sub{sub:X} [bytes {start}..{end - 1}]{line}"

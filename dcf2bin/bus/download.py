"""Write a container's index segment to a node by SDO, in container order.

A *plan* is the list of SDO writes a container makes, each with the place it comes
from (the DCF line of the entry's value, or the entry's byte offset in a container, or
its line in the JSON form), so an abort can be traced to the line that caused it. The
index segment is written as the target would see it (SPEC §3.2): the CiA 301 PDO
sequences of D-8 reach the device entry by entry, repeated writes included.

    plan = plan_from_result(compile_path(...), "io.dcf")
    net = link.open_network(link.BusConfig("virtual", "bench"))
    with sdo_client(net, 3, timeout=0.5, retries=2) as ch:
        run = execute(plan, ch)
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from dcf2bin.bus.link import abort_message

# D-9 attribute bits of the extended info segment
ATTR_BOOLEAN, ATTR_NUMERIC, ATTR_READ = 0x01, 0x10, 0x20

CONCISE_DCF_INDEX = 0x1F22      # CiA 302: concise DCF, one DOMAIN per node-ID
STORE_INDEX, STORE_SUB = 0x1010, 1
STORE_SIGNATURE = b"save"       # CiA 301: "save" written to 0x1010 stores all parameters

NO_DATA = 0x08000024            # CiA 301 abort: no data available
_DRY_HEX = 32                   # bytes shown in a dry-run line before it is cut short


@dataclass
class Write:
    number: int          # 1-based position in the index segment
    index: int
    sub: int
    data: bytes
    attr: int | None     # the entry's attribute byte; None without an extended info segment
    where: str           # "file:line" or "file:0xOFFSET" (a container's entry)

    @property
    def label(self) -> str:
        return f"0x{self.index:04X}sub{self.sub:X}"

    @property
    def readable(self) -> bool:
        return self.attr is None or bool(self.attr & ATTR_READ)

    @property
    def fixed_size(self) -> bool:
        return self.attr is not None and bool(self.attr & (ATTR_NUMERIC | ATTR_BOOLEAN))


@dataclass
class Plan:
    source: str
    writes: list[Write]
    index_segment: bytes    # the CiA 302 concise DCF, as the container holds it

    def concise(self, node_id: int) -> Plan:
        """One DOMAIN write: the whole index segment into 0x1F22 sub node_id."""
        w = Write(1, CONCISE_DCF_INDEX, node_id, self.index_segment, None, self.source)
        return Plan(self.source, [w], self.index_segment)


# -- plans --------------------------------------------------------------------------------

def plan_from_result(res, name: str) -> Plan:
    """From a compile ``Result``: each entry's place is the line of its value in the DCF
    (ParameterValue, DownloadFile or DefaultValue), else its section."""
    c, dev = res.container, res.device
    attrs = c.attributes or b""
    writes = []
    for k, (index, sub, data) in enumerate(c.entries):
        obj = dev.objects.get(index)
        entry = obj.entries.get(sub) if obj is not None else None
        where = str(entry.value_where) if entry is not None else name
        writes.append(Write(k + 1, index, sub, data, attrs[k] if k < len(attrs) else None,
                            where))
    return Plan(name, writes, c.index_bytes())


def plan_from_container(c, name: str, json_text: str | None = None) -> Plan:
    """From a container (or its JSON form, when ``json_text`` is given): each entry's
    place is its byte offset in the container, or its line in the JSON text."""
    from dcf2bin.dump import entry_offsets, locate
    attrs = c.attributes
    offsets = entry_offsets(c)
    writes = []
    for k, (index, sub, data) in enumerate(c.entries):
        if json_text is not None:
            pos = locate(json_text, ("entries", k))
            where = f"{name}:{json_text.count(chr(10), 0, pos) + 1}" if pos is not None else name
        else:
            where = f"{name}:0x{offsets[k]:X}"
        attr = attrs[k] if attrs is not None and k < len(attrs) else None
        writes.append(Write(k + 1, index, sub, data, attr, where))
    return Plan(name, writes, c.index_bytes())


def plan_from_concise(entries, name: str, json_text: str | None = None) -> Plan:
    """From a CiA 302-3 concise DCF's entries (or its JSON form, when ``json_text`` is
    given), written in its order as a configuration manager writes them: each entry's place
    is its byte offset in the file, or its line in the JSON text. Its entries have no
    attribute: each is read back (``--verify``) as far as ``--max-upload`` allows."""
    from dcf2bin import concise
    from dcf2bin.dump import locate
    offsets = concise.offsets(entries)
    writes = []
    for k, (index, sub, data) in enumerate(entries):
        if json_text is not None:
            pos = locate(json_text, ("entries", k))
            where = f"{name}:{json_text.count(chr(10), 0, pos) + 1}" if pos is not None else name
        else:
            where = f"{name}:0x{offsets[k]:X}"
        writes.append(Write(k + 1, index, sub, data, None, where))
    return Plan(name, writes, concise.to_bytes(entries))


# -- dry run ------------------------------------------------------------------------------

def render(plan: Plan, node_id: int) -> list[str]:
    """The writes as a table: entry number, index/sub, size, source line, bytes."""
    n = len(plan.writes)
    lines = [(f"{plan.source}: {n} SDO write{'s' if n != 1 else ''} to node {node_id} "
              "(dry run, nothing sent)"),
             ]
    rows = []
    for w in plan.writes:
        shown = w.data[:_DRY_HEX].hex(" ").upper()
        if len(w.data) > _DRY_HEX:
            shown += f" ... ({len(w.data)} bytes)"
        rows.append((w.number, w.label, len(w.data), shown, w.where))
    # every column as wide as its widest cell, the data (of any length) last, so that
    # nothing after it wanders
    num = max([len(str(r[0])) for r in rows] + [4])
    label = max([len(r[1]) for r in rows] + [len("entry")])
    size = max([len(str(r[2])) for r in rows] + [len("size")])
    where = max([len(r[4]) for r in rows] + [len("source")])
    lines.append(f"{'#':>{num}}  {'entry':<{label}}  {'size':>{size}}  {'source':<{where}}  "
                 "data")
    lines.extend(f"{n:>{num}}  {lab:<{label}}  {sz:>{size}}  {src:<{where}}  {shown}"
                 for n, lab, sz, shown, src in rows)
    return lines


# -- on the bus ---------------------------------------------------------------------------

@dataclass
class Abort:
    write: Write
    code: int
    written_before: int      # entries written successfully before this one

    @property
    def text(self) -> str:
        return abort_message(self.code)


@dataclass
class RunResult:
    total: int
    written: list[Write] = field(default_factory=list)
    aborts: list[Abort] = field(default_factory=list)


class Stopped(Exception):
    """A node that did not take a write as SDO says (no answer, a wrong or malformed answer,
    a restart): the run of that node ends. ``phase``: "identity" (the check before the
    writes), "write", "verify" or "save"."""

    def __init__(self, write: Write, written_before: int, error, phase: str = "write"):
        super().__init__(str(error))
        self.write, self.written_before, self.error, self.phase = (
            write, written_before, error, phase)

    def text(self, total: int) -> str:
        """One line: what the node did, at which entry, and how far the run got."""
        from dcf2bin.bus import sdo
        e = self.error
        if isinstance(e, sdo.Restarted):
            after = self.written_before if self.phase == "write" else total
            return (f"node {e.node_id} restarted during the download (after entry {after} of "
                    f"{total}{', while reading back' if self.phase == 'verify' else ''})")
        said = f"{self.write.label}: {e}" if isinstance(e, sdo.NoAnswer) else str(e)
        if self.phase == "verify":
            return said + " while reading back"
        if self.phase == "write":
            return f"{said}; {self.written_before} of {total} entries written before it"
        return said


def sdo_client(net, node_id: int, *, timeout: float, retries: int):
    """The SDO channel to ``node_id`` on ``net`` (bus/sdo.py: every write and read is raw
    bytes, nothing is converted); close it when done."""
    from dcf2bin.bus import sdo
    return sdo.Channel(net, node_id, timeout=timeout, retries=retries)


def execute(plan: Plan, ch, *, keep_going: bool = False,
            progress: Callable[[Write], None] | None = None) -> RunResult:
    """Write every entry in order. An abort stops the run (``keep_going``: is recorded and
    the run goes on); a node that does not answer, answers what was not asked or restarts
    (its boot-up message) raises ``Stopped`` either way."""
    from dcf2bin.bus import sdo
    result = RunResult(len(plan.writes))
    w = plan.writes[0] if plan.writes else Write(0, 0, 0, b"", None, plan.source)
    try:
        ch.watch_restarts()
        for w in plan.writes:
            try:
                ch.download(w.index, w.sub, w.data)
            except sdo.Aborted as exc:
                result.aborts.append(Abort(w, exc.code, len(result.written)))
                if not keep_going:
                    return result
            else:
                result.written.append(w)
            if progress is not None:
                progress(w)
        ch.check_between()          # a boot-up or a repeated answer after the last write
    except sdo.SdoError as exc:
        raise Stopped(w, len(result.written), exc) from None
    return result


@dataclass
class Difference:
    write: Write             # the last write of that entry
    read: bytes | None       # what the node holds; None when the read was aborted
    code: int | None = None  # the abort code of a failed read

    @property
    def text(self) -> str:
        if self.read is None:
            return f"{self.write.label}: cannot read back: {abort_message(self.code)}"
        return (f"{self.write.label}: wrote {_hex(self.write.data)}, "
                f"the node holds {_hex(self.read)}")


def _hex(data: bytes) -> str:
    return data.hex(" ").upper() if data else "(0 bytes)"


def final_writes(writes: list[Write]) -> list[Write]:
    """The last write of each entry, in the order those last writes were made."""
    last: dict[tuple[int, int], Write] = {}
    for w in writes:
        last.pop((w.index, w.sub), None)
        last[(w.index, w.sub)] = w
    return list(last.values())


def verify(writes: list[Write], ch, *, max_upload: int | None = None) -> list[Difference]:
    """Read back the final value of every readable entry written; return each difference.
    A fixed-size entry read back longer than written is compared on its own size (some
    devices answer a 32-bit value for a smaller type, as canopen allows). No entry is read
    beyond what it can hold: a fixed-size one 4 bytes (or its own size), any other
    ``max_upload`` bytes (or what was written, when that is more)."""
    from dcf2bin.bus import sdo
    limit = sdo.MAX_DOMAIN if max_upload is None else max_upload
    diffs = []
    for w in final_writes(writes):
        if not w.readable:
            continue
        most = max(len(w.data), 4) if w.fixed_size else max(len(w.data), limit)
        try:
            read = ch.upload(w.index, w.sub, max_size=most)
        except sdo.Aborted as exc:
            if not w.data and exc.code == NO_DATA:
                continue        # an empty value: "no data available" is what it holds
            diffs.append(Difference(w, None, exc.code))
            continue
        except sdo.SdoError as exc:
            raise Stopped(w, 0, exc, "verify") from None
        if w.fixed_size and len(read) > len(w.data):
            read = read[:len(w.data)]
        if read != w.data:
            diffs.append(Difference(w, read))
    return diffs


# -- NMT and storing ----------------------------------------------------------------------

NMT_COMMANDS = {"OPERATIONAL": 0x01, "STOPPED": 0x02, "PRE-OPERATIONAL": 0x80,
                "RESET": 0x81, "RESET COMMUNICATION": 0x82}


def nmt(net, node_id: int, state: str) -> None:
    """Send one NMT command ('PRE-OPERATIONAL', 'RESET COMMUNICATION', …) to a node."""
    net.send_message(0, bytes([NMT_COMMANDS[state], node_id]))


def store(ch, where: str) -> Abort | None:
    """Write "save" to 0x1010 sub 1 (store all parameters); the abort, if any."""
    from dcf2bin.bus import sdo
    w = Write(0, STORE_INDEX, STORE_SUB, STORE_SIGNATURE, None, where)
    try:
        ch.download(STORE_INDEX, STORE_SUB, STORE_SIGNATURE)
    except sdo.Aborted as exc:
        return Abort(w, exc.code, 0)
    except sdo.SdoError as exc:
        raise Stopped(w, 0, exc, "save") from None
    return None

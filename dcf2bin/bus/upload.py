"""Read a node's configuration back by SDO and state it in a DCF (``dcf2bin upload``,
``network upload``).

An SDO answer is bytes without a data type, so what to read and how to read it comes
from the node's description: its EDS/DCF/XDD, or the EDS the node stores in 0x1021
(0x1022, its storage format, must be 0: plain text). Every entry of it that SDO can read
is read, one request in flight per node, in index order:

* a write-only entry is not read, nor an entry the file only implies (a CompactPDO
  object, sub 0 of a CompactSubObj one): there is no section to state its value in;
  nor 0x1021, the stored EDS, which is the description itself (each one an info);
* a fixed-size entry is read as at most 8 bytes, any other as at most ``max_upload``;
  each transfer is bounded as bus/sdo.py bounds it, and the node as a whole by the sum
  of its entries' bounds or ``node_timeout``, whichever ends first;
* a value is stated only when its bytes are a value of the entry's type that
  ``values.encode`` gives back byte for byte (``values.decode``, compile's inverse);
  bytes of another size, a BOOLEAN that is neither 0 nor 1, a string the file cannot
  hold, an abort (the node refused it): a warning, and a comment in the DCF that keeps
  the abort code or the raw bytes -- never a guessed value;
* a node that stops answering, answers what SDO does not allow or restarts ends its
  upload at that entry (``keep_going``: a wrong answer is a comment and the next entry
  is read; silence and a restart still end it). ``read_nodes`` reads several nodes at
  once, each on its own SDO channel, up to a given number at a time.

The DCF is the description's own text with every value read stated as ParameterValue
and [DeviceComissioning] filled, written by ``network.dcfedit`` as ``network build``
writes a slave's DCF, so that a build and an upload of the same node compare file by
file; the comments are added after. Nothing here imports click.

    with sdo.Channel(net, 3, timeout=1.0, retries=2) as ch:
        desc = description(eds_bytes, "motor.eds", 3)
        todo, infos = targets(desc.device, max_upload=1 << 20)
        result = read_node(ch, todo, Options(), encoding=desc.ini.encoding)
    text = dcf(desc, result, {"NodeName": "motor"})
"""
from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.bus import sdo
from dcf2bin.bus.link import abort_message
from dcf2bin.diagnostics import Diagnostic, Severity, Where, shorten

STORED_EDS, STORAGE_FORMAT = 0x1021, 0x1022
NO_SUCH_ENTRY = (0x06020000, 0x06090011)   # SDO aborts: object / sub-index does not exist
FIXED_MOST = 8            # bytes a fixed-size entry is read as at most (its own size if more)
_SHOWN = 32               # bytes of a raw value a message shows (the comment keeps them all)

UPLOADED, FAILED, SILENT = "uploaded", "failed", "did not answer"
REFUSED, UNFIT, NOT_READ = "refused", "unfit", "not read"


class UploadError(Exception):
    """What makes an upload impossible, in one line for the user (no stored EDS, a
    storage format dcf2bin cannot read, a name the DCF cannot hold)."""


class Cancelled(Exception):
    """The caller asked the upload to stop (Ctrl-C while several nodes were read)."""


@dataclass
class Options:
    timeout: float = 1.0
    retries: int = 2
    max_upload: int = sdo.MAX_DOMAIN      # the most a DOMAIN or string entry may be
    node_timeout: float | None = None     # seconds one node is given in all (None: the
                                          # sum of its entries' bounds)
    keep_going: bool = False              # a wrong answer is a comment, not the end


@dataclass(frozen=True)
class Target:
    """One entry to read: its place in the description, its type, the most it may be."""
    index: int
    sub: int
    dtype: dt.DataType | None
    where: Where | None
    most: int

    @property
    def label(self) -> str:
        return sdo.entry_name(self.index, self.sub)


@dataclass
class Note:
    """An entry whose value is not stated, and why: ``text`` is the DCF comment's words
    (all of the raw bytes), ``message`` the diagnostic's (at most 32 of them); ``kind``:
    REFUSED, UNFIT, FAILED or NOT_READ."""
    target: Target
    kind: str
    text: str
    message: str = ""
    code: int | None = None        # the abort code of a refused entry
    data: bytes | None = None      # the bytes of an unfit answer (diff compares them)

    def __post_init__(self) -> None:
        self.message = self.message or self.text


@dataclass
class NodeRead:
    """What the upload of one node gave: the values (bytes that fit their type), a note
    for every entry not stated, and the failure that ended it, if any."""
    node_id: int
    total: int
    values: dict[tuple[int, int], tuple[Target, bytes]] = field(default_factory=dict)
    notes: list[Note] = field(default_factory=list)
    answered: int = 0              # entries the node answered (data or an abort)
    silent: bool = False           # it never answered at all

    @property
    def failures(self) -> list[Note]:
        return [n for n in self.notes if n.kind == FAILED]

    @property
    def status(self) -> str:
        if self.silent:
            return SILENT
        return FAILED if self.failures else UPLOADED

    def count(self, kind: str) -> int:
        return sum(n.kind == kind for n in self.notes)


# -- the description ------------------------------------------------------------------------

@dataclass
class Description:
    """A node's description as the upload uses it: the model (which entries, their types
    and lines), the CiA 306 text the DCF is made of, and the INI reading of that text."""
    device: object               # dcf2bin.model.Device
    text: bytes
    ini: object                  # dcf2bin.ini.IniFile of exactly ``text``
    path: str
    node_id: int


@dataclass
class Job:
    """One node of a ``read_nodes`` run: its description, the entries to read, and what
    the caller keeps beside them (its name, its output file, its line)."""
    desc: Description
    targets: list[Target]
    label: str = ""
    name: str = ""
    output: str = ""
    where: Where | None = None

    @property
    def node_id(self) -> int:
        return self.desc.node_id

    @property
    def encoding(self) -> str:
        return self.desc.ini.encoding


def description(data: bytes, path: str, node_id: int) -> Description:
    """Read an EDS/DCF/XDD/XDC (``data``, named ``path``). The DCF is made of the file
    itself for CiA 306 text, of its sections written as CiA 306 text for another format."""
    from dcf2bin import formats
    from dcf2bin import ini as ini_mod
    parsed = formats.read(data, path)
    dev = formats.build(parsed, node_id=node_id)
    if parsed.format == "ini":
        return Description(dev, data, parsed, path, node_id)
    from dcf2bin.formats import ini as ini_format
    text = ini_format.text(parsed).encode("utf-8")
    return Description(dev, text, ini_mod.parse_bytes(text, path), path, node_id)


def targets(dev, *, max_upload: int = sdo.MAX_DOMAIN) -> tuple[list[Target], list[Diagnostic]]:
    """The entries to read, in index order, and an info for each that is not read
    (write-only, implied by the file, the stored EDS). Data-type definitions (below
    0x1000) are no node data and are left out without a word."""
    todo: list[Target] = []
    infos: list[Diagnostic] = []

    def info(message: str, where: Where | None) -> None:
        w = where or Where(dev.path)
        infos.append(Diagnostic(Severity.INFO, message, w.file, w.line))

    for obj in dev.sorted_objects():
        if obj.index < 0x1000:
            continue
        if obj.index == STORED_EDS:
            info(f"0x{STORED_EDS:04X}: not read: it holds the stored EDS, the description "
                 "itself", obj.where)
            continue
        implied = [e.sub for e in obj.sorted_entries() if e.implicit]
        if implied:
            what = (f"0x{obj.index:04X} sub {implied[0]}: not read: the file only implies it"
                    if len(implied) == 1 else
                    f"0x{obj.index:04X}: not read: the file only implies its entries")
            info(f"{what} (no section to state a value in)", obj.where)
        for e in obj.sorted_entries():
            if e.implicit:
                continue
            if e.access == "wo":
                info(f"{sdo.entry_name(e.index, e.sub)}: not read: write-only", e.where)
                continue
            size = e.dtype.size if e.dtype is not None else None
            most = max(size, FIXED_MOST) if size is not None else max_upload
            # a DCF's ParameterValue line (which the value or its comment replaces), else
            # the entry's section
            where = (e.key_where("parametervalue") if e.has_key("parametervalue")
                     else e.where)
            todo.append(Target(e.index, e.sub, e.dtype, where, most))
    return todo, infos


def node_bound(todo: list[Target], options: Options) -> float:
    """Seconds the upload of these entries takes at most: the sum of each transfer's
    bound (bus/sdo.py), or ``node_timeout`` when that is less."""
    total = sum(sdo.bound(t.most, options.timeout, options.retries) for t in todo)
    return total if options.node_timeout is None else min(total, options.node_timeout)


# -- on the bus ------------------------------------------------------------------------------

def stored_eds(ch, options: Options, deadline: float | None = None
               ) -> tuple[bytes, list[str]]:
    """The EDS the node stores in 0x1021 (at most ``max_upload`` bytes) and what to warn
    about. 0x1022 (storage format) must be 0, plain text; a node without a 0x1022 is read
    as plain text, with a warning. ``UploadError`` when there is no stored EDS to read,
    ``sdo.SdoError`` when the node fails."""
    n = ch.node_id
    warnings = []
    try:
        raw = ch.upload(STORAGE_FORMAT, 0, max_size=4, deadline=deadline)
    except sdo.Aborted as exc:
        if exc.code not in NO_SUCH_ENTRY:
            raise UploadError(f"node {n} refused to say the format of its stored EDS "
                              f"(0x1022): {abort_message(exc.code)}; give its EDS with --eds") from None
        warnings.append(f"node {n} has no 0x1022 (storage format): its stored EDS (0x1021) "
                        "is read as plain text")
    else:
        fmt = int.from_bytes(raw, "little")
        if fmt != 0:
            raise UploadError(f"node {n} stores its EDS in format 0x{fmt:02X} (0x1022); "
                              "only 0, plain text, can be read: give its EDS with --eds")
    try:
        data = ch.upload(STORED_EDS, 0, max_size=options.max_upload, deadline=deadline)
    except sdo.Aborted as exc:
        raise UploadError(f"node {n} has no stored EDS (0x1021: {abort_message(exc.code)}), and an "
                          "SDO answer carries no data type: give its EDS with --eds") from None
    return data, warnings


def read_node(ch, todo: list[Target], options: Options, *, encoding: str = "utf-8",
              deadline: float | None = None, answered: bool = False,
              progress: Callable[[Target], None] | None = None,
              cancel: threading.Event | None = None) -> NodeRead:
    """Read every target on the SDO channel ``ch``. ``deadline`` (``time.monotonic()``)
    ends it (default: now + ``node_timeout``); ``answered``: the node answered before
    (its stored EDS), so that silence now is a failure, not a node that is not there."""
    out = NodeRead(ch.node_id, len(todo))
    if deadline is None and options.node_timeout is not None:
        deadline = time.monotonic() + options.node_timeout
    try:
        ch.watch_restarts()
    except sdo.SdoError as exc:       # an answer nobody asked for, since the last transfer
        return _stop(out, todo, 0, str(exc))
    for k, t in enumerate(todo):
        if cancel is not None and cancel.is_set():
            raise Cancelled()
        try:
            if deadline is not None and time.monotonic() >= deadline:
                return _stop(out, todo, k, _late(ch.node_id, options))
            data = ch.upload(t.index, t.sub, max_size=t.most, deadline=deadline)
        except sdo.Aborted as exc:
            out.answered += 1
            out.notes.append(Note(t, REFUSED, f"{t.label}: the node refused the upload: "
                                  f"{abort_message(exc.code)}", code=exc.code))
        except sdo.SdoError as exc:
            if deadline is not None and time.monotonic() >= deadline:
                return _stop(out, todo, k, _late(ch.node_id, options))
            if isinstance(exc, sdo.NoAnswer) and not out.answered and not answered:
                out.silent = True
            if not options.keep_going or isinstance(exc, (sdo.NoAnswer, sdo.Restarted)):
                return _stop(out, todo, k, str(exc))
            out.notes.append(Note(t, FAILED, f"{t.label}: {exc}"))
        else:
            out.answered += 1
            problem = unfit(t.dtype, data, encoding)
            if problem is None:
                out.values[(t.index, t.sub)] = (t, data)
            else:
                said = f"{t.label}: the node {problem}"
                out.notes.append(Note(t, UNFIT, f"{said}: {_hex(data)}",
                                      f"{said}: {shown(data)}; no value stated, the bytes "
                                      "are kept as a comment", data=data))
        if progress is not None:
            progress(t)
    return out


def _stop(out: NodeRead, todo: list[Target], k: int, reason: str) -> NodeRead:
    """The upload ends at ``todo[k]`` (``reason``); the targets after it are not read."""
    if k < len(todo):
        t = todo[k]
        out.notes.append(Note(t, FAILED, f"{t.label}: {reason}"))
        out.notes += [Note(r, NOT_READ, f"{r.label}: not read: the upload stopped at "
                           f"{t.label}") for r in todo[k + 1:]]
    return out


def _late(node_id: int, options: Options) -> str:
    given = ("the time" if options.node_timeout is None
             else f"the {options.node_timeout:g} s")
    return f"the upload of node {node_id} took longer than {given} a node is given"


def unfit(dtype: dt.DataType | None, data: bytes, encoding: str) -> str | None:
    """Why ``data`` cannot be stated as a value of ``dtype`` (None: it can), after
    "the node ": the inverse of compile's encoding must give ``data`` back."""
    from dcf2bin import values
    if dtype is None:
        return f"answered {_size(len(data))} for an entry whose data type is not known"
    if dtype.size is not None and len(data) != dtype.size:
        return f"answered {_size(len(data))} for {_a(dtype.name)} ({_size(dtype.size)})"
    if values.decode(dtype, data, encoding=encoding) is not None:
        return None
    if dtype.kind == dt.BOOL:
        return "answered a BOOLEAN that is neither 0 nor 1"
    return (f"answered {_size(len(data))} that are no {dtype.name} this file can hold "
            f"(one line of {encoding} text)")


def read_nodes(net, jobs: list[Job], options: Options, *, parallel: int = 1,
               on_entry: Callable[[Job], None] | None = None,
               on_node: Callable[[Job, NodeRead], None] | None = None) -> list[NodeRead]:
    """Upload several nodes, up to ``parallel`` at a time, each on an SDO channel of its
    own (one request in flight per node); the result is one ``NodeRead`` per job, in
    their order.
    ``on_entry(job)`` after each entry and ``on_node(job, result)`` for each node, in the
    order of ``jobs``, are called in the caller's thread. An exception there (Ctrl-C)
    stops every node at its next entry, and is raised."""
    events: queue.SimpleQueue = queue.SimpleQueue()
    cancel = threading.Event()
    results: list = [None] * len(jobs)
    threads: list[threading.Thread] = []

    def work(k: int) -> None:
        job = jobs[k]
        try:
            with sdo.Channel(net, job.node_id, timeout=options.timeout,
                             retries=options.retries) as ch:
                r = read_node(ch, job.targets, options, encoding=job.encoding, cancel=cancel,
                              progress=lambda t: events.put(("entry", k, None)))
            events.put(("done", k, r))
        except BaseException as exc:        # handed to the caller's thread
            events.put(("raised", k, exc))

    started = reported = 0
    try:
        while reported < len(jobs):
            while started < len(jobs) and started - _finished(results) < parallel:
                t = threading.Thread(target=work, args=(started,), daemon=True,
                                     name=f"dcf2bin-upload-{jobs[started].node_id}")
                threads.append(t)
                t.start()
                started += 1
            kind, k, value = events.get()
            if kind == "raised":
                raise value
            if kind == "entry":
                if on_entry is not None:
                    on_entry(jobs[k])
                continue
            results[k] = value
            while reported < len(jobs) and results[reported] is not None:
                if on_node is not None:
                    on_node(jobs[reported], results[reported])
                reported += 1
    finally:
        cancel.set()
        for t in threads:                 # each ends at its next entry
            t.join(options.timeout * (options.retries + 1) + 1.0)
    return results


def _finished(results: list) -> int:
    return sum(r is not None for r in results)


# -- the DCF ---------------------------------------------------------------------------------

def dcf(desc: Description, result: NodeRead, commissioning: dict[str, str] | None = None
        ) -> bytes:
    """The description's text with every value read as ParameterValue, NodeID, the
    ``commissioning`` keys (NodeName, NetworkName, Baudrate) and LSS_SerialNumber (when
    0x1018 sub 4 was read: ``lss_keys``) in [DeviceComissioning], and a comment for every
    entry not stated (an input DCF's ParameterValue of such an entry becomes that
    comment). ``UploadError`` for a name the file's encoding lacks."""
    from dcf2bin import values
    from dcf2bin.diagnostics import Diagnostics
    from dcf2bin.network.dcfedit import edit
    from dcf2bin.network.model import Write
    settings = {key: Write(t.index, t.sub, t.dtype.code, values.to_python(t.dtype, data), data)
                for key, (t, data) in result.values.items()}
    diags = Diagnostics()
    text = edit(desc.text, desc.path, settings, desc.node_id, diags, shown_as=desc.path,
                ini=desc.ini)
    if text is None:     # an entry without a section: ``targets`` never reads one
        raise AssertionError(diags.errors[0].message)
    return annotate(text, desc.path, result.notes, {**(commissioning or {}),
                                                   **lss_keys(result)})


def lss_keys(result: NodeRead) -> dict[str, str]:
    """The CiA 306 [DeviceComissioning] keys the values read give: LSS_SerialNumber, the
    serial number of the node's LSS address (0x1018 sub 4), when it was read. The other
    keys of that section are not the node's to say: NodeID, NodeName, NetworkName and
    Baudrate are the caller's; NetNumber, NodeRefd, NetRefd and CANopenManager no entry
    states (0x1F80 bit 0 says NMT master, which is not all of a CANopen manager)."""
    read = result.values.get((0x1018, 4))
    if read is None or len(read[1]) != 4:
        return {}
    return {"LSS_SerialNumber": f"0x{int.from_bytes(read[1], 'little'):08X}"}


def check_keys(desc: Description, keys: dict[str, str]) -> None:
    """``UploadError`` when a [DeviceComissioning] value cannot be written in the
    description's encoding (before the bus is touched, where the description is known)."""
    for key, value in keys.items():
        _encode(value, desc.ini.encoding, desc.path, key)


def annotate(data: bytes, path: str, notes: list[Note], keys: dict[str, str]) -> bytes:
    """``data`` (a DCF with [DeviceComissioning]) with a comment line for each note, in
    the section of its entry, and ``keys`` set in [DeviceComissioning]."""
    from dcf2bin import ini as ini_mod
    from dcf2bin.plc.merge import _lines, _set_value, section_ends, splice
    parsed = ini_mod.parse_bytes(data, path)
    lines = _lines(data)
    ends = section_ends(parsed, lines)
    canon = {id(sec): c for c, sec in parsed.sections.items()}
    enc = parsed.encoding
    nl = "\r\n" if b"\r\n" in data else "\n"
    replace: dict[int, bytes] = {}
    after: dict[int, list[str]] = {}
    for note in notes:
        sec, key = _note_place(parsed, note.target.index, note.target.sub)
        if sec is None:
            continue
        comment = "; " + note.text
        if key is not None and sec.has(key):
            k = sec.line_of(key) - 1
            replace[k] = _encode(comment, enc, path) + lines[k][len(lines[k].rstrip(b"\r\n")):]
        else:
            after.setdefault(ends[canon[id(sec)]] - 1, []).append(comment)
    sec = parsed.section("devicecomissioning") or parsed.section("devicecommissioning")
    for key, value in keys.items():
        if sec.has(key.lower()):
            k = sec.line_of(key.lower()) - 1
            _encode(value, enc, path, key)
            replace[k] = _set_value(lines[k], value, enc)
        else:
            after.setdefault(ends[canon[id(sec)]] - 1, []).append(f"{key}={value}")
    nlb = nl.encode(enc)
    return splice(data, lines, replace, after, nl=nlb, end=nlb,
                  encode=lambda text: _encode(text, enc, path))


def _note_place(parsed, index: int, sub: int):
    """(section, key) where an entry's value is stated: its own section's
    ParameterValue, a CompactSubObj sub-entry's line in [xxxxValue] (or, without one, the
    object's section), a VAR's ParameterValue in the object's section."""
    own = parsed.sections.get(f"{index:04x}sub{sub:x}")
    if own is not None:
        return own, "parametervalue"
    obj = parsed.sections.get(f"{index:04x}")
    if obj is None:
        return None, None
    if sub > 0 and obj.get("compactsubobj") not in (None, "0"):
        vsec = parsed.sections.get(f"{index:04x}value")
        return (vsec, str(sub)) if vsec is not None else (obj, None)
    return obj, "parametervalue"


def _encode(text: str, encoding: str, path: str, key: str | None = None) -> bytes:
    try:
        return text.encode(encoding)
    except UnicodeEncodeError as exc:
        what = f"{key} '{shorten(text)}'" if key else f"'{text[exc.start:exc.end]}'"
        raise UploadError(f"{what} cannot be written in the {encoding} encoding of "
                          f"{path}") from None


# -- words -----------------------------------------------------------------------------------

def _hex(data: bytes) -> str:
    return data.hex(" ").upper() if data else "(0 bytes)"


def shown(data: bytes) -> str:
    """Raw bytes as a message shows them: the first 32, and how many there are."""
    if len(data) <= _SHOWN:
        return _hex(data)
    return f"{_hex(data[:_SHOWN])} ... ({len(data)} bytes)"


def _size(n: int) -> str:
    return f"{n} byte{'s' if n != 1 else ''}"


def _a(name: str) -> str:
    return ("an " if name[0] in "AEIOU" else "a ") + name

"""The neutral model: a device's objects and entries, built from an INI file.

Every object and entry keeps where it came from (file:line of its section and
of each key), so every diagnostic can point at the line that caused it.
Values stay text here; they are encoded on demand (``Device.encode``) so that
``compile`` only fails for values it actually writes (SPEC "Errors vs warnings").
"""
from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import ini as ini_mod
from dcf2bin import layout
from dcf2bin import values
from dcf2bin.diagnostics import DcfError, Diagnostic, Severity, Where

# The index predicates live in dcf2bin.indexes (a leaf module, so that layout does not
# import model); they are re-exported here for the modules that use them with the model.
from dcf2bin.indexes import (NV_FIRST, NV_LAST, RPDO_COMM, TPDO_COMM,  # noqa: E402,F401
                             is_network_variable_index, is_pdo_comm, is_pdo_mapping,
                             is_pdo_object)

_SECTION_RE = re.compile(r"([0-9a-f]{4})(?:sub([0-9a-f]+))?")   # an object or sub-object
_SUB_HEX = {f"{i:x}": i for i in range(256)}   # canonical subindex texts
_AUX_RE = re.compile(r"([0-9a-f]{4})(name|value|denotation|objectlinks)")
# The largest DownloadFile read (bytes); the file's own size, not its name, decides.
MAX_DOWNLOAD_FILE = 16 << 20


@dataclass(slots=True)
class Problem:
    """A diagnostic about the model, tagged with the object/entry it touches.

    ``compile`` turns an error into a warning when it touches nothing it writes.
    """
    diagnostic: Diagnostic
    index: int | None = None
    sub: int | None = None   # None: the whole object


@dataclass(slots=True, eq=False)
class Entry:
    index: int
    sub: int
    name: str = ""
    dtype: dt.DataType | None = None
    access: str | None = None
    pdo_mapping: bool = False
    obj_flags: int = 0
    default: str | None = None
    param: str | None = None
    download_file: str | None = None
    low: str | None = None
    high: str | None = None
    denotation: str | None = None
    where: Where | None = None               # the section (or the object's, for compact subs)
    lines: dict[str, int] | None = None      # key -> line, where not the section's own
    implicit: bool = False                   # created by the tool (sub 0, CompactPDO)
    section: ini_mod.Section | None = None

    @property
    def configured(self) -> bool:
        """SPEC §1: an entry is configured when it has a ParameterValue or a DownloadFile."""
        return self.param is not None or self.download_file is not None

    @property
    def value_text(self) -> str | None:
        """The text of the effective value (ParameterValue, else DefaultValue)."""
        return self.param if self.param is not None else self.default

    @property
    def has_value(self) -> bool:
        return self.param is not None or self.download_file is not None or self.default is not None

    def has_key(self, key: str) -> bool:
        return bool(self.lines and key in self.lines) or (
            self.section is not None and self.section.has(key))

    def key_where(self, key: str) -> Where:
        w = self.where or Where("")
        if self.lines and key in self.lines:
            return Where(w.file, self.lines[key])
        if self.section is not None and self.section.has(key):
            return Where(w.file, self.section.line_of(key))
        return w

    @property
    def value_where(self) -> Where:
        for key in ("parametervalue", "downloadfile", "defaultvalue"):
            if self.has_key(key):
                return self.key_where(key)
        return self.where or Where("")

    @property
    def label(self) -> str:
        return f"0x{self.index:04X}sub{self.sub:X}"


@dataclass(slots=True, eq=False)
class Obj:
    index: int
    name: str = ""
    object_type: int = dt.OT_VAR
    entries: dict[int, Entry] = field(default_factory=dict)
    where: Where | None = None
    section: ini_mod.Section | None = None
    compact: int = 0           # CompactSubObj
    sub_number: int | None = None
    implicit: bool = False     # created from CompactPDO
    complex: bool = False      # ARRAY/RECORD

    def sorted_entries(self) -> list[Entry]:
        return [self.entries[k] for k in sorted(self.entries)]


@dataclass
class Device:
    path: str
    encoding: str = "utf-8"
    objects: dict[int, Obj] = field(default_factory=dict)
    node_id: int | None = None
    node_id_where: Where | None = None
    node_id_from_cli: bool = False
    dummy_usage: set[int] = field(default_factory=set)
    problems: list[Problem] = field(default_factory=list)
    ini: ini_mod.IniFile | None = None
    allow_external_files: bool = False
    channels: list = field(default_factory=list)  # layout.Channel, parsed by layout
    # (type code, value text) -> bytes: the encodings ``encode`` has made (a file repeats
    # few value texts per type, "0", "0x00"); select's hot loop reads it directly
    encoded: dict = field(default_factory=dict, repr=False)
    _warned: set = field(default_factory=set, repr=False)
    _verdicts: dict = field(default_factory=dict, repr=False)   # see text_problem

    # -- diagnostics -----------------------------------------------------------------
    def problem(self, severity: Severity, message: str, where: Where | None,
                index: int | None = None, sub: int | None = None, *, rule: str = "",
                hint: str = "") -> None:
        d = Diagnostic(severity, message, where.file if where else self.path,
                       where.line if where else None, None, None, rule, hint)
        self.problems.append(Problem(d, index, sub))

    def error(self, message, where, index=None, sub=None, **kw):
        self.problem(Severity.ERROR, message, where, index, sub, **kw)

    def warning(self, message, where, index=None, sub=None, **kw):
        self.problem(Severity.WARNING, message, where, index, sub, **kw)

    # -- access ------------------------------------------------------------------------
    def entry(self, index: int, sub: int) -> Entry | None:
        o = self.objects.get(index)
        return o.entries.get(sub) if o else None

    def sorted_objects(self) -> list[Obj]:
        return [self.objects[k] for k in sorted(self.objects)]

    def where(self, line: int | None = None) -> Where:
        return Where(self.path, line)

    # -- values ------------------------------------------------------------------------
    def encode(self, entry: Entry, text: str | None = None) -> bytes:
        """Encode an entry's effective value (or ``text``) to its exact bytes.

        Raises DcfError naming the value's file:line.
        """
        dtype = entry.dtype
        if dtype is None:
            raise DcfError(f"{entry.label} has no valid DataType", entry.where)
        if text is None:
            if entry.param is None and entry.download_file is not None:
                return self._download(entry)
            text = entry.value_text
            where = None  # worked out only for a diagnostic (entry.value_where)
        else:
            where = entry.where
        if text is None:
            return values.zero(dtype)
        cache_key = (dtype.code, text)
        data = self.encoded.get(cache_key)
        if data is not None:
            return data
        cache = len(self.encoded) < 4096
        if (";" in text or "#" in text) and (dtype.is_numeric or dtype.kind == dt.BOOL):
            number, comment = values.split_numeric_comment(text)
            if comment is not None:
                cache = False   # every entry that has the comment gets its own warning
                text = number
                if (entry.index, entry.sub) not in self._warned:
                    self._warned.add((entry.index, entry.sub))
                    self.warning(f"{entry.label}: comment '{comment}' after the number is "
                                 "ignored", where or entry.value_where, entry.index, entry.sub,
                                 rule="DCF203")
        try:
            data = values.encode(dtype, text, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            where = where or entry.value_where
            raise DcfError(
                f"value '{text}' of {entry.label} uses $NODEID but no node-ID is known",
                where, rule="DCF201",
                hint="give --node-id N or set NodeID in [DeviceComissioning]") from None
        except values.ValueProblem as exc:
            where = where or entry.value_where
            raise DcfError(f"{entry.label}: {_clip(str(exc))}", where, rule="DCF200") from None
        if cache:
            self.encoded[cache_key] = data
        return data

    def _download(self, entry: Entry) -> bytes:
        """The bytes of a DownloadFile (SPEC §1). Symlinks are resolved before the check
        that the file stays in the DCF's folder; only a regular file of at most
        MAX_DOWNLOAD_FILE bytes is read (a FIFO, a device or a directory never is), and
        it is opened without blocking, so a FIFO cannot hang the read."""
        where = entry.key_where("downloadfile")
        name = entry.download_file or ""
        shown = _clip(name, 80)
        if "\0" in name:
            raise DcfError(f"DownloadFile '{shown}' contains a NUL byte", where, rule="DCF202")
        base = os.path.realpath(os.path.dirname(os.path.abspath(self.path)))
        if os.path.isabs(name) and not self.allow_external_files:
            raise DcfError(f"DownloadFile '{shown}' is an absolute path", where, rule="DCF202",
                           hint="use a path relative to the DCF, or --allow-external-files")
        full = os.path.realpath(os.path.join(base, name))
        if not self.allow_external_files and os.path.commonpath([base, full]) != base:
            leaves = "leaves" if os.path.commonpath([base, os.path.normpath(
                os.path.join(base, name))]) != base else "leads through a symbolic link out of"
            raise DcfError(f"DownloadFile '{shown}' {leaves} the DCF's folder", where,
                           rule="DCF202", hint="use --allow-external-files to permit it")
        try:
            fd = os.open(full, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)
                         | getattr(os, "O_BINARY", 0))
        except OSError as exc:
            raise DcfError(f"cannot read DownloadFile '{shown}': {exc.strerror}", where,
                           rule="DCF202") from None
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            os.close(fd)
            raise DcfError(f"DownloadFile '{shown}' is not a regular file", where,
                           rule="DCF202", hint="name a regular file, not a device, pipe "
                           "or directory")
        with os.fdopen(fd, "rb") as f:
            try:
                data = f.read(MAX_DOWNLOAD_FILE + 1)
            except OSError as exc:
                raise DcfError(f"cannot read DownloadFile '{shown}': {exc.strerror}", where,
                               rule="DCF202") from None
        if len(data) > MAX_DOWNLOAD_FILE:
            raise DcfError(f"DownloadFile '{shown}' is larger than {MAX_DOWNLOAD_FILE >> 20} MiB",
                           where, rule="DCF202", hint="a DOMAIN value this large cannot be "
                           "meant for a container")
        return data

    def effective_int(self, entry: Entry) -> int:
        """The effective value of an integer entry as a Python int (raises DcfError)."""
        data = self.encode(entry)
        signed = entry.dtype is not None and entry.dtype.kind == dt.SINT
        return int.from_bytes(data, "little", signed=signed)

    def default_int(self, entry: Entry) -> int | None:
        """The DefaultValue of an integer entry as a Python int, None without one (D-12:
        the COB-ID a DIS-2 drive has). Raises DcfError at the DefaultValue's line."""
        text, dtype = entry.default, entry.dtype
        if text is None or dtype is None:
            return None
        number = text
        if dtype.is_numeric or dtype.kind == dt.BOOL:
            number = values.split_numeric_comment(text)[0]
        where = entry.key_where("defaultvalue")
        try:
            data = values.encode(dtype, number, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            raise DcfError(
                f"value '{text}' of {entry.label} uses $NODEID but no node-ID is known",
                where, rule="DCF201",
                hint="give --node-id N or set NodeID in [DeviceComissioning]") from None
        except values.ValueProblem as exc:
            raise DcfError(f"{entry.label} DefaultValue: {_clip(str(exc))}", where,
                           rule="DCF200") from None
        return int.from_bytes(data, "little", signed=dtype.kind == dt.SINT)

    # -- values compile does not write (SPEC "Errors vs warnings") -----------------------
    def text_problem(self, dtype: dt.DataType, text: str) -> str | None:
        """What is wrong with ``text`` as a value of ``dtype`` (None: nothing), in the
        words of validate's DCF200. Without a node-ID, a ``$NODEID`` value must fit for
        node-IDs 1 and 127. Remembered per (type, text): a file repeats few value texts."""
        key = (dtype.code, text)
        verdicts = self._verdicts
        if key in verdicts:
            return verdicts[key]
        if key in self.encoded:   # encoded once already, so nothing is wrong with it
            return None
        number = text
        if dtype.is_numeric or dtype.kind == dt.BOOL:
            number = values.split_numeric_comment(text)[0]   # DCF203 is validate's
        problem = None
        try:
            values.encode(dtype, number, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            for trial in (1, 127):
                try:
                    values.encode(dtype, number, node_id=trial, encoding=self.encoding)
                except values.ValueProblem as exc:
                    problem = f"{_clip(str(exc))} (with node-ID {trial})"
                    break
        except values.ValueProblem as exc:
            problem = _clip(str(exc))
        if len(verdicts) < 4096:
            verdicts[key] = problem
        return problem

    def value_problems(self, written, whole: set[int] | frozenset = frozenset()
                       ) -> list[Problem]:
        """The values in the file that cannot be encoded (DCF200) and the unreadable
        DownloadFiles (DCF202), as errors, except the effective value of every entry that
        ``written(index, sub)`` says is written (encoding it reports its own error);
        ``whole`` are objects written whole. ``written(index, None)``: any entry of the
        object. ``compile`` prints these as warnings; a large PLC file costs a few
        attribute reads per variable (its values are all written)."""
        out: list[Problem] = []
        seen: set = set()   # CompactSubObj: one DefaultValue line for N entries
        for idx, obj in self.objects.items():
            in_whole = idx in whole
            if in_whole and not is_pdo_mapping(idx):
                # every effective value is written (60,000 network variables): only a
                # DefaultValue behind a ParameterValue/DownloadFile is not
                for e in obj.entries.values():
                    if e.default is not None and (e.param is not None or e.download_file
                                                  is not None) and e.dtype is not None \
                            and not e.implicit:
                        self._text_check(out, seen, e, "defaultvalue", e.default)
                continue
            some = in_whole or written(idx, None)
            for sub, e in obj.entries.items():
                if e.dtype is None or e.implicit:
                    continue
                param, default = e.param, e.default
                behind = param is not None or e.download_file is not None
                if default is not None and behind:
                    self._text_check(out, seen, e, "defaultvalue", default)
                if in_whole or (some and written(idx, sub)):
                    continue   # the effective value is written
                if param is not None:
                    self._text_check(out, seen, e, "parametervalue", param)
                elif e.download_file is not None:
                    try:
                        self._download(e)
                    except DcfError as exc:
                        out.append(Problem(exc.diagnostic, idx, sub))
                elif default is not None:
                    self._text_check(out, seen, e, "defaultvalue", default)
            if is_pdo_mapping(idx) and not (some and written(idx, 0)):
                unstated = unstated_mapping_count(obj)
                if unstated is not None:
                    where, message = unstated
                    out.append(Problem(Diagnostic(Severity.ERROR, message, where.file,
                                                  where.line, rule="DCF419"), idx, 0))
        return out

    def _text_check(self, out: list, seen: set, e: Entry, key: str, text: str) -> None:
        problem = self.text_problem(e.dtype, text)
        if problem is None:
            return
        line = e.key_where(key).line
        if (line, e.dtype.code, text) in seen:
            return
        seen.add((line, e.dtype.code, text))
        shown = "ParameterValue" if key == "parametervalue" else "DefaultValue"
        out.append(Problem(Diagnostic(Severity.ERROR, f"{e.label} {shown}: {problem}",
                                      self.path, line, rule="DCF200"), e.index, e.sub))

    # -- interop -----------------------------------------------------------------------
    def to_canopen(self):
        """This model as a ``canopen.objectdictionary.ObjectDictionary``.

        Values that cannot be encoded (bad value, missing node-ID) are left at the
        type's zero; use ``dcf2bin validate`` to see them.
        """
        from dcf2bin.interop import to_canopen
        return to_canopen(self)


def unstated_mapping_count(obj: Obj) -> tuple[Where, str] | None:
    """A PDO mapping object with sub-entries whose sub 0 gives no value (no sub 0 section,
    or one without DefaultValue/ParameterValue: Elmo EDS files write only HighLimit=8)
    does not say how many objects it maps; the model's sub 0 is then the highest subindex
    present (SPEC §1). Returns where to say so and the message (DCF419), else None.
    ``compile`` refuses to write a PDO block from such a count (README, choices)."""
    if not is_pdo_mapping(obj.index) or obj.implicit or obj.compact or len(obj.entries) < 2:
        return None
    e0 = obj.entries.get(0)
    if e0 is None:
        return None
    highest = max(obj.entries)
    if e0.implicit:
        what = f"PDO mapping 0x{obj.index:04X} has no sub 0"
    elif e0.section is not None and not any(
            e0.section.values.get(k) for k in ("parametervalue", "defaultvalue", "downloadfile")):
        what = f"{e0.label} has no DefaultValue or ParameterValue"
    else:
        return None
    return (e0.where or obj.where or Where(""),
            f"{what}: the number of mapped objects is not given (the highest subindex "
            f"present, {highest}, would be taken)")


# -- building ----------------------------------------------------------------------------

def load(path: str, *, node_id: int | None = None, allow_external_files: bool = False,
         data: bytes | None = None) -> Device:
    """Read a DCF/EDS file into a Device. Problems are collected, never raised."""
    if data is None:
        with open(path, "rb") as f:
            data = f.read()
    parsed = ini_mod.parse_bytes(data, path)
    return build(parsed, node_id=node_id, allow_external_files=allow_external_files)


def build(parsed: ini_mod.IniFile, *, node_id: int | None = None,
          allow_external_files: bool = False) -> Device:
    dev = Device(parsed.path, parsed.encoding, ini=parsed,
                 allow_external_files=allow_external_files)
    for d in parsed.diagnostics:
        dev.problems.append(Problem(d))
    _Builder(dev, parsed).run(node_id)
    return dev


def _int_or(text: str | None, default: int) -> int:
    if text is None:
        return default
    return values.parse_int(values.split_numeric_comment(text)[0])


class _Builder:
    def __init__(self, dev: Device, parsed: ini_mod.IniFile):
        self.dev = dev
        self.ini = parsed
        self.path = parsed.path

    def w(self, line: int | None) -> Where:
        return Where(self.path, line)

    def run(self, node_id: int | None) -> None:
        self._duplicates()
        self._node_id(node_id)
        self._dummy_usage()
        subs: dict[int, dict[int, ini_mod.Section]] = {}
        aux: dict[tuple[int, str], ini_mod.Section] = {}
        mains: dict[int, ini_mod.Section] = {}
        section_match, aux_match = _SECTION_RE.fullmatch, _AUX_RE.fullmatch
        hex4: dict[str, int] = {}   # the object indexes seen, as their section names
        for canon, sec in self.ini.sections.items():
            # the common case, a sub-section "<index>sub<n>" of an object already seen
            obj_hex, is_sub, sub_hex = canon.partition("sub")
            if is_sub:
                idx, sub = hex4.get(obj_hex), _SUB_HEX.get(sub_hex)
                if idx is not None and sub is not None:
                    group = subs.get(idx)
                    if group is None:
                        group = subs[idx] = {}
                    group[sub] = sec
                    continue
            m = section_match(canon)
            if m is not None:
                obj_hex, sub_hex = m.groups()
                idx = hex4[obj_hex] = int(obj_hex, 16)
                if sub_hex is None:
                    mains[idx] = sec
                    continue
                sub = int(sub_hex, 16)
                if sub > 0xFF:
                    self.dev.error(f"subindex 0x{sub:X} of [{sec.name}] is above 0xFF",
                                   self.w(sec.line), idx, rule="DCF005")
                    continue
                subs.setdefault(idx, {})[sub] = sec
                continue
            m = aux_match(canon)
            if m:
                aux[(int(m.group(1), 16), m.group(2))] = sec
        for idx in sorted(set(subs) - set(mains)):
            first = min(subs[idx].values(), key=lambda s: s.line)
            self.dev.error(f"[{first.name}] has no object section [{idx:04X}]",
                           self.w(first.line), idx, rule="DCF006")
        for idx in sorted(mains):
            try:
                self._object(idx, mains[idx], subs.get(idx, {}), aux)
            except values.ValueProblem as exc:  # defensive: a bad structural number
                self.dev.error(f"[{mains[idx].name}]: {exc}", self.w(mains[idx].line), idx,
                               rule="DCF020")
        for (idx, kind), sec in aux.items():
            if idx not in mains and kind in ("name", "value", "denotation"):
                self.dev.warning(f"[{sec.name}] has no object section [{idx:04X}]; ignored",
                                 self.w(sec.line), rule="DCF007")
        self._compact_pdo()
        layout.attach_channels(self.dev)

    # -- file-level keys ---------------------------------------------------------------
    def _duplicates(self) -> None:
        for d in self.ini.duplicates:
            idx, sub = _section_target(d.section)
            sec = self.ini.sections.get(d.section)
            shown = sec.name if sec else d.section
            if d.key is None:
                msg = f"section [{shown}] repeated (first at line {d.first_line})"
            else:
                key = sec.keys[d.key].name if sec and d.key in sec.keys else d.key
                msg = f"key '{key}' repeated in [{shown}] (first at line {d.first_line})"
            self.dev.error(msg, self.w(d.line), idx, sub, rule="DCF010",
                           hint="remove one of them; dcf2bin does not guess which is meant")

    def _node_id(self, cli_node_id: int | None) -> None:
        sec1 = self.ini.section("devicecomissioning")
        sec2 = self.ini.section("devicecommissioning")
        if sec1 is not None and sec2 is not None:
            self.dev.warning("both [DeviceComissioning] and [DeviceCommissioning] present; "
                             "[DeviceComissioning] wins", self.w(sec2.line), rule="DCF011")
        sec = sec1 if sec1 is not None else sec2
        if cli_node_id is not None:
            self.dev.node_id = cli_node_id
            self.dev.node_id_from_cli = True
            return
        if sec is None:
            return
        text = sec.get("nodeid")
        if text is None:
            return
        where = self.w(sec.line_of("nodeid"))
        if values.uses_nodeid(text):
            self.dev.error("NodeID cannot itself use $NODEID", where, rule="DCF012")
            return
        try:
            nid = values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem as exc:
            self.dev.error(f"NodeID: {exc}", where, rule="DCF012")
            return
        if not 1 <= nid <= 127:
            self.dev.error(f"NodeID {nid} is outside 1..127", where, rule="DCF012")
            return
        self.dev.node_id = nid
        self.dev.node_id_where = where

    def _dummy_usage(self) -> None:
        sec = self.ini.section("dummyusage")
        if sec is None:
            return
        for key, k in sec.keys.items():
            if key.startswith("dummy") and len(key) == 9:
                try:
                    code = int(key[5:], 16)
                    if k.value and values.parse_int(values.split_numeric_comment(k.value)[0]) == 1:
                        self.dev.dummy_usage.add(code)
                except (ValueError, values.ValueProblem):
                    self.dev.warning(f"bad [DummyUsage] entry '{k.name}={k.value}'",
                                     self.w(k.line), rule="DCF013")

    # -- objects -----------------------------------------------------------------------
    def _int_key(self, sec: ini_mod.Section, key: str, default: int | None,
                 idx: int, sub: int | None = None) -> int | None:
        text = sec.get(key)
        if text is None:
            return default
        try:
            return values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem as exc:
            self.dev.error(f"[{sec.name}] {sec.keys[key].name}: {exc}",
                           self.w(sec.line_of(key)), idx, sub, rule="DCF020")
            return default

    def _object(self, idx: int, sec: ini_mod.Section, subsecs: dict[int, ini_mod.Section],
                aux: dict[tuple[int, str], ini_mod.Section]) -> None:
        dev = self.dev
        obj = Obj(idx, sec.get("parametername") or "", where=self.w(sec.line), section=sec)
        ot = self._int_key(sec, "objecttype", None, idx)
        obj.sub_number = self._int_key(sec, "subnumber", None, idx)
        obj.compact = self._int_key(sec, "compactsubobj", 0, idx) or 0
        if obj.compact and not 1 <= obj.compact <= 0xFE:
            dev.error(f"CompactSubObj={obj.compact} is outside 1..254", self.w(
                sec.line_of("compactsubobj")), idx, rule="DCF021")
            obj.compact = 0
        has_subs = bool(subsecs) or bool(obj.sub_number) or obj.compact > 0
        if ot is not None and ot not in dt.OBJECT_TYPES:
            dev.error(f"[{sec.name}] unknown ObjectType 0x{ot:X}", self.w(sec.line_of("objecttype")),
                      idx, rule="DCF022")
            ot = None
        if ot in (dt.OT_ARRAY, dt.OT_RECORD):
            obj.complex = True
        elif has_subs:
            obj.complex = True
            if ot is not None:
                dev.warning(f"[{sec.name}] has ObjectType 0x{ot:X} but sub-objects; "
                            "treated as ARRAY/RECORD", self.w(sec.line_of("objecttype")), idx,
                            rule="DCF023")
            ot = dt.OT_RECORD if not is_network_variable_index(idx) else dt.OT_ARRAY
        obj.object_type = ot if ot is not None else dt.OT_VAR
        dev.objects[idx] = obj
        obj_flags = self._int_key(sec, "objflags", 0, idx) or 0
        obj_map = _pdo_flag(sec.get("pdomapping"))
        nv = is_network_variable_index(idx)

        if not obj.complex:
            if nv:
                dev.error(f"[{sec.name}] is a VAR; objects in 0xA000-0xAFFF must be ARRAYs",
                          self.w(sec.line), idx, rule="DCF300")
            e = self._entry(idx, 0, sec, obj_flags=obj_flags, obj_map=obj_map)
            obj.entries[0] = e
            return

        if obj.compact:
            for s in sorted(subsecs):
                if s != 0:
                    dev.warning(f"[{subsecs[s].name}] given although [{sec.name}] has "
                                "CompactSubObj; the sub-section wins", self.w(subsecs[s].line),
                                idx, s, rule="DCF024")
            if sec.get("parametervalue") is not None:
                dev.warning(f"ParameterValue in [{sec.name}] of a CompactSubObj object is "
                            "ignored (use [%04XValue])" % idx,
                            self.w(sec.line_of("parametervalue")), idx, rule="DCF025")
            names = aux.get((idx, "name"))
            vals = aux.get((idx, "value"))
            dens = aux.get((idx, "denotation"))
            base_name = obj.name
            proto = lines = None     # every compact sub-entry is the object's section
            for s in range(1, obj.compact + 1):
                if s in subsecs:
                    continue
                if proto is not None:
                    obj.entries[s] = Entry(idx, s, f"{base_name}{s}", *proto,
                                           Where(self.path, sec.line), dict(lines), False,
                                           None)
                    continue
                problems = len(dev.problems)
                e = self._entry(idx, s, sec, obj_flags=obj_flags, obj_map=obj_map)
                e.name = f"{base_name}{s}"
                e.param = None
                e.section = None            # its keys are the object's: lines by hand
                e.lines = {k: sec.line_of(k) for k in sec.values if k != "parametervalue"}
                obj.entries[s] = e
                if len(dev.problems) == problems:   # else each reports its own
                    proto, lines = _proto(e), e.lines
            for kind, asec in (("name", names), ("value", vals), ("denotation", dens)):
                if asec is None:
                    continue
                for key, k in asec.keys.items():
                    if key == "nrofentries":
                        continue
                    try:
                        s = int(key, 10)  # SPEC §1: decimal subindexes
                    except ValueError:
                        dev.warning(f"[{asec.name}] key '{k.name}' is not a decimal subindex",
                                    self.w(k.line), idx, rule="DCF026")
                        continue
                    e = obj.entries.get(s)
                    if e is None or s == 0:
                        dev.warning(f"[{asec.name}] subindex {s} is outside CompactSubObj="
                                    f"{obj.compact}; ignored", self.w(k.line), idx, rule="DCF026")
                        continue
                    if kind == "name":
                        e.name = k.value
                    elif kind == "value":
                        e.param = k.value if k.value != "" else None
                        e.lines["parametervalue"] = k.line
                    else:
                        e.denotation = k.value
        else:
            vsec = aux.get((idx, "value"))
            if vsec is not None:
                dev.warning(f"[{vsec.name}] without CompactSubObj in [{sec.name}] is ignored",
                            self.w(vsec.line), idx, rule="DCF027")

        protos: dict[int, tuple] = {}
        entries, path = obj.entries, self.path
        for s in sorted(subsecs):
            ssec = subsecs[s]
            if s and ssec.param_name is not None:
                # an entry like one already built but for its names (see _entry),
                # inline: 60,000 of them in a large PLC file
                proto = protos.get(id(ssec.rest))
                if proto is not None:
                    e = entries[s] = Entry(idx, s, ssec.param_name or "", *proto,
                                           Where(path, ssec.line), None, False, ssec)
                    if ssec.denotation is not None:   # cut out of the template too
                        e.denotation = ssec.denotation or None
                    continue
            if s == 0:
                # an explicit sub 0 section inherits ObjFlags/PDOMapping like any
                # sub-entry (SPEC §1); only an implied or created sub 0 does not
                e = self._entry(idx, 0, ssec, obj_flags=obj_flags, obj_map=obj_map, sub0=True)
            else:
                e = self._entry(idx, s, ssec, obj_flags=obj_flags, obj_map=obj_map,
                                protos=protos)
            obj.entries[s] = e
        ordered = not obj.compact   # so far added by ascending subindex
        if 0 not in obj.entries:
            highest = max((s for s in obj.entries), default=0)
            ordered = ordered and not obj.entries   # sub 0 goes last
            obj.entries[0] = Entry(idx, 0, "Highest sub-index supported", dt.UNSIGNED8, "ro",
                                   default=str(obj.compact or highest), where=obj.where,
                                   implicit=True)
        else:
            e0 = obj.entries[0]
            if e0.default is None and e0.param is None:
                e0.default = str(obj.compact or max(obj.entries))
        if not ordered:  # entries are kept by ascending subindex
            obj.entries = dict(sorted(obj.entries.items()))

    def _entry(self, idx: int, sub: int, sec: ini_mod.Section, *, obj_flags: int = 0,
               obj_map: bool = False, sub0: bool = False,
               protos: dict[int, tuple] | None = None) -> Entry:
        """One sub-object. ``protos`` (one dict per object, whose ObjFlags and PDOMapping
        its sub-entries inherit) remembers the fields of an entry whose section shares the
        INI reader's template (``Section.rest``: the same text but for the values of
        ParameterName and Denotation), so that ``_object`` builds the other sub-entries
        of a network-variable array from them. Only an entry that raised no problem is
        remembered: every faulty one reports its own."""
        shape = sec.rest if protos is not None and sec.param_name is not None else None
        problems = len(self.dev.problems)
        e = self._entry_from(idx, sub, sec, obj_flags, obj_map, sub0)
        if shape is not None and len(self.dev.problems) == problems:
            protos[id(shape)] = _proto(e)
        return e

    def _entry_from(self, idx: int, sub: int, sec: ini_mod.Section, obj_flags: int,
                    obj_map: bool, sub0: bool) -> Entry:
        dev = self.dev
        get = sec.values.get  # '' counts as absent
        # positional, in field order
        e = Entry(idx, sub, get("parametername") or "", None, None, False, 0,
                  get("defaultvalue") or None, get("parametervalue") or None,
                  get("downloadfile") or None, get("lowlimit") or None,
                  get("highlimit") or None, get("denotation") or None,
                  Where(self.path, sec.line), None, False, sec)
        e.obj_flags = (self._int_key(sec, "objflags", obj_flags, idx, sub) or 0
                       if get("objflags") else obj_flags)
        pm = get("pdomapping") or None
        e.pdo_mapping = _pdo_flag(pm) if pm is not None else obj_map
        nv = is_network_variable_index(idx) and sub >= 1
        text = get("datatype")
        if text:
            e.dtype = _DTYPES.get(text)
            if e.dtype is None:
                e.dtype = self._datatype(sec, text, idx, sub)
        elif sub0:
            e.dtype = dt.UNSIGNED8
        elif not nv:
            dev.error(f"[{sec.name}] has no DataType", self.w(sec.line), idx, sub,
                      rule="DCF031")
        text = get("accesstype")
        if text:
            acc = _ACCESS.get(text) or text.strip().lower()
            if acc in dt.ACCESS_ATTR:
                e.access = acc
            else:
                dev.error(f"[{sec.name}] unknown AccessType '{text}'",
                          self.w(sec.line_of("accesstype")), idx, sub, rule="DCF032")
        elif sub0:
            e.access = "ro"
        elif not nv:
            dev.error(f"[{sec.name}] has no AccessType", self.w(sec.line), idx, sub,
                      rule="DCF033")
        return e

    def _datatype(self, sec: ini_mod.Section, text: str, idx: int, sub: int):
        try:
            code = values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem as exc:
            self.dev.error(f"[{sec.name}] DataType: {exc}", self.w(sec.line_of("datatype")),
                           idx, sub, rule="DCF030")
            return None
        dtype = dt.BY_CODE.get(code)
        if dtype is None:
            self.dev.error(f"[{sec.name}] unknown or unsupported DataType 0x{code:04X}",
                           self.w(sec.line_of("datatype")), idx, sub, rule="DCF030")
        elif len(_DTYPES) < 256:
            _DTYPES[text] = dtype
        return dtype

    # -- CompactPDO (CiA 306 §4.6.3.4.1, SPEC §1) -------------------------------------------
    def _compact_pdo(self) -> None:
        dev = self.dev
        info = self.ini.section("deviceinfo")
        if info is None:
            return
        numbers = []
        for key in ("compactpdo", "nrofrxpdo", "nroftxpdo"):
            try:
                numbers.append(_int_or(info.get(key), 0))
            except values.ValueProblem as exc:   # at the key's line, not the header's
                dev.error(f"[DeviceInfo] {info.keys[key].name}: {exc}", self.w(info.line_of(key)),
                          rule="DCF040")
                return
        mask, n_rx, n_tx = numbers
        if not mask:
            return
        where = self.w(info.line_of("compactpdo"))
        for base, n, cob_bases in ((RPDO_COMM, n_rx, (0x200, 0x300, 0x400, 0x500)),
                                   (TPDO_COMM, n_tx, (0x180, 0x280, 0x380, 0x480))):
            for k in range(min(n, 512)):
                comm, mapping = base + k, base + 0x200 + k
                if comm not in dev.objects:
                    obj = Obj(comm, "PDO communication parameter", dt.OT_RECORD, where=where,
                              implicit=True, complex=True)
                    present = [s for s in range(1, 7) if mask & (1 << (s - 1))]
                    obj.entries[0] = Entry(comm, 0, "Highest sub-index supported", dt.UNSIGNED8,
                                           "ro", default=str(max(present, default=0)),
                                           where=where, implicit=True)
                    for s in present:
                        if s == 1:
                            cob = (f"$NODEID+0x{cob_bases[k]:X}" if k < 4 else "0x80000000")
                            e = Entry(comm, 1, "COB-ID", dt.UNSIGNED32, "rw", default=cob)
                        elif s == 2:
                            e = Entry(comm, 2, "Transmission type", dt.UNSIGNED8, "rw",
                                      default="255")
                        elif s in (3, 5):
                            e = Entry(comm, s, "Inhibit time" if s == 3 else "Event timer",
                                      dt.UNSIGNED16, "rw", default="0")
                        else:
                            e = Entry(comm, s, "Reserved" if s == 4 else "SYNC start value",
                                      dt.UNSIGNED8, "rw", default="0")
                        e.where, e.implicit = where, True
                        obj.entries[s] = e
                    dev.objects[comm] = obj
                if mapping not in dev.objects:
                    obj = Obj(mapping, "PDO mapping parameter", dt.OT_RECORD, where=where,
                              implicit=True, complex=True)
                    obj.entries[0] = Entry(mapping, 0, "Number of mapped objects", dt.UNSIGNED8,
                                           "rw", default="0", where=where, implicit=True)
                    for s in range(1, 9):
                        obj.entries[s] = Entry(mapping, s, f"Mapped object {s}", dt.UNSIGNED32,
                                               "rw", default="0", where=where, implicit=True)
                    dev.objects[mapping] = obj


def _clip(message: str, n: int = 160) -> str:
    """Keep diagnostics one readable line even for a 4 KiB DOMAIN value or control bytes."""
    if not message.isprintable():
        message = "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in message)
    return message if len(message) <= n else message[:n - 20] + "..." + message[-17:]


# Caches of the few distinct texts a file uses for these keys (hot path: one lookup
# per entry instead of parsing "0x0007" 60,000 times).
_DTYPES: dict[str, dt.DataType] = {}
_ACCESS = {a: a for a in dt.ACCESS_ATTR}
_PDO_FLAG: dict[str, bool] = {}


def _pdo_flag(text: str | None) -> bool:
    if text is None:
        return False
    flag = _PDO_FLAG.get(text)
    if flag is None:
        try:
            flag = values.parse_int(values.split_numeric_comment(text)[0]) == 1
        except values.ValueProblem:
            flag = False
        if len(_PDO_FLAG) < 64:
            _PDO_FLAG[text] = flag
    return flag


def _proto(e: Entry) -> tuple:
    """The fields of ``e`` that entries built like it share: Entry's fields after index,
    sub and name, up to where (``Entry(index, sub, name, *_proto(e), where, ...)``)."""
    return (e.dtype, e.access, e.pdo_mapping, e.obj_flags, e.default, e.param,
            e.download_file, e.low, e.high, e.denotation)


def _section_target(canon: str) -> tuple[int | None, int | None]:
    m = _SECTION_RE.fullmatch(canon)
    if m:
        obj_hex, sub_hex = m.groups()
        return int(obj_hex, 16), int(sub_hex, 16) if sub_hex is not None else None
    m = _AUX_RE.fullmatch(canon)
    if m:
        return int(m.group(1), 16), None
    return None, None

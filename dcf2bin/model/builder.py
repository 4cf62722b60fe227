"""INI file -> ``Device``: ``load``/``build`` and ``_Builder``, which runs the steps in order
(sections, $NODEID, [DummyUsage], objects, entries, CompactPDO) and records problems.
"""
from __future__ import annotations

from dcf2bin import ini as ini_mod, layout, values
from dcf2bin.diagnostics import Diagnostic, Severity, Where, shorten, summary_finding
from dcf2bin.model.build_entry import _EntrySteps
from dcf2bin.model.build_object import _ObjectStep
from dcf2bin.model.compact_pdo import _CompactPdoStep
from dcf2bin.model.device import Device
from dcf2bin.model.objects import Problem
from dcf2bin.model.sections import _AUX_RE, _SECTION_RE, _section_target, _SUB_HEX


def load(path: str, *, node_id: int | None = None, allow_external_files: bool = False,
         data: bytes | None = None) -> Device:
    """Read a DCF/EDS file into a Device. Problems are collected, never raised."""
    if data is None:
        from dcf2bin.fileio.reading import read_file    # bounded; OSError as open's
        data = read_file(path)
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


class _Builder(_ObjectStep, _EntrySteps, _CompactPdoStep):
    def __init__(self, dev: Device, parsed: ini_mod.IniFile):
        self.dev = dev
        self.ini = parsed
        self.path = parsed.path
        # what an entry read from its own section stores for its ``where`` (see Entry):
        # the path, from which Entry.where makes the Where when it is first read
        self.lazy_where = parsed.path if type(parsed.path) is str else None

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
        for canon in self.ini.respelled:       # [1018sub001]: DCF061
            self._sub_spelling(canon, self.ini.sections[canon])
        last_hex = last_group = None     # the sub-sections of an object come in a run
        sub_hex_get = _SUB_HEX.get
        for canon, sec in self.ini.sections.items():
            # the common case, a sub-section "<index>sub<n>" of an object already seen
            obj_hex, is_sub, sub_hex = canon.partition("sub")
            if is_sub:
                sub = sub_hex_get(sub_hex)
                if sub is not None:
                    if obj_hex == last_hex:
                        last_group[sub] = sec
                        continue
                    idx = hex4.get(obj_hex)
                    if idx is not None:
                        group = subs.get(idx)
                        if group is None:
                            group = subs[idx] = {}
                        group[sub] = sec
                        last_hex, last_group = obj_hex, group
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
                    self.dev.error(f"subindex {shorten(f'0x{sub:X}')} of [{shorten(sec.name)}] "
                                   "is above 0xFF",
                                   self.w(sec.line), idx, rule="DCF005")
                    continue
                subs.setdefault(idx, {})[sub] = sec
                continue
            m = aux_match(canon)
            if m:
                aux[(int(m.group(1), 16), m.group(2))] = sec
        for idx in sorted(set(subs) - set(mains)):
            first = min(subs[idx].values(), key=lambda s: s.line)
            self.dev.error(f"[{shorten(first.name)}] has no object section [{idx:04X}]",
                           self.w(first.line), idx, rule="DCF006")
        for idx in sorted(mains):
            try:
                self._object(idx, mains[idx], subs.get(idx, {}), aux)
            except values.ValueProblem as exc:  # defensive: a bad structural number
                self.dev.error(f"[{shorten(mains[idx].name)}]: {exc}", self.w(mains[idx].line), idx,
                               rule="DCF020")
        for (idx, kind), sec in aux.items():
            if idx not in mains and kind in ("name", "value", "denotation"):
                self.dev.warning(f"[{shorten(sec.name)}] has no object section [{idx:04X}]; "
                                 "ignored",
                                 self.w(sec.line), rule="DCF007")
        self._compact_pdo()
        layout.attach_channels(self.dev)

    def _sub_spelling(self, canon: str, sec: ini_mod.Section) -> None:
        """[1018sub001] is read as [1018sub1]: say so in validate's words (DCF061)."""
        obj_hex, is_sub, _ = canon.partition("sub")
        digits = sec.name.strip().lower().partition("sub")[2]
        if not is_sub or len(digits) <= 2 or digits.strip("0123456789abcdef"):
            return
        sub = int(digits, 16)
        if sub > 0xFF:
            return   # DCF005
        self.dev.warning(f"[{shorten(sec.name)}] has a subindex of {len(digits)} digits; it is "
                         "read "
                         f"as [{obj_hex.upper()}sub{sub:X}], the canonical spelling",
                         self.w(sec.line), int(obj_hex, 16), sub, rule="DCF061",
                         hint="a subindex has 1 or 2 hex digits: write the canonical "
                              "section name")

    # -- file-level keys ---------------------------------------------------------------
    def _duplicates(self) -> None:
        hint = "remove one of them; dcf2bin does not guess which is meant"
        for d in self.ini.duplicates:
            idx, sub = _section_target(d.section)
            self.dev.error(self._repeated(d), self.w(d.line), idx, sub, rule="DCF010",
                           hint=hint)
        n, d = self.ini.more_duplicates, self.ini.first_left_out
        if n:
            # the repeats the reader only counted (after diagnostics.LIMIT): one finding
            # that touches no one object, so that compile stops on it (it cannot tell
            # whether they touch an entry it writes)
            self.dev.problems.append(Problem(summary_finding(Diagnostic(
                Severity.ERROR, self._repeated(d), self.path, d.line, rule="DCF010",
                hint=hint), n)))

    def _repeated(self, d) -> str:
        sec = self.ini.sections.get(d.section)
        shown = sec.name if sec else d.section
        if d.key is None:
            return f"section [{shorten(shown)}] repeated (first at line {d.first_line})"
        key = sec.keys[d.key].name if sec and d.key in sec.keys else d.key
        return f"key '{shorten(key)}' repeated in [{shorten(shown)}] (first at line {d.first_line})"

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
                    self.dev.warning(f"bad [DummyUsage] entry "
                                     f"'{shorten(k.name)}={shorten(k.value)}'",
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
            self.dev.error(f"[{shorten(sec.name)}] {shorten(sec.keys[key].name)}: {exc}",
                           self.w(sec.line_of(key)), idx, sub, rule="DCF020")
            return default

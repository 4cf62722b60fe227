"""The keys and values of the network file (SPEC §10.1, D-16): which keys each part
reads, their value syntax and ranges, and the readers of the lists (PDOs, mappings, sdo
writes) that ``yamlfile`` uses. Every finding names its ``file:line``."""
from __future__ import annotations

import functools
import os

from dcf2bin import values
from dcf2bin.diagnostics import Diagnostics, Where, shorten
from dcf2bin.network.model import RPDO, TPDO, MapConfig, Network, Node, PdoConfig, SdoConfig
from dcf2bin.network.yamltree import LongInt, YMap, YSeq

PLACEHOLDER = "@BUS_CONFIG_PATH@/"

# key -> kind of value: int, bool, float (a number), str (a text, not empty), text (a
# text, maybe empty), cob (a COB-ID), behavior ({sub: value}), or a special reader. Every
# key lely's dcfgen (dcf-tools 2.4.2) reads is here: docs/network.md says what each does
# for a lely master and for a PLC master.
OPTION_KEYS = {"heartbeat_multiplier": "float", "retry_factor": "int", "dcf_path": "text"}
MASTER_KEYS = {
    "node_id": "int", "dcf": "path", "name": "str", "heartbeat_producer": "int",
    "heartbeat_consumer": "consumer", "heartbeat_multiplier": "float", "sync_period": "int",
    "sync_window": "int", "start": "bool", "start_nodes": "bool", "start_all_nodes": "bool",
    "reset_all_nodes": "bool", "stop_all_nodes": "bool", "boot_time": "int",
    "bitrate": "int", "baudrate": "int",
    # the lely master's own identity (0x1018, [DeviceInfo]) and communication objects
    "vendor_id": "int", "product_code": "int", "revision_number": "int",
    "serial_number": "int", "sync_overflow": "int", "time_cob_id": "cob",
    "emcy_inhibit_time": "int", "nmt_inhibit_time": "int", "error_behavior": "behavior",
}
SLAVE_KEYS = {
    "dcf": "path", "node_id": "int", "rpdo": "pdos", "tpdo": "pdos",
    "heartbeat_producer": "int", "heartbeat_consumer": "bool", "heartbeat_multiplier": "float",
    "boot": "bool", "mandatory": "bool", "reset_communication": "bool", "retry_factor": "int",
    "guard_time": "int", "life_time_factor": "int", "vendor_id": "int", "product_code": "int",
    "revision_number": "int", "serial_number": "int", "software_version": "int",
    "sdo": "sdo", "names": "names", "time_cob_id": "cob", "error_behavior": "behavior",
    "software_file": "str", "restore_configuration": "int", "configuration_file": "str",
    "dcf_path": "text",
}
PDO_KEYS = {"enabled": "bool", "cob_id": "cob", "transmission": "int", "inhibit_time": "int",
            "event_timer": "int", "event_deadline": "int", "sync_start": "int",
            "mapping": "mapping"}
MAP_KEYS = {"index": "int", "sub_index": "int", "name": "str"}
SDO_KEYS = {"index": "int", "sub_index": "int", "value": "any"}
# keys lely's dcfgen or ros2_canopen read that dcf2bin does not use: info, never a near-miss
KNOWN_UNUSED = frozenset("""
baud_rate driver package polling period enable_lazy_load position_mode
sdo_timeout_ms boot_timeout_ms scale_pos_to_dev scale_pos_from_dev scale_vel_to_dev
scale_vel_from_dev scale_eff_to_dev scale_eff_from_dev switching_state homing_timeout_seconds
diagnostics use_ros2_control time_producer offset_pos_to_dev offset_pos_from_dev
""".split())
# ranges of the integer keys (inclusive); a time multiplied later is checked there
RANGES = {
    "node_id": (1, 127), "heartbeat_producer": (0, 0xFFFF), "sync_period": (0, 0xFFFFFFFF),
    "sync_window": (0, 0xFFFFFFFF), "boot_time": (0, 0xFFFFFFFF), "bitrate": (1, 10**7),
    "baudrate": (1, 10**4), "retry_factor": (0, 0xFF), "guard_time": (0, 0xFFFF),
    "life_time_factor": (0, 0xFF), "vendor_id": (0, 0xFFFFFFFF),
    "product_code": (0, 0xFFFFFFFF), "revision_number": (0, 0xFFFFFFFF),
    "serial_number": (0, 0xFFFFFFFF), "software_version": (0, 0xFFFFFFFF),
    "transmission": (0, 0xFF), "inhibit_time": (0, 0xFFFF), "event_timer": (0, 0xFFFF),
    "event_deadline": (0, 0xFFFF), "sync_start": (0, 0xFF), "index": (0, 0xFFFF),
    "sub_index": (0, 0xFF), "heartbeat_consumer": (0, 0xFFFF),   # {slave: ms}: 16 bits
    # at the type of the entry each is written to: 0x1019 UNSIGNED8, 0x1015 and 0x102A
    # UNSIGNED16 (x 100 us), 0x1F8A UNSIGNED8 (a sub-index of the slave's 0x1011)
    "sync_overflow": (0, 0xFF), "emcy_inhibit_time": (0, 0xFFFF),
    "nmt_inhibit_time": (0, 0xFFFF), "restore_configuration": (0, 0xFF),
}

# keys whose values are object indexes: a value out of range is shown in hex
HEX_KEYS = frozenset({"index"})

# error_behavior: {sub: value}, 0x1029 sub 1..254 (sub 0 is the count), UNSIGNED8 values
BEHAVIOR_SUBS, BEHAVIOR_VALUES = (1, 0xFE), (0, 0xFF)


# -- near misses (NET006) ------------------------------------------------------------------
# A key is a near miss of a known key when, written in lower case with '-' and blanks as
# '_', it is that key, or one edit away from it: a character left out, one added, one
# replaced, two neighbours swapped; from a known key of 8 or more characters also two
# left out ("hearbeat_produer"). Found by deletions (as SymSpell does): the known keys'
# variants with up to one (two) characters left out are indexed once per vocabulary,
# and a key is looked up with itself and its variants with one character left out. The
# cost is a few dict lookups per key, whatever the file holds (difflib's ratio against
# every known key cost 1.2 ms a key: 30,000 unknown keys took 39 s, issue 26).


@functools.lru_cache(maxsize=None)
def _near_index(known: tuple[str, ...]) -> tuple[dict[str, tuple[int, int, str]], int,
                                                   dict[int, None]]:
    """(variant -> (edits, position, known key) with the fewest edits, then the first
    known key; the longest known key; the characters of the known keys, to delete)."""
    index: dict[str, tuple[int, int, str]] = {}
    for order, k in enumerate(known):
        variants = {k: 0}
        for i in range(len(k)):
            variants.setdefault(k[:i] + k[i + 1:], 1)
        if len(k) >= 8:
            for v, n in list(variants.items()):
                if n == 1:
                    for j in range(len(v)):
                        variants.setdefault(v[:j] + v[j + 1:], 2)
        for v, n in variants.items():
            if v not in index or (n, order) < index[v][:2]:
                index[v] = (n, order, k)
    chars = dict.fromkeys(map(ord, "".join(known)))
    return index, max(map(len, known), default=0), chars


def near_miss(text: str, known) -> str | None:
    """The known key that ``text`` is a near miss of (see above), or None."""
    index, longest, chars = _near_index(tuple(known))
    t = text.lower().replace("-", "_").replace(" ", "_")
    if not 3 <= len(t) <= longest + 1 or len(t.translate(chars)) > 1:
        return None               # (a near miss has at most one character no key has)
    best = index.get(t)
    for i in range(len(t)):
        hit = index.get(t[:i] + t[i + 1:])
        if hit is not None and (best is None or (hit[0] + 1, hit[1]) < best[:2]):
            best = (hit[0] + 1, hit[1], hit[2])
    return best[2] if best is not None else None


class _Bad(Exception):
    """A value that cannot be read; the caller names the line."""


def as_int(value, what: str = "") -> int:
    """D-16: a YAML integer or a string in SPEC §1's integer syntax, never $NODEID."""
    if isinstance(value, bool):
        raise _Bad(f"expected an integer, found a boolean ({value})")
    if isinstance(value, int):
        return value
    if isinstance(value, LongInt):
        raise _Bad(str(values.too_long(value.digits)))
    if isinstance(value, str):
        if values.uses_nodeid(value):
            raise _Bad(f"$NODEID is not allowed in the network file: '{shorten(value)}'")
        try:
            return values.parse_int(value)
        except values.ValueProblem as exc:
            raise _Bad(str(exc)) from None
    raise _Bad(f"expected an integer, found {kind_of(value)}")


def as_bool(value) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.lower() in ("true", "false"):
        return value.lower() == "true"
    raise _Bad(f"expected true or false, found {kind_of(value)}")


def kind_of(value) -> str:
    if isinstance(value, YMap):
        return "a mapping"
    if isinstance(value, YSeq):
        return "a list"
    if value is None:
        return "nothing"
    if isinstance(value, LongInt):
        return f"an integer of {value.digits} digits"
    if isinstance(value, str):
        return f"'{shorten(value)}'"
    if isinstance(value, int):
        return f"int {shorten(value)}"
    return shorten(f"{type(value).__name__} {value!r}")



class _Values:
    """Where, errors, and the value of one key (``scalar``)."""

    def __init__(self, net: Network, folder: str):
        self.net = net
        self.path = net.path
        self.folder = folder
        self.diags: Diagnostics = net.diagnostics

    def w(self, line: int | None) -> Where:
        return Where(self.path, line)

    def err(self, message: str, line: int | None, rule: str = "NET004") -> None:
        self.diags.error(message, self.w(line), rule=rule)

    def resolve(self, text: str) -> str:
        if text.startswith(PLACEHOLDER):
            text = text[len(PLACEHOLDER):]
        return os.path.normpath(os.path.join(self.folder, text)) if text else text

    def unknown(self, key, line: int, known: dict) -> None:
        text = str(key)
        if text not in KNOWN_UNUSED:
            best = near_miss(text, known)
            if best is not None:
                self.diags.warning(f"unknown key '{shorten(text)}': did you mean '{best}'?",
                                   self.w(line), rule="NET006")
                return
        self.diags.info(f"key '{shorten(text)}' is not used by dcf2bin; ignored", self.w(line),
                        rule="NET007")

    def scalar(self, key: str, kind: str, value, line: int):
        """The value of ``key`` as ``kind``, range-checked; None (reported) when bad."""
        try:
            if isinstance(value, LongInt) and kind in ("int", "float", "any"):
                raise _Bad(str(values.too_long(value.digits)))
            if kind == "int":
                got = as_int(value)
                lo, hi = RANGES.get(key, (0, 0xFFFFFFFF))
                if not lo <= got <= hi:
                    if key in HEX_KEYS:     # an object index is hex, as users write it
                        raise _Bad(f"{'-' if got < 0 else ''}0x{abs(got):X} is outside "
                                   f"0x{lo:04X}..0x{hi:04X}")
                    raise _Bad(f"{got} is outside {lo}..{hi}")
                if key == "sync_overflow" and (got == 1 or got > 240):
                    # CiA 301: a device refuses them (SDO abort 0x06090030)
                    raise _Bad(f"{got} is not 0 or 2..240 (CiA 301 reserves 1 and 241..255)")
                return got
            if kind == "cob":
                return as_cob(value)
            if kind == "behavior":
                return self.behavior(key, value, line)
            if kind == "bool":
                return as_bool(value)
            if kind == "float":
                if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                    raise _Bad(f"expected a number, found {kind_of(value)}")
                try:
                    got = float(value)
                except ValueError:
                    raise _Bad(f"expected a number, found {kind_of(value)}") from None
                if not 0 <= got <= 1000 or got != got:
                    raise _Bad(f"{shorten(value)} is outside 0..1000")
                return got
            if kind in ("str", "text"):
                if not isinstance(value, str) or isinstance(value, LongInt) or (
                        not value and kind == "str"):
                    raise _Bad(f"expected a text, found {kind_of(value)}")
                return value
            if kind == "any":
                return value
        except _Bad as exc:
            self.err(f"{key}: {exc}", line)
            return None
        raise AssertionError(kind)

    def behavior(self, key: str, value, line: int) -> dict[int, tuple[int, Where]]:
        """``error_behavior: {1: 0x00}``: 0x1029 sub -> (value, its line); each item
        checked (a bad one reported and left out)."""
        if not isinstance(value, YMap):
            raise _Bad(f"expected a mapping of 0x1029 sub-indexes to values, found "
                       f"{kind_of(value)}")
        out: dict[int, tuple[int, Where]] = {}
        for k, v in value.items():
            kline = value.lines[k]
            try:
                sub = as_int(k)
                lo, hi = BEHAVIOR_SUBS
                if not lo <= sub <= hi:
                    raise _Bad(f"sub-index {sub} is outside {lo}..{hi}")
                got = as_int(v)
                lo, hi = BEHAVIOR_VALUES
                if not lo <= got <= hi:
                    raise _Bad(f"0x1029sub{sub:X}: {got} is outside {lo}..{hi}")
            except _Bad as exc:
                self.err(f"{key}: {exc}", kline)
                continue
            out[sub] = (got, self.w(kline))
        return out


def as_cob(value, accepted: str = "") -> int:
    """A COB-ID (CiA 301): an UNSIGNED32 whose bits 11-28 are clear unless bit 29 marks a
    29-bit CAN-ID. ``accepted`` ends the message of a value that is no such integer."""
    try:
        cob = as_int(value)
        if not 0 <= cob <= 0xFFFFFFFF:
            raise _Bad(f"{cob} is outside 0..0xFFFFFFFF")
    except _Bad as exc:
        raise _Bad(f"{exc}{accepted}") from None
    if not cob & 0x20000000 and cob & 0x1FFFF800:
        raise _Bad(f"0x{cob:X} has bits 11-28 set but not bit 29 (an 11-bit CAN-ID is at "
                   "most 0x7FF; bit 29 marks a 29-bit one)")
    return cob


class Items(_Values):
    """The readers of a node's lists and mappings: heartbeat consumers, PDOs, mappings,
    sdo writes."""

    # -- master heartbeat_consumer ---------------------------------------------------------
    def consumer(self, node: Node, value, line: int) -> None:
        if not isinstance(value, YMap):
            got = self.scalar("heartbeat_consumer", "bool", value, line)
            if got is not None:
                node.config["heartbeat_consumer"] = got
            return
        times = {}
        for key, v in value.items():
            t = self.scalar("heartbeat_consumer", "int", v, value.lines[key])
            if t is not None:
                times[str(key)] = (t, self.w(value.lines[key]))
        node.config["heartbeat_consumer"] = times

    # -- rpdo / tpdo -----------------------------------------------------------------------
    def pdos(self, node: Node, kind_key: str, value, line: int) -> None:
        kind = TPDO if kind_key == "tpdo" else RPDO
        if not isinstance(value, YMap):
            self.err(f"'{kind_key}' must be a mapping of PDO numbers, found {kind_of(value)}",
                     line)
            return
        for key, v in value.items():
            kline = value.lines[key]
            try:
                number = as_int(key)
            except _Bad:
                number = None
            if number is None or not 1 <= number <= 512:
                self.err(f"{kind_key}: PDO number '{shorten(key)}' is not an integer 1..512", kline)
                continue
            if (kind, number) in node.pdo_config:
                first = node.pdo_config[(kind, number)].where.line
                self.err(f"{kind_key} {number} repeated (first at line {first})", kline,
                         "NET002")
                continue
            pc = PdoConfig(kind, number, self.w(kline))
            node.pdo_config[(kind, number)] = pc
            if v is None:
                continue
            if not isinstance(v, YMap):
                self.err(f"{kind_key} {number} must be a mapping, found {kind_of(v)}", kline)
                continue
            for k, item in v.items():
                iline = v.lines[k]
                pkind = PDO_KEYS.get(k)
                if pkind is None:
                    self.unknown(k, iline, PDO_KEYS)
                    continue
                pc.wheres[k] = self.w(iline)
                if pkind == "mapping":
                    pc.mapping = self.mapping(item, iline)
                    pc.empty_mapping = item is None or isinstance(item, YSeq) and not item
                elif pkind == "cob":
                    if isinstance(item, str) and item.lower() == "auto":
                        pc.cob_id = "auto"
                    else:
                        try:
                            pc.cob_id = as_cob(item, " (auto or an integer)")
                        except _Bad as exc:
                            self.err(f"cob_id: {exc}", iline)
                else:
                    setattr(pc, k, self.scalar(k, pkind, item, iline))

    def mapping(self, value, line: int) -> list[MapConfig] | None:
        if value is None:
            return []
        if not isinstance(value, YSeq):
            self.err(f"mapping must be a list of {{index, sub_index}}, found {kind_of(value)}",
                     line)
            return None
        if len(value) > 64:
            self.err(f"mapping has {len(value)} objects; a PDO maps at most 64", line)
            return None
        out = []
        for item, iline in zip(value, value.lines):
            got = self.item(item, iline, MAP_KEYS, "mapping")
            if got is None:
                continue
            name = got.get("name")
            out.append(MapConfig(got["index"], got.get("sub_index", 0), name, self.w(iline),
                                 self.w(got["_lines"].get("name", iline))))
        return out

    def item(self, item, line: int, keys: dict, what: str) -> dict | None:
        if not isinstance(item, YMap):
            self.err(f"a {what} item must be a mapping with index and sub_index, found "
                     f"{kind_of(item)}", line)
            return None
        got: dict = {"_lines": {}}
        ok = True
        for k, v in item.items():
            kline = item.lines[k]
            kind = keys.get(k)
            if kind is None:
                self.unknown(k, kline, keys)
                continue
            x = self.scalar(k, kind, v, kline)
            if x is None and kind != "any":
                ok = False
            got[k] = x
            got["_lines"][k] = kline
        if "index" not in got:
            if ok:
                self.err(f"a {what} item without index", line, "NET005")
            return None
        if what == "sdo" and "value" not in got:
            self.err("an sdo item without value", line, "NET005")
            return None
        return got if ok else None

    def sdos(self, node: Node, value, line: int) -> None:
        if not isinstance(value, YSeq):
            self.err(f"sdo must be a list of {{index, sub_index, value}}, found {kind_of(value)}",
                     line)
            return
        for item, iline in zip(value, value.lines):
            got = self.item(item, iline, SDO_KEYS, "sdo")
            if got is not None:
                node.sdo_config.append(SdoConfig(got["index"], got.get("sub_index", 0),
                                                 got["value"], self.w(iline)))

"""Predicting what compile makes of the DCF text, to say what will not round-trip.

The rules of SPEC §3 are replayed on the objects of a ``DcfSpec``: the D-8 groups
and the CiA 301 PDO blocks, the D-9 attributes, the §2 layout and the D-10
addresses. Where the prediction differs from the container, one B2D010 warning
names the first difference (or the options that give the same bytes).
tests/test_bin2dcf.py checks the prediction against the real compiler.
"""
from __future__ import annotations

from itertools import repeat
from operator import itemgetter

from dcf2bin import datatypes as dt
from dcf2bin.dcfwriter.spec import R_PDO, R_SUMMARY, DcfSpec, Issues, short, table_type
from dcf2bin.diagnostics import Severity
from dcf2bin.layout import INPUT, OUTPUT, PER_INDEX, RANGE_LEN
from dcf2bin.model import NV_FIRST
from dcf2bin.model import is_network_variable_index as is_nv
from dcf2bin.model import is_pdo_comm as is_comm
from dcf2bin.model import is_pdo_mapping as is_mapping
from dcf2bin.select import CAN_ID_MASK, COB_INVALID, PdoRules

# parts of a predicted write (index, sub, data, attribute)
_ENTRY, _ATTR, _KEY = itemgetter(0, 1, 2), itemgetter(3), itemgetter(0, 1)
_DIS2_OFF = 0xC0000000   # DIS-2 disables a PDO with bits 31 and 30 (no RTR) set


def mark_old_cob_ids(spec: DcfSpec) -> list:
    """D-12 (Metronix DIS-2): a PDO block that starts with ``old | 0xC0000000`` before
    ``final | 0xC0000000``, ``old`` with another CAN-ID, was compiled with ``--profile
    dis2`` from a comm sub 1 whose DefaultValue is the COB-ID the drive has. Give that
    sub the DefaultValue ``old`` (bits 30 and 31 clear: the block sets them), so that the
    DCF compiles back with that profile. Returns the subs it marked."""
    marked = []
    for index, obj in spec.objects.items():
        cob = obj.subs.get(1) if is_comm(index) else None
        if cob is None or len(cob.writes) < 2 or cob.dtype.code != dt.UNSIGNED32.code \
                or any(len(w.data) != 4 for w in cob.writes[:2]):
            continue
        old, first = (int.from_bytes(w.data, "little") for w in cob.writes[:2])
        final = int.from_bytes(cob.data, "little")
        if ((old & _DIS2_OFF) == _DIS2_OFF and first == final | _DIS2_OFF
                and (old ^ first) & CAN_ID_MASK and cob.writes[1].pos == cob.writes[0].pos + 1):
            cob.default = f"0x{old & ~_DIS2_OFF:08X}"
            marked.append(cob)
    return marked


def predict(spec: DcfSpec) -> tuple[bool, list[str]]:
    """(compile with default options gives the container's bytes, the compile options
    that would give them otherwise); warnings go to ``spec.issues``. A container whose
    PDO blocks only DIS-2's rules give (``mark_old_cob_ids``) needs ``--profile dis2``:
    said as an info, not a warning, when that profile gives every byte back."""
    if any(is_comm(i) and 1 in o.subs and o.subs[1].default for i, o in spec.objects.items()):
        from dcf2bin.profiles import get_profile
        trial = Issues(spec.name)
        if _Predictor(spec, get_profile("dis2").pdo_rules(), trial).run() == (True, []):
            spec.issues.add(R_SUMMARY, None, "compile gives the same bytes with --profile "
                            "dis2: the PDO blocks first disable under the COB-ID the drive "
                            "had (its DefaultValue), as Metronix DIS-2 drives need",
                            Severity.INFO)
            return False, ["--profile dis2"]
    return _Predictor(spec).run()


class _Predictor:
    def __init__(self, spec: DcfSpec, rules: PdoRules | None = None,
                 issues: Issues | None = None):
        self.spec = spec
        self.c = spec.container
        self.issues = spec.issues if issues is None else issues
        self.objects = spec.objects
        self.offsets = spec.offsets
        self.rules = rules or PdoRules()

    def run(self) -> tuple[bool, list[str]]:
        """Replay compile's rules on the objects written; warn where the bytes would differ."""
        c = self.c
        idxs = sorted(i for i in self.objects if i >= 0x1000)
        creation = self._creation(idxs)
        pdo, error = self._pdo_blocks(idxs)
        writes = creation + self._configuration(idxs, everything=False) + pdo
        layout = None
        if error is None:
            layout, error = self._expected_layout(writes)
        if error is not None:
            self.issues.add(R_SUMMARY, None, f"the DCF will not compile: {error}; for a "
                            "lossless copy use 'dcf2bin dump --format json'")
            return False, []
        attrs = c.attributes or b""
        actual = c.entries
        first_diff = _first_difference(c, writes)
        entries_ok = first_diff is None and len(attrs) == len(actual)
        select_all = False
        if first_diff is not None and len(attrs) == len(actual):
            # SPEC §3.2 --entries all: group 2 takes every entry with a value, ro ones too
            select_all = _first_difference(
                c, creation + self._configuration(idxs, everything=True) + pdo) is None
        addresses, pi = layout
        pi_ok = (addresses == c.addresses and pi == c.pi and c.raw_piparam is None)
        no_pi_ok = c.addresses is None and c.pi is None and c.raw_piparam is None
        version_ok = c.version == 1
        layout_ok = c.header is None
        if entries_ok and pi_ok and version_ok and layout_ok:
            return True, []
        options = []
        if (entries_ok or select_all) and layout_ok and \
                (pi_ok or (no_pi_ok and addresses is not None)):
            if select_all:
                options.append("--entries all")
            if not version_ok:
                options.append(f"--container-version {c.version}")
            if not pi_ok:
                options.append("--no-process-image")
            if select_all:
                self.issues.add(R_SUMMARY, *self._difference(writes, first_diff,
                                f"compile gives the same bytes only with {' '.join(options)}"))
            else:
                self.issues.add(R_SUMMARY, None, "compile gives the same bytes only with "
                                f"{' '.join(options)}")
            return False, options
        if first_diff is not None:
            self.issues.add(R_SUMMARY, *self._difference(
                writes, first_diff, "for a lossless copy use 'dcf2bin dump --format json'"))
        elif not entries_ok:
            self.issues.add(R_SUMMARY, None, "the DCF will not compile back to the same "
                            "container (attribute segment); for a lossless copy use "
                            "'dcf2bin dump --format json'")
        else:
            what = []
            if not (pi_ok or no_pi_ok):
                if addresses != c.addresses:
                    what.append("PI addresses")
                if pi != c.pi or c.raw_piparam is not None:
                    what.append("PI parameters")
            if not version_ok:
                what.append("header version")
            if not layout_ok:
                what.append("header layout")
            if no_pi_ok and addresses is not None and not pi_ok:
                what.append("PI segments (--no-process-image)")
            self.issues.add(R_SUMMARY, None, "the DCF will not compile back to the same "
                            f"container ({', '.join(what)}); for a lossless copy use "
                            "'dcf2bin dump --format json'")
        return False, options

    def _difference(self, writes, i: int, advice: str) -> tuple[int | None, str]:
        """(offset, message) of the B2D010 warning that names entry ``i``."""
        attrs = self.c.attributes or b""
        actual = self.c.entries
        where = self.offsets[i] if i < len(actual) else None
        got = _describe(actual[i], attrs[i] if i < len(attrs) else None) \
            if i < len(actual) else "nothing"
        exp = _describe(writes[i][:3], writes[i][3]) if i < len(writes) else "nothing"
        return where, (f"the DCF will not compile back to the same container: entry {i + 1} "
                       f"is {got}, compile writes {exp}; {advice}")

    def _creation(self, idxs: list[int]) -> list[tuple[int, int, bytes, int]]:
        """D-8 group 1: network-variable objects, all sub-entries, sub 0 first."""
        objs = self.objects
        return [(index, sub, s.value_bytes, 0x30 if sub == 0 else 0xF0)
                for index in idxs if is_nv(index) for sub, s in objs[index].subs.items()]

    def _configuration(self, idxs: list[int], everything: bool
                       ) -> list[tuple[int, int, bytes, int]]:
        """D-8 group 2: configured, writable entries (every written entry is configured);
        with ``everything`` (--entries all) every entry with a value, of any access."""
        objs = self.objects
        exp = []
        for index in idxs:
            if is_nv(index) or is_comm(index) or is_mapping(index):
                continue
            for sub, s in objs[index].subs.items():
                if everything:
                    if s.writes or s.default:
                        exp.append((index, sub, s.value_bytes, s.attr))
                elif s.writes and s.access not in ("ro", "const"):
                    exp.append((index, sub, s.data, s.attr))
        return exp

    def _pdo_blocks(self, idxs: list[int]) -> tuple[list[tuple[int, int, bytes, int]],
                                                    str | None]:
        """D-8 group 3: one CiA 301 block per PDO, or the error that stops compile."""
        objs = self.objects
        exp: list[tuple[int, int, bytes, int]] = []
        for index in idxs:
            if is_comm(index) and index + 0x200 not in objs:
                return exp, (f"PDO communication object 0x{index:04X} has no mapping object "
                             f"0x{index + 0x200:04X} in the container")
            if is_mapping(index) and index - 0x200 not in objs:
                return exp, (f"PDO mapping object 0x{index:04X} has no communication object "
                             f"0x{index - 0x200:04X} in the container")
        for index in idxs:
            if not is_comm(index):
                continue
            err = self._pdo_block(index, exp)
            if err:
                return exp, err
        return exp, None

    def _pdo_block(self, comm_idx: int, exp: list) -> str | None:
        comm, mapping = self.objects[comm_idx], self.objects[comm_idx + 0x200]
        cob = comm.subs.get(1)
        if cob is None or not cob.writes:
            return f"PDO 0x{comm_idx:04X} has no COB-ID (sub 1) in the container"
        if cob.dtype.code != dt.UNSIGNED32.code:
            return f"0x{comm_idx:04X}sub1: the COB-ID is not 4 bytes NUMERIC"
        final = int.from_bytes(cob.data, "little")
        rules = self.rules
        if rules.old_cob_first and cob.default:   # D-12
            old = int(cob.default, 16)
            if (old ^ final) & CAN_ID_MASK:
                exp.append((comm_idx, 1, (old | rules.disable_mask).to_bytes(4, "little"),
                            cob.attr))
        exp.append((comm_idx, 1, (final | rules.disable_mask).to_bytes(4, "little"), cob.attr))
        for s in (2, 3, 5, 6):
            e = comm.subs.get(s)
            if e is not None and e.writes:
                exp.append((comm_idx, s, e.data, e.attr))
        sub0 = mapping.subs[0]
        n = int.from_bytes(sub0.value_bytes, "little", signed=sub0.dtype.kind == dt.SINT)
        if n > rules.max_mapped or n < 0:
            return f"0x{mapping.index:04X}sub0: {n} mapped objects"
        size0 = sub0.dtype.size or 1
        exp.append((mapping.index, 0, (0).to_bytes(size0, "little"), sub0.attr))
        for k in range(1, n + 1):
            e = mapping.subs.get(k)
            if e is None:
                return (f"PDO mapping 0x{mapping.index:04X} maps {n} objects but sub {k} is "
                        "not in the container")
            exp.append((mapping.index, k, e.data, e.attr))
        exp.append((mapping.index, 0, n.to_bytes(size0, "little"), sub0.attr))
        if not final & COB_INVALID:
            exp.append((comm_idx, 1, (final | rules.enable_mask).to_bytes(4, "little"),
                        cob.attr))
        for s in sorted(comm.subs):
            if s in (0, 4) or s >= 7:
                e = comm.subs[s]
                if e.writes:
                    self.issues.add(R_PDO, e.writes[-1].offset, f"0x{comm_idx:04X}sub{s:X}: "
                                    "compile never writes comm sub 0, 4 or >= 7 in a PDO block")
        for k in sorted(mapping.subs):
            if k > n and mapping.subs[k].writes:
                self.issues.add(R_PDO, mapping.subs[k].writes[-1].offset,
                                f"0x{mapping.index:04X}sub{k:X} lies above the {n} mapped "
                                "objects; compile does not write it")
        return None

    def _expected_layout(self, writes):
        """SPEC §2.2-2.4 and D-10 for the variables written -> (addresses, PI) or an error."""
        nv_objs = [i for i in self.objects if is_nv(i)]
        if not nv_objs:
            return (None, None), None
        has_nv = any(s for i in nv_objs for s in self.objects[i].subs)
        blocks: dict[str, list] = {INPUT: [], OUTPUT: []}   # one run of variables an index
        order_keys: list[tuple[int, int]] = []    # (index, sub) placed, in placement order
        where: list[tuple[str, int]] = []          # (area, offset in it) of each
        for index in sorted(nv_objs):
            ch = _channel(self.spec, index)
            if ch is None:
                return None, (f"0x{index:04X} lies in 0xA900-0xAFFF without a "
                              "[DynamicChannels] segment")
            first, dtype, direction, pp = ch
            subs = self.objects[index].subs
            keys = [sub for sub in subs if sub]
            code = dtype.code
            bad = next((sub for sub in keys
                        if sub > PER_INDEX or subs[sub].dtype.code != code), None)
            if bad is not None:
                if bad > PER_INDEX:
                    return None, f"0x{index:04X}sub{bad:X}: subindex above 254"
                return None, (f"0x{index:04X}sub{bad:X}: {subs[bad].dtype.name} does not "
                              f"match the range type {dtype.name}")
            if not keys:
                continue
            # the variables of one index, one after the other from its place in the range
            size = dtype.size
            base = pp + ((index - first) * PER_INDEX - 1) * size
            offs = [base + sub * size for sub in keys]
            order_keys += zip(repeat(index), keys)
            where += zip(repeat(direction), offs)
            blocks[direction].append((offs[0], offs[-1] + size, index, keys[0], offs, keys,
                                      size))
        sizes = {}
        for area, lst in blocks.items():
            error = _overlap(lst, area)
            if error:
                return None, error
            sizes[area] = max((b[1] for b in lst), default=0)
        in_size, out_size = sizes[INPUT], sizes[OUTPUT]
        out_off = -(-in_size // 8) * 8 if out_size else 0
        total = out_off + out_size if out_size else in_size
        # the placed variables in the order of their first write (D-10): compile writes
        # them first, in placement order (then it is that order; else look them up)
        if list(map(_KEY, writes[:len(order_keys)])) != order_keys:
            placed = dict(zip(order_keys, where))
            order = dict.fromkeys(filter(placed.__contains__, map(_KEY, writes)))
            order_keys, where = list(order), list(map(placed.__getitem__, order))
        addresses = [off if direction == INPUT else out_off + off for direction, off in where]
        if addresses and max(addresses) > 0xFFFF:
            (index, sub), addr = next((key, addr) for key, addr in zip(order_keys, addresses)
                                      if addr > 0xFFFF)
            return None, f"0x{index:04X}sub{sub:X}: address 0x{addr:X} above 0xFFFF"
        if not has_nv:
            return (None, None), None
        return (addresses, (total, 0, in_size, out_off, out_size)), None


def _overlap(blocks: list, area: str) -> str | None:
    """The error of the first variable that overlaps another in ``area`` (None: none does).
    ``blocks``: one per index, its variables one after the other (start, end, index, first
    sub, offsets, subs, size). Blocks that do not overlap hold no overlapping variables;
    else the variables are sorted and checked one by one."""
    blocks.sort(key=itemgetter(0, 1, 2, 3))
    reach = -1
    for start, end, *_ in blocks:
        if start < reach:
            break
        reach = max(reach, end)
    else:
        return None
    spans = sorted((off, off + size, index, sub) for _, _, index, _, offs, subs, size in blocks
                   for off, sub in zip(offs, subs))
    reach = -1
    for start, end, index, sub in spans:
        if start < reach:
            return f"0x{index:04X}sub{sub:X} overlaps another variable in the {area} area"
        reach = max(reach, end)
    return None


def _first_difference(c, writes) -> int | None:
    """The first entry where ``writes`` and the container differ (None: they agree)."""
    attrs = c.attributes or b""
    actual = c.entries
    n = len(actual)
    if len(writes) == n and len(attrs) >= n and \
            list(map(_ENTRY, writes)) == actual and \
            list(map(_ATTR, writes)) == list(attrs[:n]):
        return None      # the common case, compared in bulk; else find the entry below
    for i in range(max(len(writes), len(actual))):
        e = writes[i] if i < len(writes) else None
        a = actual[i] if i < len(actual) else None
        a_attr = attrs[i] if i < len(attrs) else None
        if e is None or a is None or e[:3] != a or e[3] != a_attr:
            return i
    return None


def _channel(spec: DcfSpec, index: int):
    """(first index, type, area, PPOffset) of a network-variable index: its reconstructed
    [DynamicChannels] segment, else its CiA 405 range; None outside both."""
    for ch in spec.channels:
        if ch.first <= index <= ch.last:
            return ch.first, ch.dtype, ch.direction, ch.pp
    tt = table_type(index)
    if tt is None:
        return None
    return NV_FIRST + (index - NV_FIRST) // RANGE_LEN * RANGE_LEN, tt[0], tt[1], 0


def _describe(entry, attr) -> str:
    index, sub, data = entry
    a = f"attribute 0x{attr:02X}" if attr is not None else "no attribute"
    return f"0x{index:04X}sub{sub:X} = {short(data) or '(empty)'} ({a})"


__all__ = ["mark_old_cob_ids", "predict"]

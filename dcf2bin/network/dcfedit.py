"""State configured values in a DCF as ``ParameterValue``, every other line as it was
(line ends and encoding too), as ``allocate --into`` edits a file.

An entry with its own section gets its ``ParameterValue=`` line replaced, or one added
after the section's last key; a sub-entry of a CompactSubObj object goes into the
object's value section, e.g. ``[1016Value]`` (made at the end of the file when missing);
``[DeviceComissioning] NodeID`` likewise. An entry the file only implies (made from
CompactPDO, an implied sub 0) has no section to write into: that is an error.

A slave's DCF also states the identity the network file gives it (``identity``; beyond
D-17's configured values and NodeID, docs/compile.md, choice 17): 0x1018 sub 1-4 as
ParameterValue, so that the DCF of a build and the DCF read back from the node (``network
upload``) hold the same identity and ``diff`` compares them.
"""
from __future__ import annotations

from itertools import accumulate

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import Diagnostics, Where
from dcf2bin.network.model import Write


def value_text(w: Write, encoding: str = "utf-8") -> str:
    """The ParameterValue text of a write, for a file in ``encoding`` (a string's bytes
    are that encoding's; a UNICODE_STRING is text, not hex)."""
    dtype = dt.BY_CODE.get(w.datatype)
    if isinstance(w.value, bool) or dtype is None or dtype.size is None \
            or not dtype.is_integer:
        from dcf2bin import values
        if dtype is not None and dtype.kind in (dt.OSTRING, dt.DOMAIN):
            return w.data.hex().upper() if w.data else '""'
        text = values.decode(dtype, w.data, encoding=encoding) if dtype is not None else None
        return text if text is not None else w.data.hex().upper()
    if isinstance(w.value, int) and w.value >= 0:
        return f"0x{w.value:0{dtype.size * 2}X}"
    return str(w.value)


# the network file's identity keys and the 0x1018 sub-index each one is
IDENTITY = (("vendor_id", 1, "vendor-ID"), ("product_code", 2, "product code"),
            ("revision_number", 3, "revision number"), ("serial_number", 4, "serial number"))


def identity(node) -> dict[tuple[int, int], Write]:
    """0x1018 sub 1-4 of a slave as its network file gives them (``vendor_id``,
    ``product_code``, ``revision_number``, ``serial_number``; each when nonzero, as the
    master checks it), for its built DCF: only the subs the slave's file has, and only
    where it can state a value (an entry with a section, or a CompactSubObj value). The
    entries are ``ro``: compile does not write them, and the node is not sent them."""
    from dcf2bin.network.entries import int_write
    dev = node.device
    if dev is None or dev.ini is None:
        return {}
    out = {}
    for key, sub, what in IDENTITY:
        value = node.config.get(key)
        if not value or not isinstance(value, int) or dev.entry(0x1018, sub) is None \
                or _where_value_goes(dev.ini, 0x1018, sub)[0] is None:
            continue
        out[(0x1018, sub)] = int_write(dt.UNSIGNED32, 0x1018, sub, value, "",
                                       f"{node.name}'s {what}", node.config_where.get(key))
    return out


def _where_value_goes(ini, index: int, sub: int):
    """("section", its Section) for an entry with a section of its own (a sub-object's,
    or a VAR's object section for sub 0); ("compact", None) for a sub-entry of a
    CompactSubObj object; (None, None) for an entry the file only implies."""
    sec = ini.sections.get(f"{index:04x}sub{sub:x}")
    if sec is not None:
        return "section", sec
    obj = ini.sections.get(f"{index:04x}")
    if obj is None:
        return None, None
    if sub > 0 and obj.get("compactsubobj") not in (None, "0"):
        return "compact", None
    if sub == 0 and not obj.get("subnumber") and not obj.get("compactsubobj") \
            and not any(f"{index:04x}sub{s:x}" in ini.sections for s in (1, 2)):
        return "section", obj                # a VAR: its value is in its own section
    return None, None


def edit(data: bytes, path: str, settings: dict[tuple[int, int], Write], node_id: int,
         diags: Diagnostics, *, shown_as: str, ini=None,
         cache: dict | None = None, merge_plan=None) -> bytes | None:
    """``data`` (the file ``path``) with the settings and NodeID stated; None (reported
    at the setting's YAML line) when an entry has no section to hold its value. ``ini``:
    the INI reading of exactly ``data``, when the caller has it; ``cache``: a dict the
    caller keeps across calls, so that the slaves sharing one file are edited from one
    reading of its lines; ``merge_plan``: the variables ``allocate --into`` adds to the
    same ``data`` (a ``dcf2bin.plc.merge.Plan``), made in the same pass."""
    from dcf2bin import ini as ini_mod
    from dcf2bin.plc.merge import _lines, _set_value, section_ends, splice
    if ini is None:
        ini = ini_mod.parse_bytes(data, path)
    enc = ini.encoding
    cache = {} if cache is None else cache
    cached = cache.get(id(ini))
    if cached is None or cached[0] is not ini or cached[1] is not data:
        if merge_plan is not None and merge_plan.ends is not None:
            lines, ends = merge_plan.lines, merge_plan.ends     # the same base, read once
        else:
            lines = _lines(data)
            ends = section_ends(ini, lines)
        offsets = list(accumulate(map(len, lines), initial=0))
        cached = (ini, data, lines, offsets, ends,
                  {id(sec): c for c, sec in ini.sections.items()},
                  "\r\n" if b"\r\n" in data else "\n")
        cache[id(ini)] = cached
    _, _, lines, offsets, ends, canon, nl = cached
    replace: dict[int, bytes] = {}
    after: dict[int, list[str]] = {}
    tail: list[str] = []
    compact_values: dict[int, list[tuple[int, str]]] = {}
    ok = True

    def last_line(sec) -> int:
        return ends[canon[id(sec)]]

    for (index, sub), w in sorted(settings.items()):
        text = value_text(w, enc)
        how, sec = _where_value_goes(ini, index, sub)
        if how == "section":
            if sec.has("parametervalue"):
                k = sec.line_of("parametervalue") - 1
                replace[k] = _set_value(lines[k], text, enc)
            else:
                after.setdefault(last_line(sec) - 1, []).append(f"ParameterValue={text}")
        elif how == "compact":
            compact_values.setdefault(index, []).append((sub, text))
        else:
            diags.error(f"{shown_as}: 0x{index:04X}sub{sub:X} is implied by the file "
                        "(CompactPDO or a missing sub 0 section): there is no section to "
                        "state its value in", w.where or Where(path), rule="NET120")
            ok = False
    for index, items in compact_values.items():
        vsec = ini.section(f"{index:04x}value")
        if vsec is None:
            tail.append(f"[{index:04X}Value]{nl}NrOfEntries={len(items)}{nl}"
                        + "".join(f"{s}={t}{nl}" for s, t in items))
            continue
        added = 0
        for s, t in items:
            key = str(s)
            if vsec.has(key):
                k = vsec.line_of(key) - 1
                replace[k] = _set_value(lines[k], t, enc)
            else:
                after.setdefault(last_line(vsec) - 1, []).append(f"{s}={t}")
                added += 1
        if added and vsec.has("nrofentries"):
            k = vsec.line_of("nrofentries") - 1
            count = sum(1 for key in vsec.keys if key.isdigit()) + added
            replace[k] = _set_value(lines[k], str(count), enc)
    sec = ini.section("devicecomissioning") or ini.section("devicecommissioning")
    if sec is None:
        tail.insert(0, f"[DeviceComissioning]{nl}NodeID={node_id}{nl}")
    elif sec.has("nodeid"):
        k = sec.line_of("nodeid") - 1
        replace[k] = _set_value(lines[k], str(node_id), enc)
    else:
        after.setdefault(last_line(sec) - 1, []).insert(0, f"NodeID={node_id}")
    if not ok:
        return None
    if merge_plan is not None:
        from dcf2bin.plc import merge
        merge_plan.replace.update(replace)     # merge edits network-variable objects and
        for k, texts in after.items():         # the object lists only: other lines
            merge_plan.after.setdefault(k, []).extend(t + nl for t in texts)
        merge_plan.tail.extend(tail)
        return merge.apply(data, merge_plan)
    nlb = nl.encode(enc)
    return splice(data, lines, replace, after, tail, nl=nlb, end=nlb, offsets=offsets,
                  encode=lambda text: text.encode(enc))

"""What ``simulate`` prints: the emulation's outcome as text, as JSON, and the object
dictionary after DynBuildOd as a DCF (``--emit-od``). No click here."""
from __future__ import annotations

import json

from dcf2bin import datatypes as dt
from dcf2bin import dcfparts
from dcf2bin.dynod.check import value_text
from dcf2bin.dynod.emulate import Outcome


def _pdo_label(comm: int) -> str:
    if comm < 0x1800:
        return f"RPDO{comm - 0x1400 + 1}"
    return f"TPDO{comm - 0x1800 + 1}"


def verdict(out: Outcome, name: str) -> str:
    """One line, the verdict first."""
    head = f"0x{out.code:02X} {out.name}"
    if out.ok:
        return f"{head}: {name}: {out.entries_applied} entries applied"
    at = ""
    if out.entry is not None:
        at = f" entry {out.entry} {out.label} = {value_text(out.value)}"
        if out.offset is not None:
            at += f" (byte 0x{out.offset:X})"
        at += ":"
    elif out.offset is not None:
        at = f" byte 0x{out.offset:X}:"
    return f"{head}: {out.where or name}:{at} {out.reason}"


def text(out: Outcome, name: str) -> str:
    lines = [verdict(out, name)]
    d = out.descriptor
    mem = "unlimited" if d is None or d.memory is None else f"{d.memory} bytes"
    if d is not None and d.out is not None:
        total, in_off, in_size, out_off, out_size = d.out
        lines.append(f"process image: {total} bytes (input {in_size} @ {in_off}, output "
                     f"{out_size} @ {out_off}); target memory {mem}")
    else:
        lines.append(f"process image: none (no PI parameter segment); target memory {mem}")
    c = out.created
    lines.append(f"created: {len(c.objects)} objects, {c.entries} entries, {c.bytes} bytes"
                 + ("" if out.ok else f" (before entry {out.entry or 1})"))
    if out.ok:
        if not out.pdos:
            lines.append("valid PDOs: none")
        else:
            lines.append("")
            rows = [("PDO", "COB-ID", "bits", "object", "len", "PI address")]
            for p in out.pdos:
                first = True
                pos = 0
                label = f"{_pdo_label(p.comm_index)} 0x{p.comm_index:04X}"
                cob = f"0x{p.cob_id:08X}"
                if not p.mapped:
                    rows.append((label, cob, "-", "(nothing mapped)", "", ""))
                for idx, sub, bits, addr in p.mapped:
                    obj = f"0x{idx:04X}sub{sub:X}"
                    rows.append((label if first else "", cob if first else "",
                                 f"{pos}..{pos + bits - 1}" if bits else f"{pos}",
                                 obj, str(bits), "" if addr is None else
                                 f"{addr} (0x{addr:04X})"))
                    first = False
                    pos += bits
            widths = [max(len(r[i]) for r in rows) for i in range(6)]
            for r in rows:
                lines.append("  ".join(v.ljust(w) for v, w in zip(r, widths)).rstrip())
    return "\n".join(lines) + "\n"


FORMAT, VERSION = "dcf2bin-simulate", 1     # schema: dcf2bin/schemas/simulate.json


def _index(i: int | None) -> str | None:
    return None if i is None else f"0x{i:04X}"


def to_dict(out: Outcome, name: str) -> dict:
    """The result as the JSON document of ``simulate --format json``: indexes ``"0x1A00"``,
    COB-IDs and CAN-IDs ``"0x%08X"``, the return code ``"0x78"``, the rest JSON integers."""
    d = out.descriptor
    desc = None
    if d is not None:
        desc = {"memory": d.memory}
        keys = ("pi_size", "input_offset", "input_size", "output_offset", "output_size")
        desc.update(dict(zip(keys, d.out)) if d.out is not None else dict.fromkeys(keys))
    return {
        "format": FORMAT,
        "version": VERSION,
        "file": name,
        "code": f"0x{out.code:02X}",
        "name": out.name,
        "ok": out.ok,
        "rule": None if out.ok else out.rule,
        "step": out.step or None,
        "entry": out.entry,
        "index": _index(out.index),
        "subindex": out.subindex,
        "offset": out.offset,
        "where": out.where,
        "value": None if out.value is None else out.value.hex().upper(),
        "reason": out.reason or None,
        "entries_applied": out.entries_applied,
        "warnings": [{"rule": w.rule, "message": w.message} for w in out.warnings],
        "descriptor": desc,
        "created": {"objects": [_index(i) for i in out.created.objects],
                    "entries": out.created.entries, "bytes": out.created.bytes},
        "pdos": [{"direction": p.direction, "comm_index": _index(p.comm_index),
                  "cob_id": f"0x{p.cob_id:08X}", "can_id": f"0x{p.can_id:08X}", "bits": p.bits,
                  "mapped": [{"index": _index(i), "subindex": s, "bits": b, "pi_address": a}
                             for i, s, b, a in p.mapped]} for p in out.pdos],
    }


def to_json(out: Outcome, name: str) -> str:
    return json.dumps(to_dict(out, name), indent=2) + "\n"


# -- the object dictionary after DynBuildOd as a DCF -------------------------------------------

def _value(e) -> str | None:
    from dcf2bin import values
    t = e.dtype
    if t is None:
        return None
    if t.size is not None and len(e.data) != t.size:
        return None
    try:
        return values.decode(t, e.data)
    except Exception:  # noqa: BLE001 - a value that cannot be shown is left out
        return None


def emit_od(out: Outcome, name: str, static_names=None) -> str:
    """A DCF of ``out.od``: every object with its entries, types, access and the value each
    holds after DynBuildOd (as DefaultValue). ``static_names(index, sub)`` may give names."""
    od = out.od
    lines = ["; The object dictionary after DynBuildOd, written by dcf2bin simulate --emit-od",
             f"; from {name}: 0x{out.code:02X} {out.name}"
             + ("" if out.ok else f" at entry {out.entry} (entries before it applied)"),
             "", "[FileInfo]", "FileName=" + name.rsplit("/", 1)[-1].rsplit(".", 1)[0] + "_od.dcf",
             "FileVersion=1", "FileRevision=0", "EDSVersion=4.0",
             "Description=Object dictionary after DynBuildOd", "CreatedBy=dcf2bin simulate", "",
             "[DeviceInfo]", "VendorName=unknown", "ProductName=unknown",
             "BaudRate_250=1", "SimpleBootUpMaster=0", "SimpleBootUpSlave=1", "Granularity=8",
             "DynamicChannelsSupported=0", "GroupMessaging=0",
             f"NrOfRXPDO={sum(1 for i in od if 0x1400 <= i <= 0x15FF)}",
             f"NrOfTXPDO={sum(1 for i in od if 0x1800 <= i <= 0x19FF)}", "LSS_Supported=0", ""]
    extra, more_subs, dummies = _undescribed(od)
    if dummies:
        lines += ["[DummyUsage]"] + [f"Dummy{code:04X}=1" for code in sorted(dummies)] + [""]
    every = sorted({*od, *extra})
    mandatory = [i for i in every if i in dcfparts.MANDATORY]
    optional = [i for i in every if i not in mandatory and (0x1000 <= i <= 0x1FFF or i >= 0x6000)]
    manufacturer = [i for i in every if 0x2000 <= i <= 0x5FFF]
    for title, group in (("MandatoryObjects", mandatory), ("OptionalObjects", optional),
                         ("ManufacturerObjects", manufacturer)):
        lines.append(f"[{title}]")
        lines.append(f"SupportedObjects={len(group)}")
        lines.extend(f"{k}=0x{i:04X}" for k, i in enumerate(group, 1))
        lines.append("")
    for index in mandatory + optional + manufacturer:
        if index in extra:
            lines.extend(extra[index])
        else:
            lines.extend(_object(index, od[index], static_names, more_subs.get(index, ())))
    return "\n".join(lines) + "\n"


_WHERE = "not in the simulated object dictionary (no --static-od)"


def _undescribed(od):
    """What the simulated OD lacks that the firmware has (issue 26 item 16; no --static-od
    gives it): the objects every device has (no value: the firmware's), the entries its
    PDOs map (from the mapping: dcf2bin.dcfparts) and the dummy types they map. Returns
    (whole objects' lines by index, sub sections' lines by index, dummy types)."""
    from dcf2bin.indexes import is_pdo_mapping
    mapped, dummies = dcfparts.mapped_entries(
        (i, {sub: e.data for sub, e in subs.items()}) for i, subs in od.items()
        if is_pdo_mapping(i))
    extra = {i: dcfparts.mandatory_sections(i, mappable={s for (j, s) in mapped if j == i},
                                            comment=_NOT_SIMULATED)
             for i in dcfparts.MANDATORY if i not in od}
    wanted: dict[int, dict] = {}
    for (index, sub), m in mapped.items():
        subs = od.get(index)
        if index in extra or (subs is not None and (sub in subs or list(subs) == [0])):
            continue
        s = dcfparts.stub(index, sub, m, _WHERE)
        if s is not None:
            wanted.setdefault(index, {})[sub] = s
    more_subs = {}
    for index, stubs in sorted(wanted.items()):
        if index in od:
            more_subs[index] = [line for sub, s in stubs.items()
                                for line in dcfparts.stub_sub(index, sub, s, obj_flags=True)]
        else:
            extra[index] = dcfparts.stub_object(index, stubs, None, _WHERE)
    return extra, more_subs, dummies


_NOT_SIMULATED = f"; {_WHERE}: every CANopen device has it; its value is the firmware's"


def _entry_name(index: int, sub: int, e, static_names) -> str:
    if static_names is not None:
        n = static_names(index, sub)
        if n:
            return n
    if 0xA000 <= index <= 0xAFFF:
        return "Highest sub-index supported" if sub == 0 else \
            f"{'in' if index < 0xA480 else 'out'}_{e.dtype.name if e.dtype else 'DOMAIN'}" \
            f"_{index:04X}_{sub}"
    return f"Created 0x{index:04X}sub{sub:X}" if e.created else f"0x{index:04X}sub{sub:X}"


def _entry_keys(e, name: str) -> list[str]:
    t = e.dtype or dt.DOMAIN_T
    keys = [f"ParameterName={name}", "ObjectType=0x7", f"DataType=0x{t.code:04X}",
            f"AccessType={e.access}"]
    value = _value(e)
    if value is not None and "\n" not in value and "\r" not in value:
        keys.append(f"DefaultValue={value}")
    keys.append(f"PDOMapping={1 if e.mappable else 0}")
    return keys


def _object(index: int, subs: dict, static_names, more=()) -> list[str]:
    """An object of the OD; ``more``: the lines of mapped subs it lacks (``_undescribed``)."""
    only0 = list(subs) == [0]
    lines = [f"[{index:04X}]"]
    if only0:
        e = subs[0]
        return lines + _entry_keys(e, _entry_name(index, 0, e, static_names)) + [""]
    ot = 0x8 if 0xA000 <= index <= 0xAFFF else 0x9
    name = static_names(index, None) if static_names is not None else None
    n = len(subs) + sum(1 for line in more if line.startswith("["))
    lines += [f"ParameterName={name or f'Object 0x{index:04X}'}", f"ObjectType=0x{ot:X}",
              f"SubNumber={n}", ""]
    for sub, e in subs.items():
        lines.append(f"[{index:04X}sub{sub:X}]")
        lines += _entry_keys(e, _entry_name(index, sub, e, static_names)) + [""]
    return lines + list(more)


__all__ = ["emit_od", "text", "to_dict", "to_json", "verdict"]

"""DCF32x: network variables and [DynamicChannels] (SPEC §2), beyond the layout's own
errors DCF300-DCF315."""
from __future__ import annotations

import re

from dcf2bin import layout, values
from dcf2bin.lint.registry import INFO, WARNING, Finding, rule
from dcf2bin.model import NV_FIRST, NV_LAST


def _nv_objects(ctx):
    for idx in sorted(ctx.dev.objects):
        if NV_FIRST <= idx <= NV_LAST:
            yield idx, ctx.dev.objects[idx]


@rule("DCF320", "openpcs-unsupported-type", INFO,
      "A network variable type that OpenPCS does not support (only INTEGER8/16/32, "
      "UNSIGNED8/16/32 and REAL32).",
      hint="fine for other IEC 61131 runtimes; OpenPCS cannot use these variables")
def openpcs(ctx):
    groups: dict[str, list] = {}
    for idx, obj in _nv_objects(ctx):
        ch = layout.channel_for(ctx.dev, idx)
        if ch is None or ch.dtype.name in layout.OPENPCS_TYPES or len(obj.entries) < 2:
            continue
        groups.setdefault(ch.dtype.name, []).append(obj)
    for name, objs in groups.items():   # once per type, at its first object
        first = objs[0]
        more = f" ({len(objs)} objects from [{first.index:04X}])" if len(objs) > 1 else \
            f" ([{first.index:04X}])"
        yield Finding(f"{name} network variables{more} are not supported by OpenPCS",
                      first.where.line if first.where else None)


@rule("DCF321", "dynch-not-supported", WARNING,
      "[DynamicChannels] is given but [DeviceInfo] DynamicChannelsSupported=0.",
      hint="set DynamicChannelsSupported to the number of segments the device supports")
def dynch_not_supported(ctx):
    sec = ctx.section("dynamicchannels")
    info = ctx.section("deviceinfo")
    if sec is None or info is None:
        return
    text = info.get("dynamicchannelssupported")
    try:
        n = values.parse_int(values.split_numeric_comment(text)[0]) if text else None
    except values.ValueProblem:
        return
    if n == 0:
        line = info.line_of("dynamicchannelssupported")
        yield Finding(f"[DeviceInfo] DynamicChannelsSupported=0 but [DynamicChannels] is given "
                      f"(line {sec.line})", line, ctx.value_column(line))


_NUMBERED = re.compile(r"(type|dir|range|ppoffset|pioffset|maxcnt)([0-9]+)")


@rule("DCF322", "dynch-key-beyond-nrofseg", WARNING,
      "A [DynamicChannels] key numbers a segment outside 1..NrOfSeg; it is ignored.",
      hint="raise NrOfSeg or renumber the segment")
def dynch_beyond(ctx):
    sec = ctx.section("dynamicchannels")
    if sec is None:
        return
    text = sec.get("nrofseg")
    try:
        n = values.parse_int(values.split_numeric_comment(text)[0]) if text else 0
    except values.ValueProblem:
        return  # DCF310
    for key in ctx.key_names(sec):     # (the report is sorted by line)
        m = _NUMBERED.fullmatch(key)
        if m and (len(m.group(2)) > 18 or not 1 <= int(m.group(2)) <= n):
            line = sec.line_of(key)
            yield Finding(f"[DynamicChannels] {sec.keys[key].name} is ignored: NrOfSeg={n}",
                          line, 1)


_INPUT_ACCESS = {"ro", "const"}


@rule("DCF323", "nv-access-ignored", INFO,
      "A network variable's AccessType disagrees with its area (input: ro; output: rw); the "
      "area decides.",
      hint="the range (or segment Dir) decides the direction, not AccessType")
def nv_access(ctx):
    for idx, obj in _nv_objects(ctx):
        ch = layout.channel_for(ctx.dev, idx)
        if ch is None:
            continue
        # the access first (an attribute), the section's AccessType only where it disagrees
        is_input = ch.direction == layout.INPUT
        wrong = [e for s, e in obj.entries.items() if (e.access in _INPUT_ACCESS) != is_input
                 and s and e.section is not None and e.section.get("accesstype") is not None]
        if wrong:
            e = wrong[0]
            more = f" (and {len(wrong) - 1} more in [{idx:04X}])" if len(wrong) > 1 else ""
            line = e.key_where("accesstype").line
            yield Finding(f"{e.label} is {e.access} but lies in the {ch.direction} area of "
                          f"{ch.label}{more}", line, ctx.value_column(line))


@rule("DCF324", "dynch-segment-unused", INFO,
      "A [DynamicChannels] segment without MaxCnt covers no object.",
      hint="remove the segment, or check its Range")
def dynch_unused(ctx):
    nv = [i for i in ctx.dev.objects if NV_FIRST <= i <= NV_LAST]
    for ch in ctx.dev.channels:
        if ch.max_count is not None:
            continue
        if not any(ch.first <= i <= ch.last for i in nv):
            yield Finding(f"{ch.label} (0x{ch.first:04X}-0x{ch.last:04X}) covers no object",
                          ch.where.line if ch.where else None)

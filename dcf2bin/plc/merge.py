"""Allocating into an existing DCF (SPEC.md §9.2, D-15 ``--into``).

Variables the DCF already has (same name, Denotation or ParameterName, without regard to
case) keep their index/sub; the others are placed after the bytes the existing ones
occupy. Every line of the DCF stays as it was (line ends and encoding too) except the
ones that must change: ``SubNumber=`` of an object that gains sub-objects, its sub 0's
``DefaultValue=``/``ParameterValue=`` (the highest subindex), and ``[OptionalObjects]``
(``SupportedObjects=`` and one line per new object). New sub-sections follow the last
section of their object; new objects (and an ``[OptionalObjects]`` section the file
lacks) go at the end.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import accumulate

from dcf2bin.diagnostics import Diagnostic, Severity, shorten
from dcf2bin.layout import INPUT, OUTPUT, channel_for
from dcf2bin.plc.allocate import (RULE_BASE, AllocationError, Placed, Var, _err, _object_text,
                                  _objects, _sub_section, allocate)

def _lines(data: bytes) -> list[bytes]:
    """The file's lines with their line ends, as the INI reader counts them."""
    out = [line + b"\n" for line in data.split(b"\n")]
    out[-1] = out[-1][:-1]
    if not out[-1]:
        out.pop()
    return out


def section_ends(ini, lines: list[bytes]) -> dict[str, int]:
    """canonical section name -> its last line (1-based) that is neither blank nor a
    comment: the line new keys go after (without building every section's keys)."""
    order = sorted(ini.sections.items(), key=lambda kv: kv[1].line)
    out = {}
    for k, (canon, sec) in enumerate(order):
        end = order[k + 1][1].line - 1 if k + 1 < len(order) else len(lines)
        while end > sec.line and (not lines[end - 1].strip()
                                  or lines[end - 1].lstrip()[:1] in (b";", b"#")):
            end -= 1
        out[canon] = end
    return out


def _set_value(line: bytes, value: str, encoding: str) -> bytes:
    """``Key=old`` -> ``Key=value``, keeping the key as written and the line end."""
    body = line.rstrip(b"\r\n")
    end = line[len(body):]
    eq = body.index(b"=")
    lead = body[:eq + 1]
    rest = body[eq + 1:]
    spaces = rest[:len(rest) - len(rest.lstrip(b" \t"))]
    return lead + spaces + value.encode(encoding) + end


def splice(data: bytes, lines: list[bytes], replace: dict[int, bytes], after: dict,
           tail=(), *, nl: bytes, encode, end: bytes = b"",
           offsets: list[int] | None = None) -> bytes:
    """``data`` (split into ``lines``, ``_lines``) with line i replaced by ``replace[i]``,
    the texts ``after[i]`` inserted after it (each ``encode(text) + end``) and the texts
    of ``tail`` at the end of the file (each after a line end); every other line copied
    as it is, the lines between two changes as one slice. The one writer of an edited
    DCF's bytes: ``allocate --into`` (``apply``), a network's configured DCFs
    (``network.dcfedit``) and an uploaded DCF (``bus.upload.annotate``)."""
    if offsets is None:
        offsets = list(accumulate(map(len, lines), initial=0))
    out: list[bytes] = []
    pos = 0
    for i in sorted(set(replace) | set(after)):
        out.append(data[pos:offsets[i]])
        line = replace.get(i, lines[i])
        if i in after and not line.endswith((b"\n", b"\r")):
            line += nl
        out.append(line)
        out += [encode(text) + end for text in after.get(i, ())]
        pos = offsets[i + 1]
    out.append(data[pos:])
    body = b"".join(out)
    if tail:
        if body and not body.endswith((b"\n", b"\r")):
            body += nl
        body += b"".join(nl + encode(text) for text in tail)
    return body


def existing_variables(dev) -> dict[str, tuple[int, int, str, object]]:
    """casefolded name -> (index, sub, direction, dtype) of the DCF's network variables."""
    out = {}
    for idx, obj in dev.objects.items():
        ch = channel_for(dev, idx)
        if ch is None or not 0xA000 <= idx <= 0xAFFF:
            continue
        for sub, e in obj.entries.items():
            if sub == 0:
                continue
            name = e.denotation or e.name
            if name:
                out.setdefault(name.casefold(), (idx, sub, ch.direction, e.dtype or ch.dtype))
    return out


def merge(base: bytes, base_path: str, variables: list[Var], vars_path: str
          ) -> tuple[bytes, list[Placed], list[tuple[Var, int, int]]]:
    """-> (the merged DCF, the variables placed now, the ones kept (var, index, sub))."""
    edit, placed, kept = plan(base, base_path, variables, vars_path)
    return apply(base, edit), placed, kept


@dataclass
class Plan:
    """The line edits of a merge, by 0-based line of the base: ``replace`` (line -> new
    bytes), ``after`` (line -> texts inserted after it, each with its line ends), ``tail``
    (blocks added at the end, each after a blank line). ``apply`` makes the bytes; a
    caller may add edits of its own to other lines first (network build does)."""
    lines: list[bytes]
    replace: dict[int, bytes]
    after: dict[int, list[str]]
    tail: list[str]
    nl: str
    encoding: str
    placed: list[Placed]
    vars_path: str
    ends: dict[str, int] | None = None    # section_ends of the base, as computed here


def plan(base: bytes, base_path: str, variables: list[Var], vars_path: str, *, dev=None
         ) -> tuple[Plan, list[Placed], list[tuple[Var, int, int]]]:
    """``merge`` without making the bytes: -> (its Plan, placed, kept). ``dev``: the
    model of exactly ``base``, when the caller has it."""
    from dcf2bin import layout, model
    if dev is None:
        dev = model.load(base_path, data=base)
    if dev.ini is not None and dev.ini.section("dynamicchannels") is not None:
        sec = dev.ini.section("dynamicchannels")
        raise AllocationError([_err(
            "the DCF has a [DynamicChannels] section: its segments fix the layout, so "
            "variables cannot be allocated by the CiA 405 ranges", base_path, sec.line,
            RULE_BASE)])
    lay = layout.compute(dev) if any(0xA000 <= i <= 0xAFFF for i in dev.objects) else None
    errors = [p.diagnostic for p in dev.problems if p.diagnostic.severity is Severity.ERROR
              and (p.index is None or 0xA000 <= p.index <= 0xAFFF
                   or p.diagnostic.rule.startswith("DCF0"))]
    if errors:
        raise AllocationError(errors)
    have = existing_variables(dev)
    diags: list[Diagnostic] = []
    new: list[Var] = []
    kept: list[tuple[Var, int, int]] = []
    for v in variables:
        old = have.get(v.name.casefold())
        if old is None:
            new.append(v)
            continue
        idx, sub, direction, dtype = old
        if direction != v.direction or dtype is None or dtype.code != v.dtype.code:
            diags.append(_err(
                f"'{shorten(v.name)}' is already in {base_path} as 0x{idx:04X}sub{sub:X}, "
                f"{dtype.name if dtype else '?'} {direction}, not {v.dtype.name} {v.direction}",
                vars_path, v.line, RULE_BASE))
            continue
        kept.append((v, idx, sub))
    if diags:
        raise AllocationError(diags)
    used = {INPUT: lay.input_size if lay else 0, OUTPUT: lay.output_size if lay else 0}
    placed = allocate(new, vars_path, used)
    return _plan_edit(base, dev, placed, vars_path), placed, kept


def _encoder(encoding: str, vars_path: str):
    def enc(text: str, v: Var | None = None) -> bytes:
        try:
            return text.encode(encoding)
        except UnicodeEncodeError:
            raise AllocationError([_err(
                f"'{shorten(v.name if v else text)}' cannot be written in the {encoding} "
                "encoding of "
                "the DCF", vars_path, v.line if v else None, RULE_BASE)]) from None
    return enc


def _plan_edit(base: bytes, dev, placed: list[Placed], vars_path: str) -> Plan:
    encoding = dev.encoding
    nl = "\r\n" if b"\r\n" in base else "\n"     # lines end at LF, as the INI reader counts
    lines = _lines(base)
    replace: dict[int, bytes] = {}       # 0-based line -> new bytes
    after: dict[int, list[str]] = {}     # 0-based line -> text inserted after it
    tail: list[str] = []
    ini = dev.ini

    last = section_ends(ini, lines)

    # the sections of each object, to find where it ends
    ends: dict[int, int] = {}
    from dcf2bin.model import _section_target
    for canon, sec in ini.sections.items():
        if canon[:1] != "a":         # only network-variable objects gain sub-objects
            continue
        idx, _ = _section_target(canon)
        if idx is not None:
            ends[idx] = max(ends.get(idx, 0), last[canon])

    objs = _objects(placed)
    new_objects = []
    for idx, ps in objs.items():
        obj = dev.objects.get(idx)
        if obj is None:
            new_objects.append(idx)
            text = _object_text(idx, ps, nl)
            tail.append(text)
            continue
        if obj.compact:
            raise AllocationError([_err(
                f"0x{idx:04X} is a CompactSubObj object in the DCF; allocate cannot add "
                "sub-objects to it", vars_path, ps[0].var.line, RULE_BASE)])
        clash = [p for p in ps if p.sub in obj.entries]
        if clash:   # cannot happen: new elements lie after every used byte (D-15)
            raise AssertionError(f"0x{idx:04X}sub{clash[0].sub:X} is taken")
        subs = set(obj.entries) | {p.sub for p in ps}
        highest = max(subs)
        sec = obj.section
        if sec is not None and sec.has("subnumber"):
            # SubNumber as the DCF reader parsed it (any literal form, a trailing comment)
            n = obj.sub_number + len(ps) if obj.sub_number is not None else len(subs)
            k = sec.line_of("subnumber") - 1
            replace[k] = _set_value(lines[k], str(n), encoding)
        e0 = obj.entries.get(0)
        if e0 is not None and e0.section is not None:
            for key in ("defaultvalue", "parametervalue"):
                if e0.section.has(key) and e0.section.values.get(key):
                    k = e0.section.line_of(key) - 1
                    replace[k] = _set_value(lines[k], str(highest), encoding)
        after.setdefault(ends[idx] - 1, []).extend(nl + _sub_section(idx, p, nl) for p in ps)

    if new_objects:
        opt = ini.section("optionalobjects")
        numbers = []
        if opt is not None:
            for key in opt.keys:
                if key.isdigit():
                    numbers.append(int(key))
        start = max(numbers, default=0) + 1
        entries = [f"{start + i}=0x{idx:04X}" for i, idx in enumerate(new_objects)]
        if opt is not None:
            if opt.has("supportedobjects"):
                k = opt.line_of("supportedobjects") - 1
                count = len(numbers) + len(new_objects)
                replace[k] = _set_value(lines[k], str(count), encoding)
            else:
                entries.insert(0, f"SupportedObjects={len(numbers) + len(new_objects)}")
            after.setdefault(last["optionalobjects"] - 1, []).append(nl.join(entries) + nl)
        else:
            tail.insert(0, f"[OptionalObjects]{nl}SupportedObjects={len(new_objects)}{nl}"
                        + "".join(e + nl for e in entries))

    return Plan(lines, replace, after, tail, nl, encoding, placed, vars_path, last)


def apply(base: bytes, edit: Plan) -> bytes:
    """The bytes of ``base`` with the plan's edits; the lines between edits are copied
    as they are."""
    enc = _encoder(edit.encoding, edit.vars_path)
    return splice(base, edit.lines, edit.replace, edit.after, edit.tail,
                  nl=edit.nl.encode(edit.encoding),
                  encode=lambda text: _encode_block(text, edit.placed, enc))


def _encode_block(text: str, placed: list[Placed], enc) -> bytes:
    try:
        return enc(text)
    except AllocationError:
        for p in placed:     # name the variable whose name cannot be written
            if f"ParameterName={p.var.name}" in text:
                enc(p.var.name, p.var)
        raise

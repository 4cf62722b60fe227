"""Tables the rules share, each worked out once per file and in bulk (no findings here).

A generated PLC DCF is mostly thousands of sections of one shape: the sub-objects of a
network-variable array differ only in their ``ParameterName``/``Denotation``, and the
INI reader gives all of them one shared dict of their other values (``Section.rest``).
A rule whose verdict depends on those other values decides once per such template
(``groups``) and reports every section of an offending template, each at its own line;
only the names are looked at section by section (``name_values``). Tables of sections
and entries are built with C-level passes (``map``, ``compress``, ``groupby``, one
regular expression over all section names) rather than a Python step per item (issue 22:
the rules' share of validating 60,000 variables fell from 0.32 to 0.05 s).

Everything is cached in ``ctx.cache``; every function returns exactly what a plain walk
over ``ctx.ini.sections`` / ``ctx.dev.objects`` would (the tests compare them).
"""
from __future__ import annotations

import re
from array import array
from itertools import compress, groupby, repeat
from operator import attrgetter, is_not, itemgetter

from dcf2bin.lint.vocabulary import classify

# a line end not followed by a sub-object section's name (vocabulary._SUB_RE) and another
_NOT_SUB = re.compile(r"\n(?![0-9a-f]{4}sub[0-9a-f]+\n)")
# a run of sub-object names of one index, the subindex at most 0xFF (1 or 2 digits)
_SUB_RUN = re.compile(r"\n([0-9a-f]{4})sub[0-9a-f]{1,2}(?=\n)(?:\n\1sub[0-9a-f]{1,2}(?=\n))*")
_NOT_CANONICAL_SUB = re.compile(r"sub0[0-9a-f]")   # (or another name with this in it)
_SUB_NUMBERS = {f"{i:x}": i for i in range(256)}              # canonical subindex -> number
_HEAD, _TAIL = itemgetter(slice(0, 4)), itemgetter(slice(7, None))
_REST = attrgetter("rest")
NAME_KEYS = {"parametername": "param_name", "denotation": "denotation"}  # cut out of ``rest``


def _split(ctx) -> tuple[list[str], list[bool], list[str], list[str | None], str]:
    """(every canonical name, whether each is a sub-object section's, the names of the
    others in file order and their kinds (two lists: a pair each was 64 bytes more a
    section, issue 26), the names joined: each after a line end, and one at the end).
    The sub-object sections are told apart by one search over all names for the others
    (in a PLC DCF, a few hundred of 60,000); only those are classified one by one
    (vocabulary.classify)."""
    got = ctx.cache.get("split")
    if got is not None:
        return got
    names = list(ctx.ini.sections)
    is_sub = [True] * len(names)
    other_names, other_kinds = [], []
    joined = "\n" + "\n".join(names) + "\n" if names else ""
    if names:
        line, pos = 0, 0
        last = len(joined) - 1              # the line end after the last name
        for m in _NOT_SUB.finditer(joined):
            if m.start() == last:
                break
            line += joined.count("\n", pos, m.start())   # the m.start()-th name follows it
            pos = m.start()
            is_sub[line] = False
            other_names.append(names[line])
            other_kinds.append(classify(names[line]))
    got = ctx.cache["split"] = (names, is_sub, other_names, other_kinds, joined)
    return got


def kind_sections(ctx, kind: str | None) -> list:
    """The sections of one kind, in file order."""
    if kind == "sub":
        got = ctx.cache.get("sub sections")
        if got is None:
            names, is_sub, others, _, _ = _split(ctx)
            got = ctx.cache["sub sections"] = list(compress(ctx.ini.sections.values(), is_sub)) \
                if len(others) < len(names) else []
        return got
    table = ctx.cache.get("other sections")
    if table is None:
        table = ctx.cache["other sections"] = {}
        sections = ctx.ini.sections
        for canon, k in zip(*_split(ctx)[2:4]):
            table.setdefault(k, []).append(sections[canon])
    return table.get(kind, [])


def by_kind(ctx) -> dict[str | None, list]:
    """kind (vocabulary.classify) -> [(canonical name, section)] in file order."""
    got = ctx.cache.get("by_kind")
    if got is None:
        names, is_sub, others, other_kinds, _ = _split(ctx)
        sections = ctx.ini.sections
        got = {}
        if len(others) < len(names):
            got["sub"] = list(compress(sections.items(), is_sub))
        for canon, kind in zip(others, other_kinds):
            got.setdefault(kind, []).append((canon, sections[canon]))
        ctx.cache["by_kind"] = got
    return got


def of_kind(ctx, kind: str | None) -> list:
    """``by_kind(ctx).get(kind, [])``, without pairing the sub-object sections for
    another kind."""
    if kind == "sub" or "by_kind" in ctx.cache:
        return by_kind(ctx).get(kind, [])
    key = ("pairs of", kind)
    got = ctx.cache.get(key)
    if got is None:
        sections = ctx.ini.sections
        got = ctx.cache[key] = [(c, sections[c]) for c, k in zip(*_split(ctx)[2:4])
                                if k == kind]
    return got


def each_of_kind(ctx, kind: str | None):
    """The pairs of ``of_kind(ctx, kind)``, one after the other, without a list of them (a
    file can have a million sections of one kind, 72 bytes a pair: DCF051 reads them once)."""
    if kind == "sub" or "by_kind" in ctx.cache or ("pairs of", kind) in ctx.cache:
        yield from of_kind(ctx, kind)
        return
    sections = ctx.ini.sections
    for c, k in zip(*_split(ctx)[2:4]):
        if k == kind:
            yield c, sections[c]


def kinds(ctx) -> dict[str, str | None]:
    """canonical name -> kind, in file order: ``{c: classify(c) for c in sections}``."""
    got = ctx.cache.get("kinds")
    if got is None:
        names, is_sub, others, other_kinds, _ = _split(ctx)
        got = dict.fromkeys(names, "sub")
        got.update(zip(others, other_kinds))
        ctx.cache["kinds"] = got
    return got


def sub_sections(ctx) -> dict[int, dict[int, object]]:
    """index -> {subindex: [<index>subN] section}, the subindex at most 0xFF (as the
    sub-object sections stand in the file)."""
    got = ctx.cache.get("sub_sections")
    if got is not None:
        return got
    names, is_sub, _, _, _ = _split(ctx)
    names = list(compress(names, is_sub))
    secs = kind_sections(ctx, "sub")
    numbers = list(map(_SUB_NUMBERS.get, map(_TAIL, names)))
    if None in numbers:      # not canonical, or above 0xFF: read as written
        for i, number in enumerate(numbers):
            if number is None:
                sub = int(names[i][7:], 16)
                numbers[i] = sub if sub <= 0xFF else None
    got = {}
    at = 0
    for head, run in groupby(map(_HEAD, names)):
        n = len(list(run))
        subs = got.setdefault(int(head, 16), {})
        part = zip(numbers[at:at + n], secs[at:at + n])
        if None in numbers[at:at + n]:
            part = ((s, sec) for s, sec in part if s is not None)
        subs.update(part)
        at += n
    for idx in [i for i, subs in got.items() if not subs]:
        del got[idx]
    ctx.cache["sub_sections"] = got
    return got


def groups(ctx) -> list[tuple[str | None, dict | None, list]]:
    """(kind, template, sections) for every section, the sections of one kind that share
    one template (``Section.rest``) together, in file order of their first; a section
    without a template (the exact reader's) is a group of its own with template None."""
    got = ctx.cache.get("groups")
    if got is not None:
        return got
    got = []
    kinds_ = dict.fromkeys(["sub"] + _split(ctx)[3])
    for kind in kinds_:
        secs = kind_sections(ctx, kind)
        if not secs:
            continue
        try:
            rests = list(map(_REST, secs))
        except AttributeError:          # a reader without templates
            rests = [None] * len(secs)
        by_rest: dict[int, tuple] = {}
        at = 0
        for rid, run in groupby(map(id, rests)):
            n = len(list(run))
            rest = rests[at]
            if rest is None:
                got.extend((kind, None, [s]) for s in secs[at:at + n])
            else:
                group = by_rest.get(rid)
                if group is None:
                    group = by_rest[rid] = (kind, rest, [])
                    got.append(group)
                group[2].extend(secs[at:at + n])
            at += n
    ctx.cache["groups"] = got
    return got


def group_get(rest: dict | None, secs: list, key: str) -> str | None:
    """``sec.get(key)``, the same for every section of a group; not for the names (see
    ``name_values``)."""
    if rest is None:
        return secs[0].get(key)
    return rest.get(key) or None


def name_values(rest: dict | None, secs: list, key: str) -> list:
    """``[sec.get(key) for sec in secs]`` for ``parametername`` or ``denotation``, the
    values kept per section (an empty one is None, as ``get`` says)."""
    if rest is None:
        return [s.get(key) for s in secs]
    own = list(map(attrgetter(NAME_KEYS[key]), secs))
    if None in own:                       # not cut out of the template: its value is there
        if own.count(None) == len(own):
            return [rest.get(key) or None] * len(own)
        return [s.get(key) for s in secs]
    if "" in own:
        return [v or None for v in own]
    return own


def longest_name(rest: dict | None, secs: list, key: str) -> int:
    """``max(len(sec.get(key) or "") for sec in secs)`` for ``parametername`` or
    ``denotation``, without a list of the values."""
    if rest is None or len(secs) == 1:
        return max(len(s.get(key) or "") for s in secs)
    own = max(map(len, filter(None, map(attrgetter(NAME_KEYS[key]), secs))), default=0)
    return max(own, len(rest.get(key) or ""))   # the template's: where not cut out


# the kinds whose sections name themselves (DCF114); a set of the ids of a million unknown
# sections without a name was 60 bytes a section (issue 26)
NAMED_KINDS = ("object", "sub")


def nameless(ctx) -> dict[str | None, set[int]]:
    """kind -> ``id`` of every object or sub-object section (``NAMED_KINDS``) of that kind
    without a ParameterName (``get`` says None); kinds with none are left out."""
    got = ctx.cache.get("nameless")
    if got is None:
        got = {}
        for kind, rest, secs in groups(ctx):
            if kind not in NAMED_KINDS:
                continue
            if rest is not None and len(secs) == 1:    # most groups but the variables'
                s = secs[0]
                v = s.param_name
                if (v if v is not None else rest.get("parametername")):
                    continue        # (name_values' answer for one section, without lists)
                got.setdefault(kind, set()).add(id(s))
                continue
            names = name_values(rest, secs, "parametername")
            if None in names:
                got.setdefault(kind, set()).update(
                    id(s) for s, v in zip(secs, names) if v is None)
        ctx.cache["nameless"] = got
    return got


def sub_counts(ctx) -> dict[int, int]:
    """index -> the number of its [<index>subN] sections (N at most 0xFF): the lengths of
    ``sub_sections``, counted by one search over all names, a match per run of one
    index's sub-object names."""
    got = ctx.cache.get("sub_counts")
    if got is not None:
        return got
    joined = _split(ctx)[4]
    if _NOT_CANONICAL_SUB.search(joined):   # (the readers write canonical names)
        got = {idx: len(subs) for idx, subs in sub_sections(ctx).items()}
    else:
        got = {}
        for m in _SUB_RUN.finditer(joined):
            idx = int(m.group(1), 16)
            got[idx] = got.get(idx, 0) + m.group().count("\n")
    ctx.cache["sub_counts"] = got
    return got


# -- entries ----------------------------------------------------------------------------------

def entries(ctx) -> list:
    """Every entry that stands in the file (not those the tool creates), by index, then in
    each object's order."""
    got = ctx.cache.get("entries")
    if got is None:
        objects = ctx.dev.objects
        got = [e for idx in sorted(objects) for e in objects[idx].entries.values()
               if not e.implicit]
        ctx.cache["entries"] = got
    return got


def entries_of_kinds(ctx, kinds_: frozenset) -> list:
    """``entries`` whose DataType is of one of these kinds (datatypes.BOOL, SINT, ...)."""
    key = ("entries of", kinds_)
    got = ctx.cache.get(key)
    if got is None:
        every = entries(ctx)
        types = ctx.cache.get("entry types")
        if types is None:
            # each entry's DataType object as a small number (an array: one byte an entry,
            # where a list of their ids held an int object each, 40 bytes), and those objects
            dtypes = list(map(attrgetter("dtype"), every))
            objects = dict(zip(map(id, dtypes), dtypes))        # (a few dozen)
            number = {i: k for k, i in enumerate(objects)}
            codes = array("B" if len(number) <= 256 else "I",
                          map(number.__getitem__, map(id, dtypes)))
            types = ctx.cache["entry types"] = (codes, {k: objects[i]
                                                        for i, k in number.items()})
        codes, dtypes = types
        wanted = {k for k, d in dtypes.items() if d is not None and d.kind in kinds_}
        got = ctx.cache[key] = list(compress(every, map(wanted.__contains__, codes))) \
            if wanted else []
    return got


def entries_with(ctx, *attrs: str) -> list:
    """``entries`` with at least one of ``attrs`` (download_file, low, param, ...) not None."""
    key = ("entries with", attrs)
    got = ctx.cache.get(key)
    if got is None:
        every = entries(ctx)
        if len(attrs) == 1:
            values = list(map(attrgetter(attrs[0]), every))
            got = [] if values.count(None) == len(values) else list(
                compress(every, map(is_not, values, repeat(None))))
        else:
            ids = set().union(*(map(id, entries_with(ctx, a)) for a in attrs))
            got = list(compress(every, map(ids.__contains__, map(id, every)))) if ids else []
        ctx.cache[key] = got
    return got

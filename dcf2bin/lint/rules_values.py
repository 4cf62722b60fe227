"""DCF2xx: values of entries (SPEC §1): encodable, within the type, within the limits."""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import DcfError, shorten
from dcf2bin.lint import tables
from dcf2bin.lint.registry import ERROR, INFO, WARNING, Finding, rule
from dcf2bin.model import is_network_variable_index

_NO_LIMITS = frozenset({dt.VSTRING, dt.OSTRING, dt.USTRING, dt.DOMAIN})
_STRINGS = frozenset({dt.VSTRING, dt.USTRING})
_HEX_KINDS = frozenset({dt.OSTRING, dt.DOMAIN})


_entries = tables.entries   # every entry that stands in the file, shared by the rules


def _texts(e):
    if e.param is not None:
        yield "parametervalue", "ParameterValue", e.param
    if e.default is not None:
        yield "defaultvalue", "DefaultValue", e.default


def _encode(ctx, dtype: dt.DataType, text: str, node_id: int | None) -> bytes:
    if dtype.is_numeric or dtype.kind == dt.BOOL:
        text = values.split_numeric_comment(text)[0]
    return values.encode(dtype, text, node_id=node_id, encoding=ctx.dev.encoding)


@rule("DCF200", "bad-value", ERROR,
      "A DefaultValue/ParameterValue cannot be encoded as its DataType or lies outside the "
      "type's range (compile: an error for the values it writes, a warning for the "
      "others).",
      hint="write a value of the entry's DataType; values are never truncated")
def bad_value(ctx):
    seen: set = set()
    verdicts: dict[int, dict[str, str | None]] = {}   # type -> text -> problem
    for e in _entries(ctx):     # a flat loop: it sees every entry of the file
        dtype = e.dtype
        if dtype is None:
            continue
        known = verdicts.get(dtype.code)
        if known is None:
            known = verdicts[dtype.code] = {}
        param, default = e.param, e.default
        # True: not decided yet (_bad_values decides it); None: fine
        if (param is not None and known.get(param, True) is not None) or \
                (default is not None and known.get(default, True) is not None):
            yield from _bad_values(ctx, e, known, seen)


def _bad_values(ctx, e, known: dict, seen: set):
    dtype = e.dtype
    for key, shown, text in _texts(e):
        problem = known.get(text, False)
        if problem is False:
            problem = known[text] = _value_problem(ctx, dtype, text)
        if problem is None:
            continue
        line = e.key_where(key).line
        if (line, dtype.code, text) in seen:
            continue   # CompactSubObj: one DefaultValue line for N entries
        seen.add((line, dtype.code, text))
        yield Finding(f"{e.label} {shown}: {problem}", line, ctx.value_column(line))


def _value_problem(ctx, dtype, text: str) -> str | None:
    if (dtype.code, text) in ctx.dev.encoded:
        return None     # the model encoded it already (the selection's values): no problem
    try:
        _encode(ctx, dtype, text, ctx.dev.node_id)
    except values.NeedsNodeId:
        for trial in (1, 127):   # no node-ID known: the value must fit for any
            try:
                _encode(ctx, dtype, text, trial)
            except values.ValueProblem as exc:
                return f"{_clip(str(exc))} (with node-ID {trial})"
    except values.ValueProblem as exc:
        return _clip(str(exc))
    return None


@rule("DCF203", "numeric-comment", WARNING,
      "A numeric value (DefaultValue, ParameterValue, LowLimit, HighLimit) is followed by a "
      "';' or '#' comment; the comment is ignored.",
      hint="CiA 306 has no inline comments: put the comment on its own line")
def numeric_comment(ctx):
    if not ctx.blank_comment:
        return   # no value anywhere is followed by a comment: skip the walk
    seen: set[int] = set()
    split = values.split_numeric_comment
    for e in _entries(ctx):
        if e.dtype is None or not (e.dtype.is_numeric or e.dtype.is_integer):
            continue
        for key, text in (("parametervalue", e.param), ("defaultvalue", e.default),
                          ("lowlimit", e.low), ("highlimit", e.high)):
            if text is None or (";" not in text and "#" not in text):
                continue
            number, comment = split(text)
            if comment is None:
                continue
            line = e.key_where(key).line
            if line in seen:
                continue
            seen.add(line)
            col = ctx.value_column(line)
            yield Finding(f"{e.label}: comment '{shorten(comment)}' after the number "
                          f"'{shorten(number)}' is ignored", line, col + len(number) if col else None)


@rule("DCF202", "download-file", ERROR,
      "A DownloadFile cannot be read, is absolute or leaves the DCF's folder.",
      hint="use a readable path relative to the DCF, or --allow-external-files")
def download_file(ctx):
    for e in tables.entries_with(ctx, "download_file"):
        if e.param is not None or e.dtype is None:
            continue
        try:
            ctx.dev.encode(e)
        except DcfError as exc:
            d = exc.diagnostic
            yield Finding(d.message, d.line, ctx.value_column(d.line), hint=d.hint)


def _number(ctx, e, text: str):
    """The value of ``text`` as a number of e's type; None if $NODEID without a node-ID."""
    return values.as_number(e.dtype, text, ctx.dev.node_id, encoding=ctx.dev.encoding)


def _limits(ctx, e):
    """(low, high) as numbers (None where absent or unusable); cached per entry."""
    cache = ctx.cache.setdefault("limits", {})
    key = id(e)
    if key not in cache:
        out = []
        for text in (e.low, e.high):
            try:
                out.append(None if text is None else _number(ctx, e, text))
            except values.ValueProblem:
                out.append(None)
        cache[key] = tuple(out)
    return cache[key]


def _limit_entries(ctx):
    got = ctx.cache.get("limit entries")
    if got is None:
        limited = tables.entries_with(ctx, "low", "high")
        got = ctx.cache["limit entries"] = [
            e for e in limited if e.dtype is not None and e.dtype.kind not in _NO_LIMITS]
    return got


@rule("DCF210", "bad-limit", ERROR,
      "LowLimit or HighLimit is not a valid value of the entry's DataType.",
      hint="limits are values of the entry's type")
def bad_limit(ctx):
    seen: set = set()
    for e in _limit_entries(ctx):
        for key, shown, text in (("lowlimit", "LowLimit", e.low), ("highlimit", "HighLimit",
                                                                     e.high)):
            if text is None:
                continue
            line = e.key_where(key).line
            if (line, e.dtype.code) in seen:
                continue
            seen.add((line, e.dtype.code))
            try:
                _number(ctx, e, text)
            except values.ValueProblem as exc:
                yield Finding(f"{e.label} {shown}: {_clip(str(exc))}", line,
                              ctx.value_column(line))


@rule("DCF211", "limits-inverted", ERROR,
      "LowLimit is greater than HighLimit.",
      hint="swap the limits")
def limits_inverted(ctx):
    seen: set = set()
    for e in _limit_entries(ctx):
        low, high = _limits(ctx, e)
        message = values.inverted_limits(e.label, e.low, low, e.high, high)
        if message is None:
            continue
        line = e.key_where("lowlimit").line
        if line in seen:
            continue
        seen.add(line)
        yield Finding(message, line, ctx.value_column(line))


@rule("DCF212", "value-outside-limits", ERROR,
      "A DefaultValue/ParameterValue lies outside LowLimit..HighLimit.",
      hint="change the value, or the limits")
def outside_limits(ctx):
    seen: set = set()
    for e in _limit_entries(ctx):
        low, high = _limits(ctx, e)
        if low is None and high is None or (low is not None and high is not None and low > high):
            continue
        for key, shown, text in _texts(e):
            line = e.key_where(key).line
            if (line, text) in seen:
                continue
            seen.add((line, text))
            try:
                v = _number(ctx, e, text)
            except values.ValueProblem:
                continue  # DCF200
            if v is None:
                continue
            message = values.limit_problem(e.label, shown, text, v, e.low, low, e.high, high)
            if message is not None:
                yield Finding(message, line, ctx.value_column(line))


@rule("DCF213", "parametervalue-read-only", INFO,
      "A ParameterValue on a ro/const entry: it records what was read and is not written.",
      hint="compile does not write ro/const entries")
def param_read_only(ctx):
    for e in tables.entries_with(ctx, "param"):
        if e.access not in ("ro", "const") \
                or is_network_variable_index(e.index):
            continue
        line = e.key_where("parametervalue").line
        yield Finding(f"{e.label} is {e.access}; its ParameterValue is not written", line,
                      ctx.value_column(line))


@rule("DCF214", "nodeid-in-string", INFO,
      "A string value contains $NODEID, which is plain text in strings.",
      hint="$NODEID is a formula only in integer values")
def nodeid_in_string(ctx):
    for e in tables.entries_of_kinds(ctx, _STRINGS):
        for key, shown, text in _texts(e):
            if values.uses_nodeid(text):
                line = e.key_where(key).line
                yield Finding(f"{e.label} {shown} '{_clip(text, 60)}' is a "
                              f"{e.dtype.name}: $NODEID stays text", line,
                              ctx.value_column(line))


@rule("DCF215", "download-file-misuse", WARNING,
      "A DownloadFile on an entry that is not a DOMAIN, or together with a ParameterValue "
      "(which wins).",
      hint="DownloadFile supplies the value of a DOMAIN entry")
def download_misuse(ctx):
    for e in tables.entries_with(ctx, "download_file"):
        line = e.key_where("downloadfile").line
        if e.param is not None:
            yield Finding(f"{e.label} has DownloadFile and ParameterValue; the ParameterValue "
                          "is used", line, ctx.value_column(line))
        elif e.dtype is not None and e.dtype.kind != dt.DOMAIN:
            yield Finding(f"{e.label} is {e.dtype.name}; DownloadFile is meant for DOMAIN "
                          "entries", line, ctx.value_column(line))


@rule("DCF216", "objflags-reserved-bits", WARNING,
      "ObjFlags sets bits other than 0 (do not write on download) and 1 (do not read on scan).",
      hint="CiA 306 defines ObjFlags bits 0 and 1 only")
def objflags_reserved(ctx):
    for _, rest, secs in ctx.groups:     # once per shared template
        text = tables.group_get(rest, secs, "objflags")
        if text is None:
            continue
        try:
            v = values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem:
            continue  # DCF020
        if v & ~3 or v < 0:
            for sec in secs:
                line = sec.line_of("objflags")
                yield Finding(f"[{shorten(sec.name)}] ObjFlags=0x{v & 0xFFFFFFFF:X} sets "
                              "reserved bits",
                              line, ctx.value_column(line))


@rule("DCF217", "limits-on-non-numeric", WARNING,
      "LowLimit/HighLimit on a string, octet string or DOMAIN entry; they are ignored.",
      hint="remove the limits")
def limits_non_numeric(ctx):
    seen: set = set()
    for e in tables.entries_of_kinds(ctx, _NO_LIMITS):
        if e.low is None and e.high is None:
            continue
        for key in ("lowlimit", "highlimit"):
            if (e.low if key == "lowlimit" else e.high) is not None:
                line = e.key_where(key).line
                if line not in seen:
                    seen.add(line)
                    yield Finding(f"{e.label} is {e.dtype.name}; limits do not apply", line)


@rule("DCF218", "hex-0x-prefix", WARNING,
      "An OCTET_STRING or DOMAIN value starts with 0x; CiA 306 writes hex byte pairs "
      "without a prefix, and the bytes after it are used.",
      hint="write the hex byte pairs without 0x (Sevcon DriveWizard writes them with it)")
def hex_0x_prefix(ctx):
    seen: set = set()
    for e in tables.entries_of_kinds(ctx, _HEX_KINDS):
        for key, shown, text in _texts(e):
            if values.hex_prefix(text) and values.hex_problem(e.dtype, text) is None:
                line = e.key_where(key).line
                if line not in seen:   # CompactSubObj: one line for N entries
                    seen.add(line)
                    yield Finding(f"{e.label} {shown}: {values.hex_prefix_problem(e.dtype)}",
                                  line, ctx.value_column(line))


_clip = values.clip

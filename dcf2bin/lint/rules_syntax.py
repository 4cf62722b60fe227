"""DCF05x/06x: syntax and file structure beyond what the reader reports itself."""
from __future__ import annotations

import re

from dcf2bin import values
from dcf2bin.diagnostics import shorten
from dcf2bin.lint.registry import INFO, WARNING, Finding, rule
from dcf2bin.lint.tables import group_get, longest_name, name_values
from dcf2bin.lint.vocabulary import classify, unknown_keys

MAX_LINE = 255   # CiA 306: a line holds at most 255 characters
MAX_NAME = 241   # CiA 306: ParameterName (and Denotation) at most 241 characters

# Looks like an object section but is not one: wrong digit count, an 'x' template, junk.
_ALMOST_RE = re.compile(r"([0-9a-fx]{1,8})(?:sub.*)?|([0-9a-f]{4})\S*")


def _almost_object(canon: str) -> bool:
    m = _ALMOST_RE.fullmatch(canon)
    if m is None:
        return False
    head = m.group(1) or m.group(2)
    return any(c.isdigit() for c in head)


@rule("DCF050", "unknown-key", WARNING,
      "A key that CiA 306 does not define for its section (kept, but no tool reads it).",
      hint="check the spelling; vendor keys belong in a vendor section")
def unknown_key(ctx):
    verdicts: dict[tuple, list[str]] = {}   # generated files repeat the same key sets
    for kind, rest, secs in ctx.groups:     # one verdict per shared template
        if kind is None or kind == "aux":
            continue   # [<index>Name]/[<index>Value]/[<index>Denotation] keys: DCF026
        # a template's keys are its sections' (the names' lines are in it, empty)
        names = tuple(rest) if rest is not None else tuple(ctx.key_names(secs[0]))
        unknown = verdicts.get((kind, names))
        if unknown is None:
            unknown = verdicts[(kind, names)] = unknown_keys(kind, names)
        for sec in secs if unknown else ():
            for key in unknown:
                k = sec.keys.get(key)
                name = k.name if k else key
                yield Finding(f"key '{shorten(name)}' is not defined by CiA 306 for "
                              f"[{shorten(sec.name)}]",
                              sec.line_of(key), 1)


@rule("DCF051", "unknown-section", INFO,
      "A section that CiA 306 does not define (a vendor section); kept, never an error.",
      hint="fine for vendor data; check the spelling otherwise")
def unknown_section(ctx):
    for canon, sec in ctx.each_of_kind(None):
        if not _almost_object(canon):
            yield Finding(f"section [{shorten(sec.name)}] is not defined by CiA 306", sec.line)


@rule("DCF052", "line-too-long", WARNING,
      f"A line longer than {MAX_LINE} characters (the CiA 306 limit).",
      hint="shorten the value; other tools may cut the line")
def line_too_long(ctx):
    text = ctx.text                 # (the file's bytes when each is one character)
    nl, cr, blanks = _symbols(text)
    line, pos = 1, 0
    for start, end in _lines_of_names(ctx):
        while end > start and text[end - 1:end] == cr:     # (no copy of a 60 MB line)
            end -= 1
        if end - start <= MAX_LINE:
            continue
        line += text.count(nl, pos, start)
        pos = at = start
        while text[at:at + 1] in blanks:
            at += 1
        low = text[at:at + 14].lower()
        if isinstance(low, bytes):
            low = low.decode("latin-1")
        if low.startswith("parametername") or low.startswith("denotation"):
            continue  # DCF053 names it more precisely
        yield Finding(f"line has {end - start} characters, more than {MAX_LINE}", line,
                      MAX_LINE + 1)


def _symbols(text: str | bytes) -> tuple:
    """(line end, CR, the blanks) in the type of ``text``."""
    if isinstance(text, bytes):
        return b"\n", b"\r", (b" ", b"\t")
    return "\n", "\r", (" ", "\t")


# The shortest line that can hold a name of more than MAX_NAME characters: "Denotation="
# and the name (a ParameterName line is 3 characters longer). Every longer line is one.
_NAME_LINE = len("Denotation=") + MAX_NAME + 1


def _lines_of_names(ctx) -> list[tuple[int, int]]:
    """(start, end) in ``ctx.text`` of the lines of ``_NAME_LINE`` characters or more:
    DCF052 looks at those, and DCF053 looks at nothing when there are none."""
    got = ctx.cache.get("long lines")
    if got is None:
        got = ctx.cache["long lines"] = list(_long_lines(ctx.text, _NAME_LINE))
    return got


def _long_lines(text: str | bytes, width: int):
    """(start, end) of every line of at least ``width`` characters (CRs counted), as
    ``re.finditer(r"^[^\n]{width,}", text, re.M)`` finds them: from a line's start, the
    last line end within ``width`` characters is where to look next (none: a long line),
    about one step per ``width`` characters instead of one per line."""
    n, at = len(text), 0
    rfind, find = text.rfind, text.find
    lf = _symbols(text)[0]
    while at + width <= n:
        nl = rfind(lf, at, at + width)
        if nl >= 0:
            at = nl + 1
            continue
        end = find(lf, at)
        if end < 0:
            end = n
        yield at, end
        at = end + 1


@rule("DCF053", "name-too-long", WARNING,
      f"A ParameterName or Denotation longer than {MAX_NAME} characters (CiA 306).",
      hint="shorten the name")
def name_too_long(ctx):
    if not _lines_of_names(ctx):
        return   # no line can hold a name that long
    for _, rest, secs in ctx.groups:
        for key in ("parametername", "denotation"):
            if longest_name(rest, secs, key) <= MAX_NAME:
                continue
            names = name_values(rest, secs, key)
            for sec, v in zip(secs, names):
                if v is not None and len(v) > MAX_NAME:
                    line = sec.line_of(key)
                    yield Finding(f"{shorten(sec.keys[key].name)} of [{shorten(sec.name)}] has "
                                  f"{len(v)} characters, more than {MAX_NAME}", line,
                                  ctx.value_column(line))


@rule("DCF054", "malformed-object-section-name", WARNING,
      "A section name that looks like an object section but is not one ([100], [1A00sub], "
      "[14xxsub0]); it is not part of the object dictionary.",
      hint="object sections are [<index>] with 4 hex digits, sub-objects [<index>subN]")
def malformed_object_section(ctx):
    for canon, sec in ctx.each_of_kind(None):
        if _almost_object(canon):
            yield Finding(f"section [{shorten(sec.name)}] is not a valid object section name; "
                          "ignored",
                          sec.line)


# numeric keys outside what the model parses itself (it reports its own as DCF020/030/040)
_NUMERIC_KEYS = {
    "fileinfo": ("fileversion", "filerevision"),
    "deviceinfo": ("vendornumber", "productnumber", "revisionnumber", "granularity",
                   "baudrate_10", "baudrate_20", "baudrate_50", "baudrate_125", "baudrate_250",
                   "baudrate_500", "baudrate_800", "baudrate_1000", "baudrate_auto",
                   "simplebootupmaster", "simplebootupslave", "dynamicchannelssupported",
                   "groupmessaging", "lss_supported", "canopensafetysupported", "ng_slave",
                   "ng_master", "nrofng_monitorednodes"),
    "devicecomissioning": ("baudrate", "netnumber", "canopenmanager", "noderefd", "netrefd"),
    "comments": ("lines",),
    "aux": ("nrofentries",),
}
_NUMERIC_KEYS["devicecommissioning"] = _NUMERIC_KEYS["devicecomissioning"]
_LISTS = ("mandatoryobjects", "optionalobjects", "manufacturerobjects")


def _bad_int(text: str, _cache: dict = {}) -> str | None:  # noqa: B006 - a cache
    if text in _cache:
        return _cache[text]
    try:
        values.parse_int(values.split_numeric_comment(text)[0])
        problem = None
    except values.ValueProblem as exc:
        problem = str(exc)
    if len(_cache) < 1024:
        _cache[text] = problem
    return problem


@rule("DCF055", "bad-number", WARNING,
      "A key that holds an integer ([DeviceInfo], [FileInfo], object lists, PDOMapping, "
      "NrOfEntries, ...) is not a valid integer.",
      hint="decimal, 0x-hex or 0-octal integers only")
def bad_number(ctx):
    for kind, rest, secs in ctx.groups:
        if kind in ("object", "sub"):
            v = group_get(rest, secs, "pdomapping")   # once per shared template
            if v is None or not _bad_int(v):
                continue
            keys = ("pdomapping",)
        elif kind in _LISTS:
            keys = tuple(k for k in ctx.key_names(secs[0])
                         if k == "supportedobjects" or k.isdigit())
        else:
            keys = _NUMERIC_KEYS.get(kind or "", ())
        for sec in secs if keys else ():
            for key in keys:
                v = sec.get(key)
                if v is None:
                    continue
                problem = _bad_int(v)
                if problem:
                    line = sec.line_of(key)
                    yield Finding(f"[{shorten(sec.name)}] {shorten(sec.keys[key].name)}: "
                                  f"{problem}", line,
                                  ctx.value_column(line))


# DCF056 (no sections) is the reader's: compile reports it too (core_rules.py).


# a line with '=' and later a blank and ';'/'#' (searched from the last '=' before them:
# r"=[^\n]*?[ \t][;#]" costs time quadratic in the length of a line full of '=').
_COMMENT_RE = re.compile(r"=[^=\n]*?[ \t][;#]")
_STRUCT_NUMERIC = ("objecttype", "datatype", "subnumber", "compactsubobj", "objflags",
                   "pdomapping")


@rule("DCF057", "numeric-key-comment", WARNING,
      "A number in a structural key (DataType, ObjectType, SubNumber, [DeviceInfo], object "
      "lists, ...) is followed by a ';' or '#' comment; the comment is ignored.",
      hint="CiA 306 has no inline comments: put the comment on its own line")
def numeric_key_comment(ctx):
    if not ctx.blank_comment:
        return   # no number anywhere is followed by a comment: skip the walk
    split = values.split_numeric_comment
    seen: set[int] = set()

    def check(text, line):
        if text and (";" in text or "#" in text) and line not in seen:
            number, comment = split(text)
            if comment is not None:
                seen.add(line)
                col = ctx.value_column(line)
                return Finding(f"comment '{shorten(comment)}' after the number '{shorten(number)}' "
                               "is ignored",
                               line, col + len(number) if col else None)
        return None

    for kind, rest, secs in ctx.groups:
        if kind in ("object", "sub"):
            keys = _STRUCT_NUMERIC
            if not any(v is not None and (";" in v or "#" in v)     # once per template
                       for v in (group_get(rest, secs, k) for k in keys)):
                continue
        elif kind in _LISTS:
            keys = tuple(ctx.key_names(secs[0]))
        else:
            keys = _NUMERIC_KEYS.get(kind or "", ())
        for sec in secs if keys else ():
            for key in keys:
                v = sec.get(key)
                if v is not None and (";" in v or "#" in v):
                    f = check(v, sec.line_of(key))
                    if f:
                        yield f


_FLAGS = ("baudrate_10", "baudrate_20", "baudrate_50", "baudrate_125", "baudrate_250",
          "baudrate_500", "baudrate_800", "baudrate_1000", "baudrate_auto",
          "simplebootupmaster", "simplebootupslave", "groupmessaging", "lss_supported")


@rule("DCF058", "flag-not-boolean", WARNING,
      "A yes/no key (BaudRate_*, SimpleBootUp*, GroupMessaging, LSS_Supported, PDOMapping) "
      "is neither 0 nor 1.",
      hint="write 0 or 1; anything else reads as 'no'")
def flag_not_boolean(ctx):
    def bad(v):
        try:
            return values.parse_int(values.split_numeric_comment(v)[0]) not in (0, 1)
        except values.ValueProblem:
            return False   # DCF055

    info = ctx.section("deviceinfo")
    if info is not None:
        for key in _FLAGS:
            v = info.get(key)
            if v is not None and bad(v):
                line = info.line_of(key)
                yield Finding(f"[DeviceInfo] {info.keys[key].name}={v} is not 0 or 1", line,
                              ctx.value_column(line))
    for kind, rest, secs in ctx.groups:
        v = group_get(rest, secs, "pdomapping")     # once per shared template
        if v is not None and v not in ("0", "1") and kind in ("object", "sub") and bad(v):
            for sec in secs:
                line = sec.line_of("pdomapping")
                yield Finding(f"[{shorten(sec.name)}] PDOMapping={v} is not 0 or 1 (read as not "
                              "mappable)", line, ctx.value_column(line))


@rule("DCF059", "comments-count", WARNING,
      "[Comments] Lines does not match the Line<k> keys 1..Lines.",
      hint="Lines= counts the keys Line1..LineN")
def comments_count(ctx):
    for canon, sec in ctx.of_kind("comments", "modulecomments"):
        numbers = sorted(int(k[4:]) for k in ctx.key_names(sec)
                         if k.startswith("line") and k[4:].isdigit() and k[4:].isascii()
                         and len(k) < 24)   # a longer one never matches a count of lines
        text = sec.get("lines")
        try:
            n = values.parse_int(values.split_numeric_comment(text)[0]) if text else None
        except values.ValueProblem:
            continue  # DCF055
        if n is None:
            if numbers:
                yield Finding(f"[{shorten(sec.name)}] has Line<k> keys but no Lines=", sec.line)
            continue
        # compared by length first: the count must not build a list of its own size
        if n != len(numbers) or numbers != list(range(1, n + 1)):
            yield Finding(f"[{shorten(sec.name)}] Lines={n} but the Line<k> keys are "
                          f"{_ranges(numbers) or 'none'}", sec.line_of("lines"),
                          ctx.value_column(sec.line_of("lines")))


def _ranges(numbers: list[int]) -> str:
    out, start, prev = [], None, None
    for n in numbers:
        if start is None:
            start = prev = n
        elif n == prev + 1:
            prev = n
        else:
            out.append(f"{start}" if start == prev else f"{start}-{prev}")
            start = prev = n
    if start is not None:
        out.append(f"{start}" if start == prev else f"{start}-{prev}")
    return ", ".join(out)


@rule("DCF060", "required-section-missing", WARNING,
      "[FileInfo] or [DeviceInfo], which every CiA 306 file has, is missing.",
      hint="add the section; tools read vendor, product and PDO counts from it")
def required_section_missing(ctx):
    if not ctx.ini.sections:
        return  # DCF056
    for canon, shown in (("fileinfo", "FileInfo"), ("deviceinfo", "DeviceInfo")):
        if canon not in ctx.ini.sections:
            yield Finding(f"[{shown}] is missing", None)


@rule("DCF061", "subindex-spelling", WARNING,
      "A sub-object section writes its subindex with more than 2 hex digits ([1018sub001]); "
      "it is read as the canonical [1018sub1].",
      hint="a subindex has 1 or 2 hex digits: write the canonical section name")
def subindex_spelling(ctx):
    # only a section whose name is not written canonically can have more than 2 digits:
    # the reader lists those (IniFile.respelled), so the other names are not read
    respelled = getattr(ctx.ini, "respelled", None)
    if respelled is None:
        pairs = ctx.of_kind("sub")
    else:
        pairs = [(c, ctx.ini.sections[c]) for c in dict.fromkeys(respelled)
                 if c in ctx.ini.sections and classify(c) == "sub"]
    for canon, sec in pairs:
        digits = sec.name.strip().lower().partition("sub")[2]
        if len(digits) <= 2 or digits.strip("0123456789abcdef"):
            continue
        sub = int(digits, 16)
        if sub > 0xFF:
            continue   # DCF005
        shown = f"[{canon[:4].upper()}sub{sub:X}]"
        yield Finding(f"[{shorten(sec.name)}] has a subindex of {len(digits)} digits; it is "
                      "read as "
                      f"{shown}, the canonical spelling", sec.line)

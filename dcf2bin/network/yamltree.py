"""YAML read as PyYAML's ``safe_load`` reads it, but keeping every key's line (SPEC §10.1
D-16): the document is built from libyaml's parser events (their marks give the lines)
into :class:`YMap`/:class:`YSeq`, merge keys (``<<``) and aliases resolved.

A repeated key in one mapping is an error naming both lines (``safe_load`` would keep the
last silently). An alias shares the node of its anchor; the size it stands for is
counted, so an alias bomb ("billion laughs") is stopped at :data:`MAX_NODES`; a recursive
alias and nesting deeper than :data:`MAX_DEPTH` are errors too. Scalars become the
Python values ``safe_load`` gives (YAML 1.1: ``0b1100`` is 12, ``010`` is 8, ``yes`` is
True), but for an integer of more digits than any CANopen value has
(``values.MAX_DIGITS``): that one stays its text, a :class:`LongInt`, which the reader of
its key refuses with its own rule and line (it is never converted, so no message has to
print it in decimal).
"""
from __future__ import annotations

import gc
import re

from dcf2bin import values
from dcf2bin.diagnostics import Diagnostics, Where, shorten

# expanded nodes (aliases counted as what they stand for, ``defaults:`` once per node):
# 126 slaves of 8 PDOs of 8 objects are ~50,000. A bound, so that the readers' work has
# one: libyaml alone takes ~1.6 us an event (issue 26: a 3 MB file in under 2 s).
MAX_NODES = 250_000
MAX_DEPTH = 64
MERGE_TAG = "tag:yaml.org,2002:merge"
STR_TAG = "tag:yaml.org,2002:str"
INT_TAG = "tag:yaml.org,2002:int"
# plain scalars that YAML 1.1 resolves to these integers (decimal without a leading 0,
# hexadecimal): read directly, the resolver and constructor give the same
_PLAIN_INT = re.compile(r"0|[1-9][0-9]*|0x[0-9a-fA-F]+")


class LongInt(str):
    """An integer scalar of more than ``values.MAX_DIGITS`` digits, kept as its text
    (``0x`` and 4,000 ``F``, ``0b`` and 5,000 digits, a sexagesimal ``1:2:3:...``):
    ``digits`` is how many it has. The key's reader refuses it (``values.too_long``)."""
    __slots__ = ()

    @property
    def digits(self) -> int:
        body = self.lstrip("+-")
        if body[:2].lower() in ("0x", "0o", "0b"):
            body = body[2:]
        return len(body) - body.count("_") - body.count(":")


class YMap(dict):
    """A mapping; ``lines[key]`` is the line of each key, ``line`` the mapping's own,
    ``size`` how many nodes it stands for (itself, its keys and its values, expanded)."""
    __slots__ = ("line", "lines", "size")

    def __init__(self, line: int):
        super().__init__()
        self.line = line
        self.lines: dict = {}
        self.size = 1


class YSeq(list):
    """A sequence; ``lines[i]`` is the line of item i; ``size`` as for YMap.

    The items' lines are kept only once one of them stands on another line than the
    sequence itself (``put``): a flow list (``[1, 2, 3]``, ``[[[1]]]``) has none of its
    own, which a 3 MB file of 250,000 nested one-item lists made 64 bytes a list."""
    __slots__ = ("line", "_lines", "size")

    def __init__(self, line: int):
        super().__init__()
        self.line = line
        self._lines: list[int] | None = None
        self.size = 1

    @property
    def lines(self) -> list[int]:
        got = self._lines
        return [self.line] * len(self) if got is None else got

    def put(self, value, line: int) -> None:
        """Append ``value``, read at ``line``."""
        self.append(value)
        got = self._lines
        if got is not None:
            got.append(line)
        elif line != self.line:
            self._lines = [self.line] * (len(self) - 1) + [line]


class YamlError(Exception):
    """The file cannot be read at all; the diagnostics say where."""


class _Stop(Exception):  # noqa: N818 - an internal signal, not an error type
    def __init__(self, message: str, line: int, rule: str):
        super().__init__(message)
        self.line, self.rule = line, rule


def _at_tab(text: str | bytes, index: int) -> bool:
    """Whether the problem mark points at a tab (libyaml says only that the character
    cannot start a token; its index counts characters)."""
    if isinstance(text, bytes):
        text = text.decode("utf-8-sig", "replace")
    return 0 <= index < len(text) and text[index] == "\t"


def read_tree(text: str | bytes, path: str, diags: Diagnostics):
    """The document's root as YMap/YSeq/scalars, or None for an empty document. Fatal
    problems (syntax, an alias bomb) raise YamlError after adding their diagnostic; a
    repeated key is reported and the document read on. ``text`` may be the file's UTF-8
    bytes (libyaml reads them as they are; the caller checked that they are UTF-8): a
    text would be encoded again, a third copy of a 60 MB file.

    The tree is built from libyaml's events with an explicit stack (its parser does not
    recurse, PyYAML's composer does, and a C stack overflow cannot be caught); an alias
    shares the anchored node, and the size it stands for is counted."""
    import yaml
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    builder = _Builder(path, diags, yaml)
    # the tree is many small objects without reference cycles: the cyclic GC would only
    # rescan them, more often the larger the tree (as check and build do; restored)
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        builder.run(yaml.parse(text, Loader=loader))
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        what = exc.problem or exc.context or "invalid YAML"
        if exc.context and exc.problem:
            what = f"{exc.context}: {exc.problem}"
        if "maximum nesting depth" in what:   # the libyaml of PyYAML 6.0.4 wheels stops first
            diags.error(f"the YAML nests deeper than {MAX_DEPTH} levels", Where(path, line),
                        rule="NET003")
            raise YamlError() from None
        if mark is not None and _at_tab(text, mark.index):
            what += " (a tab: YAML indents with spaces)"
        diags.error(f"YAML syntax: {what}", Where(path, line), rule="NET001")
        raise YamlError() from None
    except yaml.YAMLError as exc:
        diags.error(f"YAML: {str(exc).splitlines()[0] if str(exc) else 'invalid'}",
                    Where(path, 1), rule="NET001")
        raise YamlError() from None
    except _Stop as stop:
        diags.error(str(stop), Where(path, stop.line), rule=stop.rule)
        raise YamlError() from None
    finally:
        if was_enabled:
            gc.enable()
    return builder.root


class _Frame:
    __slots__ = ("node", "anchor", "size", "pairs", "key", "merges")

    def __init__(self, node, anchor):
        self.node = node
        self.anchor = anchor
        self.size = 1
        self.pairs: list = []       # mapping: (key, key line, value)
        self.key = None             # mapping: the key waiting for its value, (key, line)
        self.merges: list = []      # mapping: (value, line) of each '<<'


_NO_KEY = object()
_MERGE = object()


class _Builder:
    def __init__(self, path: str, diags: Diagnostics, yaml):
        from yaml.resolver import Resolver
        self.yaml = yaml
        self.path = path
        self.diags = diags
        self.resolver = Resolver()
        self.constructor = yaml.constructor.SafeConstructor()
        self.stack: list[_Frame] = []
        self.anchors: dict[str, tuple[object, int]] = {}
        self.open: set[str] = set()
        self.root = None
        self.documents = 0
        self.last_line = 0

    def run(self, events) -> None:
        """Every event; a plain scalar (most of a file) is read here without a call: its
        value from a cache by its text (a file repeats ``1``, ``true``, ``index``), and
        put into a list or mapping as ``add`` would."""
        scalar_event, seq = self.yaml.ScalarEvent, YSeq
        cache: dict[str, object] = {}
        stack = self.stack
        last = 0
        for ev in events:
            if type(ev) is not scalar_event or ev.anchor is not None or not stack:
                self.event(ev)
                continue
            line = ev.start_mark.line + 1
            if line == last:         # one int object per line, not per node (see event)
                line = last
            else:
                last = line
            value = ev.value
            if ev.tag is None and ev.implicit[0]:          # plain, no tag: by its text
                got = cache.get(value, _NO_KEY)
                if got is _NO_KEY:
                    got = self.scalar(ev, line)
                    if len(cache) < 65536 and len(value) <= 256:
                        cache[value] = got
                value = got
            elif ev.tag is not None or not ev.implicit[1]:
                value = self.scalar(ev, line)
            frame = stack[-1]
            frame.size += 1
            if frame.size > MAX_NODES:
                self.add(value, line, 0, None)             # (says so)
            node = frame.node
            if type(node) is seq:
                node.put(value, line)
            else:
                self.add(value, line, 0, None)

    def event(self, ev) -> None:
        yaml = self.yaml
        kind = type(ev)
        line = ev.start_mark.line + 1 if ev.start_mark is not None else 1
        if line == self.last_line:   # the nodes of one line share its int (28 bytes each)
            line = self.last_line
        else:
            self.last_line = line
        if kind is yaml.ScalarEvent:
            self.add(self.scalar(ev, line), line, 1, ev.anchor)
        elif kind is yaml.MappingStartEvent or kind is yaml.SequenceStartEvent:
            if len(self.stack) >= MAX_DEPTH:
                raise _Stop(f"the YAML nests deeper than {MAX_DEPTH} levels", line, "NET003")
            node = YMap(line) if kind is yaml.MappingStartEvent else YSeq(line)
            if ev.anchor is not None:
                self.open.add(ev.anchor)
            self.stack.append(_Frame(node, ev.anchor))
        elif kind is yaml.MappingEndEvent or kind is yaml.SequenceEndEvent:
            frame = self.stack.pop()
            if kind is yaml.MappingEndEvent:
                self.finish_mapping(frame)
            if frame.anchor is not None:
                self.open.discard(frame.anchor)
            frame.node.size = frame.size
            self.add(frame.node, frame.node.line, frame.size, frame.anchor)
        elif kind is yaml.AliasEvent:
            if ev.anchor in self.open:
                raise _Stop("a recursive alias (the node contains itself)", line, "NET003")
            got = self.anchors.get(ev.anchor)
            if got is None:
                raise _Stop(f"alias *{shorten(ev.anchor)} names no anchor before it", line,
                            "NET001")
            self.add(got[0], line, got[1], None)
        elif kind is yaml.DocumentStartEvent:
            self.documents += 1
            if self.documents > 1:
                raise _Stop("more than one YAML document in the network file", line,
                            "NET001")

    def scalar(self, ev, line: int):
        yaml = self.yaml
        tag = ev.tag
        value = ev.value
        if tag is None and ev.implicit[0] and len(value) <= values.MAX_DIGITS \
                and _PLAIN_INT.fullmatch(value):
            return int(value, 16) if value[1:2] == "x" else int(value)
        if tag is None or tag == "!":
            tag = self.resolver.resolve(yaml.ScalarNode, ev.value, ev.implicit)
        if tag == STR_TAG:
            return ev.value
        if tag == INT_TAG and len(value) > values.MAX_DIGITS:
            long = LongInt(value)
            if long.digits > values.MAX_DIGITS:
                return long
        if tag == MERGE_TAG:
            return _MERGE
        node = yaml.ScalarNode(tag, ev.value, ev.start_mark, ev.end_mark, ev.style)
        try:
            return self.constructor.construct_object(node, deep=True)
        except yaml.YAMLError as exc:
            raise _Stop(f"YAML: {getattr(exc, 'problem', None) or exc}", line,
                        "NET001") from None
        except (ValueError, OverflowError) as exc:
            raise _Stop(f"YAML: value '{shorten(ev.value)}' cannot be read "
                        f"({shorten(exc)})", line, "NET001") from None

    def add(self, value, line: int, size: int, anchor) -> None:
        if anchor is not None:
            self.anchors[anchor] = (value, size)
        if not self.stack:
            self.root = value
            return
        frame = self.stack[-1]
        frame.size += size
        if frame.size > MAX_NODES:
            raise _Stop(f"the YAML expands to more than {MAX_NODES:,} nodes (a network "
                        "has tens of thousands; aliases repeating aliases?)", line, "NET003")
        node = frame.node
        if type(node) is YSeq:
            node.put(value, line)
            return
        if frame.key is None:
            if isinstance(value, (YMap, YSeq)):
                raise _Stop("a mapping or list as a key", line, "NET004")
            try:
                hash(value)
            except TypeError:
                raise _Stop(f"a key of type {type(value).__name__}", line, "NET004") from None
            frame.key = (value, line)
            return
        key, kline = frame.key
        frame.key = None
        if key is _MERGE:
            frame.merges.append((value, line))
        else:
            frame.pairs.append((key, kline, value))

    def finish_mapping(self, frame: _Frame) -> None:
        out = frame.node
        for key, kline, value in frame.pairs:
            if key in out:
                self.diags.error(f"key '{shorten(key)}' repeated (first at line "
                                 f"{out.lines[key]})", Where(self.path, kline), rule="NET002")
                continue
            out[key] = value
            out.lines[key] = kline
        for value, line in frame.merges:     # explicit keys win, then earlier sources
            sources = value if isinstance(value, YSeq) else [value]
            for src in sources:
                if not isinstance(src, YMap):
                    raise _Stop("a merge key '<<' needs a mapping or a list of mappings",
                                line, "NET004")
                for k, v in src.items():
                    if k not in out:
                        out[k] = v
                        out.lines[k] = src.lines[k]

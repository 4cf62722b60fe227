"""YAML read as PyYAML's ``safe_load`` reads it, but keeping every key's line (SPEC §10.1
D-16): the document is composed (``yaml.compose``, node marks), then walked here into
:class:`YMap`/:class:`YSeq` with the lines, merge keys (``<<``) and aliases resolved.

A repeated key in one mapping is an error naming both lines (``safe_load`` would keep the
last silently). Aliases are expanded, so an alias bomb ("billion laughs") is counted and
stopped at :data:`MAX_NODES`; a recursive alias and nesting deeper than :data:`MAX_DEPTH`
are errors too. Scalars become the Python values ``safe_load`` gives (YAML 1.1: ``0b1100``
is 12, ``010`` is 8, ``yes`` is True).
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics, Where

MAX_NODES = 1_000_000      # expanded nodes: 126 slaves of 8 PDOs are ~50,000
MAX_DEPTH = 64
MERGE_TAG = "tag:yaml.org,2002:merge"


class YMap(dict):
    """A mapping; ``lines[key]`` is the line of each key, ``line`` the mapping's own."""
    __slots__ = ("line", "lines")

    def __init__(self, line: int):
        super().__init__()
        self.line = line
        self.lines: dict = {}


class YSeq(list):
    """A sequence; ``lines[i]`` is the line of item i."""
    __slots__ = ("line", "lines")

    def __init__(self, line: int):
        super().__init__()
        self.line = line
        self.lines: list[int] = []


class YamlError(Exception):
    """The file cannot be read at all; the diagnostics say where."""


class _Stop(Exception):
    def __init__(self, message: str, line: int, rule: str):
        super().__init__(message)
        self.line, self.rule = line, rule


def read_tree(text: str, path: str, diags: Diagnostics):
    """The document's root as YMap/YSeq/scalars, or None for an empty document. Fatal
    problems (syntax, an alias bomb) raise YamlError after adding their diagnostic; a
    repeated key is reported and the document read on."""
    import yaml
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        _depth_guard(yaml, text, loader, path)
        root = yaml.compose(text, Loader=loader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        what = exc.problem or exc.context or "invalid YAML"
        if exc.context and exc.problem:
            what = f"{exc.context}: {exc.problem}"
        diags.error(f"YAML syntax: {what}", Where(path, line), rule="NET001")
        raise YamlError() from None
    except yaml.YAMLError as exc:
        diags.error(f"YAML: {str(exc).splitlines()[0] if str(exc) else 'invalid'}",
                    Where(path, 1), rule="NET001")
        raise YamlError() from None
    except _Stop as stop:
        diags.error(str(stop), Where(path, stop.line), rule=stop.rule)
        raise YamlError() from None
    except RecursionError:
        diags.error(f"the YAML nests deeper than {MAX_DEPTH} levels", Where(path, 1),
                    rule="NET003")
        raise YamlError() from None
    if root is None:
        return None
    walker = _Walker(path, diags, loader)
    try:
        return walker.convert(root, 0)
    except _Stop as stop:
        diags.error(str(stop), Where(path, stop.line), rule=stop.rule)
        raise YamlError() from None


def _depth_guard(yaml, text: str, loader, path: str) -> None:
    """Refuse deep nesting before composing: the composer recurses per level (libyaml's
    parser does not), and a C stack overflow cannot be caught."""
    depth = 0
    starts = (yaml.SequenceStartEvent, yaml.MappingStartEvent)
    ends = (yaml.SequenceEndEvent, yaml.MappingEndEvent)
    for event in yaml.parse(text, Loader=loader):
        if isinstance(event, starts):
            depth += 1
            if depth > MAX_DEPTH:
                raise _Stop(f"the YAML nests deeper than {MAX_DEPTH} levels",
                            event.start_mark.line + 1, "NET003")
        elif isinstance(event, ends):
            depth -= 1


class _Walker:
    def __init__(self, path: str, diags: Diagnostics, loader):
        import yaml
        self.yaml = yaml
        self.path = path
        self.diags = diags
        self.count = 0
        self.active: set[int] = set()
        self.constructor = yaml.constructor.SafeConstructor()
        self.reported: set[tuple[int, int]] = set()

    def convert(self, node, depth: int):
        yaml = self.yaml
        self.count += 1
        line = node.start_mark.line + 1
        if self.count > MAX_NODES:
            raise _Stop(f"the YAML expands to more than {MAX_NODES} nodes (aliases "
                        "repeating aliases)", line, "NET003")
        if depth > MAX_DEPTH:
            raise _Stop(f"the YAML nests deeper than {MAX_DEPTH} levels", line, "NET003")
        if isinstance(node, yaml.ScalarNode):
            try:
                return self.constructor.construct_object(node, deep=True)
            except yaml.YAMLError as exc:
                raise _Stop(f"YAML: {getattr(exc, 'problem', None) or exc}", line,
                            "NET001") from None
            except (ValueError, OverflowError) as exc:
                raise _Stop(f"YAML: value {node.value!r} cannot be read ({exc})", line,
                            "NET001") from None
        key = id(node)
        if key in self.active:
            raise _Stop("a recursive alias (the node contains itself)", line, "NET003")
        self.active.add(key)
        try:
            if isinstance(node, yaml.SequenceNode):
                seq = YSeq(line)
                for item in node.value:
                    seq.append(self.convert(item, depth + 1))
                    seq.lines.append(item.start_mark.line + 1)
                return seq
            return self._mapping(node, depth, line)
        finally:
            self.active.discard(key)

    def _mapping(self, node, depth: int, line: int) -> YMap:
        out = YMap(line)
        merges = []
        for knode, vnode in node.value:
            if knode.tag == MERGE_TAG:
                merges.append(vnode)
                continue
            key = self.convert(knode, depth + 1)
            kline = knode.start_mark.line + 1
            if isinstance(key, (YMap, YSeq)):
                raise _Stop("a mapping or list as a key", kline, "NET004")
            try:
                hash(key)
            except TypeError:
                raise _Stop(f"a key of type {type(key).__name__}", kline, "NET004") from None
            if key in out:
                first = out.lines[key]
                if (first, kline) not in self.reported:   # an alias repeats the mapping
                    self.reported.add((first, kline))
                    self.diags.error(f"key '{key}' repeated (first at line {first})",
                                     Where(self.path, kline), rule="NET002")
                continue
            out[key] = self.convert(vnode, depth + 1)
            out.lines[key] = kline
        for mnode in merges:      # explicit keys win, then earlier merge sources
            sources = mnode.value if isinstance(mnode, self.yaml.SequenceNode) else [mnode]
            for src in sources:
                value = self.convert(src, depth + 1)
                if not isinstance(value, YMap):
                    raise _Stop("a merge key '<<' needs a mapping or a list of mappings",
                                src.start_mark.line + 1, "NET004")
                for k, v in value.items():
                    if k not in out:
                        out[k] = v
                        out.lines[k] = value.lines[k]
        return out

"""The network variables (SPEC §10.2, D-17): a PLC master's network variables; for a lely
master (D-21) the same variables, named by the same rules and checked alike, are what
``show`` lists and ``dbc`` calls its signals (its own application objects 0x2000/0x2200
are named by dcfgen's rule, :mod:`.lely.layout`).

Each slave object mapped in a linked PDO becomes one PLC variable of its data type (an
input from a slave TPDO, an output to a slave RPDO), mapped at the same position with the
same length in the PLC PDO that mirrors it; an object mapped in several PDOs of one
direction is one variable, one mapped both ways two (an input and an output); a dummy
entry stays the same dummy. Names: the first ``name:`` of the object, else the slave's
``names:`` entry for it, else ``<slave>_<INDEX>_<SUB>`` -- the last two ending in ``_in``
and ``_out`` for an object mapped both ways. Placement is ``allocate --into``'s (D-15):
inputs in link order, then outputs.
"""
from __future__ import annotations

import re

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import Diagnostics, Where, shorten
from dcf2bin.network.model import RPDO, Mapped, Network, Node, Pdo, Variable

_NOT_IEC = re.compile(r"[^A-Za-z0-9_]")
_RUNS = re.compile(r"_{2,}")


def default_name(slave: str, index: int, sub: int) -> str:
    """``<slave>_<INDEX>_<SUB>``: INDEX four upper-case hex digits, SUB upper-case hex
    without leading zeros; characters an IEC identifier cannot hold become ``_``, runs
    of ``_`` one."""
    return _RUNS.sub("_", _NOT_IEC.sub("_", f"{slave}_{index:04X}_{sub:X}"))


def is_iec_identifier(name: str) -> bool:
    from dcf2bin.plc.idents import base_ident
    return base_ident(name, 0, 0) == name


def both_ways(mirrors: list[Pdo]) -> set[tuple[int, int, int]]:
    """(slave node-ID, index, sub) of every slave object that the PLC both reads (from a
    slave TPDO) and writes (to a slave RPDO): two variables, whose names end in ``_in``
    and ``_out`` (D-17; no other name changes)."""
    seen: dict[tuple[int, int, int], set[str]] = {}
    for mirror in mirrors:
        src = mirror.mirror_of
        for m in src.mapping:
            if not m.is_dummy:
                seen.setdefault((src.node_id, m.index, m.sub), set()).add(mirror.kind)
    return {k for k, kinds in seen.items() if len(kinds) == 2}


def suffix(key: tuple, both: set) -> str:
    """``_in``/``_out`` for the variable ``key`` (node-ID, index, sub, direction) of an
    object mapped both ways, else nothing."""
    if key[:3] not in both:
        return ""
    return "_in" if key[3] == "input" else "_out"


def make_variables(net: Network, mirrors: list[Pdo], diags: Diagnostics) -> None:
    """net.variables and the mirrors' mappings (PLC objects filled in by ``place``)."""
    with_dcf = net.master.device is not None
    by_object: dict[tuple, Variable] = {}
    name_where: dict[tuple, Where] = {}
    by_name: dict[str, tuple[tuple, Where]] = {}
    both = both_ways(mirrors)
    for mirror in mirrors:
        src = mirror.mirror_of
        slave = net.node(src.node_id)
        direction = "input" if mirror.kind == RPDO else "output"
        for m in src.mapping:
            if m.is_dummy:
                mirror.mapping.append(Mapped(m.index, m.sub, m.bits, m.datatype, None, m.where))
                continue
            key = (src.node_id, m.index, m.sub, direction)
            where = m.where
            var = by_object.get(key)
            if var is None:
                var = _new(net, slave, m, direction, where, with_dcf, diags,
                           suffix(key, both))
                by_object[key] = var
                if m.name:
                    name_where[key] = where
                    _check_name(m.name, where, diags)
                _claim(var.name, key, where, by_name, diags)
            elif m.name and var.name != m.name:
                first = name_where.get(key)
                if first is not None:
                    diags.error(f"0x{m.index:04X}sub{m.sub:X} of {shorten(slave.name)} is named "
                                f"'{shorten(m.name)}' here and '{shorten(var.name)}' at line "
                                f"{first.line}", where, rule="NET107")
                else:     # the first mapping had no name: this one names it
                    by_name.pop(var.name.casefold(), None)
                    var.name = m.name
                    name_where[key] = where
                    _check_name(m.name, where, diags)
                    _claim(var.name, key, where, by_name, diags)
            mirror.mapping.append(Mapped(m.index, m.sub, m.bits, m.datatype, var.name, where))
    _slave_names(net, by_object, name_where, by_name, both, diags)
    for mirror in mirrors:      # a later name: may have renamed a variable
        for m in mirror.mapping:
            if not m.is_dummy:
                m.name = by_object[_key(mirror, m)].name


def _key(mirror: Pdo, m: Mapped) -> tuple:
    """The variable of a mirror's entry, before placement (the slave object)."""
    return (mirror.mirror_of.node_id, m.index, m.sub,
            "input" if mirror.kind == RPDO else "output")


def _slave_names(net: Network, by_object: dict, name_where: dict, by_name: dict,
                 both: set, diags: Diagnostics) -> None:
    """A slave's ``names:`` (D-17): the name of each variable of that object that no
    ``name:`` of a mapping names (``_in``/``_out`` added for an object mapped both ways);
    a mapping's ``name:`` that says otherwise is two names for one object (NET107); an
    entry for an object no linked PDO maps is not used (NET123)."""
    for slave in net.slaves:
        for (index, sub), (text, where) in slave.names.items():
            keys = [k for k in ((slave.node_id, index, sub, d) for d in ("input", "output"))
                    if k in by_object]
            if not keys:
                diags.warning(f"names: 0x{index:04X}sub{sub:X} of {shorten(slave.name)} is "
                              "mapped by no PDO linked with the master: the name is not used",
                              where, rule="NET123")
                continue
            for key in keys:
                var, want = by_object[key], text + suffix(key, both)
                first = name_where.get(key)
                if first is not None:
                    if var.name != want:
                        diags.error(f"0x{index:04X}sub{sub:X} of {shorten(slave.name)} is named "
                                    f"'{shorten(want)}' here and '{shorten(var.name)}' at line "
                                    f"{first.line}",
                                    where, rule="NET107")
                    continue
                by_name.pop(var.name.casefold(), None)
                var.name = want
                name_where[key] = where
                _check_name(want, where, diags)
                _claim(want, key, where, by_name, diags)


def _new(net: Network, slave: Node, m: Mapped, direction: str, where: Where,
         with_dcf: bool, diags: Diagnostics, end: str = "") -> Variable:
    var = Variable(m.name or default_name(slave.name, m.index, m.sub) + end, direction,
                   m.datatype or 0, slave.node_id, m.index, m.sub, where=where)
    net.variables.append(var)
    if with_dcf:
        from dcf2bin.plc.allocate import RANGE_START
        if (var.datatype, direction) not in RANGE_START:
            dtype = dt.BY_CODE.get(var.datatype)
            diags.error(f"0x{m.index:04X}sub{m.sub:X} of {shorten(slave.name)} is "
                        f"{dtype.name if dtype else 'of no known type'}: the PLC has no "
                        "network-variable range (CiA 405) for that type", where,
                        rule="NET104")
    return var


def _check_name(name: str, where: Where, diags: Diagnostics) -> None:
    """A name given (``name:``, ``names:``) is an IEC 61131-3 identifier with or without
    a master ``dcf:`` (D-17, D-21): the variable of a PLC, and for a lely master the signal
    of ``network dbc`` and the row of ``show`` -- one name for both masters."""
    if not is_iec_identifier(name):
        diags.error(f"name '{shorten(name)}' is not an IEC 61131-3 identifier (letters, digits and "
                    "single '_', not a keyword)", where, rule="NET106")


def _claim(name: str, key: tuple, where: Where, by_name: dict, diags: Diagnostics) -> None:
    fold = name.casefold()
    other = by_name.get(fold)
    if other is None:
        by_name[fold] = (key, where)
        return
    if other[0] != key:
        diags.error(f"name '{shorten(name)}' is given to two objects (also at {other[1]})", where,
                    rule="NET107")


def place(net: Network, diags: Diagnostics) -> None:
    """Allocate the variables into the PLC's file (``allocate --into``): net.plc_plan,
    each variable's PLC object, and the mirrors' mapping entries."""
    from dcf2bin.plc.allocate import AllocationError, Var
    from dcf2bin.plc.merge import plan
    master = net.master
    dev = master.device
    yaml_path = net.path
    from dcf2bin.network.files import cia306
    base, parsed = cia306(net, dev)      # (CiA 306 text: a PLC's file in XML, converted)
    order = ([v for v in net.variables if v.direction == "input"]
             + [v for v in net.variables if v.direction == "output"])
    fallback = net.node(order[0].node_id).where.line if order else None
    variables = [Var(v.name, dt.BY_CODE[v.datatype], v.direction,
                     v.where.line if v.where and v.where.file == yaml_path else fallback)
                 for v in order]
    try:
        edit, placed, kept = plan(base, dev.path, variables, yaml_path,
                                  dev=dev if parsed is dev.ini and dev.path in net.files
                                  else None)
    except AllocationError as exc:
        for d in exc.diagnostics:
            diags.error(d.message, Where(d.file, d.line), rule="NET118")
        return
    net.plc_plan = edit
    spots = {p.var.name: (p.index, p.sub, p.offset) for p in placed}
    spots.update({v.name: (idx, sub, None) for v, idx, sub in kept})
    for v in net.variables:
        got = spots.get(v.name)
        if got is not None:
            v.pi_index, v.pi_sub, v.pi_offset = got
    by_object = {(v.node_id, v.index, v.sub, v.direction): v for v in net.variables}
    for pdo in master.pdos:
        if pdo.mirror_of is None:
            continue
        for m in pdo.mapping:
            var = None if m.is_dummy else by_object.get(_key(pdo, m))
            if var is not None and var.pi_index is not None:
                m.index, m.sub = var.pi_index, var.pi_sub

"""Running lely's dcfgen (dcf-tools 2.4.2, the test extra) beside `dcf2bin network build`
and comparing their outputs entry by entry (tests/test_network_lely_dcfgen.py, and
benchmarks/network.py for the timing).

dcfgen runs as ros2_canopen's build runs it: from the network file's folder, with
``-rS`` (remote-PDO records; an EDS that its linter dislikes still builds), on the file
with ``@BUS_CONFIG_PATH@`` replaced by ``.``; a ``nodes:`` file first goes through what
ros2_canopen's cogen does (``defaults:`` written over each node, the file dumped by
PyYAML, which sorts the keys). What depends on where it ran is left out: the paths of
``UploadFile=``.
"""
from __future__ import annotations

import os
import pathlib
import re
import shutil
import subprocess
import sys

DCFGEN = shutil.which("dcfgen") or str(pathlib.Path(sys.executable).with_name("dcfgen"))


def have_dcfgen() -> bool:
    return os.path.isfile(DCFGEN)


def dcfgen_input(network: pathlib.Path) -> str:
    """The YAML dcfgen reads for ``network``: ros2_canopen's sed of @BUS_CONFIG_PATH@,
    after cogen's expansion for a ``nodes:`` file."""
    import yaml
    text = network.read_text()
    cfg = yaml.safe_load(text)
    if "nodes" in cfg:
        nodes = cfg["nodes"]
        for node in nodes.values():
            node.update(cfg.get("defaults") or {})      # cogen: the default wins
        flat = {"options": cfg.get("options") or {}, "master": cfg["master"]}
        flat.update(nodes)
        text = yaml.dump(flat)                          # sort_keys: the names sorted
    return text.replace("@BUS_CONFIG_PATH@", ".")


def run_dcfgen(network: pathlib.Path, out: pathlib.Path) -> subprocess.CompletedProcess:
    """dcfgen -rS on ``network`` from its folder, its outputs in ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    src = out / "dcfgen-input.yml"
    src.write_text(dcfgen_input(network))
    try:
        return subprocess.run([DCFGEN, "-rS", "-d", str(out), str(src)], cwd=network.parent,
                              capture_output=True, text=True, timeout=120)
    finally:
        src.unlink()


def read_ini(text: str) -> list[tuple[str, list[tuple[str, str]]]]:
    """master.dcf as (section, [(key, value)]) in file order; an UploadFile= path is
    left out (it names where dcfgen ran), its presence kept."""
    sections: list = []
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith(";"):
            continue
        if line.startswith("["):
            sections.append((line[1:-1], []))
            continue
        key, _, value = line.partition("=")
        if key == "UploadFile":
            value = "<path>"
        sections[-1][1].append((key, value))
    return sections


def read_bin(data: bytes) -> list[tuple[int, int, bytes]]:
    from dcf2bin.network.concise import read_concise
    return read_concise(data)


_OBJECT = re.compile(r"([0-9A-Fa-f]{4})(?:sub[0-9A-Fa-f]+|Value|Name)?")


def object_of(section: str) -> str:
    """``0xIIII`` for the sections of one object ([1600], [1600Value], [1600sub1]), else
    the section's name in brackets."""
    m = _OBJECT.fullmatch(section)
    return f"0x{m.group(1).upper()}" if m else f"[{section}]"


def ini_differences(mine: str | list, theirs: str | list) -> set[str]:
    """``0xIIII`` (or ``[Section]``) for each object whose sections differ (keys, values,
    their order, present in one file only), ``section order`` when the common sections
    come in another order. Each file as text or as :func:`read_ini`'s sections."""
    mine = read_ini(mine) if isinstance(mine, str) else mine
    theirs = read_ini(theirs) if isinstance(theirs, str) else theirs
    a, b = dict(mine), dict(theirs)
    out = {object_of(name) for name in set(a) | set(b) if a.get(name) != b.get(name)}
    order_a = [n for n, _ in mine if n in b]
    order_b = [n for n, _ in theirs if n in a]
    if order_a != order_b:
        out.add("section order")
    return out


# -- a lely master's PDOs, numbered by both tools ------------------------------------------
# Master PDO n is these objects, each at its base + n - 1 (D-21, dcfgen's layout): the
# communication and mapping parameters, the application record, the remote-PDO records.
PDO_OBJECTS = {"RPDO": (0x1400, 0x1600, 0x2000, 0x5800, 0x5A00),
               "TPDO": (0x1800, 0x1A00, 0x2200, 0x5C00, 0x5E00)}
_SECTION = re.compile(r"([0-9A-F]{4})((?:sub[0-9A-F]+|Value)?)")
_LISTS = ("OptionalObjects", "ManufacturerObjects")


def _pdo_of(index: int) -> tuple[str, int, int] | None:
    """(kind, number, base) of a master PDO object's index, else None."""
    for kind, bases in PDO_OBJECTS.items():
        for base in bases:
            if base <= index < base + 0x200:
                return kind, index - base + 1, base
    return None


def mirrored(sections: list) -> dict[str, dict[int, str]]:
    """kind -> master PDO number -> the slave PDO it mirrors (``node 5 TPDO2``), as its
    remote-PDO record (0x5800/0x5C00 + n - 1) names it."""
    out: dict[str, dict[int, str]] = {"RPDO": {}, "TPDO": {}}
    for name, keys in sections:
        m = _SECTION.fullmatch(name)
        where = _pdo_of(int(m.group(1), 16)) if m and not m.group(2) else None
        if where is None or where[2] not in (0x5800, 0x5C00):
            continue
        value = int(dict(keys)["DefaultValue"], 16)
        slave = "TPDO" if where[0] == "RPDO" else "RPDO"
        out[where[0]][where[1]] = f"node {value & 0xFF} {slave}{value >> 8}"
    return out


def pdo_numbers(mine: list, theirs: list) -> tuple[dict[str, dict[int, int | None]], set[str]]:
    """dcfgen's master PDO numbers -> dcf2bin's, matched by the slave PDO each mirrors
    (None: only dcfgen mirrors it), only where they differ; and a difference for each
    master PDO only one of the two has (``dcfgen TPDO2 (node 2 RPDO2)``)."""
    a, b = mirrored(mine), mirrored(theirs)
    numbers: dict[str, dict[int, int | None]] = {}
    only = set()
    for kind in PDO_OBJECTS:
        ours = {slave: n for n, slave in a[kind].items()}
        for n, slave in sorted(b[kind].items()):
            got = ours.get(slave)
            if got != n:
                numbers.setdefault(kind, {})[n] = got
            if got is None:
                only.add(f"dcfgen {kind}{n} ({slave})")
        theirs_slaves = set(b[kind].values())
        only |= {f"dcf2bin {kind}{n} ({slave})" for n, slave in a[kind].items()
                 if slave not in theirs_slaves}
    return numbers, only


def renumber(sections: list, numbers: dict[str, dict[int, int | None]]) -> list:
    """dcfgen's master.dcf with its PDOs numbered as dcf2bin numbers them (``numbers``,
    from :func:`pdo_numbers`) and without the PDOs dcf2bin does not mirror: their
    sections, their entries of the object lists, their count in NrOfRxPDO/NrOfTxPDO.
    Everything else is kept as dcfgen wrote it -- a mapping entry that points into a
    record left out stays as it was, and differs."""
    if not numbers:
        return sections

    def new_index(index: int) -> int | None:
        where = _pdo_of(index)
        if where is None or where[1] not in numbers.get(where[0], {}):
            return index
        n = numbers[where[0]][where[1]]
        return None if n is None else where[2] + n - 1

    out = []
    for name, keys in sections:
        m = _SECTION.fullmatch(name)
        if m:
            old = int(m.group(1), 16)
            index = new_index(old)
            if index is None:
                continue
            name = f"{index:04X}{m.group(2)}"
            mapping = 0x1600 <= old < 0x1800 or 0x1A00 <= old < 0x1C00
            keys = [(k, _new_value(k, v, new_index, numbers, mapping)) for k, v in keys]
        elif name in _LISTS:
            listed = [i for i in (new_index(int(v, 16)) for k, v in keys
                                  if k != "SupportedObjects") if i is not None]
            keys = [("SupportedObjects", str(len(listed)))] + [
                (str(k), f"0x{i:04X}") for k, i in enumerate(listed, 1)]
        elif name == "DeviceInfo":
            gone = {kind: sum(v is None for v in numbers.get(kind, {}).values())
                    for kind in PDO_OBJECTS}
            keys = [(k, str(int(v) - gone["RPDO" if k == "NrOfRxPDO" else "TPDO"])
                     if k in ("NrOfRxPDO", "NrOfTxPDO") else v) for k, v in keys]
        out.append((name, keys))
    return out


_RECORD = re.compile(r"0x(2[02][0-9A-F]{2})([0-9A-F]{4})")
_TITLE = re.compile(r"Mapped application objects for (RPDO|TPDO) (\d+)")


def _new_value(key: str, value: str, new_index, numbers, mapping: bool) -> str:
    """A value of a renumbered section: a master mapping entry's application record
    (``mapping``: a section of 0x1600/0x1A00; the remote records name the slave's own
    objects), the number in an application record's name."""
    m = _RECORD.fullmatch(value) if mapping else None
    if m:
        index = new_index(int(m.group(1), 16))
        return value if index is None else f"0x{index:04X}{m.group(2)}"
    m = _TITLE.fullmatch(value) if key == "ParameterName" else None
    if m:
        n = numbers.get(m.group(1), {}).get(int(m.group(2)), int(m.group(2)))
        return f"Mapped application objects for {m.group(1)} {n}"
    return value


def bin_differences(mine: bytes, theirs: bytes) -> set[str]:
    """``0xIIIIsubS`` for each entry written other values or other times, ``order`` when
    the entries both write the same way come in another order."""
    a, b = read_bin(mine), read_bin(theirs)

    def per_entry(entries):
        got: dict = {}
        for index, sub, data in entries:
            got.setdefault((index, sub), []).append(data)
        return got

    ea, eb = per_entry(a), per_entry(b)
    differ = {k for k in set(ea) | set(eb) if ea.get(k) != eb.get(k)}
    out = {f"0x{i:04X}sub{s:X}" for i, s in differ}
    if [(i, s) for i, s, _ in a if (i, s) not in differ] != \
            [(i, s) for i, s, _ in b if (i, s) not in differ]:
        out.add("order")
    return out


def differences(mine: dict[str, bytes], theirs: pathlib.Path,
                numbers: dict | None = None) -> set[tuple[str, str]]:
    """(file, what) for every difference between dcf2bin's outputs and dcfgen's folder:
    a file only one of them writes is (file, "file"); a .bin of dcfgen's that is no
    concise DCF is (file, "unreadable"). master.dcf is compared after dcfgen's master
    PDOs are numbered as dcf2bin numbers them (:func:`renumber`): a master PDO only one
    of them mirrors is one difference (``dcfgen TPDO2 (node 2 RPDO2)``), and every other
    entry is compared with its counterpart. ``numbers`` (a dict) receives that
    renumbering (:func:`pdo_numbers`)."""
    from dcf2bin.concise import ConciseError
    out = set()
    names = {p.name for p in theirs.iterdir()} | set(mine)
    for name in sorted(names):
        path = theirs / name
        if name not in mine or not path.is_file():
            out.add((name, "file"))
            continue
        if name.endswith(".dcf"):
            a, b = read_ini(mine[name].decode()), read_ini(path.read_text())
            renumbered, only = pdo_numbers(a, b)
            if numbers is not None:
                numbers.update(renumbered)
            diff = ini_differences(a, renumber(b, renumbered)) | only
        else:
            try:
                diff = bin_differences(mine[name], path.read_bytes())
            except ConciseError:
                diff = {"unreadable"}
        out |= {(name, d) for d in diff}
    return out

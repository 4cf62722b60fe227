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


def ini_differences(mine: str, theirs: str) -> set[str]:
    """``0xIIII`` (or ``[Section]``) for each object whose sections differ (keys, values,
    their order, present in one file only), ``section order`` when the common sections
    come in another order."""
    a, b = dict(read_ini(mine)), dict(read_ini(theirs))
    out = {object_of(name) for name in set(a) | set(b) if a.get(name) != b.get(name)}
    order_a = [n for n, _ in read_ini(mine) if n in b]
    order_b = [n for n, _ in read_ini(theirs) if n in a]
    if order_a != order_b:
        out.add("section order")
    return out


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


def differences(mine: dict[str, bytes], theirs: pathlib.Path) -> set[tuple[str, str]]:
    """(file, what) for every difference between dcf2bin's outputs and dcfgen's folder:
    a file only one of them writes is (file, "file"); a .bin of dcfgen's that is no
    concise DCF is (file, "unreadable")."""
    from dcf2bin.concise import ConciseError
    out = set()
    names = {p.name for p in theirs.iterdir()} | set(mine)
    for name in sorted(names):
        path = theirs / name
        if name not in mine or not path.is_file():
            out.add((name, "file"))
            continue
        if name.endswith(".dcf"):
            diff = ini_differences(mine[name].decode(), path.read_text())
        else:
            try:
                diff = bin_differences(mine[name], path.read_bytes())
            except ConciseError:
                diff = {"unreadable"}
        out |= {(name, d) for d in diff}
    return out

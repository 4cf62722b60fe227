"""The bulk paths of dump, map and bin2dcf (issue 22) against the per-entry code they
replaced: the same text for random containers and variable maps, edge cases included
(repeated writes, missing or extra attribute bytes, addresses that do not match the
variables, no PI parameters, empty containers)."""
from __future__ import annotations

import json
import random

import pytest

from dcf2bin import container, datatypes as dt, dump
from dcf2bin.container import BinContainer
from dcf2bin.dcfwriter import convert, roundtrip, text as dcftext
from dcf2bin.dump import jsonform, text as dumptext
from dcf2bin.plc import tables
from dcf2bin.plc.varmap import VarMap, make_row

from conftest import ROOT

SAMPLES = sorted((ROOT / "samples").glob("*.bin"))


# -- the per-entry code the bulk paths replaced, kept here as the reference -----------------

def _ref_table(head, rows, right):
    widths = [len(h) for h in head]
    for col, cells in enumerate(zip(*rows)):
        widths[col] = max(widths[col], max(map(len, cells)))
    fmt = "  " + "  ".join(f"{{{i}:{'>' if i in right else '<'}{w}}}"
                           for i, w in enumerate(widths))
    return [fmt.format(*head).rstrip()] + [fmt.format(*r).rstrip() for r in rows]


def _ref_nv_keys(c):
    seen, out = set(), []
    for index, sub, _ in c.entries:
        if 0xA000 <= index <= 0xAFFF and sub >= 1 and (index, sub) not in seen:
            seen.add((index, sub))
            out.append((index, sub))
    return out


def _ref_area_of(addr, pi):
    if pi is None:
        return "", ""
    _, in_off, in_size, out_off, out_size = pi
    if in_off <= addr < in_off + in_size:
        return "input", addr - in_off
    if out_off <= addr < out_off + out_size:
        return "output", addr - out_off
    return "outside", ""


def _ref_index_rows(c, h, eds, full):
    attrs = c.attributes or b""
    offsets = dump.entry_offsets(c, h)
    counts, seen, rows = {}, {}, []
    for index, sub, _ in c.entries:
        counts[(index, sub)] = counts.get((index, sub), 0) + 1
    for i, (index, sub, data) in enumerate(c.entries):
        attr = attrs[i] if i < len(attrs) else None
        key = (index, sub)
        seen[key] = seen.get(key, 0) + 1
        rep = f"{seen[key]}/{counts[key]}" if counts[key] > 1 else ""
        rows.append((str(i + 1), f"0x{offsets[i]:X}", f"0x{index:04X}", str(sub),
                     str(len(data)), dumptext._short_hex(data, full),
                     dumptext.value_text(index, sub, data, attr, eds, full),
                     f"0x{attr:02X}" if attr is not None else "-",
                     dumptext._FLAGS[attr] if attr is not None else "-", rep))
    head = ("#", "offset", "index", "sub", "size", "data", "value", "attr", "flags", "write")
    return _ref_table(head, rows, {0, 3, 4})


def _ref_address_rows(c, nvs, eds):
    addrs = c.addresses
    first = {}
    for index, sub, d in c.entries:
        first.setdefault((index, sub), d)
    rows = []
    for k in range(max(len(addrs), len(nvs))):
        a = addrs[k] if k < len(addrs) else None
        key = nvs[k] if k < len(nvs) else None
        area, off = _ref_area_of(a, c.pi) if a is not None else ("", "")
        data = first[key] if key is not None else None
        t = dumptext.nv_type(key[0], key[1], len(data), eds) if key is not None else None
        rows.append((str(k + 1), f"0x{a:04X}" if a is not None else "-", area, str(off),
                     f"0x{key[0]:04X}" if key else "-", str(key[1]) if key else "-",
                     str(len(data)) if data is not None else "-",
                     t.name if t is not None else "-",
                     eds.name(*key) if eds is not None and key else ""))
    if not rows:
        return []
    head = ("#", "address", "area", "offset", "index", "sub", "size", "type", "name")
    return _ref_table(head, rows, {0, 3, 5, 6})


def _ref_map_text_rows(vm):
    rows = vm.rows
    labels = [r.label for r in rows]
    w_off = max([len("offset")] + [len(str(r.offset)) for r in rows])
    w_entry = max([len("entry")] + [len(x) for x in labels])
    w_type = max([len("type")] + [len(t) for t in {r.dtype.name for r in rows}])
    return [f"0x{r.address:04X}   {r.direction:<6}  {r.offset:>{w_off}}  {lab:<{w_entry}}  "
            f"{r.dtype.size:>4}  {r.dtype.name:<{w_type}}  {r.name}".rstrip()
            for r, lab in zip(rows, labels)]


# -- random containers ----------------------------------------------------------------------

_INDEXES = [0x1000, 0x1018, 0x1400, 0x1600, 0x1800, 0x1A00, 0x2000, 0x6000,
            0xA000, 0xA040, 0xA0C0, 0xA100, 0xA4C0, 0xA580, 0xA640, 0xA8C0, 0xA900, 0xAFFF]


def _random_container(rng: random.Random) -> BinContainer:
    entries = []
    for _ in range(rng.randrange(0, 120)):
        index = rng.choice(_INDEXES) + rng.randrange(0, 3)
        sub = rng.choice([0, 1, 1, 2, 3, 17, 254, 255])
        size = rng.choice([0, 1, 1, 2, 4, 4, 8, 3, 20, 40])
        entries.append((index, sub, bytes(rng.randrange(256) for _ in range(size))))
    if entries and rng.random() < 0.3:          # repeated writes
        entries += rng.sample(entries, rng.randrange(1, len(entries) + 1))
    n = len(entries)
    attrs = bytes(rng.randrange(256) for _ in range(n))
    roll = rng.random()
    if roll < 0.1:
        attrs = None
    elif roll < 0.2:
        attrs = attrs[:rng.randrange(n + 1)]
    elif roll < 0.3:
        attrs += b"\x07\x30"
    c = BinContainer(entries=entries, attributes=attrs)
    nvs = _ref_nv_keys(c)
    if rng.random() < 0.85:
        k = len(nvs) + rng.choice([0, 0, 0, -1, 2])
        c.addresses = [rng.randrange(0, 0x10000 if rng.random() < 0.1 else 400)
                       for _ in range(max(k, 0))]
        if rng.random() < 0.85:
            c.pi = (400, 0, 200, 200, rng.choice([0, 100, 200]))
    return c


@pytest.mark.parametrize("seed", range(60))
def test_report_tables_match_the_per_entry_rows(seed):
    rng = random.Random(seed)
    c = _random_container(rng)
    h = dump.header_of(c)
    full = seed % 2 == 1
    got = dump.report(c, "x.bin", full=full)
    want_index = _ref_index_rows(c, h, None, full) if c.entries else []
    assert "\n".join(want_index) in got
    nvs = _ref_nv_keys(c)
    assert dump.nv_keys(c) == nvs
    if c.addresses is not None:
        want_pi = _ref_address_rows(c, nvs, None)
        assert "\n".join(want_pi) in got
        lines = got.splitlines()
        if want_pi:
            start = lines.index(want_pi[0])
            assert lines[start:start + len(want_pi)] == want_pi
    if want_index:
        start = got.splitlines().index(want_index[0])
        assert got.splitlines()[start:start + len(want_index)] == want_index


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_report_of_samples_matches_the_per_entry_rows(path):
    c, _ = container.read(path.read_bytes())
    h = dump.header_of(c)
    lines = dump.report(c, path.name).splitlines()
    want = _ref_index_rows(c, h, None, False)
    start = lines.index(want[0])
    assert lines[start:start + len(want)] == want


def test_table_columns_of_numbers_and_text():
    rng = random.Random(7)
    for _ in range(200):
        n = rng.randrange(0, 30)
        nums = [rng.randrange(0, rng.choice([10, 1000, 0x10000])) for _ in range(n)]
        texts = ["".join(rng.choice("ab %-") for _ in range(rng.randrange(0, 8)))
                 for _ in range(n)]
        head = ("#", "hex", "text", "n")
        right = {0, 3}
        cols = [dumptext._Num(nums), dumptext._Num(nums, "0x", 4), texts,
                dumptext._Num(nums)]
        rows = list(zip(map(str, nums), (f"0x{v:04X}" for v in nums), texts,
                        map(str, nums)))
        assert dumptext._table_columns(head, cols, right) == _ref_table(head, rows, right)
        assert dumptext._Num(nums, "0x", 4).texts() == [f"0x{v:04X}" for v in nums]


def test_segment_sizes_are_the_lengths_of_the_segments():
    rng = random.Random(3)
    for _ in range(50):
        c = _random_container(rng)
        if rng.random() < 0.2:
            c.raw_piparam = b"\x01\x02\x03"
        assert c.segment_sizes() == {k: len(v) for k, v in c.segments().items()}


# -- map ------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(20))
def test_map_text_matches_the_per_row_format(seed):
    rng = random.Random(seed)
    types = [dt.BY_NAME[n] for n in ("BOOLEAN", "UNSIGNED8", "INTEGER16", "UNSIGNED32", "REAL64")]
    rows = []
    for _ in range(rng.randrange(0, 50)):
        t = rng.choice(types)
        off = rng.randrange(0, rng.choice([10, 100000]))
        name = rng.choice(["", "v", "a long name", "trailing  ", "pct%s"])
        rows.append(make_row(name, 0xA000 + rng.randrange(0, 0x900), rng.randrange(1, 255), t,
                             rng.choice(["input", "output"]), off, off + rng.randrange(0, 9)))
    vm = VarMap("m.dcf", rows, (100, 0, 50, 56, 44))
    got = tables.to_text(vm).splitlines()
    assert got[5:] == _ref_map_text_rows(vm)


# -- bin2dcf --------------------------------------------------------------------------------

@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_bin2dcf_template_matches_the_per_sub_text(path, monkeypatch):
    c, _ = container.read(path.read_bytes())
    bulk = convert(c, path.name, dcf_name="x.dcf").text
    monkeypatch.setattr(dcftext, "_alike", lambda subs: False)
    assert convert(c, path.name, dcf_name="x.dcf").text == bulk


def test_bin2dcf_template_of_a_large_container(monkeypatch):
    from dcf2bin.compiler import compile_path
    import sys
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import gen_dcf
    data = gen_dcf.generate(1200).encode("ascii")
    res = compile_path("g.dcf", data=data)
    c, _ = container.read(res.data)
    bulk = convert(c, "g.bin", dcf_name="g.dcf")
    assert bulk.roundtrip
    monkeypatch.setattr(dcftext, "_alike", lambda subs: False)
    assert convert(c, "g.bin", dcf_name="g.dcf").text == bulk.text


def _ref_first_difference(c, writes):
    attrs = c.attributes or b""
    actual = c.entries
    for i in range(max(len(writes), len(actual))):
        e = writes[i] if i < len(writes) else None
        a = actual[i] if i < len(actual) else None
        a_attr = attrs[i] if i < len(attrs) else None
        if e is None or a is None or e[:3] != a or e[3] != a_attr:
            return i
    return None


def test_first_difference_in_bulk_matches_the_search():
    rng = random.Random(11)
    for _ in range(300):
        n = rng.randrange(0, 8)
        entries = [(rng.randrange(2), rng.randrange(2), bytes([rng.randrange(2)]))
                   for _ in range(n)]
        attrs = bytes(rng.randrange(2) for _ in range(n + rng.choice([-1, 0, 0, 1])))[:max(
            n + 1, 0)]
        c = BinContainer(entries=entries, attributes=attrs or None)
        writes = [e + (a,) for e, a in zip(entries, list(attrs) + [0] * n)]
        if rng.random() < 0.5 and writes:
            k = rng.randrange(len(writes))
            i, s, d, a = writes[k]
            writes[k] = rng.choice([(i ^ 1, s, d, a), (i, s, d, a ^ 1), (i, s, b"\x05", a)])
        if rng.random() < 0.2:
            writes = writes[:-1]
        assert roundtrip._first_difference(c, writes) == _ref_first_difference(c, writes)


def test_value_texts_made_once_per_type_and_bytes_are_the_same():
    # _values caches value_text by (type, bytes): the cache must not mix types
    c, _ = container.read((ROOT / "samples" / "plc.bin").read_bytes())
    from dcf2bin.dcfwriter.reader import read_spec
    from dcf2bin.dcfwriter.spec import value_text
    spec = read_spec(c, "plc.bin")
    for obj in spec.objects.values():
        for s in obj.subs.values():
            if s.writes:
                assert s.value == value_text(s.dtype, s.data, spec.encoding)


@pytest.mark.parametrize("seed", range(30))
def test_json_entry_lines_are_json_dumps_of_to_dict(seed):
    c = _random_container(random.Random(seed))
    doc = dump.to_dict(c)
    want = dump.format_json(doc)       # every entry through json.dumps
    assert dump.to_json(c) == want
    assert [json.loads(x) for x in jsonform._entry_lines(c)] == doc["entries"]


def _ref_overlap(spans, area):
    reach = -1
    for start, end, index, sub in sorted(spans):
        if start < reach:
            return f"0x{index:04X}sub{sub:X} overlaps another variable in the {area} area"
        reach = max(reach, end)
    return None


def test_overlap_by_blocks_matches_the_per_variable_check():
    rng = random.Random(5)
    for _ in range(500):
        blocks, spans = [], []
        for index in rng.sample(range(0xA000, 0xA010), rng.randrange(0, 6)):
            size = rng.choice([1, 2, 4])
            subs = sorted(rng.sample(range(1, 20), rng.randrange(1, 6)))
            base = rng.randrange(0, 60)
            offs = [base + sub * size for sub in subs]
            blocks.append((offs[0], offs[-1] + size, index, subs[0], offs, subs, size))
            spans += [(off, off + size, index, sub) for off, sub in zip(offs, subs)]
        assert roundtrip._overlap(blocks, "input") == _ref_overlap(spans, "input")


def test_addresses_follow_the_first_writes_when_not_in_placement_order():
    # a container whose variables are written in another order than compile's: the
    # prediction looks their first writes up, and says the DCF will not round-trip
    c, _ = container.read((ROOT / "samples" / "plc.bin").read_bytes())
    nv = [k for k, e in enumerate(c.entries) if 0xA000 <= e[0] <= 0xAFFF and e[1]]
    assert len(nv) >= 2
    c.entries[nv[0]], c.entries[nv[1]] = c.entries[nv[1]], c.entries[nv[0]]
    res = convert(c, "plc.bin", dcf_name="plc.dcf")
    assert not res.roundtrip


def _read_or_error(data):
    try:
        c, warnings = container.read(data)
    except container.ContainerError as exc:
        return ("error", str(exc), exc.offset, exc.rule)
    return (c, [w.format() for w in warnings])


def test_index_read_without_bounds_checks_matches_the_checked_read(monkeypatch):
    rng = random.Random(9)
    base = (ROOT / "samples" / "plc.bin").read_bytes()
    offsets = dump.entry_offsets(container.read(base)[0])
    for _ in range(300):
        data = bytearray(base)
        for _ in range(rng.randrange(1, 3)):
            pos = rng.choice(offsets) + rng.randrange(0, 8)
            data[pos] = rng.randrange(256)
        data = bytes(data)
        fast = _read_or_error(data)
        with monkeypatch.context() as m:
            m.setattr(container, "_read_entries", lambda seg, count: None)
            checked = _read_or_error(data)
        assert fast == checked


def test_entry_offsets_in_bulk():
    rng = random.Random(2)
    for _ in range(50):
        c = _random_container(rng)
        h = dump.header_of(c)
        pos, want = h["index_offset"] + 4, []
        for _, _, data in c.entries:
            want.append(pos)
            pos += 7 + len(data)
        assert dump.entry_offsets(c, h) == want


@pytest.mark.parametrize("name", ["plc", "device", "bild8"])
def test_report_with_an_eds_matches_the_per_entry_rows(name):
    c, _ = container.read((ROOT / "samples" / f"{name}.bin").read_bytes())
    eds, _, _ = dump.load_eds(str(ROOT / "samples" / f"{name}.dcf"))
    h = dump.header_of(c)
    lines = dump.report(c, f"{name}.bin", eds=eds).splitlines()
    want = _ref_index_rows(c, h, eds, False)
    start = lines.index(want[0])
    assert lines[start:start + len(want)] == want
    if c.addresses:
        want_pi = _ref_address_rows(c, _ref_nv_keys(c), eds)
        start = lines.index(want_pi[0])
        assert lines[start:start + len(want_pi)] == want_pi

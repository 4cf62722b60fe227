"""The DynBuildOd model's shortcuts for large PLC containers (issue 22) answer as the slow
paths they skip: a shortcut may only say "nothing to find" when the slow path finds
nothing."""
from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dcf2bin.dynod import structure


def _brute(image, sizes, total):
    """What the byte-map loop decides: does any variable end beyond total or overlap?"""
    for i, (a, z) in enumerate(zip(image, sizes)):
        if total is not None and a + z > total:
            return False
        for b, y in zip(image[:i], sizes[:i]):
            if z and y and b < a + z and a < b + y:
                return False
    return True


@settings(max_examples=400, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 40), st.integers(0, 4)), max_size=12),
       st.one_of(st.none(), st.integers(0, 48)))
def test_placement_shortcut_never_hides_a_failure(vars_, total):
    # block by block (a few blocks of consecutive addresses), and in address order (as
    # many blocks as variables): either way, "clean" only where the byte map finds nothing
    image, sizes = [a for a, _ in vars_], [z for _, z in vars_]
    old = structure._FEW_BLOCKS
    for few in (old, 0):
        structure._FEW_BLOCKS = few
        try:
            if structure._clean(image, sizes, total):
                assert _brute(image, sizes, total)
        finally:
            structure._FEW_BLOCKS = old


def test_placement_shortcut_takes_ascending_runs():
    # a PLC's addresses: a few ascending runs (one per type and direction), no overlap
    image = list(range(100, 200)) + list(range(0, 100)) + list(range(200, 300, 2))
    sizes = [1] * 200 + [2] * 50
    assert structure._clean(image, sizes, 300)
    assert not structure._clean(image, sizes, 299)                  # the last ends at 300
    assert not structure._clean(image + [150], sizes + [1], None)   # byte 150 twice
    # blocks with gaps that other blocks fill, and blocks that touch
    assert structure._clean([0, 1, 10, 11, 5, 6, 20], [1, 1, 1, 9, 1, 4, 0], 20)
    assert not structure._clean([0, 1, 10, 11, 5, 6], [1, 1, 1, 9, 1, 5], None)


def _emulated(container, static, whole: bool):
    from dcf2bin.dynod import TargetOptions, emulate
    from dcf2bin.dynod.entries import _EntriesStep
    old = _EntriesStep._whole_objects
    _EntriesStep._whole_objects = whole
    try:
        out = emulate(container, TargetOptions(), static)
    finally:
        _EntriesStep._whole_objects = old
    od = out.od if out.ok else None
    return (repr(out), sorted((k, repr(v)) for k, v in od.items()) if od else None)


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data())
def test_whole_objects_at_once_equal_entry_by_entry(data):
    # compiled PLC DCFs, then one entry repeated, dropped or given another attribute byte:
    # the run that creates a whole object at once gives the outcome (code, reason, entry,
    # warnings, created objects, PDOs) and the OD of the entry-by-entry run
    import copy

    from test_dynod_random import build, plc_dcfs
    text, _ = data.draw(plc_dcfs())
    res, static = build(text)
    c = copy.deepcopy(res.container)
    k = data.draw(st.integers(0, len(c.entries) - 1))
    change = data.draw(st.sampled_from(["none", "repeat", "drop", "attr", "unmapped"]))
    attrs = bytearray(c.attributes)
    maps = [j for j, (i, s, d) in enumerate(c.entries)
            if (0x1600 <= i <= 0x17FF or 0x1A00 <= i <= 0x1BFF) and s and d != bytes(4)]
    if change == "unmapped" and maps:            # a mapped sub the created object lacks
        j = data.draw(st.sampled_from(maps))
        i, s, d = c.entries[j]
        c.entries[j] = (i, s, (int.from_bytes(d, "little") | 0xFE00).to_bytes(4, "little"))
    elif change == "repeat":
        c.entries.insert(k, c.entries[k])
        attrs.insert(k, attrs[k])
    elif change == "drop":
        del c.entries[k]
        del attrs[k]
    elif change == "attr":
        attrs[k] = data.draw(st.integers(0, 255))
    c.attributes = bytes(attrs)
    for s in (static, None):
        assert _emulated(c, s, True) == _emulated(c, s, False)


@settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data())
def test_addresses_of_wanted_variables_are_those_of_all(data):
    # the PDO results look up the mapped variables only: the same addresses as the dict
    # of every variable, restricted to them (asked for present and absent keys alike)
    from test_dynod_random import build, plc_dcfs

    from dcf2bin.dynod import TargetOptions, emulate
    text, _ = data.draw(plc_dcfs())
    res, static = build(text)
    engine = emulate(res.container, TargetOptions(), static)._engine
    every = engine.nv_addresses()
    assert every
    keys = sorted(every) + [(0xA000, 0x7F), (0x1000, 0)]
    wanted = set(data.draw(st.lists(st.sampled_from(keys), min_size=1)))
    assert engine.nv_ascending      # a compiled container: found by bisection
    assert engine.nv_addresses(wanted) == {k: v for k, v in every.items() if k in wanted}
    engine.nv_ascending = False     # as for keys in another order: by their objects
    assert engine.nv_addresses(wanted) == {k: v for k, v in every.items() if k in wanted}


def test_placement_shortcut_says_maybe_for_a_variable_inside_another():
    # a variable of 0 bytes inside another is no failure, but the shortcut only vouches
    # for variables that each end before the next starts: the byte map decides
    assert not structure._clean([0, 2], [4, 0], None)
    assert structure._clean([4, 0, 2], [2, 2, 2], 6)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([0x1000, 0x1A00, 0x9FFF, 0xA000, 0xA040, 0xAFFF,
                                           0xB000]), st.integers(0, 3)), max_size=14),
       st.booleans())
def test_first_occurrences_of_network_variables(keys, ascending):
    # ascending keys (a compiled container) take the shortcut; any order, repeats
    # included, gives the position of each variable's first occurrence
    if ascending:
        keys = sorted(set(keys))
    entries = [(i, s, b"") for i, s in keys]
    seen, expected = set(), []
    for p, (i, s, _) in enumerate(entries):
        if 0xA000 <= i <= 0xAFFF and s and (i, s) not in seen:
            seen.add((i, s))
            expected.append(p)
    assert structure.nv_firsts(entries)[0] == expected


@settings(max_examples=500, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([0x1000, 0x9FFF, 0xA000, 0xA040, 0xA041, 0xAFFF,
                                           0xB000]), st.integers(0, 3)), max_size=16),
       st.booleans())
def test_network_variables_ascend_run_by_run(keys, ascending):
    # the run-by-run shortcut says "ascending" exactly when the keys of the network
    # variables (sub 0 is none), in position order, ascend strictly: also across runs of
    # the same object split by another, and for an object written twice
    if ascending:
        keys = sorted(keys)     # repeats kept: a key twice does not ascend strictly
    entries = [(i, s, b"") for i, s in keys]
    nv = [(i << 8 | s, p) for p, (i, s, _) in enumerate(entries) if 0xA000 <= i <= 0xAFFF and s]
    strictly = all(a < b for (a, _), (b, _) in zip(nv, nv[1:]))
    positions, flag = structure.nv_firsts(entries)
    assert flag is strictly
    assert structure._ascending_runs(entries) == ([p for _, p in nv] if strictly else None)
    if strictly:
        assert positions == [p for _, p in nv]


def test_network_variables_ascend_across_a_split_object():
    # 0xA040 sub 1-2, another object, 0xA040 sub 3: ascending; sub 2 again: not
    split = [(0xA040, 0, b""), (0xA040, 1, b""), (0xA040, 2, b""), (0x1000, 0, b""),
             (0xA040, 3, b"")]
    assert structure.nv_firsts(split) == ([1, 2, 4], True)
    again = split[:4] + [(0xA040, 2, b""), (0xA040, 3, b"")]
    assert structure.nv_firsts(again) == ([1, 2, 5], False)

"""The DynBuildOd model's shortcuts for large PLC containers (issue 22) answer as the slow
paths they skip: a shortcut may only say "nothing to find" when the slow path finds
nothing."""
from __future__ import annotations

from hypothesis import given, settings
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
    image, sizes = [a for a, _ in vars_], [z for _, z in vars_]
    if structure._clean(image, sizes, total):
        assert _brute(image, sizes, total)


def test_placement_shortcut_takes_ascending_runs():
    # a PLC's addresses: a few ascending runs (one per type and direction), no overlap
    image = list(range(100, 200)) + list(range(0, 100)) + list(range(200, 300, 2))
    sizes = [1] * 200 + [2] * 50
    assert structure._clean(image, sizes, 300)
    assert not structure._clean(image, sizes, 299)                  # the last ends at 300
    assert not structure._clean(image + [150], sizes + [1], None)   # byte 150 twice

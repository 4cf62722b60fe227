"""One finding, one wording: what the container reader says (dump, bin2dcf, simulate) is
what validate's CNT rules say about the same bytes."""
from __future__ import annotations

import pytest

from conftest import ROOT
from dcf2bin import container
from dcf2bin.lint import Options, run

FIXTURES = sorted((ROOT / "tests" / "fixtures" / "lint").glob("CNT*.fail.bin"))


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.name)
def test_reader_and_validate_word_a_container_problem_alike(path):
    data = path.read_bytes()
    try:
        _, warns = container.read(data)
        said = [(w.rule, w.offset, w.message) for w in warns]
    except container.ContainerError as exc:
        said = [(exc.rule, exc.offset, str(exc))]
    if any(rule == "CNT011" for rule, _, _ in said):
        # the reader bounds the count by the bytes before reading entries (it never
        # allocates from an untrusted count); validate reads on and names the entry
        pytest.skip("CNT011: the reader and validate check different things")
    linted = {(d.rule, d.offset, d.message) for d in run([str(path)], Options()).diagnostics}
    assert set(said) <= linted


def test_truncated_container_words():
    data = (ROOT / "samples" / "bild8.bin").read_bytes()[:60]
    with pytest.raises(container.ContainerError) as info:
        container.read(data)
    assert str(info.value) == "header says 127 bytes, the file has 60 (truncated)"

"""One finding, one wording: what the container reader says (dump, bin2dcf, simulate) is
what validate's CNT rules say about the same bytes."""
from __future__ import annotations

import pytest

from conftest import ROOT
from dcf2bin import container
from dcf2bin.lint import Options, run

# CNT011 is left out on purpose: the reader bounds the entry count by the bytes before it
# reads entries (it never allocates from an untrusted count), while validate reads on and
# names the failing entry -- two different checks, so no common wording is claimed.
FIXTURES = sorted(p for p in (ROOT / "tests" / "fixtures" / "lint").glob("CNT*.fail.bin")
                  if not p.name.startswith("CNT011"))


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.name)
def test_reader_and_validate_word_a_container_problem_alike(path):
    data = path.read_bytes()
    try:
        _, warns = container.read(data)
        said = [(w.rule, w.offset, w.message) for w in warns]
    except container.ContainerError as exc:
        said = [(exc.rule, exc.offset, str(exc))]
    linted = {(d.rule, d.offset, d.message) for d in run([str(path)], Options()).diagnostics}
    assert set(said) <= linted


def test_truncated_container_words():
    data = (ROOT / "samples" / "bild8.bin").read_bytes()[:60]
    with pytest.raises(container.ContainerError) as info:
        container.read(data)
    assert str(info.value) == "header says 127 bytes, the file has 60 (truncated)"

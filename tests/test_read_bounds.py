"""What one DCF/EDS file is read into, and how many findings of one rule are kept (issue 26,
items 4 and 5): a section has at most ``ini.MAX_KEYS`` keys (DCF014), a file at most
``ini.MAX_SECTIONS`` sections (DCF015); what lies beyond is counted, not read, by the fast
and the exact reader alike. validate and compile keep the first ``diagnostics.LIMIT``
findings of one rule in one file and count the others in one finding.

Before: 5 million ``KeyNNNNNNN=1`` lines in one section (60 MB) ended validate in a
MemoryError (exit 70) at 4 GiB; 5.7 million sections likewise (benchmarks/README.md)."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from dcf2bin import ini
from dcf2bin.cli import main
from dcf2bin.compiler import compile_path
from dcf2bin.diagnostics import LIMIT, Capped, Diagnostic, Severity, Where, summarise
from dcf2bin.lint import Options, lint_bytes

HEAD = """[FileInfo]
FileName=t.eds
[DeviceInfo]
VendorName=v
"""


def run(*args):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def lint(data: bytes, name: str = "t.eds", **opts):
    return lint_bytes(name, data, Options(**opts)).diagnostics


def _both(text: str, monkeypatch, keys: int, sections: int, big: int | None = None):
    """(fast, exact) readings of ``text`` with the bounds lowered."""
    monkeypatch.setattr(ini, "MAX_KEYS", keys)
    monkeypatch.setattr(ini, "MAX_SECTIONS", sections)
    if big is not None:
        monkeypatch.setattr(ini, "_BIG", big)
    return ini._parse_fast(text, "t.dcf", "utf-8"), ini._parse_exact(text, "t.dcf", "utf-8")


def _reading(f: ini.IniFile):
    return ([d.format() for d in f.diagnostics], f.line_count,
            {c: (s.name, s.line, dict(s.values), {k: v.line for k, v in s.keys.items()})
             for c, s in f.sections.items()})


# -- the bounds, in both readers ----------------------------------------------------------------

def test_keys_beyond_the_bound_are_counted_not_read(monkeypatch):
    text = "[A]\n" + "".join(f"K{i}=v{i}\n" for i in range(8)) + "; c\n[B]\nx=1\n"
    # only a section of more than _BIG characters can have more than MAX_KEYS keys (see
    # the test below): with the bound lowered, so is _BIG
    fast, exact = _both(text, monkeypatch, keys=5, sections=10, big=20)
    assert fast is not None
    assert _reading(fast) == _reading(exact)
    assert _reading(fast)[0] == [
        "t.dcf:7: error: [A] (line 1) has 8 keys, more than the 5 a section may have: the "
        "3 from this line on are not read [DCF014]"]
    assert list(fast.sections["a"].values) == ["k0", "k1", "k2", "k3", "k4"]
    assert fast.sections["b"].line == 11


def test_only_a_section_read_in_the_file_can_have_too_many_keys():
    """The fast path counts keys in ``_Templates.big`` alone: a section of at most _BIG
    characters has fewer key lines than MAX_KEYS (the shortest is "k=" and a line end)."""
    assert ini._BIG // len("k=\n") < ini.MAX_KEYS


def test_repeated_keys_count_as_keys(monkeypatch):
    """A key repeated on every line: the repeats are counted too (each would be kept as a
    duplicate otherwise), and the first LIMIT repeats of the file are reported."""
    text = "[A]\n" + "x=1\n" * 9
    fast, exact = _both(text, monkeypatch, keys=5, sections=10)
    assert fast is None                       # a repeated key: the exact reader's
    assert [d.format() for d in exact.diagnostics] == [
        "t.dcf:7: error: [A] (line 1) has 9 keys, more than the 5 a section may have: the "
        "4 from this line on are not read [DCF014]"]
    assert [(d.key, d.first_line, d.line) for d in exact.duplicates] == [
        ("x", 2, 3), ("x", 2, 4), ("x", 2, 5), ("x", 2, 6)]


@pytest.mark.parametrize("head", ["", "; a comment\n\n"])
def test_sections_beyond_the_bound_are_counted_not_read(monkeypatch, head):
    text = head + "[A]\nx=1\n[B]\n[C]\n[D]\ny=2\n[E]\n[F]\nbad line\n[G]\n"
    fast, exact = _both(text, monkeypatch, keys=10, sections=4)
    assert fast is not None                  # the bad line is not read
    assert _reading(fast) == _reading(exact)
    first = 7 + head.count("\n")
    assert _reading(fast)[0] == [
        f"t.dcf:{first}: error: the file has 7 sections, more than the 4 a file may have: "
        "the 3 from this line on are not read [DCF015]"]
    assert list(fast.sections) == ["a", "b", "c", "d"]
    # the names as written are looked up in the text read, not beyond it
    assert fast.sections["d"].name == "D" and fast.sections["d"].keys["y"].line == first - 1


def test_repeated_sections_count_as_sections(monkeypatch):
    fast, exact = _both("[A]\n" * 7, monkeypatch, keys=10, sections=4)
    assert fast is None
    assert [d.format() for d in exact.diagnostics] == [
        "t.dcf:5: error: the file has 7 sections, more than the 4 a file may have: the 3 "
        "from this line on are not read [DCF015]"]
    assert len(exact.duplicates) == 3


def test_exact_reader_reads_lines_in_blocks():
    text = "a\n\nbb\r\nc\n" * 5 + "last"
    for block in (0, 1, 3, 7, 100):
        assert list(ini._split_lines(text, block)) == text.split("\n")
        assert list(ini._split_lines(text + "\n", block)) == (text + "\n").split("\n")



def test_the_fast_reader_cuts_sections_a_block_at_a_time(monkeypatch):
    # _Chunks gives the pieces of text.split("<nl>[") (a section of more than _BIG
    # characters as a _Big, the first one's '[' counted in), the first ``limit`` only,
    # and where the rest starts and how many sections it has; blocks of 5 characters
    from itertools import chain
    monkeypatch.setattr(ini, "_BIG", 5)
    texts = ["[A]\nx=1\n[B]\n[C]\ny=22222222\n[D]", "[A]", "[A]\n[", "[Abcdef]\n[B]",
             ";c\r\n[A]\r\n[Bcdefghij]\r\nk=1\r\n[C]\r\n"]
    for text in texts:
        nl = "\r\n" if "\r" in text else "\n"
        start = 1 if text[0] == "[" else text.find(nl + "[") + len(nl) + 1
        for limit in (1, 2, 3, 100):
            chunks = ini._Chunks(text, nl, start, limit)
            got = [(c.text[c.start:c.end], True) if type(c) is ini._Big else (c, False)
                   for c in chain.from_iterable(chunks.blocks())]
            parts = text[start:].split(nl + "[", limit)
            rest = parts.pop() if len(parts) > limit else None
            assert got == [(p, len(p) + (start == 1 and k == 0) > 5) for k, p in enumerate(parts)]
            assert chunks.count == len(parts)
            if rest is None:
                assert chunks.stop is None and chunks.unread is None
            else:
                assert text[chunks.stop:] == "[" + rest
                assert chunks.unread == rest.count(nl + "[") + 1


def test_the_lines_before_the_first_header_are_read_in_place(monkeypatch):
    # more than _BIG characters before the first header: looked at in the text, line by
    # line, as the lines of a shorter head are (a comment, a blank -- indented too; anything
    # else, or a lone CR or LF, is the exact reader's)
    monkeypatch.setattr(ini, "_BIG", 4)
    for nl in ("\n", "\r\n"):
        fast = ini._parse_fast(f";comment{nl}{nl}# more{nl}[A]{nl}x=1{nl}", "t.dcf", "utf-8")
        assert [(c, s.line, s.get("x")) for c, s in fast.sections.items()] == [("a", 4, "1")]
        for head in (f";comment{nl}k=1{nl}", f";com\rment{nl}", f"= ;x{nl}", f";comment{nl}[B{nl}"):
            assert ini._parse_fast(head + f"[A]{nl}x=1{nl}", "t.dcf", "utf-8") is None, head

# -- at the real bounds ------------------------------------------------------------------------

def test_a_section_of_65537_keys_is_one_error_in_validate_and_compile(tmp_path):
    """Fails before this change: the 65,537th key was read like the others (no error)."""
    keys = "".join(f"Key{i:07d}=1\n" for i in range(ini.MAX_KEYS + 1))
    p = tmp_path / "k.eds"
    p.write_text(HEAD + keys + "[ManufacturerObjects]\nSupportedObjects=0\n")
    # VendorName= and 65,537 more: the 65,537th key line of the section is line 65,540
    message = ("k.eds:65540: error: [DeviceInfo] (line 3) has 65,538 keys, more than the "
               "65,536 a section may have: the 2 from this line on are not read [DCF014]")
    r = run("validate", str(p))
    assert r.exit_code == 1
    assert message.replace("k.eds", str(p)) in r.output.splitlines()
    r = run("compile", str(p), "-o", str(tmp_path / "k.bin"))
    assert r.exit_code == 1 and not (tmp_path / "k.bin").exists()
    assert message.replace("k.eds", str(p)) in r.output.splitlines()


def test_the_section_bound_is_what_the_network_variable_area_holds():
    # 0xA000-0xAFFF: 4,096 arrays of 256 sections (the object, sub 0, 254 variables)
    assert ini.MAX_SECTIONS == 0x1000 * 256
    assert ini.MAX_KEYS == 0x10000                # one key per index of an object list


# -- findings of one rule: the first LIMIT, then one that counts the others --------------------

def _unknown_keys(n: int) -> bytes:
    return (HEAD + "".join(f"Key{i:05d}=1\n" for i in range(n))).encode()


def test_validate_keeps_the_first_1000_findings_of_a_rule_and_counts_the_others(tmp_path):
    diags = lint(_unknown_keys(LIMIT + 5))
    dcf050 = [d for d in diags if d.rule == "DCF050"]
    assert len(dcf050) == LIMIT + 1
    assert dcf050[-1].format() == (
        "t.eds:1005: warning: ... and 5 more DCF050 findings like this [DCF050]")
    assert dcf050[-1].more == 5 and dcf050[-2].line == 1004
    # every format counts them all; the text form still prints 20 and says how many more
    p = tmp_path / "t.eds"
    p.write_bytes(_unknown_keys(LIMIT + 5))
    doc = json.loads(run("validate", "-f", "json", str(p)).output)
    assert doc["summary"]["warnings"] == doc["files"][0]["warnings"] == LIMIT + 5 + 1
    assert len([d for d in doc["diagnostics"] if d["rule"] == "DCF050"]) == LIMIT + 1
    text = run("validate", str(p)).output.splitlines()
    assert f"{p}: note: 985 more DCF050 diagnostics left out (text output shows 20 per rule " \
           "and file)" in text
    # (DCF101 3 times and DCF108: the file has no mandatory objects)
    assert text[-1] == "3 errors, 1006 warnings, 0 infos in 1 file"


def test_one_left_out_is_shown_as_it_is():
    dcf050 = [d for d in lint(_unknown_keys(LIMIT + 1)) if d.rule == "DCF050"]
    assert len(dcf050) == LIMIT + 1 and dcf050[-1].more == 0
    assert dcf050[-1].message == "key 'Key01000' is not defined by CiA 306 for [DeviceInfo]"


def test_a_rule_the_core_reports_too_is_counted_once():
    """DCF200: the check and the selection report one bad ParameterValue each; past the
    limit the check's are counted, and the selection's at those lines are the same."""
    subs = "".join(f"[2000sub{s:X}]\nParameterName=v\nObjectType=0x7\nDataType=0x0005\n"
                   f"AccessType=rw\nParameterValue=0x1FF\n" for s in range(1, 255))
    objects = "".join(subs.replace("[2000", f"[{0x2000 + k:04X}") for k in range(4))
    mains = "".join(f"[{0x2000 + k:04X}]\nParameterName=a\nObjectType=0x8\nSubNumber=255\n"
                    for k in range(4))
    data = (HEAD + "[ManufacturerObjects]\nSupportedObjects=4\n1=0x2000\n2=0x2001\n3=0x2002\n"
            "4=0x2003\n" + mains + objects).encode()
    dcf200 = [d for d in lint(data) if d.rule == "DCF200"]
    assert len(dcf200) == LIMIT + 1
    assert dcf200[-1].message == "... and 16 more DCF200 findings like this"


def test_the_reader_keeps_the_first_1000_bad_lines(tmp_path):
    data = (HEAD + "bad line\n" * (LIMIT + 3)).encode()
    dcf002 = [d for d in lint(data) if d.rule == "DCF002"]
    assert [d.format() for d in dcf002[-2:]] == [
        "t.eds:1004: error: line without '=': 'bad line' [DCF002]",
        "t.eds:1005: error: ... and 3 more DCF002 findings like this [DCF002]"]
    p = tmp_path / "t.eds"
    p.write_bytes(data)
    r = run("compile", str(p), "-o", str(tmp_path / "t.bin"))
    assert r.exit_code == 1
    assert r.output.splitlines()[-1] == f"{p}: 1003 errors, nothing written"


def test_repeats_past_the_limit_stop_compile(tmp_path):
    """The repeats the reader only counts may touch an entry compile writes: the finding
    that counts them is an error of the whole file (the kept ones of an object compile
    does not write are warnings, as before)."""
    data = (HEAD + "[2000]\nParameterName=a\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\n"
            "DefaultValue=1\n" + "[3000]\n" * (LIMIT + 3)).encode()
    p = tmp_path / "t.eds"
    p.write_bytes(data)
    res = compile_path(str(p), select="all")
    assert not res.ok
    dcf010 = [d for d in res.diagnostics if d.rule == "DCF010"]
    assert [d.format() for d in dcf010[-2:]] == [
        f"{p}:1011: warning: section [3000] repeated (first at line 11) (not written by "
        "compile) [DCF010]",
        f"{p}:1012: error: ... and 2 more DCF010 findings like this [DCF010]"]
    assert len(dcf010) == LIMIT + 1


def test_compile_keeps_the_first_1000_findings_of_a_rule(tmp_path):
    subs = "".join(f"[3000sub{s:X}]\nParameterName=v\nObjectType=0x7\nAccessType=rw\n"
                   for s in range(1, 255))
    objects = "".join(subs.replace("[3000", f"[{0x3000 + k:04X}") for k in range(4))
    mains = "".join(f"[{0x3000 + k:04X}]\nParameterName=a\nObjectType=0x8\nSubNumber=255\n"
                    for k in range(4))
    p = tmp_path / "t.eds"
    p.write_text(HEAD + mains + objects)
    res = compile_path(str(p))
    dcf031 = [d for d in res.diagnostics if d.rule == "DCF031"]
    assert len(dcf031) == LIMIT + 1 and res.ok
    assert dcf031[-1].message == "... and 16 more DCF031 findings like this"
    assert dcf031[-1].severity is Severity.WARNING


# -- the collectors ----------------------------------------------------------------------------

def test_capped_keeps_the_first_of_each_rule_and_counts_the_others():
    c = Capped(limit=2)
    for i in range(5):
        c.error(f"e{i}", Where("f", i), rule="A")
        c.warning(f"w{i}", Where("f", 10 + i), rule="A")
    c.error("x", Where("g", 1), rule="A")
    assert [(d.message, d.line, d.more) for d in c] == [
        ("e0", 0, 0), ("w0", 10, 0), ("e1", 1, 0), ("w1", 11, 0),
        ("... and 3 more A findings like this", 2, 3),
        ("... and 3 more A findings like this", 12, 3), ("x", 1, 0)]
    assert sum(d.weight for d in c) == 11


def test_summarise_adds_the_counts_of_summaries():
    def d(line, more=0):
        return Diagnostic(Severity.INFO, f"m{line}", "f", line, rule="R", more=more)
    out = summarise([d(1), d(2), d(3, more=7), d(4)], limit=2)
    assert [(x.message, x.line, x.more) for x in out] == [
        ("m1", 1, 0), ("m2", 2, 0), ("... and 8 more R findings like this", 3, 8)]
    assert summarise([d(1), d(2)], limit=2) == [d(1), d(2)]

"""Building the model from INI text (SPEC §1)."""
from __future__ import annotations

import pytest

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import Where
from helpers import compile_text, load_text, messages


def problems(dev):
    return [p.diagnostic.format() for p in dev.problems]


def test_sub0_created_and_defaults():
    dev = load_text("[2000]\nObjectType=0x9\n[2000sub2]\nDataType=0x0005\nAccessType=rw\n"
                    "PDOMapping=1\n")
    e0 = dev.entry(0x2000, 0)
    assert (e0.dtype, e0.access, e0.default, e0.implicit, e0.pdo_mapping) == (
        dt.UNSIGNED8, "ro", "2", True, False)
    assert dev.entry(0x2000, 2).pdo_mapping


def test_array_without_subs_holds_only_sub0():
    dev = load_text("[2000]\nObjectType=0x8\n")
    assert list(dev.objects[0x2000].entries) == [0]
    assert dev.encode(dev.entry(0x2000, 0)) == b"\x00"


def test_sub_flags_inherit_from_object():
    dev = load_text("[2000]\nObjectType=0x8\nObjFlags=1\nPDOMapping=1\n"
                    "[2000sub1]\nDataType=0x0005\nAccessType=rw\n")
    e = dev.entry(0x2000, 1)
    assert (e.obj_flags, e.pdo_mapping) == (1, True)
    # a created sub 0 inherits neither (SPEC §1) ...
    assert (dev.entry(0x2000, 0).obj_flags, dev.entry(0x2000, 0).pdo_mapping) == (0, False)
    # ... an explicit sub 0 section inherits both, unless it says otherwise
    dev = load_text("[2000]\nObjectType=0x8\nObjFlags=1\nPDOMapping=1\n"
                    "[2000sub0]\nDefaultValue=1\n[2000sub1]\nDataType=0x0005\nAccessType=rw\n")
    assert (dev.entry(0x2000, 0).obj_flags, dev.entry(0x2000, 0).pdo_mapping) == (1, True)
    dev = load_text("[2000]\nObjectType=0x8\nObjFlags=1\nPDOMapping=1\n"
                    "[2000sub0]\nObjFlags=0\nPDOMapping=0\n")
    assert (dev.entry(0x2000, 0).obj_flags, dev.entry(0x2000, 0).pdo_mapping) == (0, False)


def test_compact_sub_obj_with_names_and_values():
    dev = load_text("[1016]\nParameterName=HB\nObjectType=0x8\nDataType=0x0007\nAccessType=rw\n"
                    "DefaultValue=0\nCompactSubObj=3\nParameterValue=9\n"
                    "[1016Name]\nNrOfEntries=1\n2=Node 2\n[1016Value]\nNrOfEntries=1\n2=0x20064\n")
    obj = dev.objects[0x1016]
    assert list(obj.entries) == [0, 1, 2, 3]
    assert dev.entry(0x1016, 0).default == "3"
    assert dev.entry(0x1016, 2).name == "Node 2"
    assert dev.entry(0x1016, 2).configured and not dev.entry(0x1016, 1).configured
    assert problems(dev) == ["test.dcf:8: warning: ParameterValue in [1016] of a CompactSubObj "
                             "object is ignored (use [1016Value]) [DCF025]"]
    # the sub-entries are built from one worked-out entry, each with lines of its own
    assert [(e.name, e.value_where.line) for e in obj.entries.values()] == [
        ("Highest sub-index supported", 1), ("HB1", 6), ("Node 2", 14), ("HB3", 6)]
    # each is where the object's section is (not the section it was built from: none)
    assert [(e.where, e.section) for e in obj.entries.values()] == [
        (Where("test.dcf", 1), None)] * 4


def test_compact_sub_obj_without_data_type_reports_every_sub_entry():
    dev = load_text("[2000]\nParameterName=P\nObjectType=0x8\nAccessType=rw\nCompactSubObj=2\n")
    assert problems(dev) == ["test.dcf:1: error: [2000] has no DataType [DCF031]"] * 2


def test_compact_pdo_creates_implicit_objects():
    dev = load_text("[DeviceInfo]\nCompactPDO=0x21\nNrOfRXPDO=1\nNrOfTXPDO=0\n"
                    "[1600]\nObjectType=0x9\n[1600sub0]\nDataType=0x0005\nAccessType=rw\n"
                    "ParameterValue=0\n", node_id=4)
    comm = dev.objects[0x1400]
    assert comm.implicit and list(comm.entries) == [0, 1, 6]
    assert dev.encode(comm.entries[0]) == b"\x06"
    assert dev.encode(comm.entries[1]) == (0x204).to_bytes(4, "little")
    assert not dev.objects[0x1600].implicit
    # the implicit comm object takes part in the PDO block of its configured mapping
    res = compile_text("[DeviceInfo]\nCompactPDO=0x01\nNrOfRXPDO=1\n"
                       "[1600]\nObjectType=0x9\n[1600sub0]\nDataType=0x0005\nAccessType=rw\n"
                       "ParameterValue=0\n", node_id=4)
    assert [(i, s, d.hex()) for i, s, d in res.container.entries] == [
        (0x1400, 1, "04020080"), (0x1600, 0, "00"), (0x1600, 0, "00"), (0x1400, 1, "04020000")]


def test_structural_errors():
    dev = load_text("[2000sub1]\nDataType=0x0005\n[2001]\nAccessType=rw\n"
                    "[2002]\nDataType=0x0099\nAccessType=rw\n[2003]\nDataType=0x0005\n"
                    "AccessType=rx\n")
    assert problems(dev) == [
        "test.dcf:1: error: [2000sub1] has no object section [2000] [DCF006]",
        "test.dcf:3: error: [2001] has no DataType [DCF031]",
        "test.dcf:6: error: [2002] unknown or unsupported DataType 0x0099 [DCF030]",
        "test.dcf:10: error: [2003] unknown AccessType 'rx' [DCF032]",
    ]


def test_node_id_sources():
    text = "[DeviceComissioning]\nNodeID=0x10\n[DeviceCommissioning]\nNodeID=5\n"
    dev = load_text(text)
    assert dev.node_id == 16
    assert problems(dev) == ["test.dcf:3: warning: both [DeviceComissioning] and "
                             "[DeviceCommissioning] present; [DeviceComissioning] wins [DCF011]"]
    assert load_text(text, node_id=7).node_id == 7
    assert load_text("[DeviceCommissioning]\nNodeID=012\n").node_id == 10   # octal
    assert problems(load_text("[DeviceComissioning]\nNodeID=128\n")) == [
        "test.dcf:2: error: NodeID 128 is outside 1..127 [DCF012]"]


def test_duplicate_touching_written_entry_is_error_else_warning():
    text = "[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=1\nParameterValue=2\n"
    assert messages(compile_text(text)) == [
        "test.dcf:5: error: key 'ParameterValue' repeated in [2000] (first at line 4) [DCF010]"]
    text = "[2000]\nDataType=0x0005\nAccessType=rw\nDefaultValue=1\nDefaultValue=2\n"
    res = compile_text(text)
    assert res.ok
    assert messages(res, "warning") == [
        "test.dcf:5: warning: key 'DefaultValue' repeated in [2000] (first at line 4) "
        "(not written by compile) [DCF010]",
        "test.dcf: warning: nothing is configured (no ParameterValue or DownloadFile, no "
        "network variable): the container holds no entries [DCF009]"]


def test_numeric_comment_is_ignored():
    res = compile_text("[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=5 ; five\n")
    assert [(i, s, d) for i, s, d in res.container.entries] == [(0x2000, 0, b"\x05")]
    assert messages(res, "warning") == [
        "test.dcf:4: warning: 0x2000sub0: comment '; five' after the number is ignored [DCF203]"]


def test_numeric_comment_warns_for_every_entry_that_has_it():
    """The encoding cache must not hide the warning of a second entry with the same text."""
    text = ("[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=5 ; five\n"
            "[2001]\nDataType=0x0005\nAccessType=rw\nParameterValue=5 ; five\n")
    res = compile_text(text)
    assert [(i, s, d) for i, s, d in res.container.entries] == [
        (0x2000, 0, b"\x05"), (0x2001, 0, b"\x05")]
    assert messages(res, "warning") == [
        "test.dcf:4: warning: 0x2000sub0: comment '; five' after the number is ignored [DCF203]",
        "test.dcf:8: warning: 0x2001sub0: comment '; five' after the number is ignored [DCF203]"]


def test_download_file(tmp_path):
    (tmp_path / "blob.bin").write_bytes(b"\x01\x02")
    dcf = tmp_path / "d.dcf"
    dcf.write_text("[2000]\nDataType=0x000F\nAccessType=rw\nDownloadFile=blob.bin\n")
    from dcf2bin.compiler import CompileOptions, compile_path
    res = compile_path(str(dcf), CompileOptions())
    assert res.container.entries == [(0x2000, 0, b"\x01\x02")]
    dcf.write_text("[2000]\nDataType=0x000F\nAccessType=rw\nDownloadFile=../etc/passwd\n")
    res = compile_path(str(dcf), CompileOptions())
    assert messages(res) == [f"{dcf}:4: error: DownloadFile '../etc/passwd' leaves the DCF's "
                             "folder [DCF202]"]


def test_entries_built_from_a_shared_template_keep_their_own_names():
    """Sub-sections that differ only in ParameterName and Denotation share the INI
    template; the model builds them from one worked-out entry, each with its names."""
    text = "[A4C0]\nObjectType=0x8\nSubNumber=4\n" + "".join(
        f"[A4C0sub{s}]\nParameterName=out{s}\nDataType=0x0005\nAccessType=rw\n"
        f"DefaultValue={7 if s == 3 else 0}\nPDOMapping=1\nDenotation=Valve {s}\n"
        for s in (1, 2, 3))
    dev = load_text(text)
    got = [(e.sub, e.name, e.denotation, e.default, e.access, e.pdo_mapping, e.where.line)
           for e in dev.objects[0xA4C0].entries.values()]
    assert got == [(0, "Highest sub-index supported", None, "3", "ro", False, 1),
                   (1, "out1", "Valve 1", "0", "rw", True, 4),
                   (2, "out2", "Valve 2", "0", "rw", True, 11),
                   (3, "out3", "Valve 3", "7", "rw", True, 18)]


def test_a_faulty_entry_in_a_shared_template_reports_itself_every_time():
    text = "[2000]\nObjectType=0x8\nSubNumber=3\n" + "".join(
        f"[2000sub{s}]\nParameterName=p{s}\nDataType=0x0099\nAccessType=rw\n"
        for s in (1, 2)) + "[3000]\nDataType=0x0005\nAccessType=rw\n"
    dev = load_text(text)
    sub1, sub2 = dev.objects[0x2000].entries[1].section, dev.objects[0x2000].entries[2].section
    assert sub1.rest is sub2.rest     # one template
    assert [p.diagnostic.format() for p in dev.problems] == [
        "test.dcf:6: error: [2000sub1] unknown or unsupported DataType 0x0099 [DCF030]",
        "test.dcf:10: error: [2000sub2] unknown or unsupported DataType 0x0099 [DCF030]"]


# -- the template path builds what the key-by-key path builds -----------------------------

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from dcf2bin import ini, model  # noqa: E402

_KEYS = {"DataType": ["0x0005", "0x0006", "0x0099", ""], "AccessType": ["rw", "ro", "bad"],
         "DefaultValue": ["0", "300"], "ParameterValue": ["5"], "PDOMapping": ["1", "0"],
         "ObjFlags": ["1", "x"], "LowLimit": ["0"], "ObjectType": ["0x7"]}
# a section's key lines (at most one value per key), as text in file order
_TEMPLATE = st.lists(st.sampled_from(sorted(_KEYS)), unique=True, max_size=5).flatmap(
    lambda keys: st.tuples(*(st.sampled_from(_KEYS[k]).map(lambda v, k=k: f"{k}={v}")
                             for k in keys)).map(list))


def _fields(dev: model.Device):
    return {(o.index, e.sub): (e.name, e.dtype, e.access, e.pdo_mapping, e.obj_flags,
                               e.default, e.param, e.download_file, e.low, e.high,
                               e.denotation, e.where, e.implicit)
            for o in dev.objects.values() for e in o.entries.values()}


@settings(max_examples=200, deadline=None)
@given(st.sampled_from([0x2000, 0xA040, 0xA4C0]), st.lists(_TEMPLATE, min_size=1, max_size=2),
       st.lists(st.tuples(st.integers(0, 1), st.integers(0, 5),
                          st.sampled_from([None, "", "Sig"])), min_size=1, max_size=6))
def test_template_path_equals_key_by_key_path(index, templates, subs):
    """The INI fast path shares templates (and the model builds entries from them);
    the exact reader shares nothing. Both must give the same entries and problems."""
    out = [f"[{index:04X}]", "ObjectType=0x8", "ObjFlags=0", "PDOMapping=1"]
    for s, (which, name_at, denotation) in enumerate(subs, 1):
        lines = list(templates[which % len(templates)])
        lines.insert(min(name_at, len(lines)), f"ParameterName=v{s}")
        if denotation is not None:
            lines.insert(min(5 - name_at, len(lines)), f"Denotation={denotation}{s}")
        out += [f"[{index:04X}sub{s:X}]"] + lines
    text = "\n".join(out) + "\n"
    fast = ini._parse_fast(text, "t.dcf", "utf-8")
    assert fast is not None      # clean lines, no key twice: the fast reader's case
    a, b = model.build(fast), model.build(ini._parse_exact(text, "t.dcf", "utf-8"))
    assert _fields(a) == _fields(b)
    assert [p.diagnostic.format() for p in a.problems] == [
        p.diagnostic.format() for p in b.problems]


from conftest import SAMPLES, corpus_params  # noqa: E402


def _fast_read_params():
    """The corpus files and samples that the INI fast path takes (decided at collection:
    the others go to the exact reader whole, so there is no template path to compare)."""
    out = []
    for param in corpus_params() + [pytest.param(p, id=p.name)
                                    for p in sorted(SAMPLES.glob("*.dcf"))]:
        path = param.values[0]
        if path is not None:
            text, encoding = ini.decode_bytes(path.read_bytes())
            if ini._parse_fast(text, str(path), encoding) is None:
                continue
        out.append(param)
    return out


@pytest.mark.parametrize("path", _fast_read_params())
def test_template_path_equals_key_by_key_path_on_real_files(path):
    text, encoding = ini.decode_bytes(path.read_bytes())
    a = model.build(ini._parse_fast(text, str(path), encoding))
    b = model.build(ini._parse_exact(text, str(path), encoding))
    assert _fields(a) == _fields(b)
    assert [p.diagnostic.format() for p in a.problems] == [
        p.diagnostic.format() for p in b.problems]


def test_entry_where_is_made_from_its_section_when_first_read(tmp_path):
    # the builder stores the file's path for the entries it builds from a template; their
    # ``where`` is the section's file:line, the same object each time it is read, and can
    # be set like any field; the repr is the dataclass's it always was
    from pathlib import Path

    from dcf2bin.diagnostics import Where
    text = ("[A040]\nParameterName=in\nObjectType=0x8\nSubNumber=3\n"
            "[A040sub1]\nParameterName=a\nDataType=0x0005\nAccessType=ro\n"
            "[A040sub2]\nParameterName=b\nDataType=0x0005\nAccessType=ro\n"
            "[A040sub3]\nParameterName=c\nDataType=0x0005\nAccessType=ro\n")
    dev = model.load("t.dcf", data=text.encode())
    e = dev.entry(0xA040, 2)
    assert e._where == "t.dcf"                  # built from the template of sub 1
    first = dev.entry(0xA040, 1)                # built from its own section: the same
    assert first._where == "t.dcf" and first.where == Where("t.dcf", 5)
    assert e.where == Where("t.dcf", 9) and e.where is e.where
    e.where = Where("u.dcf", 1)
    assert e.where == Where("u.dcf", 1)
    assert repr(dev.entry(0xA040, 1)).startswith(
        "Entry(index=41024, sub=1, name='a', dtype=DataType(")
    assert "where=Where(file='t.dcf', line=5), lines=None, implicit=False, section=" in repr(
        dev.entry(0xA040, 1))
    path = tmp_path / "p.dcf"                   # a path that is no str: made at once
    path.write_text(text)
    dev = model.load(Path(path))
    assert dev.entry(0xA040, 2)._where == Where(Path(path), 9)

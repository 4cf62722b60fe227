"""Issue 28 item 2 on real files: every CiA 311 file of ../shared/corpus/xdd converted both
ways, and every corpus EDS/DCF converted to CiA 311 and back, the model compared field by
field (tests/convert_compare.py). Skips with a reason without ../shared."""
from __future__ import annotations

import pytest
from click.testing import CliRunner
from conftest import ROOT, corpus_params
from convert_compare import differences

from dcf2bin import formats
from dcf2bin.cli import main
from dcf2bin.diagnostics import Severity

XDD = ROOT.parent / "shared" / "corpus" / "xdd"
needs_xdd = pytest.mark.skipif(
    not XDD.is_dir(), reason=f"CiA 311 corpus not found at {XDD} (a fresh clone without ../shared)")
CANOPEN = ["canopennode_example/DS301_profile.xpd", "canopeneditor/minimal_project.xdd",
           "canopeneditor/DSP302-NMTMaster.xpd", "canopeneditor/DS301_profile_old.xpd"]
# what a conversion said it cannot keep, and the names of the written file
WARNED = ("compact", "compactpdo", "implicit", "filename", "edsversion", "filerevision",
          "description", "lasteds")


def load(data: bytes, suffix: str):
    return formats.load(f"x.{suffix}", data=data)


def errors(dev) -> list[str]:
    return [p.diagnostic.format() for p in dev.problems
            if p.diagnostic.severity is Severity.ERROR]


@needs_xdd
@pytest.mark.parametrize("name", CANOPEN)
def test_each_cia311_file_to_eds_and_back(name):
    dev = formats.load(str(XDD / name))
    eds = load(formats.dump(dev, "eds").data, "eds")
    back = load(formats.dump(eds, "xdd").data, "xdd")
    assert errors(eds) == errors(back) == errors(dev) == []
    # an EDS holds every object but the CO_disabled ones, none of the specifics
    assert differences(dev, eds, skip_fields=WARNED, specifics=False) == []
    assert differences(dev, back, skip_fields=WARNED, specifics=False) == []
    # the specifics of the XDD written from the EDS: CiA 306's PDOMapping=1, nothing else
    assert {str(v) for v in back.specifics.values()} <= {"{'PDOmapping': 'optional'}"}
    assert not back.ini.disabled


@needs_xdd
@pytest.mark.parametrize("name", CANOPEN)
def test_each_cia311_file_to_cia311_keeps_everything(name):
    dev = formats.load(str(XDD / name))
    again = load(formats.dump(dev, "xdd").data, "xdd")
    assert differences(dev, again, skip_fields=("filename",)) == []
    assert sorted(again.ini.disabled) == sorted(dev.ini.disabled)   # CO_disabled, kept
    assert [p.diagnostic.rule for p in again.problems] == \
        [p.diagnostic.rule for p in dev.problems]


@needs_xdd
@pytest.mark.parametrize("name", CANOPEN)
def test_a_written_eds_validates_as_its_source_does(name, tmp_path):
    out = tmp_path / "x.eds"
    r = CliRunner().invoke(main, ["convert", str(XDD / name), "-o", str(out), "-q"])
    assert (r.exit_code, r.stderr) == (0, "")
    source = CliRunner().invoke(main, ["validate", str(XDD / name), "--select", "DCF"])
    written = CliRunner().invoke(main, ["validate", str(out), "--select", "DCF"])
    assert written.stdout.splitlines()[-1] == source.stdout.splitlines()[-1]


@needs_xdd
def test_the_xpd_to_eds_is_the_eds_canopeneditor_wrote_of_it():
    example = XDD / "canopennode_example"
    ours = load(formats.dump(formats.load(str(example / "DS301_profile.xpd")), "eds").data,
                "eds")
    theirs = formats.load(str(example / "DS301_profile.eds"))
    # the objects and every field alike; the header differs where each file names itself
    # and where CANopenEditor writes XML Schema's defaults out (RevisionNumber=0, ...)
    assert differences(ours, theirs, headers=()) == []


@needs_xdd
@pytest.mark.parametrize("name", ["ROS_CNPLC.xdd", "DefaultTemplate.xdd"])
def test_a_powerlink_file_is_not_converted(name, tmp_path):
    r = CliRunner().invoke(main, ["convert", str(XDD / "powerlink" / name), "-o",
                                  str(tmp_path / "x.eds")])
    assert r.exit_code == 1 and "XDD004" in r.stderr
    assert r.stderr.splitlines()[-1].endswith(": 1 error, nothing written")
    assert not (tmp_path / "x.eds").exists()


@pytest.mark.parametrize("path", corpus_params())
def test_every_corpus_file_to_cia311_and_back(path):
    data = path.read_bytes()
    dev = formats.load(str(path), data=data)
    if errors(dev):             # convert refuses such a file: nothing is written
        assert not formats.convert(data, str(path), "xdd").ok
        return
    for target, back, configured in (("xdd", "eds", False), ("xdc", "dcf", True)):
        written = formats.dump(dev, target)
        assert all(d.severity is Severity.WARNING for d in written.diagnostics)
        one = load(written.data, target)
        two = load(formats.dump(one, back).data, back)
        assert errors(one) == errors(two) == [], target
        skip = WARNED + (() if configured else ("param", "denotation", "node_id"))
        # DownloadFile has no CiA 311 form (CNV005)
        skip += ("download_file",)
        heads = ("deviceinfo", "dummyusage", "fileinfo") + (
            ("devicecomissioning",) if configured else ())
        for other in (one, two):
            found = differences(dev, other, skip_fields=skip, headers=heads, specifics=False)
            assert [d for d in found if not (not configured and _filled(dev, d))
                    and _sayable(d)] == []


def _sayable(line: str) -> bool:
    """Whether a difference is in what CiA 311 can say: an object, or a header key that
    has a CiA 311 attribute or element (any other is a CNV005 warning)."""
    from dcf2bin.formats.xdd.writer_header import COMMISSIONING, FILE_INFO, GENERAL, IDENTITY
    if not line.startswith("["):
        return True
    section, key = line[1:].split("] ")[0], line.split("] ")[1].split(":")[0]
    known = {k.lower() for k, _ in FILE_INFO} | {
        k.lower() for k, _, _ in IDENTITY + GENERAL + COMMISSIONING} | {
        "simplebootupmaster"} | {f"baudrate_{r}" for r in (10, 20, 50, 125, 250, 500, 800,
                                                             1000)}
    return section == "dummyusage" or key in known


def _filled(dev, line: str) -> bool:
    """A sub 0 that had a ParameterValue and no DefaultValue: without its ParameterValue
    (an EDS/XDD holds none) the reader counts the sub-entries, as for any such sub 0."""
    head, _, rest = line.partition(" default: None != ")
    if not rest or "sub" not in head:
        return False
    idx, sub = head[2:6], head.partition("sub")[2]
    e = dev.entry(int(idx, 16), int(sub, 16))
    return e is not None and e.param is not None

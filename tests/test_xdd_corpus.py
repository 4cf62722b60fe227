"""Issue 28: the real CiA 311 files of ../shared/corpus/xdd (MANIFEST.tsv): CANopenNode's
example trio, three CANopenEditor files, two Ethernet POWERLINK files as negatives."""
from __future__ import annotations

import pytest
from click.testing import CliRunner
from conftest import ROOT

from dcf2bin import formats
from dcf2bin.cli import main

XDD = ROOT.parent / "shared" / "corpus" / "xdd"
pytestmark = pytest.mark.skipif(
    not XDD.is_dir(), reason=f"CiA 311 corpus not found at {XDD} (a fresh clone without ../shared)")
EXAMPLE = XDD / "canopennode_example"
FIELDS = ("name", "dtype", "access", "pdo_mapping", "obj_flags", "default", "param", "low",
          "high", "denotation")
DISABLED = [0x1002, 0x1008, 0x1009, 0x100A, 0x100C, 0x100D, 0x1013, 0x1020, 0x1021, 0x1022,
            0x1023, 0x1024, 0x1025, 0x1026, 0x1027, 0x1028, 0x1029, 0x1201, 0x1404, 0x1604,
            0x1804, 0x1A04]


@pytest.mark.parametrize("name, objects", [
    ("canopennode_example/DS301_profile.xpd", 33), ("canopeneditor/minimal_project.xdd", 9),
    ("canopeneditor/DSP302-NMTMaster.xpd", 4), ("canopeneditor/DS301_profile_old.xpd", 29)])
def test_each_canopen_file_reads_without_a_reader_error(name, objects):
    dev = formats.load(str(XDD / name))
    assert len(dev.objects) == objects
    reader = [p.diagnostic for p in dev.problems if p.diagnostic.rule.startswith(("XDD", "DCF0"))]
    assert all(d.rule == "XDD020" for d in reader), [d.format() for d in reader]


@pytest.mark.parametrize("name, line", [("ROS_CNPLC.xdd", 176), ("DefaultTemplate.xdd", 203)])
def test_a_powerlink_xdd_is_one_line_and_never_misread(name, line):
    path = XDD / "powerlink" / name
    r = CliRunner().invoke(main, ["validate", str(path)])
    assert (r.exit_code, r.stdout) == (1, (
        f"{path}:{line}: error: an Ethernet POWERLINK device description (an ObjectList of "
        "Object elements), not a CANopen one; dcf2bin reads CANopen's CiA 311 XDD/XDC "
        "[XDD004]\n1 error, 0 warnings, 0 infos in 1 file\n"))
    assert formats.load(str(path)).objects == {}


def test_the_xpd_and_the_eds_canopeneditor_exported_from_it_are_the_same_objects():
    xpd = formats.load(str(EXAMPLE / "DS301_profile.xpd"))
    eds = formats.load(str(EXAMPLE / "DS301_profile.eds"))
    # The one difference in the objects: the 22 objects the .xpd marks CO_disabled are in
    # neither model -- CANopenEditor leaves them out of its EDS, dcf2bin out of the device
    # (one XDD020 line names them), and keeps their sections for a writer.
    assert sorted({int(c[:4], 16) for c in xpd.ini.disabled}) == DISABLED
    assert not set(DISABLED) & set(eds.objects)
    assert [p.diagnostic.rule for p in xpd.problems] == ["XDD020"]
    assert sorted(xpd.objects) == sorted(eds.objects)
    for idx, obj in xpd.objects.items():
        other = eds.objects[idx]
        assert (obj.name, obj.object_type, obj.sub_number) == \
            (other.name, other.object_type, other.sub_number), hex(idx)
        assert sorted(obj.entries) == sorted(other.entries), hex(idx)
        for sub, e in obj.entries.items():
            f = other.entries[sub]
            assert [getattr(e, k) for k in FIELDS] == [getattr(f, k) for k in FIELDS], \
                f"0x{idx:04X}sub{sub}"


def test_the_header_of_the_xpd_and_of_its_eds():
    xpd = formats.load(str(EXAMPLE / "DS301_profile.xpd")).ini
    eds = formats.load(str(EXAMPLE / "DS301_profile.eds")).ini
    info, other = xpd.section("deviceinfo").values, eds.section("deviceinfo").values
    assert {k: v for k, v in other.items() if k in info} == info
    # what the .xpd leaves to XML Schema's defaults (absent attributes), the EDS writes as 0
    assert {k: v for k, v in other.items() if k not in info} == {
        "revisionnumber": "0", "simplebootupmaster": "0", "simplebootupslave": "0",
        "dynamicchannelssupported": "0", "compactpdo": "0", "groupmessaging": "0"}
    assert xpd.section("dummyusage").values == eds.section("dummyusage").values
    # [FileInfo] differs by what each file says of itself: its name, and when it was written
    assert xpd.section("fileinfo").values["creationdate"] == \
        eds.section("fileinfo").values["creationdate"] == "11-23-2020"


def test_canopennodes_own_settings_and_the_descriptions_are_kept():
    dev = formats.load(str(EXAMPLE / "DS301_profile.xpd"))
    spec = dev.specifics[(0x1001, None)]
    assert (spec["CO_countLabel"], spec["PDOmapping"]) == ("EM", "TPDO")
    assert spec["description"].startswith("* bit 7: manufacturer specific\n* bit 6:")
    assert dev.specifics[(0x1017, None)]["CO_storageGroup"] == "PERSIST_COMM"


def test_the_xpd_and_its_eds_compile_to_the_same_container(tmp_path):
    out = []
    for name in ("DS301_profile.xpd", "DS301_profile.eds"):
        r = CliRunner().invoke(main, ["compile", str(EXAMPLE / name), "--entries", "all",
                                      "-n", "1", "-q", "-o", str(tmp_path / f"{name}.bin")])
        assert r.exit_code == 0, r.stderr
        out.append((tmp_path / f"{name}.bin").read_bytes())
    assert out[0] == out[1] and len(out[0]) == 982

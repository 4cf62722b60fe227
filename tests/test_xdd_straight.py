"""Issue 28 (speed): ``direct.Straight`` reads a CANopenEditor object in one pass and gives
its sections shared templates; it must give exactly what ``objects.Objects`` gives without
it -- sections, key lines, specifics, findings, the model -- and decline what it does not
take. And the DOCTYPE check, which now decodes 4 KiB first, still looks at 64 KiB."""
from __future__ import annotations

import pytest
from conftest import ROOT

from dcf2bin import formats
from dcf2bin.formats.xdd import direct, markup

XDD = ROOT.parent / "shared" / "corpus" / "xdd"
CANOPENEDITOR = ["canopennode_example/DS301_profile.xpd", "canopeneditor/minimal_project.xdd",
                 "canopeneditor/DSP302-NMTMaster.xpd", "canopeneditor/DS301_profile_old.xpd"]

# one object of each kind Straight takes or declines: plain, limits and a denotation (read
# through _Param), CO_disabled, a sub-object naming no parameter, a subIndex given twice,
# a subIndex of one digit, an attribute of another style (dataType); and one like the first
MIXED = b"""<?xml version="1.0" encoding="utf-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.1">
  <ISO15745Profile>
    <ProfileBody xmlns="" fileName="mixed.xdd">
      <ApplicationProcess>
        <parameterList>
          <parameter uniqueID="P1000" access="read"><label lang="en">Device type</label><UDINT /><defaultValue value="0x00000191" /></parameter>
          <parameter uniqueID="P2000" access="readWrite"><label lang="en">Speed</label><denotation><label lang="en">motor  speed</label></denotation><UINT /><defaultValue value="5" /><allowedValues><range><minValue value="1" /><maxValue value="9" /></range></allowedValues></parameter>
          <parameter uniqueID="P2001"><label lang="en">Off</label><UDINT /><property name="CO_disabled" value="true" /></parameter>
          <parameter uniqueID="P2002"><label lang="en">Rec</label><description lang="en">a record</description><dataTypeIDRef uniqueIDRef="T1" /></parameter>
          <parameter uniqueID="P200200"><label lang="en">Highest</label><USINT /><defaultValue value="1" /></parameter>
          <parameter uniqueID="P200201" access="readWrite"><label lang="en">Value</label><BITSTRING /></parameter>
        </parameterList>
        <dataTypeList><struct uniqueID="T1" name="rec" /></dataTypeList>
      </ApplicationProcess>
    </ProfileBody>
  </ISO15745Profile>
  <ISO15745Profile>
    <ProfileBody xmlns="">
      <ApplicationLayers>
        <CANopenObjectList>
          <CANopenObject index="1000" name="Device type" objectType="7" PDOmapping="no" uniqueIDRef="P1000" />
          <CANopenObject index="2000" objectType="7" PDOmapping="TPDO" uniqueIDRef="P2000" />
          <CANopenObject index="2001" name="Off" objectType="7" uniqueIDRef="P2001" />
          <CANopenObject index="2002" name="Rec" objectType="9" subNumber="2" uniqueIDRef="P2002">
            <CANopenSubObject subIndex="00" name="Highest" objectType="7" uniqueIDRef="P200200" />
            <CANopenSubObject subIndex="01" name="Value" objectType="7" PDOmapping="optional" uniqueIDRef="P200201" />
          </CANopenObject>
          <CANopenObject index="2003" name="Rec" objectType="9" uniqueIDRef="P2002">
            <CANopenSubObject subIndex="00" name="Highest" objectType="7" uniqueIDRef="P200200" />
            <CANopenSubObject subIndex="01" name="Lost" objectType="7" uniqueIDRef="PX" />
          </CANopenObject>
          <CANopenObject index="2004" name="Rec" objectType="9" uniqueIDRef="P2002">
            <CANopenSubObject subIndex="00" name="Highest" objectType="7" uniqueIDRef="P200200" />
            <CANopenSubObject subIndex="00" name="Again" objectType="7" uniqueIDRef="P200200" />
            <CANopenSubObject subIndex="1" name="Short" objectType="7" uniqueIDRef="P200201" />
          </CANopenObject>
          <CANopenObject index="2005" name="Typed" objectType="7" dataType="0007" uniqueIDRef="P1000" />
          <CANopenObject index="2006" name="Rec" objectType="9" uniqueIDRef="P2002">
            <CANopenSubObject subIndex="00" name="Highest" objectType="7" uniqueIDRef="P200200" />
          </CANopenObject>
        </CANopenObjectList>
      </ApplicationLayers>
    </ProfileBody>
  </ISO15745Profile>
</ISO15745ProfileContainer>
"""


def _section(sec) -> tuple:
    return (sec.name, sec.line, list(sec.values.items()),
            [(low, k.name, k.value, k.line) for low, k in sec.keys.items()],
            [(k, sec.get(k), sec.has(k), sec.line_of(k)) for k in [*sec.values, "none"]])


def _reading(data: bytes, name: str) -> tuple:
    doc = formats.read(data, name)
    dev = formats.build(formats.read(data, name))
    return ([(c, _section(s)) for c, s in doc.sections.items()],
            [(c, _section(s)) for c, s in doc.disabled.items()],
            list(doc.specifics.items()), doc.problems,
            [p.diagnostic.format() for p in dev.problems],
            [(i, s, e.name, e.dtype, e.access, e.pdo_mapping, e.default, e.low, e.high,
              e.denotation, str(e.where)) for i, o in sorted(dev.objects.items())
             for s, e in o.entries.items()])


def _without_straight(monkeypatch, data: bytes, name: str) -> tuple:
    with monkeypatch.context() as m:
        m.setattr(direct.Straight, "read", lambda self, el: False)
        return _reading(data, name)


def test_straight_gives_what_the_reader_gives_and_declines_what_it_does_not_take(monkeypatch):
    taken = []
    read = direct.Straight.read
    monkeypatch.setattr(direct.Straight, "read", lambda self, el: taken.append(read(self, el))
                        or taken[-1])
    fast = _reading(MIXED, "mixed.xdd")
    monkeypatch.undo()
    assert taken == [True, True, True, True, False, False, False, True] * 2     # (read twice)
    assert fast == _without_straight(monkeypatch, MIXED, "mixed.xdd")
    rules = sorted(p[5] for p in fast[3])
    assert rules == ["XDD010", "XDD013", "XDD014", "XDD020"]


@pytest.mark.skipif(not XDD.is_dir(), reason=f"CiA 311 corpus not found at {XDD}")
@pytest.mark.parametrize("name", CANOPENEDITOR)
def test_straight_reads_the_canopeneditor_files_as_the_reader_does(monkeypatch, name):
    data = (XDD / name).read_bytes()
    assert _reading(data, name) == _without_straight(monkeypatch, data, name)


def test_alike_sub_objects_share_one_template_as_a_dcfs_sections_do():
    doc = formats.read(MIXED, "mixed.xdd")
    one, two = doc.sections["2002sub0"], doc.sections["2006sub0"]
    assert one.rest is two.rest and one.param_name == two.param_name == "Highest"
    assert (one.line, two.line) == (26, 40)
    assert one.keys["datatype"].line == two.keys["datatype"].line == 11


def test_a_doctype_after_a_comment_longer_than_4_kib_is_still_refused():
    data = b"<?xml version='1.0'?>\n<!-- " + b"x" * 5000 + b" -->\n<!DOCTYPE a>\n<a/>"
    assert markup.doctype(data) == (
        "the file has a DOCTYPE; a CiA 311 description has no DOCTYPE, and dcf2bin expands "
        "no entity and fetches no DTD", 3)
    assert markup.doctype(data.replace(b"<!DOCTYPE a>", b"")) is None

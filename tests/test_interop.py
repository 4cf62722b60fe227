"""Model -> python-canopen ObjectDictionary."""
from __future__ import annotations

from conftest import SAMPLES
from dcf2bin import model


def test_plc_sample_to_canopen():
    dev = model.load(str(SAMPLES / "plc.dcf"))
    od = dev.to_canopen()
    assert od.node_id == 16
    assert od[0x1017].value == 1000 and od[0x1017].default == 0
    assert od[0x1017].data_type == 0x06 and od[0x1017].access_type == "rw"
    assert od[0x1800][1].value == 0x190          # $NODEID+0x180 with NodeID 0x10
    assert od[0x1600][5].value == 0xA0C00310          # RPDO1 receives the inputs
    assert od[0xA0C0][3].data_type == 0x03 and od[0xA0C0][3].pdo_mappable
    assert od[0xA0C0][0].default == 4
    assert sorted(od.indices) == sorted(i for i in dev.objects if i >= 0x1000)


def test_device_sample_types():
    od = model.load(str(SAMPLES / "device.dcf")).to_canopen()
    assert od[0x2001].value == -8388608           # INTEGER24 kept exact
    assert od[0x2004].value == 0xFFFFFFFFFFFF     # UNSIGNED48
    assert od[0x2002].value == 0.5
    assert od[0x2000].value == "Hall 3; rack #2"
    assert od[0x2003].value == b"\xde\xad\xbe\xef"
    assert od[0x1016][2].value == 0x000200C8      # CompactSubObj + [1016Value]


def test_a_latin1_file_gives_its_strings_to_canopen_as_written(tmp_path):
    # a DCF in Latin-1 (not valid UTF-8): the container holds the Latin-1 bytes, and
    # python-canopen gets the text those bytes are, not U+FFFD for each non-ASCII byte
    text = ("[1008]\nParameterName=Device name\nObjectType=0x7\nDataType=0x0009\n"
            "AccessType=const\nDefaultValue=Gr\xfc\xdfe\nParameterValue=Stra\xdfe\n")
    (tmp_path / "x.dcf").write_bytes(text.encode("latin-1"))
    dev = model.load(str(tmp_path / "x.dcf"))
    assert dev.encoding == "latin-1"
    od = dev.to_canopen()
    assert (od[0x1008].default, od[0x1008].value) == ("Gr\xfc\xdfe", "Stra\xdfe")

"""`network build` of a lely master against lely's dcfgen (SPEC §10.2a, D-21).

Each network of tests/fixtures/network/lely/ is built by dcf2bin and by ``dcfgen -rS``
(dcf-tools 2.4.2, the test extra; run as ros2_canopen runs it, tests/dcfgen_compare.py),
and the outputs are compared entry by entry: master.dcf as INI (object by object, the
UploadFile= paths left out), each .bin as a concise DCF (entry by entry, and the order of
the entries both write alike). Where dcfgen mirrors a slave PDO that dcf2bin does not,
its later master PDOs are numbered one further: RENUMBERED states that numbering, the
PDO only dcfgen has is one difference, and dcf2bin's master PDO n is compared with
dcfgen's PDO of the same slave PDO, entry by entry. Every difference must be listed in
EXPECTED with its reason, and every row of EXPECTED must still happen. Where dcfgen
stops with a traceback, the test asserts that it did and that dcf2bin builds.
"""
from __future__ import annotations

import fnmatch
import pathlib

import pytest

from dcf2bin.network.build import build_network
from dcfgen_compare import differences, have_dcfgen, run_dcfgen

HERE = pathlib.Path(__file__).resolve().parent
LELY = HERE / "fixtures" / "network" / "lely"
CORPUS = HERE.parent.parent / "shared" / "corpus" / "files"

# Why dcf2bin's outputs differ from dcfgen's (docs/network.md, "dcf2bin as dcfgen").
GIVEN = "D-18: every value the YAML gives is written; dcfgen skips one equal to the file's"
ORDER = ("D-18: the PDOs first, then 0x100C/0x100D/0x1017, the master's heartbeat "
         "consumer, time_cob_id (0x1012), error_behavior (0x1029), the sdo list; dcfgen "
         "writes 0x1016 first and 0x1012, 0x1017 and 0x1029 before the PDOs")
DISABLE = ("D-18: a PDO listed with enabled: false gets its COB-ID with bit 31 set even "
           "when its file already has it so")
AUTO = ("D-18: cob_id: auto of PDOs 5-8 takes the lowest free CAN-ID from 0x181; dcfgen "
        "counts from 0x680")
NODE_WINS = ("NET009: a key in both defaults: and the node is the node's for dcf2bin; "
             "ros2_canopen's cogen writes the default's over it")
MIRRORED = ("dcfgen is wrong: it mirrors a PDO that enabled: false disables (its "
            "file's COB-ID is valid), and numbers every later master PDO one further")
STRING_FALSE = ("dcfgen is wrong: enabled: \"false\" (a string) enables the PDO for dcfgen "
                "(Python's bool of a non-empty string); dcf2bin reads false")
COLLISION = ("dcfgen is wrong: its auto TPDO1 of node 5 is 0x185, which b's TPDO2 uses "
             "explicitly (two master RPDOs on one CAN-ID); dcf2bin takes a free ID")
REAL = "dcfgen is wrong: it writes the REAL32 value 1.5 as 1.0 (int() of the YAML value)"
SIZE = ("dcfgen is wrong: UNSIGNED24 and INTEGER40 are written with size 3 and 5 but 4 "
        "and 8 bytes of data, so the rest of its .bin cannot be read")
SERIAL = ("the master's own serial_number: dcfgen writes it in master.bin, into 0x1018 sub 4, "
          "which its master.dcf marks ro (a concise DCF that writes a read-only entry); "
          "dcf2bin states it as that entry's DefaultValue in master.dcf")
FILE_INFO = ("dcfgen writes no [FileInfo], which CiA 306 requires: dcf2bin's master.dcf "
             "has one (FileName, versions, no creation date: the same network builds the "
             "same bytes), so that validate --strict passes it (DCF060)")

# dcfgen's master PDO number -> dcf2bin's for the same slave PDO, where they differ
# (None: dcfgen mirrors a slave PDO that dcf2bin does not, the "dcfgen RPDOn (...)" row
# of EXPECTED says why); every other master PDO has the same number in both.
RENUMBERED = {
    "flat": {"TPDO": {2: None, 3: 2, 4: 3}},
    "dcfgen_wrong": {"RPDO": {2: None, 3: 2, 4: 3, 5: 4},
                     "TPDO": {2: None, 3: 2, 4: 3, 5: 4, 6: 5, 7: 6, 8: 7, 9: 8}},
    "plc-as-lely": {"TPDO": {2: None, 3: None, 4: None}},
}

EXPECTED = [
    ("flat", ("drive.bin 0x1400sub2", "drive.bin 0x1800sub2"), GIVEN),
    ("flat", ("drive.bin order",), ORDER),
    ("flat", ("io.bin 0x6126sub1",), REAL),
    ("flat", ("master.dcf dcfgen TPDO2 (node 2 RPDO2)",), MIRRORED),
    ("nodes", ("base.bin 0x1017sub0", "master.dcf 0x1016"), NODE_WINS),
    ("nodes", ("*.bin 0x1802sub1", "*.bin 0x1803sub1"), DISABLE),
    ("nodes", ("elbow.bin order", "wrist.bin order"), ORDER),
    ("anchors", ("*.bin 0x1800sub2",), GIVEN),
    ("anchors", ("*.bin order",), ORDER),
    ("pdo8", ("axis_?.bin 0x1[48]0[4-7]sub1", "master.dcf 0x1[48]0[4-7C-F]"), AUTO),
    ("pdo8", ("axis_?.bin 0x180[4-7]sub2",), GIVEN),
    ("both_ways", ("*.bin order",), ORDER),
    ("dcfgen_wrong", ("a.bin 0x1800sub1",), COLLISION),
    ("dcfgen_wrong", ("a.bin 0x1801sub1",), STRING_FALSE),
    ("dcfgen_wrong", ("c.bin unreadable",), SIZE),
    ("dcfgen_wrong", ("master.dcf 0x1400",), COLLISION + " (master RPDO1: a's TPDO1)"),
    ("dcfgen_wrong", ("master.dcf dcfgen RPDO2 (node 5 TPDO2)",), STRING_FALSE),
    ("dcfgen_wrong", ("master.dcf dcfgen TPDO2 (node 5 RPDO2)",), MIRRORED),
    ("plc", ("drive.bin 0x1400sub2", "drive.bin 0x1800sub2"), GIVEN),
    ("plc", ("drive.bin order",), ORDER),
    ("plc_nodes", ("*.bin order",), ORDER),
    # --master lely on the PLC file: dcfgen does not read the master's dcf: either
    ("plc-as-lely", ("drive.bin 0x1400sub2", "drive.bin 0x1800sub2"), GIVEN),
    ("plc-as-lely", ("drive.bin order",), ORDER),
    ("plc-as-lely", ("master.dcf dcfgen TPDO[234] (node 2 RPDO[234])",),
     MIRRORED + " (drive's RPDO2-4: its file's COB-IDs are valid)"),
    ("keys", ("cn.bin order",), ORDER),
    ("keys", ("master.dcf 0x1018", "master.bin 0x1018sub4"), SERIAL),
] + [(ident, ("master.dcf [[]FileInfo]",), FILE_INFO)    # (fnmatch: [[] is "[")
     for ident in ("flat", "nodes", "anchors", "pdo8", "both_ways", "dcfgen_wrong",
                   "plc-as-lely", "keys")]

# Where dcfgen stops: the last line of its traceback.
CRASHES = {
    "eds_key": "KeyError: 'dcf'",
    "event_deadline": ("UnboundLocalError: cannot access local variable 'event_timer' "
                       "where it is not associated with a value"),
}

# (id, file, --master, compare only the slaves' .bin: a PLC master is not dcfgen's)
NETWORKS = [
    ("flat", "flat.yml", None, False),
    ("nodes", "nodes.yml", None, False),
    ("anchors", "anchors.yml", None, False),
    ("pdo8", "pdo8.yml", None, False),
    ("both_ways", "both_ways.yml", None, False),
    ("dcfgen_wrong", "dcfgen_wrong.yml", None, False),
    ("eds_key", "eds_key.yml", None, False),
    ("event_deadline", "event_deadline.yml", None, False),
    ("plc", "plc.yml", None, True),
    ("plc_nodes", "plc_nodes.yml", None, True),
    ("plc-as-lely", "plc.yml", "lely", False),
    ("keys", "keys.yml", None, False),
]


def _skip_reason(network: pathlib.Path) -> str | None:
    if not have_dcfgen():
        return "dcfgen (dcf-tools, the test extra) is not installed"
    if "shared/corpus" in network.read_text() and not CORPUS.is_dir():
        return f"corpus not found at {CORPUS} (a fresh clone without ../shared)"
    return None


def _params():
    out = []
    for ident, name, kind, slaves_only in NETWORKS:
        reason = _skip_reason(LELY / name)
        marks = pytest.mark.skip(reason=reason) if reason else ()
        out.append(pytest.param(ident, LELY / name, kind, slaves_only, id=ident, marks=marks))
    return out


def _explained(ident: str, found: set[str]) -> tuple[set[str], list]:
    """The differences no row explains, and the rows that explain none."""
    rows = [r for r in EXPECTED if r[0] == ident]
    unexplained = {d for d in found
                   if not any(fnmatch.fnmatchcase(d, p) for _, pats, _ in rows for p in pats)}
    unused = [(pats, why) for _, pats, why in rows
              if not any(fnmatch.fnmatchcase(d, p) for d in found for p in pats)]
    return unexplained, unused


@pytest.mark.parametrize("ident,network,kind,slaves_only", _params())
def test_build_matches_dcfgen(ident, network, kind, slaves_only, tmp_path):
    res = build_network(str(network), master=kind)
    assert res.ok, [str(d) for d in res.diagnostics]
    assert res.mode == (kind or ("plc" if slaves_only else "lely"))
    ran = run_dcfgen(network, tmp_path)
    if ident in CRASHES:
        assert ran.returncode == 1
        assert ran.stderr.strip().splitlines()[-1] == CRASHES[ident]
        return
    assert ran.returncode == 0, ran.stderr
    # dcfgen writes no <slave>.dcf; dcf2bin does, for diff (docs/network.md, the table)
    dcfs = {s.name + ".dcf" for s in res.network.slaves}
    outputs = {k: v for k, v in res.outputs.items() if k not in dcfs}
    if slaves_only:
        slaves = {s.name + ".bin" for s in res.network.slaves}
        outputs = {k: v for k, v in outputs.items() if k in slaves}
        for p in tmp_path.iterdir():
            if p.name not in slaves:
                p.unlink()
    numbers: dict = {}
    found = {f"{name} {what}" for name, what in differences(outputs, tmp_path, numbers)}
    assert numbers == RENUMBERED.get(ident, {}), "dcfgen's master PDOs numbered otherwise"
    unexplained, unused = _explained(ident, found)
    assert unexplained == set(), "differences from dcfgen that EXPECTED does not explain"
    assert unused == [], "rows of EXPECTED that no longer happen"


def test_every_crash_and_expected_row_names_a_network():
    idents = {n[0] for n in NETWORKS}
    assert {r[0] for r in EXPECTED} <= idents
    assert set(CRASHES) <= idents
    assert set(RENUMBERED) <= idents


@pytest.mark.skipif(not have_dcfgen(), reason="dcfgen (dcf-tools, the test extra) is not "
                    "installed")
def test_a_wrong_master_pdo_after_the_shift_is_found(tmp_path):
    """flat: dcf2bin's master TPDO2 is dcfgen's TPDO3 (drive's RPDO3); an entry of it
    made wrong is a difference, not hidden by the renumbering -- nor is a PDO only
    dcf2bin mirrors."""
    res = build_network(str(LELY / "flat.yml"))
    assert run_dcfgen(LELY / "flat.yml", tmp_path).returncode == 0
    outputs = {k: v for k, v in res.outputs.items() if k not in ("drive.dcf", "io.dcf")}
    master = res.outputs["master.dcf"].decode()
    right = "[1A01Value]\nNrOfEntries=2\n1=0x22000110\n2=0x22010120\n"
    assert right in master
    outputs["master.dcf"] = master.replace(right, right.replace("0x22010120", "0x22010110")
                                           ).encode()
    assert ("master.dcf", "0x1A01") in differences(outputs, tmp_path)
    # drive's RPDO3 mirrored, in dcfgen's place of it, by a PDO of another slave
    outputs["master.dcf"] = master.replace("[5C01]\nParameterName=Remote RPDO number and "
                                           "node-ID\nDataType=0x0007\nAccessType=rw\n"
                                           "DefaultValue=0x00000302",
                                           "[5C01]\nParameterName=Remote RPDO number and "
                                           "node-ID\nDataType=0x0007\nAccessType=rw\n"
                                           "DefaultValue=0x00000303").encode()
    found = differences(outputs, tmp_path)
    assert {("master.dcf", "dcf2bin TPDO2 (node 3 RPDO3)"),
            ("master.dcf", "dcfgen TPDO3 (node 2 RPDO3)")} <= found

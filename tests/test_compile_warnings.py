"""compile and the problems of entries it does not write (SPEC "Errors vs warnings").

A value compile writes and cannot encode is an error (exit 1, nothing written); every
other DefaultValue/ParameterValue/DownloadFile is checked too and a problem there is a
warning worded as validate words it, plus "(not written by compile)", and the container
is still built. Also DCF419: a PDO mapping whose sub 0 gives no count (Elmo EDS style).
"""
from __future__ import annotations

from click.testing import CliRunner

from conftest import CORPUS, needs_corpus
from dcf2bin.cli import main

HEAD = "[DeviceComissioning]\nNodeID=5\n\n"   # lines 1-3

# line 4: [2000]; 8: its value line. [2001] (rw, configured) is always written.
TWO = """[2000]
ParameterName=Limit
DataType=0x0005
AccessType={access}
{key}=300

[2001]
ParameterName=Speed
DataType=0x0006
AccessType=rw
ParameterValue=7
"""


def run(*args):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def write(tmp_path, text, name="w.dcf"):
    path = tmp_path / name
    path.write_text(HEAD + text)
    return path


def lines(r):
    return r.stderr.splitlines()


def nothing(src):
    """compile's warning for a container without entries (these files configure nothing)."""
    return [f"{src}: warning: nothing is configured (no ParameterValue or DownloadFile, no "
            "network variable): the container holds no entries [DCF009]",
            "    hint: --entries all also writes every DefaultValue (the device's defaults)"]


def findings(r):   # validate prints its findings on standard output
    return r.stdout.splitlines()


def test_bad_value_of_an_unwritten_entry_is_a_warning(tmp_path):
    # ro and not configured: compile does not write 0x2000 -- a warning, exit 0, built
    src = write(tmp_path, TWO.format(access="ro", key="DefaultValue"))
    out = tmp_path / "w.bin"
    r = run("compile", str(src), "-o", str(out))
    assert r.exit_code == 0, r.output
    assert lines(r) == [f"{src}:8: warning: 0x2000sub0 DefaultValue: value 300 out of range "
                        "for UNSIGNED8 (0..255) (not written by compile) [DCF200]"]
    # the container holds the one written entry: 0x2001sub0 := 7 (UNSIGNED16 rw, 0x70)
    data = out.read_bytes()
    assert data[40:44] == b"\x01\x00\x00\x00"
    assert data[44:53] == bytes.fromhex("012000 02000000 0700".replace(" ", ""))
    # validate words it the same way (at its severity)
    v = run("validate", str(src))
    assert f"{src}:8: error: 0x2000sub0 DefaultValue: value 300 out of range for UNSIGNED8 " \
           "(0..255) [DCF200]" in findings(v)


def test_configured_ro_entry_is_not_written_either(tmp_path):
    src = write(tmp_path, TWO.format(access="ro", key="ParameterValue"))
    r = run("compile", str(src), "-o", str(tmp_path / "w.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:8: warning: 0x2000sub0 ParameterValue: value 300 out of range "
                        "for UNSIGNED8 (0..255) (not written by compile) [DCF200]"]


def test_the_same_value_in_a_written_entry_is_an_error(tmp_path):
    src = write(tmp_path, TWO.format(access="rw", key="ParameterValue"))
    out = tmp_path / "w.bin"
    r = run("compile", str(src), "-o", str(out))
    assert r.exit_code == 1
    assert lines(r) == [f"{src}:8: error: 0x2000sub0: value 300 out of range for UNSIGNED8 "
                        "(0..255) [DCF200]", f"{src}: 1 error, nothing written"]
    assert not out.exists()


def test_quiet_hides_the_warning(tmp_path):
    src = write(tmp_path, TWO.format(access="ro", key="DefaultValue"))
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "w.bin"))
    assert r.exit_code == 0 and r.stderr == ""


def test_default_value_behind_a_written_parameter_value(tmp_path):
    # 0x2001 is written with its ParameterValue; its DefaultValue never is
    text = TWO.format(access="ro", key="DefaultValue").replace(
        "DefaultValue=300", "DefaultValue=3").replace(
        "ParameterValue=7", "ParameterValue=7\nDefaultValue=0x10000")
    src = write(tmp_path, text)
    r = run("compile", str(src), "-o", str(tmp_path / "w.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:15: warning: 0x2001sub0 DefaultValue: value 0x10000 (= 65536) "
                        "out of range for UNSIGNED16 (0..65535) (not written by compile) "
                        "[DCF200]"]


def test_nodeid_values_not_written_must_fit_any_node_id(tmp_path):
    # no node-ID: an unwritten $NODEID value is fine when it fits node-IDs 1 and 127 ...
    text = TWO.format(access="ro", key="DefaultValue").replace("300", "$NODEID+0x80")
    src = tmp_path / "n.dcf"
    src.write_text(text)
    r = run("compile", str(src), "-o", str(tmp_path / "n.bin"))
    assert r.exit_code == 0 and r.stderr == ""
    # ... and a warning naming the node-ID it breaks for otherwise (never "needs a node-ID")
    src.write_text(text.replace("$NODEID+0x80", "$NODEID+0xF0"))
    r = run("compile", str(src), "-o", str(tmp_path / "n.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:5: warning: 0x2000sub0 DefaultValue: value $NODEID+0xF0 (= 367) "
                        "out of range for UNSIGNED8 (0..255) (with node-ID 127) (not written "
                        "by compile) [DCF200]"]


def test_compact_sub_obj_reports_its_one_line_once(tmp_path):
    text = ("[2100]\nParameterName=Table\nObjectType=0x8\nCompactSubObj=4\nDataType=0x0005\n"
            "AccessType=ro\nDefaultValue=0x100\n")
    src = write(tmp_path, text)
    r = run("compile", str(src), "-o", str(tmp_path / "c.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:10: warning: 0x2100sub1 DefaultValue: value 0x100 (= 256) out "
                        "of range for UNSIGNED8 (0..255) (not written by compile) [DCF200]"
                        ] + nothing(src)


def test_download_file_of_an_unwritten_entry(tmp_path):
    text = ("[2200]\nParameterName=Blob\nDataType=0x000F\nAccessType=ro\n"
            "DownloadFile=missing.bin\n")
    src = write(tmp_path, text)
    r = run("compile", str(src), "-o", str(tmp_path / "d.bin"))
    assert r.exit_code == 0
    assert lines(r) == [
        f"{src}:8: warning: cannot read DownloadFile 'missing.bin': No such file or directory "
        "(not written by compile) [DCF202]"] + nothing(src)


# -- DCF419: a PDO mapping that does not say how many objects it maps ---------------------

ELMO = """[1800]
ParameterName=TPDO1 communication parameter
ObjectType=0x9
[1800sub1]
ParameterName=COB-ID
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
{cob}
[1A00]
ParameterName=TPDO1 mapping parameter
ObjectType=0x9
[1A00sub0]
ParameterName=Number of mapped application objects in TPDO
DataType=0x0005
AccessType=rw
HighLimit=8
[1A00sub1]
ParameterName=Mapped object 1
DataType=0x0007
AccessType=rw
DefaultValue=0x60410010
[1A00sub2]
ParameterName=Mapped object 2
DataType=0x0007
AccessType=rw
DefaultValue=0
[6041]
ParameterName=Statusword
DataType=0x0006
AccessType=ro
PDOMapping=1
DefaultValue=0
"""
MSG = ("0x1A00sub0 has no DefaultValue or ParameterValue: the number of mapped objects is not "
       "given (the highest subindex present, 2, would be taken)")


def test_unstated_mapping_count_of_an_unwritten_pdo_is_a_warning(tmp_path):
    src = write(tmp_path, ELMO.format(cob=""))
    r = run("compile", str(src), "-o", str(tmp_path / "e.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:16: warning: {MSG} (not written by compile) [DCF419]"
                        ] + nothing(src)
    assert f"{src}:16: warning: {MSG} [DCF419]" in findings(run("validate", str(src)))


def test_unstated_mapping_count_of_a_written_pdo_is_an_error(tmp_path):
    src = write(tmp_path, ELMO.format(cob="ParameterValue=$NODEID+0x180"))
    out = tmp_path / "e.bin"
    r = run("compile", str(src), "-o", str(out))
    assert r.exit_code == 1 and not out.exists()
    assert lines(r) == [f"{src}:16: error: {MSG} [DCF419]", f"{src}: 1 error, nothing written"]
    # validate says it at the severity compile does
    v = run("validate", "--select", "DCF419", str(src))
    assert findings(v)[0] == f"{src}:16: error: {MSG} [DCF419]"
    # a mapping without any sub 0 section says it on the object's line
    src.write_text(HEAD + ELMO.format(cob="ParameterValue=$NODEID+0x180").replace(
        "[1A00sub0]\nParameterName=Number of mapped application objects in TPDO\n"
        "DataType=0x0005\nAccessType=rw\nHighLimit=8\n", ""))
    r = run("compile", str(src), "-o", str(out))
    assert lines(r)[0] == (f"{src}:13: error: PDO mapping 0x1A00 has no sub 0: the number of "
                           "mapped objects is not given (the highest subindex present, 2, "
                           "would be taken) [DCF419]")


def test_pdo_sequence_none_does_not_need_the_count(tmp_path):
    # that block writes the configured sub-entries only: sub 0 is not written, so a warning
    src = write(tmp_path, ELMO.format(cob="ParameterValue=$NODEID+0x180"))
    r = run("compile", "--pdo-sequence", "none", str(src), "-o", str(tmp_path / "e.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:16: warning: {MSG} (not written by compile) [DCF419]"]


# -- the corpus file that started it ------------------------------------------------------

SEVCON = CORPUS / "sevcon" / ("2019-06-13-ME0913-0705-0013-GEN4-110V-300A-PARINAUTES-"
                              "Ok-a-vide-19h39.dcf")


@needs_corpus
def test_sevcon_dcf_warns_about_values_it_does_not_write():
    # 0x5600 is ro: its ParameterValues ("0x..." for a DOMAIN, DCF218) are never written;
    # 0x4617sub1 (rw, configured) is written, its DefaultValue (line 18843) is not. Ten
    # written values lie outside their LowLimit/HighLimit (DCF212): warnings by default,
    # errors with --limit-check error. What stops this file is its TPDO on a CAN-ID CiA 301
    # restricts (TGT023), which the target itself refuses.
    r = run("compile", str(SEVCON), "-o", "/dev/null")
    got = [(ln.split(": ")[1], ln.split(":")[1], ln.endswith("(not written by compile) [DCF218]"))
           for ln in lines(r) if "[DCF218]" in ln]
    assert got == [("warning", "18838", False), ("warning", "18843", True)] + [
        ("warning", line, True) for line in
        ("22187", "22198", "22209", "22220", "22231", "22242", "22253", "22264")]
    written = ["1016", "1080", "1144", "1208", "1272", "1336", "1400", "1464", "18302", "18334"]
    assert [ln.split(":")[1] for ln in lines(r)
            if ": warning: " in ln and ln.endswith("[DCF212]")
            and "(not written by compile)" not in ln] == written
    errors = [ln for ln in lines(r) if ": error: " in ln]
    assert len(errors) == 1 and errors[0].endswith("[TGT023]") and r.exit_code == 1
    r = run("compile", "--limit-check", "error", str(SEVCON), "-o", "/dev/null")
    errors = [ln for ln in lines(r) if ": error: " in ln]
    assert [ln.split(":")[1] for ln in errors] == written
    assert all(ln.endswith("[DCF212]") for ln in errors) and r.exit_code == 1


def test_network_variable_default_behind_its_parameter_value(tmp_path):
    # group 1 writes every network variable with its effective value (the ParameterValue);
    # the DefaultValue behind it is not written: a warning. The same text as the written
    # value is an error.
    text = ("[A4C0]\nSubNumber=3\n[A4C0sub1]\nParameterName=a\nParameterValue=1\n"
            "DefaultValue=256\n[A4C0sub2]\nParameterName=b\n")
    src = write(tmp_path, text)
    r = run("compile", str(src), "-o", str(tmp_path / "nv.bin"))
    assert r.exit_code == 0
    assert lines(r) == [f"{src}:9: warning: 0xA4C0sub1 DefaultValue: value 256 out of range for "
                        "UNSIGNED8 (0..255) (not written by compile) [DCF200]"]
    src.write_text(HEAD + text.replace("ParameterValue=1\n", ""))
    r = run("compile", str(src), "-o", str(tmp_path / "nv.bin"))
    assert r.exit_code == 1
    assert lines(r)[0] == (f"{src}:8: error: 0xA4C0sub1: value 256 out of range for UNSIGNED8 "
                           "(0..255) [DCF200]")


def test_three_digit_subindex_section_is_named_by_compile_as_by_validate(tmp_path):
    # [2001sub001] is read as [2001sub1]: compile says so in validate's words (DCF061),
    # and the bytes are those of the canonical spelling
    body = ("[2001]\nParameterName=Rec\nObjectType=0x9\nSubNumber=2\n\n"
            "[2001sub0]\nParameterName=n\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\n\n"
            "[2001{sub}]\nParameterName=v\nDataType=0x0006\nAccessType=rw\n"
            "ParameterValue=7\n")
    odd = write(tmp_path, body.format(sub="sub001"), "odd.dcf")
    canon = write(tmp_path, body.format(sub="sub1"), "canon.dcf")
    r = run("compile", str(odd), "-o", str(tmp_path / "odd.bin"))
    assert r.exit_code == 0
    line = (f"{odd}:15: warning: [2001sub001] has a subindex of 3 digits; it is read as "
            "[2001sub1], the canonical spelling [DCF061]")
    assert lines(r) == [line, "    hint: a subindex has 1 or 2 hex digits: write the "
                              "canonical section name"]
    assert run("compile", str(canon), "-o", str(tmp_path / "canon.bin")).stderr == ""
    assert (tmp_path / "odd.bin").read_bytes() == (tmp_path / "canon.bin").read_bytes()
    v = run("validate", str(odd))
    assert [x for x in findings(v) if "DCF061" in x] == [line]


def test_both_ini_readers_note_a_respelled_section():
    # the fast reader keeps names lazily; both readers list the sections written otherwise
    from dcf2bin import ini
    text = "[2001]\nSubNumber=1\n\n[2001sub001]\nDataType=0x0005\n\n[2001sub02]\nX=1\n"
    assert ini.parse_bytes(text.encode(), "f").respelled == ["2001sub1", "2001sub2"]
    assert ini._parse_exact(text, "f").respelled == ["2001sub1", "2001sub2"]

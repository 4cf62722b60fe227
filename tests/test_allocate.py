"""dcf2bin allocate (SPEC.md §9.2, D-15): CSV -> DCF, standalone or merged into a DCF."""
from __future__ import annotations

import importlib.util
import json

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, assume, example, given, settings, strategies as st

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin.layout import TABLE_405

GOLDEN = ROOT / "tests" / "golden" / "plc"
HEADER = "name,type,direction\n"


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


def map_rows(path) -> dict[str, dict]:
    r = run("map", path, "-f", "json")
    assert r.exit_code == 0, r.stderr
    # the map writes indexes as "0xA4C0" strings; the tests compare numbers
    return {v["name"]: dict(v, index=int(v["index"], 16))
            for v in json.loads(r.stdout)["variables"]}


def test_bild8_standalone_golden_and_container(tmp_path):
    """Seed Bild 8 from its variable list: three UNSIGNED8 take bytes 0-2, the first
    UNSIGNED16 gets e = ceil(3/2) = 2 -> A580 sub 3 -> offset 4; compiled, the container is
    byte for byte samples/bild8.bin."""
    out = tmp_path / "bild8.alloc.dcf"
    r = run("allocate", GOLDEN / "bild8.vars.csv", "-o", out)
    assert r.exit_code == 0, r.stderr
    assert out.read_text() == (GOLDEN / "bild8.alloc.dcf").read_text()
    assert run("validate", "--strict", out).exit_code == 0
    binary = tmp_path / "b.bin"
    assert run("compile", out, "-o", binary).exit_code == 0
    assert binary.read_bytes() == (SAMPLES / "bild8.bin").read_bytes()
    rows = map_rows(out)
    assert [(v["index"], v["subindex"], v["offset"]) for v in rows.values()] == [
        (0xA4C0, 1, 0), (0xA4C0, 2, 1), (0xA4C0, 3, 2), (0xA580, 3, 4)]


def test_stdout_and_verbose():
    r = run("allocate", "-", "-v", input=HEADER + "x,0x0006,in\ny,BOOLEAN,OUT\n")
    assert r.exit_code == 0
    assert "[A100sub1]\nParameterName=x\n" in r.stdout
    assert "[A500sub1]\nParameterName=y\n" in r.stdout
    assert "FileName=allocated.dcf\n" in r.stdout
    assert r.stderr.splitlines() == ["x: 0xA100sub1, input offset 0",
                                     "y: 0xA500sub1, output offset 0"]


def test_csv_errors_at_their_lines(tmp_path):
    src = tmp_path / "bad.csv"
    src.write_text(HEADER + "ok,UNSIGNED8,input\n,UNSIGNED8,input\nOK,UNSIGNED8,output\n"
                   "t,UNSIGNED12,input\ns,VISIBLE_STRING,in\nd,UNSIGNED8,sideways\n"
                   "x,UNSIGNED8\n\nlast,REAL64,out\n")
    out = tmp_path / "out.dcf"
    r = run("allocate", src, "-o", out)
    assert r.exit_code == 1 and not out.exists()
    assert r.stderr.splitlines() == [
        f"{src}:3: error: empty name [ALC004]",
        f"{src}:4: error: name 'OK' repeats line 2 (names are compared without regard to "
        "case) [ALC005]",
        f"{src}:5: error: unknown data type 'UNSIGNED12' (a CiA 306 name such as UNSIGNED16, "
        "or a code such as 0x0006) [ALC006]",
        f"{src}:6: error: data type VISIBLE_STRING has no network-variable range (CiA 405 "
        "ranges exist for the integer types of 8 to 64 bits, BOOLEAN and REAL32) [ALC007]",
        f"{src}:7: error: direction 'sideways' must be input or output (in, out) [ALC008]",
        f"{src}:8: error: expected 3 fields (name, type, direction), found 2 [ALC001]",
        f"{src}:10: error: data type REAL64 has no network-variable range (CiA 405 ranges "
        "exist for the integer types of 8 to 64 bits, BOOLEAN and REAL32) [ALC007]",
        f"{src}: 7 errors, nothing written"]


def test_header_row_required(tmp_path):
    src = tmp_path / "h.csv"
    src.write_text("name,direction,type\nx,in,UNSIGNED8\n")
    r = run("allocate", src)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [f"{src}:1: error: the first line must be the header row "
                                     "'name,type,direction' [ALC001]",
                                     f"{src}: 1 error, nothing written"]


def test_a_kind_fills_its_0x40_indices_exactly(tmp_path):
    """16,256 UNSIGNED8 outputs fill A4C0..A4FF; one more is an error at its line."""
    n = 0x40 * 254
    src = tmp_path / "full.csv"
    src.write_text(HEADER + "".join(f"v{i},UNSIGNED8,out\n" for i in range(n)))
    out = tmp_path / "full.dcf"
    assert run("allocate", src, "-o", out).exit_code == 0
    rows = map_rows(out)
    assert (rows["v0"]["index"], rows["v0"]["subindex"]) == (0xA4C0, 1)
    last = rows[f"v{n - 1}"]
    assert (last["index"], last["subindex"], last["offset"]) == (0xA4FF, 254, n - 1)
    src.write_text(src.read_text() + "one_more,UNSIGNED8,out\n")
    r = run("allocate", src, "-o", tmp_path / "over.dcf")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}:{n + 2}: error: 'one_more': the UNSIGNED8 outputs do not fit their 0x40 "
        "indices 0xA4C0-0xA4FF (this is element 16256; there are 16256) [ALC002]",
        f"{src}: 1 error, nothing written"]


# -- --into --------------------------------------------------------------------------------------

MERGE_CSV = HEADER + ("DigIn_2,UNSIGNED8,in\nNewIn,UNSIGNED8,input\nSpeed,INTEGER16,input\n"
                      "Flag,BOOLEAN,output\nDigOut_3,UNSIGNED8,out\n")


def _crlf_latin1_base(tmp_path):
    text = (SAMPLES / "plc.dcf").read_text().replace("; Small PLC", "; Kleine SPS für Öl",
                                                     1)
    base = tmp_path / "base.dcf"
    base.write_bytes(text.replace("\n", "\r\n").encode("latin-1"))
    return base


def test_into_keeps_every_other_line(tmp_path):
    base = _crlf_latin1_base(tmp_path)
    csv = tmp_path / "m.csv"
    csv.write_text(MERGE_CSV)
    out = tmp_path / "merged.dcf"
    r = run("allocate", csv, "--into", base, "-o", out, "-v")
    assert r.exit_code == 0, r.stderr
    assert r.stderr.splitlines() == [
        "DigIn_2: 0xA040sub2 (kept)",
        "NewIn: 0xA040sub9, input offset 8",       # used = 8 bytes of inputs: e = 8
        "Speed: 0xA0C0sub6, input offset 10",      # used = 9: e = ceil(9/2) = 5
        "Flag: 0xA500sub9, output offset 8",       # used = 8 bytes of outputs
        "DigOut_3: 0xA4C0subA, output offset 9"]
    old = base.read_bytes().decode("latin-1").split("\r\n")
    new = out.read_bytes().decode("latin-1").split("\r\n")
    assert "\n" not in out.read_bytes().decode("latin-1").replace("\r\n", "")   # CRLF only

    def sub(section, name, code, access):
        return ["", f"[{section}]", f"ParameterName={name}", "ObjectType=0x7",
                f"DataType={code}", f"AccessType={access}", "PDOMapping=1"]
    # by line number of the base (1-based): the lines that change, and what follows a line
    changed = {48: "SupportedObjects=10", 316: "SubNumber=6", 323: "DefaultValue=9",
               361: "SubNumber=4", 368: "DefaultValue=6", 390: "SubNumber=4",
               397: "DefaultValue=10"}
    after = {57: ["10=0xA500"],
             356: sub("A040sub9", "NewIn", "0x0005", "ro"),        # after [A040sub4]
             385: sub("A0C0sub6", "Speed", "0x0003", "ro"),        # after [A0C0sub4]
             414: sub("A4C0subA", "DigOut_3", "0x0005", "rw")}     # after [A4C0sub2]
    for line, text in changed.items():
        assert old[line - 1].split("=")[0] == text.split("=")[0]
    expect = []
    for i, line in enumerate(old[:-1], 1):
        expect.append(changed.get(i, line))
        expect += after.get(i, [])
    expect += ["", "[A500]", "ParameterName=BOOLEAN outputs 0xA500", "ObjectType=0x8",
               "SubNumber=2", "", "[A500sub0]", "ParameterName=Highest sub-index supported",
               "ObjectType=0x7", "DataType=0x0005", "AccessType=ro", "DefaultValue=9",
               "PDOMapping=0"] + sub("A500sub9", "Flag", "0x0001", "rw") + [""]
    assert new == expect
    assert out.read_bytes().startswith(b"; Kleine SPS f\xfcr \xd6l configuration")  # Latin-1
    rows = map_rows(out)
    assert {k: (v["index"], v["subindex"], v["offset"]) for k, v in rows.items()
            if k in ("DigIn_2", "NewIn", "Speed", "Flag", "DigOut_3")} == {
        "DigIn_2": (0xA040, 2, 1), "NewIn": (0xA040, 9, 8), "Speed": (0xA0C0, 6, 10),
        "Flag": (0xA500, 9, 8), "DigOut_3": (0xA4C0, 10, 9)}
    v = run("validate", out)
    assert v.exit_code == 0, v.stdout


def test_into_a_dcf_without_network_variables_is_standalone_layout(tmp_path):
    base = tmp_path / "dev.dcf"
    base.write_bytes((SAMPLES / "device.dcf").read_bytes())
    csv = tmp_path / "v.csv"
    csv.write_bytes((GOLDEN / "bild8.vars.csv").read_bytes())
    out = tmp_path / "o.dcf"
    assert run("allocate", csv, "--into", base, "-o", out).exit_code == 0
    rows = map_rows(out)
    assert [(v["index"], v["subindex"], v["offset"]) for v in rows.values()] == [
        (0xA4C0, 1, 0), (0xA4C0, 2, 1), (0xA4C0, 3, 2), (0xA580, 3, 4)]
    old = base.read_bytes().split(b"\n")
    new = out.read_bytes().split(b"\n")
    assert old[41] == b"SupportedObjects=4" and new[41] == b"SupportedObjects=6"
    assert new[:41] == old[:41] and new[42:46] == old[42:46]
    assert new[46:48] == [b"5=0xA4C0", b"6=0xA580"]           # [OptionalObjects]
    assert new[48:48 + len(old) - 47] == old[46:-1]           # up to the end of the base
    assert new[48 + len(old) - 47:][:3] == [b"", b"[A4C0]", b"ParameterName=UNSIGNED8 outputs "
                                            b"0xA4C0"]


def test_into_dynamic_channels_is_an_error(tmp_path):
    base = tmp_path / "dyn.dcf"
    base.write_text("[FileInfo]\nFileName=dyn.dcf\n\n[DynamicChannels]\nNrOfSeg=1\n"
                    "Type1=0x0005\nDir1=ro\nRange1=0xA900-0xA93F\n")
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "x,UNSIGNED8,in\n")
    r = run("allocate", csv, "--into", base)
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr.splitlines() == [
        f"{base}:4: error: the DCF has a [DynamicChannels] section: its segments fix the "
        "layout, so variables cannot be allocated by the CiA 405 ranges [ALC003]",
        f"{csv}: 1 error, nothing written"]


def test_into_existing_name_with_another_type(tmp_path):
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "x,UNSIGNED8,in\ndigin_1,INTEGER8,in\n")
    r = run("allocate", csv, "--into", SAMPLES / "plc.dcf")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{csv}:3: error: 'digin_1' is already in {SAMPLES / 'plc.dcf'} as 0xA040sub1, "
        "UNSIGNED8 input, not INTEGER8 input [ALC003]",
        f"{csv}: 1 error, nothing written"]


def test_into_latin1_base_rejects_a_name_it_cannot_hold(tmp_path):
    base = _crlf_latin1_base(tmp_path)
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "Druck \u2192 Ventil,UNSIGNED8,in\n")
    r = run("allocate", csv, "--into", base)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{csv}:2: error: 'Druck \u2192 Ventil' cannot be written in the latin-1 encoding of "
        "the DCF [ALC003]",
        f"{csv}: 1 error, nothing written"]


def test_never_overwrites_its_inputs(tmp_path):
    base = tmp_path / "b.dcf"
    base.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "x,UNSIGNED8,in\n")
    r = run("allocate", csv, "--into", base, "-o", base)
    assert r.exit_code == 2
    assert base.read_bytes() == (SAMPLES / "plc.dcf").read_bytes()


# -- property: allocate -> compile -> map puts every variable where D-15 says ----------------------

KINDS = sorted({t.name for t, _ in TABLE_405.values()})
RANGE = {(t.name, d): first for first, (t, d) in TABLE_405.items()}
SIZE = {t.name: t.size for t, _ in TABLE_405.values()}


def expected_d15(variables):
    """D-15 written out again, independently: name -> (index, sub, offset)."""
    out = {}
    for area in ("input", "output"):
        kinds = []
        for _, t, d in variables:
            if d == area and t not in kinds:
                kinds.append(t)
        used = 0
        for t in kinds:
            s = SIZE[t]
            e = (used + s - 1) // s
            mine = [n for n, tt, d in variables if d == area and tt == t]
            for j, name in enumerate(mine):
                x = e + j
                out[name] = (RANGE[(t, area)] + x // 254, x % 254 + 1, x * s)
            used = (e + len(mine)) * s
    return out


def first_past_the_range(variables, want):
    """[(name, type, area, element)]: the first variable of each type and area that D-15
    puts past its type's 0x40 indices (254 elements each), inputs first, in list order."""
    first = {}                              # a type's first variable: the order of its error
    for k, (_, t, d) in enumerate(variables):
        first.setdefault((t, d), k)
    seen, full = set(), []
    for n, t, d in variables:
        index, sub, _ = want[n]
        if (t, d) not in seen and index - RANGE[(t, d)] >= 0x40:
            seen.add((t, d))
            full.append((n, t, d, (index - RANGE[(t, d)]) * 254 + sub - 1))
    return sorted(full, key=lambda f: (f[2] != "input", first[(f[1], f[2])]))


variable_lists = st.lists(
    st.tuples(st.sampled_from(KINDS), st.sampled_from(["input", "output"]),
              st.integers(1, 600)),
    min_size=1, max_size=6).map(
    lambda groups: [(f"v{i}_{j}", t, d) for i, (t, d, n) in enumerate(groups)
                    for j in range(n)])


def _interleave(variables, seed):
    import random
    shuffled = list(variables)
    random.Random(seed).shuffle(shuffled)
    return shuffled


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(variables=variable_lists, seed=st.integers(0, 1000))
@example(variables=[(f"v{i}_{j}", t, "input") for i, (t, n) in enumerate(
    [("INTEGER64", 158), ("INTEGER64", 600), ("BOOLEAN", 593), ("INTEGER64", 600),
     ("INTEGER64", 600)]) for j in range(n)], seed=0)
def test_property_allocate_compile_map(tmp_path, variables, seed):
    variables = _interleave(variables, seed)
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "".join(f"{n},{t},{d}\n" for n, t, d in variables))
    dcf = tmp_path / "v.dcf"
    r = run("allocate", csv, "-o", dcf)
    want = expected_d15(variables)
    full = first_past_the_range(variables, want)
    if full:
        # the types' process-image bytes are shared: a type placed after larger ones can run
        # past its 0x40 indices even with few variables of its own (16,256 elements)
        line = {n: i + 2 for i, (n, _, _) in enumerate(variables)}
        assert r.exit_code == 1
        assert r.stderr.splitlines() == [
            f"{csv}:{line[n]}: error: '{n}': the {t} {area}s do not fit their 0x40 indices "
            f"0x{RANGE[(t, area)]:04X}-0x{RANGE[(t, area)] + 0x3F:04X} (this is element {x}; "
            f"there are 16256) [ALC002]" for n, t, area, x in full] + [
            f"{csv}: {len(full)} error{'s' if len(full) > 1 else ''}, nothing written"]
        assert not dcf.exists()
        return
    assert r.exit_code == 0, r.stderr
    bin_ = tmp_path / "v.bin"
    r = run("compile", dcf, "-o", bin_)
    assert r.exit_code == 0, r.stderr
    rows = map_rows(bin_.with_suffix(".dcf"))
    assert {n: (v["index"], v["subindex"], v["offset"]) for n, v in rows.items()} == want
    # no two variables of one area share a byte
    for area in ("input", "output"):
        spans = sorted((v["offset"], v["offset"] + v["size"]) for v in rows.values()
                       if v["direction"] == area)
        assert all(a[1] <= b[0] for a, b in zip(spans, spans[1:]))
    # and the container's PI addresses are the map's
    from_bin = run("map", bin_, "--eds", dcf, "-f", "json")
    assert {v["name"]: v["address"] for v in json.loads(from_bin.stdout)["variables"]} == \
        {n: v["address"] for n, v in rows.items()}


HAS_TARGET = importlib.util.find_spec("dcf2bin.dynod") is not None


@pytest.mark.skipif(not HAS_TARGET, reason="needs dcf2bin.dynod")
@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(variables=variable_lists)
def test_property_target_builds_the_od(tmp_path, variables):
    from dcf2bin.dynod import TargetOptions, emulate
    csv = tmp_path / "v.csv"
    csv.write_text(HEADER + "".join(f"{n},{t},{d}\n" for n, t, d in variables))
    dcf = tmp_path / "v.dcf"
    assume(not first_past_the_range(variables, expected_d15(variables)))   # the test above
    assert run("allocate", csv, "-o", dcf).exit_code == 0
    from dcf2bin.compiler import CompileOptions, compile_path
    res = compile_path(str(dcf), CompileOptions())
    assert res.ok
    assert emulate(res.container, TargetOptions()).code == 0     # kCopSuccessful


@settings(max_examples=50, deadline=None)
@given(groups=st.lists(st.tuples(st.sampled_from(KINDS), st.sampled_from(["input", "output"]),
                                 st.integers(1, 16256)), min_size=1, max_size=4))
def test_property_up_to_the_index_limit(groups):
    """The library alone, with counts up to a whole range: allocate places every variable
    where D-15 (written out again here) puts it, and fails exactly when an element lies
    beyond the type's 0x40 indices, naming the first variable that does not fit."""
    from dcf2bin.plc.allocate import AllocationError, Var, allocate
    from dcf2bin import datatypes as dt
    variables = [(f"v{i}_{j}", t, d) for i, (t, d, n) in enumerate(groups) for j in range(n)]
    want = expected_d15(variables)
    kind = {n: (t, d) for n, t, d in variables}
    over = [n for n in kind if want[n][0] - RANGE[kind[n]] >= 0x40]     # in list order
    vs = [Var(n, dt.BY_NAME[t], d, k + 2) for k, (n, t, d) in enumerate(variables)]
    if not over:
        placed = allocate(vs, "v.csv")
        assert {p.var.name: (p.index, p.sub, p.offset) for p in placed} == want
    else:
        with pytest.raises(AllocationError) as exc:
            allocate(vs, "v.csv")
        firsts = {}
        for n in over:                     # the first one of each kind that does not fit
            firsts.setdefault(kind[n], n)
        assert sorted(dg.message.split("'")[1] for dg in exc.value.diagnostics) == \
            sorted(firsts.values())


def test_a_name_with_a_control_character_and_an_empty_file(tmp_path):
    src = tmp_path / "c.csv"
    src.write_text(HEADER + "a\tb,UNSIGNED8,in\n")
    r = run("allocate", src)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}:2: error: name 'a\\tb' holds a control character [ALC004]",
        f"{src}: 1 error, nothing written"]
    src.write_text("")
    r = run("allocate", src)
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}: error: empty file: expected the header row 'name,type,direction' [ALC001]",
        f"{src}: 1 error, nothing written"]

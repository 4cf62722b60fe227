"""Property tests of the DynBuildOd emulation (SPEC §8, D-11): containers compiled from
random valid PLC DCFs simulate to 0x00 with the PDOs the DCF configures; a single mutation
of a mapping entry, a COB-ID or a PI field gives the code (and entry) the model predicts."""
from __future__ import annotations

import copy

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from dcf2bin import model
from dcf2bin.compiler import CompileOptions, compile_device
from dcf2bin.dynod import StaticOD, TargetOptions, emulate
from dcf2bin.dynod import codes as C

# (range index, DataType code, bits) -- CiA 405 (SPEC §2.1)
INPUTS = [(0xA040, 0x05, 8), (0xA0C0, 0x03, 16), (0xA100, 0x06, 16), (0xA200, 0x07, 32),
          (0xA080, 0x01, 8)]
OUTPUTS = [(0xA4C0, 0x05, 8), (0xA540, 0x03, 16), (0xA680, 0x07, 32), (0xA500, 0x01, 8)]


@st.composite
def plc_dcfs(draw):
    node = draw(st.integers(1, 127))
    kinds = {}      # (index, code, bits) -> (first sub, last sub, access)
    for pool, access in ((INPUTS, "ro"), (OUTPUTS, "rw")):
        used = 0    # kinds of one area share its bytes: allocate as the configurator does
        for k in draw(st.lists(st.sampled_from(pool), min_size=1, max_size=3, unique=True)):
            size, n = k[2] // 8, draw(st.integers(1, 6))
            e = -(-used // size)
            kinds[k] = (e + 1, e + n, access)
            used = (e + n) * size
    text = [f"[DeviceComissioning]\nNodeID={node}\n"]
    for (idx, code, _), (lo, hi, access) in sorted(kinds.items()):
        text.append(f"[{idx:04X}]\nParameterName=V{idx:04X}\nObjectType=0x8\n"
                    f"SubNumber={hi - lo + 2}\n\n[{idx:04X}sub0]\nParameterName=n\n"
                    f"ObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue={hi}\n")
        for s in range(lo, hi + 1):
            text.append(f"[{idx:04X}sub{s:X}]\nParameterName=V{idx:04X}_{s}\nObjectType=0x7\n"
                        f"DataType=0x{code:04X}\nAccessType={access}\nPDOMapping=1\n")
    pdos = []
    for base, cob_base, pool in ((0x1400, 0x200, INPUTS), (0x1800, 0x180, OUTPUTS)):
        vars_ = [(k[0], s, k[2]) for k, (lo, hi, _) in sorted(kinds.items()) if k in pool
                 for s in range(lo, hi + 1)]
        for k in range(draw(st.integers(0, 3))):
            chosen = draw(st.lists(st.sampled_from(vars_), min_size=1, max_size=8, unique=True))
            mapped, total = [], 0
            for v in chosen:
                if total + v[2] <= 64:
                    mapped.append(v)
                    total += v[2]
            comm = base + k
            pdos.append((comm, cob_base + 0x100 * k + node, mapped))
            text.append(
                f"[{comm:04X}]\nParameterName=C\nObjectType=0x9\nSubNumber=3\n\n"
                f"[{comm:04X}sub0]\nParameterName=n\nObjectType=0x7\nDataType=0x0005\n"
                f"AccessType=ro\nDefaultValue=2\n\n[{comm:04X}sub1]\nParameterName=COB\n"
                f"ObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x80000000\n"
                f"ParameterValue=$NODEID+0x{cob_base + 0x100 * k:X}\n\n[{comm:04X}sub2]\n"
                f"ParameterName=T\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\n"
                f"ParameterValue=255\n")
            m = comm + 0x200
            text.append(f"[{m:04X}]\nParameterName=M\nObjectType=0x9\nSubNumber={len(mapped) + 1}"
                        f"\n\n[{m:04X}sub0]\nParameterName=n\nObjectType=0x7\nDataType=0x0005\n"
                        f"AccessType=rw\nParameterValue={len(mapped)}\n")
            for j, (idx, s, bits) in enumerate(mapped, 1):
                text.append(f"[{m:04X}sub{j:X}]\nParameterName=E\nObjectType=0x7\n"
                            f"DataType=0x0007\nAccessType=rw\n"
                            f"ParameterValue=0x{idx << 16 | s << 8 | bits:08X}\n")
    return "\n".join(text), pdos


def build(text: str):
    dev = model.load("random.dcf", data=text.encode())
    res = compile_device(dev, CompileOptions())
    assert res.ok, [d.format() for d in res.diagnostics if d.severity.value == "error"]
    static = StaticOD.from_device(dev, res.selection.created)
    return res, static


SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(plc_dcfs())
def test_compiled_plc_dcfs_simulate_to_success(case):
    text, pdos = case
    res, static = build(text)
    for s in (static, None):                       # with the DCF, and as a container alone
        out = emulate(res.container, TargetOptions(), s)
        assert (out.code, out.reason) == (C.OK, "")
        got = [(p.comm_index, p.cob_id, [(i, sub, b) for i, sub, b, _ in p.mapped])
               for p in out.pdos]
        assert got == [(comm, cob, mapped) for comm, cob, mapped in sorted(pdos)]
        for p in out.pdos:
            for idx, sub, _, addr in p.mapped:
                assert addr == res.layout.address(idx, sub)


MUTATIONS = ["length", "index", "restricted", "duplicate", "pi_total", "pi_memory",
             "pi_address"]


@SETTINGS
@given(plc_dcfs(), st.sampled_from(MUTATIONS), st.data())
def test_one_mutation_gives_the_predicted_code(case, mutation, data):
    text, _ = case
    res, static = build(text)
    c = copy.deepcopy(res.container)
    entries = c.entries
    opts = TargetOptions()
    maps = [k for k, (i, s, d) in enumerate(entries)
            if (0x1600 <= i <= 0x17FF or 0x1A00 <= i <= 0x1BFF) and s and int.from_bytes(d,
                                                                                      "little")]
    enables = [k for k, (i, s, d) in enumerate(entries)
               if (0x1400 <= i <= 0x15FF or 0x1800 <= i <= 0x19FF) and s == 1
               and not int.from_bytes(d, "little") & 0x80000000]
    if mutation == "length":
        assume(maps)
        k = data.draw(st.sampled_from(maps))
        i, s, d = entries[k]
        v = int.from_bytes(d, "little")
        entries[k] = (i, s, (v & ~0xFF | (v & 0xFF) + 8).to_bytes(4, "little"))
        expected = (C.PDO_MAPPING, k + 1)
    elif mutation == "index":
        assume(maps)
        k = data.draw(st.sampled_from(maps))
        i, s, d = entries[k]
        v = int.from_bytes(d, "little")
        entries[k] = (i, s, (0x3000 << 16 | v & 0xFFFF).to_bytes(4, "little"))
        expected = (C.INDEX_NOT_EXIST, k + 1)
    elif mutation == "restricted":
        assume(enables)
        k = data.draw(st.sampled_from(enables))
        i, s, _ = entries[k]
        entries[k] = (i, s, data.draw(st.integers(0x701, 0x77F)).to_bytes(4, "little"))
        expected = (C.ILLEGAL_CAN_ID, k + 1)
    elif mutation == "duplicate":
        # the enable of a later PDO takes the CAN-ID of an earlier valid one of its direction
        pairs = [(a, b) for a in enables for b in enables
                 if a < b and (entries[a][0] < 0x1800) == (entries[b][0] < 0x1800)]
        assume(pairs)
        a, b = data.draw(st.sampled_from(pairs))
        i, s, _ = entries[b]
        entries[b] = (i, s, entries[a][2])
        expected = (C.COB_EXISTS, b + 1)
    elif mutation == "pi_total":
        c.pi = (c.pi[0] - 1,) + tuple(c.pi[1:])
        expected = (C.INVALID_CONFIG, None)
    elif mutation == "pi_memory":
        opts = TargetOptions(pi_size=c.pi[0] - 1)
        expected = (C.NO_MEMORY, None)
    else:
        nv = []
        seen = set()
        for k, (i, s, _) in enumerate(entries):
            if 0xA000 <= i <= 0xAFFF and s and (i, s) not in seen:
                seen.add((i, s))
                nv.append(k)
        j = data.draw(st.integers(0, len(nv) - 1))
        c.addresses = list(c.addresses)
        c.addresses[j] = c.pi[0]                   # starts at the end of the image
        expected = (C.INVALID_CONFIG, nv[j] + 1)
    out = emulate(c, opts, static)
    assert (out.code, out.entry) == expected, out.reason
    if expected[1] is not None:
        assert out.index == entries[expected[1] - 1][0]

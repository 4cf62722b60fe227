"""Value texts to bytes and back (dcf2bin.values, SPEC §1 and §4)."""
from __future__ import annotations

import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dcf2bin.datatypes import BY_CODE, BY_NAME
from dcf2bin.values import (NeedsNodeId, ValueProblem, decode, encode, eval_int, parse_int,
                            hex_prefix, split_numeric_comment, to_python, uses_nodeid,
                            zero)

T = BY_NAME
FIXED = [t for t in BY_CODE.values() if t.size is not None]
INTEGER_LIKE = [t for t in BY_CODE.values() if t.kind in ("sint", "uint", "time")]


def problem(dtype, text, **kw) -> str:
    with pytest.raises(ValueProblem) as info:
        encode(dtype, text, **kw)
    return str(info.value)


# ---------------------------------------------------------------------------------------
# Integer literals

@pytest.mark.parametrize("text, value", [
    ("0", 0), ("10", 10), ("+10", 10), ("-10", -10), (" 42\t", 42),
    ("0x10", 16), ("0X1f", 31), ("-0x10", -16), ("+0x10", 16),
    ("012", 10), ("-010", -8), ("00", 0), ("-0", 0), ("0777", 511),
    ("18446744073709551615", 2**64 - 1),
])
def test_parse_int(text, value):
    assert parse_int(text) == value


@pytest.mark.parametrize("text, message", [
    ("08", "invalid octal literal '08'"),
    ("-09", "invalid octal literal '-09'"),
    ("0128", "invalid octal literal '0128'"),
    ("0x", "invalid hex literal '0x'"),
    ("0xG1", "invalid hex literal '0xG1'"),
    ("1_000", "invalid integer '1_000'"),
    ("1.0", "invalid integer '1.0'"),
    ("--1", "invalid integer '--1'"),
    ("- 1", "invalid integer '- 1'"),
    ("1 2", "invalid integer '1 2'"),
    ("\u0661", "invalid integer '\u0661'"),  # ARABIC-INDIC DIGIT ONE: int() would take it
    ("", "missing integer value"),
    ("$NODEID", "$NODEID is not allowed here: '$NODEID'"),
    ("1" * 5000, "integer literal too long (5000 digits, at most 64)"),
])
def test_parse_int_errors(text, message):
    with pytest.raises(ValueProblem) as info:
        parse_int(text)
    assert str(info.value) == message


@pytest.mark.parametrize("text, result", [
    ("0x10", (16, True)), ("0XFF", (255, True)), ("+0xFF", (255, True)),  # SPEC: "no -"
    ("-0x10", (-16, False)), ("16", (16, False)), ("020", (16, False)), ("-020", (-16, False)),
])
def test_eval_int_bit_pattern_flag(text, result):
    assert eval_int(text, None) == result


@pytest.mark.parametrize("text", [
    "$NODEID+0x180", "$nodeid+0x180", "$NodeId + 0x180", "$NODEID\t+\t384",
    "0x180+$NODEID", "0x180 + $nodeid", "384+$NODEID", "0600 + $NODEID", " $NODEID+0x180 ",
])
def test_nodeid_formulas(text):
    assert uses_nodeid(text)
    assert eval_int(text, 5) == (0x185, False)


def test_nodeid_bare():
    assert eval_int("$NODEID", 127) == (127, False)
    assert eval_int("$nodeid", 1) == (1, False)


@pytest.mark.parametrize("text", [
    "$NODEID-1", "$NODEID+", "+$NODEID", "$NODEID+-1", "$NODEID+0x1+1", "$NODEID+$NODEID",
    "2*$NODEID", "$NODEID 0x180", "$ NODEID", "0x180+$NODEID+1",
])
def test_nodeid_bad_formulas(text):
    with pytest.raises(ValueProblem) as info:
        eval_int(text, 5)
    assert not isinstance(info.value, NeedsNodeId)
    assert "$NODEID formula" in str(info.value) or "invalid" in str(info.value)


def test_nodeid_bad_formula_message():
    with pytest.raises(ValueProblem) as info:
        eval_int("$NODEID-1", 5)
    assert str(info.value) == ("invalid $NODEID formula '$NODEID-1' "
                               "(expected $NODEID, $NODEID+N or N+$NODEID)")
    with pytest.raises(ValueProblem) as info:
        eval_int("$NODEID+08", 5)
    assert str(info.value) == "invalid octal literal '08'"


def test_needs_nodeid():
    with pytest.raises(NeedsNodeId) as info:
        eval_int("$NODEID+0x180", None)
    assert str(info.value) == ("'$NODEID+0x180' uses $NODEID but no node-ID is known "
                               "(give --node-id or [DeviceComissioning] NodeID)")
    with pytest.raises(NeedsNodeId):
        encode(T["UNSIGNED32"], "0x200 + $NODEID")
    with pytest.raises(NeedsNodeId):
        encode(T["BOOLEAN"], "$NODEID")
    # A malformed formula is a plain ValueProblem, node-ID or not.
    with pytest.raises(ValueProblem) as info:
        eval_int("$NODEID-1", None)
    assert not isinstance(info.value, NeedsNodeId)


def test_uses_nodeid():
    assert uses_nodeid("$NODEID") and uses_nodeid("x$nOdEiDy")
    assert not uses_nodeid("NODEID") and not uses_nodeid("0x180")


def test_nodeid_encode_and_range():
    assert encode(T["UNSIGNED32"], "$NODEID+0x180", node_id=0x7F) == b"\xff\x01\x00\x00"
    assert encode(T["UNSIGNED8"], "$NODEID", node_id=0x22) == b"\x22"
    assert problem(T["UNSIGNED8"], "$NODEID+0x180", node_id=1) == (
        "value $NODEID+0x180 (= 385) out of range for UNSIGNED8 (0..255)")
    # A formula is never a bit pattern, even for a signed type.
    assert problem(T["INTEGER8"], "$NODEID+0x7F", node_id=1) == (
        "value $NODEID+0x7F (= 128) out of range for INTEGER8 (-128..127)")


# ---------------------------------------------------------------------------------------
# Integer types at their limits (every type in the table)

@pytest.mark.parametrize("dtype", INTEGER_LIKE, ids=lambda t: t.name)
def test_integer_limits(dtype):
    size, lo, hi, name = dtype.size, dtype.min, dtype.max, dtype.name
    signed = dtype.kind == "sint"
    assert encode(dtype, str(lo)) == lo.to_bytes(size, "little", signed=signed)
    assert encode(dtype, str(hi)) == hi.to_bytes(size, "little", signed=signed)
    assert encode(dtype, hex(hi)) == hi.to_bytes(size, "little", signed=signed)
    assert len(encode(dtype, "0")) == size
    assert problem(dtype, str(hi + 1)) == f"value {hi + 1} out of range for {name} ({lo}..{hi})"
    assert problem(dtype, str(lo - 1)) == f"value {lo - 1} out of range for {name} ({lo}..{hi})"
    assert zero(dtype) == bytes(size)


@pytest.mark.parametrize("dtype", [t for t in INTEGER_LIKE if t.kind == "sint"], ids=lambda t: t.name)
def test_signed_bit_patterns(dtype):
    bits, size, name = dtype.bits, dtype.size, dtype.name
    all_ones = "0x" + "FF" * size
    assert encode(dtype, all_ones) == b"\xff" * size                      # = -1
    assert encode(dtype, f"0x8{'0' * (2 * size - 1)}") == dtype.min.to_bytes(size, "little", signed=True)
    assert encode(dtype, f"-0x{-dtype.min:X}") == dtype.min.to_bytes(size, "little", signed=True)
    too_wide = f"0x1{'0' * (2 * size)}"
    assert problem(dtype, too_wide) == f"hex literal {too_wide} is wider than {name} ({bits} bits)"
    # a negative hex literal is a value, not a pattern
    assert problem(dtype, f"-0x{-dtype.min + 1:X}") == (
        f"value -0x{-dtype.min + 1:X} (= {dtype.min - 1}) out of range for {name} "
        f"({dtype.min}..{dtype.max})")


def test_signed_examples_from_spec():
    assert encode(T["INTEGER8"], "0xFF") == b"\xff"
    assert encode(T["INTEGER8"], "0x00FF") == b"\xff"   # width is the value's, not the digits'
    assert encode(T["INTEGER32"], "0x80000000") == b"\x00\x00\x00\x80"
    assert encode(T["INTEGER16"], "-0x10") == b"\xf0\xff"
    assert problem(T["INTEGER8"], "0x1FF") == "hex literal 0x1FF is wider than INTEGER8 (8 bits)"
    assert problem(T["INTEGER8"], "255") == "value 255 out of range for INTEGER8 (-128..127)"


def test_octal_rules():
    assert encode(T["UNSIGNED8"], "012") == b"\x0a"
    assert encode(T["INTEGER8"], "-010") == b"\xf8"
    assert problem(T["UNSIGNED8"], "08") == "invalid octal literal '08'"
    # octal literals are never bit patterns
    assert problem(T["INTEGER8"], "0377") == "value 0377 (= 255) out of range for INTEGER8 (-128..127)"


def test_unsigned_negative_and_hex_range():
    assert problem(T["UNSIGNED8"], "-1") == "value -1 out of range for UNSIGNED8 (0..255)"
    assert problem(T["UNSIGNED16"], "-0x1") == "value -0x1 (= -1) out of range for UNSIGNED16 (0..65535)"
    assert problem(T["UNSIGNED8"], "0x100") == "value 0x100 (= 256) out of range for UNSIGNED8 (0..255)"
    assert encode(T["UNSIGNED8"], "-0") == b"\x00"
    assert encode(T["UNSIGNED8"], "+0x0A") == b"\x0a"


def test_odd_widths_are_not_truncated_or_padded():
    assert encode(T["UNSIGNED24"], "0x123456") == b"\x56\x34\x12"
    assert encode(T["INTEGER24"], "-2") == b"\xfe\xff\xff"
    assert encode(T["UNSIGNED40"], "0x0102030405") == bytes.fromhex("0504030201")
    assert encode(T["INTEGER48"], "-1") == b"\xff" * 6
    assert encode(T["UNSIGNED56"], "0x01020304050607") == bytes.fromhex("07060504030201")
    assert problem(T["UNSIGNED24"], "0x1000000") == (
        "value 0x1000000 (= 16777216) out of range for UNSIGNED24 (0..16777215)")


def test_integer_blanks_trimmed():
    assert encode(T["UNSIGNED16"], " 0x1234\t") == b"\x34\x12"
    assert encode(T["UNSIGNED16"], "  7 ") == b"\x07\x00"


@pytest.mark.parametrize("text", ["1.5", "abc", "0x1_0", "1e3", "", "12 ;c"])
def test_integer_syntax_errors(text):
    with pytest.raises(ValueProblem):
        encode(T["UNSIGNED32"], text)


# ---------------------------------------------------------------------------------------
# BOOLEAN and TIME types

@pytest.mark.parametrize("text, byte", [
    ("0", b"\x00"), ("1", b"\x01"), ("TRUE", b"\x01"), ("false", b"\x00"), ("True", b"\x01"),
    ("0x1", b"\x01"), ("00", b"\x00"), ("01", b"\x01"), (" FALSE ", b"\x00"),
])
def test_boolean(text, byte):
    assert encode(T["BOOLEAN"], text) == byte


def test_boolean_errors():
    assert problem(T["BOOLEAN"], "2") == "value 2 out of range for BOOLEAN (0..1)"
    assert problem(T["BOOLEAN"], "-1") == "value -1 out of range for BOOLEAN (0..1)"
    assert problem(T["BOOLEAN"], "yes") == "invalid BOOLEAN value 'yes' (expected 0, 1, TRUE or FALSE)"
    assert problem(T["BOOLEAN"], "0xFF") == "value 0xFF (= 255) out of range for BOOLEAN (0..1)"


@pytest.mark.parametrize("name", ["TIME_OF_DAY", "TIME_DIFFERENCE"])
def test_time_types(name):
    dtype = T[name]
    # ms in the low 28 bits of the first DWORD, days in the WORD: 2 days + 1000 ms
    assert encode(dtype, str(2 << 32 | 1000)) == b"\xe8\x03\x00\x00\x02\x00"
    assert encode(dtype, "0xFFFFFFFFFFFF") == b"\xff" * 6
    assert problem(dtype, "0x1000000000000") == (
        f"value 0x1000000000000 (= {2**48}) out of range for {name} (0..{2**48 - 1})")
    assert problem(dtype, "-1") == f"value -1 out of range for {name} (0..{2**48 - 1})"


# ---------------------------------------------------------------------------------------
# REAL32 / REAL64

@pytest.mark.parametrize("name, fmt", [("REAL32", "<f"), ("REAL64", "<d")])
@pytest.mark.parametrize("text", ["1.5", "-2e3", "0", "0.1", "+.5", "5.", "1E-3", "-0.0",
                                  "3.4028235e38", "1e-50", " 2.5 "])
def test_real_decimal(name, fmt, text):
    assert encode(T[name], text) == struct.pack(fmt, float(text))


def test_real_decimal_is_never_octal():
    assert encode(T["REAL32"], "010") == struct.pack("<f", 10.0)
    assert encode(T["REAL64"], "-010") == struct.pack("<d", -10.0)
    assert encode(T["REAL32"], "08") == struct.pack("<f", 8.0)


def test_real_raw_bits():
    assert encode(T["REAL32"], "0x3F800000") == struct.pack("<f", 1.0)
    assert encode(T["REAL32"], "0XFFFFFFFF") == b"\xff" * 4                # a NaN, kept as is
    assert encode(T["REAL64"], "0x3FF0000000000000") == struct.pack("<d", 1.0)
    assert encode(T["REAL32"], "0x0") == bytes(4)
    assert problem(T["REAL32"], "0x100000000") == "hex literal 0x100000000 is wider than REAL32 (32 bits)"
    assert problem(T["REAL64"], "0x10000000000000000") == (
        "hex literal 0x10000000000000000 is wider than REAL64 (64 bits)")
    assert problem(T["REAL32"], "-0x1") == "negative hex literal -0x1 is not a REAL32 bit pattern"
    assert problem(T["REAL32"], "0xZZ") == "invalid hex literal '0xZZ'"


def test_real_errors():
    assert problem(T["REAL32"], "1e39") == "REAL32 overflow: 1e39"
    assert problem(T["REAL32"], "-3.5e38") == "REAL32 overflow: -3.5e38"
    assert problem(T["REAL64"], "1e309") == "REAL64 overflow: 1e309"
    assert problem(T["REAL32"], "1e400") == "REAL32 overflow: 1e400"
    assert problem(T["REAL64"], "inf") == "REAL64 value must be finite: 'inf'"
    assert problem(T["REAL32"], "-Infinity") == "REAL32 value must be finite: '-Infinity'"
    assert problem(T["REAL32"], "nan") == "REAL32 value must be finite: 'nan'"
    assert problem(T["REAL32"], "1.5f") == "invalid REAL32 value '1.5f'"
    assert problem(T["REAL32"], "1_0.0") == "invalid REAL32 value '1_0.0'"
    assert problem(T["REAL64"], "$NODEID", node_id=1) == "$NODEID is not allowed in a REAL64 value: '$NODEID'"


# ---------------------------------------------------------------------------------------
# Strings, OCTET_STRING, DOMAIN

def test_visible_string():
    vs = T["VISIBLE_STRING"]
    assert encode(vs, "Motor #1") == b"Motor #1"
    assert encode(vs, '"quoted"') == b"quoted"
    assert encode(vs, '""') == b""
    assert encode(vs, '" padded "') == b" padded "
    assert encode(vs, 'say "hi"') == b'say "hi"'          # quotes kept unless they wrap it all
    assert encode(vs, '"a"b"') == b'a"b'
    assert encode(vs, '"') == b'"'
    assert encode(vs, "$NODEID") == b"$NODEID"             # plain text in a string
    assert encode(vs, "Grüße") == "Grüße".encode("utf-8")
    assert encode(vs, "Grüße", encoding="latin-1") == b"Gr\xfc\xdfe"
    assert problem(vs, "€", encoding="latin-1") == "character '€' cannot be written in latin-1"
    assert zero(vs) == b""


def test_unicode_string():
    us = T["UNICODE_STRING"]
    assert encode(us, "Ab") == b"A\x00b\x00"                # no BOM, no terminator
    assert encode(us, '"€ "') == "€ ".encode("utf-16-le")
    assert encode(us, "\U0001F600") == "\U0001F600".encode("utf-16-le")  # surrogate pair
    assert encode(us, '""') == b""


@pytest.mark.parametrize("name", ["OCTET_STRING", "DOMAIN"])
def test_hex_bytes(name):
    dtype = T[name]
    assert encode(dtype, "0102AbfF") == b"\x01\x02\xab\xff"
    assert encode(dtype, "01 02\t03") == b"\x01\x02\x03"
    assert encode(dtype, '""') == b""
    assert problem(dtype, "123") == f"odd number of hex digits in {name} value '123'"
    assert problem(dtype, "0 12") == f"odd number of hex digits in {name} value '0 12'"
    assert problem(dtype, "0 1") == f"a blank splits a hex byte pair in {name} value '0 1'"
    assert problem(dtype, "0G") == f"invalid character 'G' in {name} value '0G'"
    # Sevcon DriveWizard writes a 0x prefix: the same bytes as without it (lint warns, DCF218)
    assert encode(dtype, "0x0102") == encode(dtype, "0102") == b"\x01\x02"
    assert encode(dtype, "0X01 02") == b"\x01\x02"
    assert problem(dtype, "0x") == f"{name} value '0x' has no hex byte pairs after 0x"
    assert problem(dtype, "0x 01") == f"{name} value '0x 01' has no hex byte pairs after 0x"
    assert problem(dtype, "0x012") == f"odd number of hex digits in {name} value '0x012'"
    assert problem(dtype, "0x01 0x02") == f"invalid character 'x' in {name} value '0x01 0x02'"
    assert problem(dtype, "01\u00e402") == f"invalid character '\u00e4' in {name} value '01\u00e402'"
    assert zero(dtype) == b""


def test_hex_prefix():
    assert hex_prefix("0x01") and hex_prefix("0XaB") and hex_prefix(" 0x0")
    assert not hex_prefix("0x") and not hex_prefix("0x 01") and not hex_prefix("0102")
    assert not hex_prefix("x01") and not hex_prefix("00x1")


# ---------------------------------------------------------------------------------------
# Numeric comments

@pytest.mark.parametrize("text, result", [
    ("0x10", ("0x10", None)),
    ("0x10 ; speed", ("0x10", "; speed")),
    ("12\t# note ", ("12", "# note")),
    ("12   ;", ("12", ";")),
    ("$NODEID + 0x180 ; default", ("$NODEID + 0x180", "; default")),
    ("12;x", ("12;x", None)),                  # no blank before ';' -> no comment
    ("12#x", ("12#x", None)),
    (";x", (";x", None)),
    ("1 ;a ;b", ("1", ";a ;b")),
    ("1 2 ; c", ("1 2", "; c")),
])
def test_split_numeric_comment(text, result):
    assert split_numeric_comment(text) == result


# ---------------------------------------------------------------------------------------
# decode: text conventions and round trips

@pytest.mark.parametrize("name, data, text", [
    ("UNSIGNED8", b"\x05", "0x05"),
    ("UNSIGNED8", b"\x00", "0x00"),
    ("UNSIGNED32", b"\x81\x01\x00\x80", "0x80000181"),
    ("UNSIGNED24", b"\x56\x34\x12", "0x123456"),
    ("TIME_OF_DAY", b"\xe8\x03\x00\x00\x02\x00", "0x2000003E8"),
    ("INTEGER8", b"\xff", "-1"),
    ("INTEGER32", b"\x00\x00\x00\x80", "-2147483648"),
    ("INTEGER24", b"\xff\xff\x7f", "8388607"),
    ("BOOLEAN", b"\x01", "1"),
    ("BOOLEAN", b"\x00", "0"),
    ("REAL32", struct.pack("<f", 0.1), "0.1"),
    ("REAL32", struct.pack("<f", 1.0), "1.0"),
    ("REAL32", struct.pack("<f", -0.0), "-0.0"),
    ("REAL32", struct.pack("<f", 1e20), "1e+20"),
    ("REAL32", b"\xff\xff\x7f\x7f", "3.4028235e+38"),
    ("REAL64", struct.pack("<d", 0.1), "0.1"),
    ("REAL32", b"\x00\x00\xc0\x7f", "0x7FC00000"),              # NaN: raw bits
    ("REAL32", b"\x00\x00\x80\xff", "0xFF800000"),              # -inf: raw bits
    ("REAL64", struct.pack("<d", float("inf")), "0x7FF0000000000000"),
    ("VISIBLE_STRING", b"Motor #1", "Motor #1"),
    ("VISIBLE_STRING", b"", '""'),
    ("VISIBLE_STRING", b" lead", '" lead"'),
    ("VISIBLE_STRING", b"trail\t", '"trail\t"'),
    ("VISIBLE_STRING", b'"x"', '""x""'),
    ("VISIBLE_STRING", b'"', '"'),
    ("VISIBLE_STRING", b'a"b', 'a"b'),
    ("UNICODE_STRING", "€".encode("utf-16-le"), "€"),
    ("UNICODE_STRING", b"", '""'),
    ("OCTET_STRING", b"\x0a\xbc", "0ABC"),
    ("OCTET_STRING", b"", '""'),
    ("DOMAIN", b"\x00\x01", "0001"),
    ("DOMAIN", b"", '""'),
])
def test_decode_conventions(name, data, text):
    assert decode(T[name], data) == text
    assert encode(T[name], text) == data


@pytest.mark.parametrize("name, data, kw", [
    ("UNSIGNED16", b"\x01", {}),                  # wrong size
    ("REAL64", b"\x00" * 4, {}),
    ("BOOLEAN", b"\x02", {}),
    ("VISIBLE_STRING", b"\xff", {}),              # not UTF-8
    ("VISIBLE_STRING", b"a\nb", {}),              # no way to write a line end
    ("VISIBLE_STRING", b"a\r", {"encoding": "latin-1"}),
    ("UNICODE_STRING", b"a", {}),                 # odd length
    ("UNICODE_STRING", b"\x00\xd8", {}),          # lone surrogate
    ("UNICODE_STRING", "€".encode("utf-16-le"), {"encoding": "latin-1"}),
])
def test_decode_impossible(name, data, kw):
    assert decode(T[name], data, **kw) is None


def test_decode_latin1():
    vs = T["VISIBLE_STRING"]
    assert decode(vs, b"Gr\xfc\xdfe", encoding="latin-1") == "Grüße"
    assert encode(vs, "Grüße", encoding="latin-1") == b"Gr\xfc\xdfe"
    assert decode(vs, b"Gr\xfc\xdfe") is None                  # not UTF-8
    assert decode(T["UNICODE_STRING"], "ü".encode("utf-16-le"), encoding="latin-1") == "ü"


@pytest.mark.parametrize("dtype", FIXED, ids=lambda t: t.name)
@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_fixed_round_trip(dtype, data):
    raw = data.draw(st.binary(min_size=dtype.size, max_size=dtype.size))
    if dtype.name == "BOOLEAN":
        raw = bytes([raw[0] & 1])
    text = decode(dtype, raw)
    assert text is not None
    assert encode(dtype, text) == raw


@pytest.mark.parametrize("name", ["OCTET_STRING", "DOMAIN"])
@settings(max_examples=200, deadline=None)
@given(raw=st.binary(max_size=64))
def test_hex_round_trip(name, raw):
    assert encode(T[name], decode(T[name], raw)) == raw


@pytest.mark.parametrize("encoding", ["utf-8", "latin-1"])
@settings(max_examples=300, deadline=None)
@given(raw=st.binary(max_size=32))
def test_visible_string_round_trip(encoding, raw):
    text = decode(T["VISIBLE_STRING"], raw, encoding=encoding)
    if text is None:
        assert b"\n" in raw or b"\r" in raw or encoding == "utf-8"
    else:
        assert encode(T["VISIBLE_STRING"], text, encoding=encoding) == raw


@settings(max_examples=300, deadline=None)
@given(s=st.text(max_size=32))
def test_string_text_round_trip(s):
    for name, raw in (("VISIBLE_STRING", s.encode("utf-8", "surrogatepass")),
                      ("UNICODE_STRING", s.encode("utf-16-le", "surrogatepass"))):
        text = decode(T[name], raw)
        if "\n" in s or "\r" in s or any("\ud800" <= ch <= "\udfff" for ch in s):
            assert text is None
        else:
            assert text is not None
            assert encode(T[name], text) == raw


@settings(max_examples=300, deadline=None)
@given(f=st.floats(allow_nan=False, allow_infinity=False, width=32))
def test_real32_decimal_text(f):
    raw = struct.pack("<f", f)
    text = decode(T["REAL32"], raw)
    assert not text.startswith("0x")                # finite values stay readable
    assert encode(T["REAL32"], text) == raw


@pytest.mark.parametrize("dtype", INTEGER_LIKE, ids=lambda t: t.name)
@settings(max_examples=100, deadline=None)
@given(data=st.data())
def test_integer_text_round_trip(dtype, data):
    value = data.draw(st.integers(dtype.min, dtype.max))
    for text in (str(value), hex(value).replace("0x-", "-0x") if value >= 0 else f"-0x{-value:X}",
                 f"{'-' if value < 0 else ''}0{abs(value):o}"):
        raw = encode(dtype, text)
        assert raw == (value & ((1 << dtype.bits) - 1)).to_bytes(dtype.size, "little")
        assert to_python(dtype, raw) == value
        assert encode(dtype, decode(dtype, raw)) == raw


# ---------------------------------------------------------------------------------------
# to_python and zero

def test_to_python():
    assert to_python(T["BOOLEAN"], b"\x01") is True
    assert to_python(T["BOOLEAN"], b"\x00") is False
    assert to_python(T["INTEGER24"], b"\xfe\xff\xff") == -2
    assert to_python(T["UNSIGNED40"], b"\x01\x00\x00\x00\x80") == 0x8000000001
    assert to_python(T["TIME_DIFFERENCE"], b"\xe8\x03\x00\x00\x02\x00") == 2 << 32 | 1000
    assert to_python(T["REAL32"], struct.pack("<f", 1.5)) == 1.5
    assert to_python(T["REAL64"], struct.pack("<d", 0.1)) == 0.1
    assert to_python(T["VISIBLE_STRING"], b"ab\xff") == "ab\ufffd"
    assert to_python(T["UNICODE_STRING"], "€".encode("utf-16-le")) == "€"
    assert to_python(T["OCTET_STRING"], b"\x01") == b"\x01"
    assert to_python(T["DOMAIN"], bytearray(b"\x02")) == b"\x02"
    with pytest.raises(ValueProblem) as info:
        to_python(T["UNSIGNED32"], b"\x00")
    assert str(info.value) == "UNSIGNED32 needs 4 bytes, got 1"


@pytest.mark.parametrize("dtype", list(BY_CODE.values()), ids=lambda t: t.name)
def test_zero(dtype):
    z = zero(dtype)
    assert z == (b"" if dtype.size is None else bytes(dtype.size))
    assert encode(dtype, decode(dtype, z)) == z


# ---------------------------------------------------------------------------------------
# Cross-check against python-canopen

def test_codes_match_canopen():
    datatypes = pytest.importorskip("canopen.objectdictionary.datatypes")
    for dtype in BY_CODE.values():
        assert getattr(datatypes, dtype.name) == dtype.code


@pytest.mark.parametrize("dtype", [t for t in FIXED if t.kind in ("sint", "uint", "real", "bool")],
                         ids=lambda t: t.name)
def test_bytes_match_canopen_struct_types(dtype):
    od = pytest.importorskip("canopen.objectdictionary")
    packer = od.ODVariable.STRUCT_TYPES[dtype.code]
    assert packer.size == dtype.size
    if dtype.kind == "real":
        samples = ["0", "1.5", "-2e3", "0.1", "3.4028235e38" if dtype.size == 4 else "1e300"]
        for text in samples:
            assert encode(dtype, text) == packer.pack(float(text))
        return
    if dtype.kind == "bool":
        assert encode(dtype, "TRUE") == packer.pack(True)
        assert encode(dtype, "0") == packer.pack(False)
        return
    for value in (dtype.min, dtype.max, 0, 1, dtype.max // 3):
        assert encode(dtype, str(value)) == packer.pack(value)
        assert packer.unpack(encode(dtype, str(value)))[0] == value


def _parse_int_reference(text: str):
    """parse_int without its fast paths: the literal grammar of SPEC §1 alone."""
    from dcf2bin import values
    t = text.strip(" \t")
    try:
        if values.uses_nodeid(t):
            raise ValueProblem(f"$NODEID is not allowed here: '{values._q(t)}'")
        return values._literal(t)[0]
    except ValueProblem as exc:
        return str(exc)


@settings(max_examples=2000, deadline=None)
@given(st.text(alphabet="0123456789abcdefABCDEFxXg_+- \t$NODEID\u0663", max_size=70)
       | st.from_regex(r"[ \t]*(0[xX][0-9A-Fa-f_g]{0,70}|[0-9]{1,70})[ \t]*", fullmatch=True))
def test_parse_int_fast_paths_agree_with_the_grammar(text):
    # the decimal and 0x fast paths give what the regular expression gives, and leave
    # every other text (a sign, a leading 0, '_', a non-ASCII digit, too many digits,
    # $NODEID) to it, with its message
    try:
        got = parse_int(text)
    except ValueProblem as exc:
        got = str(exc)
    assert got == _parse_int_reference(text)

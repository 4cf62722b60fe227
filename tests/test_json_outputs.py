"""Every JSON output of every command follows one convention (docs/options.md, "JSON
outputs") and validates against its JSON Schema shipped in dcf2bin/schemas/, on the samples
and on a few corpus files. The schemas must fail on a document that breaks the convention, too."""
from __future__ import annotations

import json
import re

import pytest
from click.testing import CliRunner
from conftest import compile_corpus_file, corpus_files, CORPUS, ROOT, SAMPLES

from dcf2bin import schemas
from dcf2bin.cli import main

jsonschema = pytest.importorskip("jsonschema")

SAMPLE_DCFS = ["bild8", "device", "dis2", "dis2_cobid", "plc"]
INDEX = re.compile(r"^0x[0-9A-F]{4}$")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def check(name: str, text: str) -> dict:
    """``text`` is one document of output ``name``: format and version first, valid."""
    doc = json.loads(text)
    assert list(doc)[:2] == ["format", "version"], list(doc)[:3]
    assert doc["format"] == schemas.FORMATS[name] and isinstance(doc["version"], int)
    jsonschema.Draft202012Validator.check_schema(schemas.load(name))
    jsonschema.validate(doc, schemas.load(name),
                        format_checker=jsonschema.Draft202012Validator.FORMAT_CHECKER)
    return doc


def outputs(dcf, tmp_path, *, extra=()):
    """(schema name, stdout) of every JSON output for one DCF and the container it compiles to."""
    binary = tmp_path / "x.bin"
    r = run("compile", dcf, "-o", binary, *extra)
    assert r.exit_code == 0, r.stderr
    dumped = tmp_path / "x.json"
    for args, name in [(("dump", binary, "-f", "json"), "dump"),
                       (("map", dcf, "-f", "json", *extra), "map"),
                       (("map", binary, "-f", "json"), "map"),
                       (("simulate", dcf, "-f", "json", *extra), "simulate"),
                       (("simulate", binary, "-f", "json"), "simulate"),
                       (("validate", dcf, "-f", "json", *extra), "validate"),
                       (("validate", binary, "-f", "json"), "validate")]:
        r = run(*args)
        assert r.stdout, (args, r.stderr)
        yield name, args, r.stdout
        if name == "dump" and args[1] == binary:
            dumped.write_text(r.stdout)
    r = run("simulate", dumped, "-f", "json")            # the dump as input
    yield "simulate", ("simulate", dumped), r.stdout


@pytest.mark.parametrize("sample", SAMPLE_DCFS)
def test_every_json_output_of_a_sample_matches_its_schema(sample, tmp_path):
    seen = set()
    for name, args, text in outputs(SAMPLES / f"{sample}.dcf", tmp_path):
        check(name, text)
        seen.add(name)
    assert seen == {"dump", "map", "simulate", "validate"}


def test_rule_list_matches_its_schema():
    doc = check("rules", run("validate", "--list-rules", "-f", "json").stdout)
    assert {"TGT078", "TGT101"} <= {r["id"] for r in doc["rules"]}


def _corpus_picks():
    files = [p for p in corpus_files(".dcf") if compile_corpus_file(p).ok]
    if not files:
        return [pytest.param(None, marks=pytest.mark.skip(
            reason=f"no compiling corpus DCF under {CORPUS} (a fresh clone without ../shared)"))]
    step = max(1, len(files) // 4)
    return [pytest.param(p, id=str(p.relative_to(CORPUS))) for p in files[::step][:4]]


@pytest.mark.parametrize("path", _corpus_picks())
def test_every_json_output_of_corpus_files_matches_its_schema(path, tmp_path):
    node = ("--node-id", "1") if any(d.rule == "DCF201" for d in
                                     compile_corpus_file(path).diagnostics) else ()
    for name, args, text in outputs(path, tmp_path, extra=node):
        check(name, text)


def test_indexes_cob_ids_and_sizes_follow_the_convention(tmp_path):
    """The values, not only the shape, on plc (SPEC §3, samples/plc.dcf): TPDO1 0x1800 with
    COB-ID 0x190 maps 0xA4C0sub1 at PI address 8; the image is 16 bytes."""
    sim = json.loads(run("simulate", SAMPLES / "plc.bin", "-f", "json").stdout)
    tpdo = next(p for p in sim["pdos"] if p["comm_index"] == "0x1800")
    assert (tpdo["cob_id"], tpdo["mapped"][0]["index"], tpdo["mapped"][0]["pi_address"]) == \
        ("0x00000190", "0xA4C0", 8)
    assert sim["descriptor"]["pi_size"] == 16 and sim["code"] == "0x00"
    vmap = json.loads(run("map", SAMPLES / "plc.dcf", "-f", "json").stdout)
    assert vmap["areas"]["pi_size"] == 16
    assert all(INDEX.match(v["index"]) for v in vmap["variables"])
    dump = json.loads(run("dump", SAMPLES / "plc.bin", "-f", "json").stdout)
    assert dump["pi_parameters"]["total_size"] == 16           # the segment's own field name
    assert all(INDEX.match(e["index"]) for e in dump["entries"])


@pytest.mark.parametrize("name, edit", [
    ("map", lambda d: d["variables"][0].update(index=0xA040)),          # old integer index
    ("map", lambda d: d["areas"].update(complete_size=d["areas"].pop("pi_size"))),
    ("simulate", lambda d: d.update(code=0)),
    ("simulate", lambda d: d["pdos"][0].update(cob_id=0x210)),
    ("simulate", lambda d: d.pop("version")),
    ("dump", lambda d: d.update(schema_version=d.pop("version"))),      # reader-only old name
    ("dump", lambda d: d["entries"][0].update(index="0xa040")),
])
def test_the_schemas_refuse_the_old_forms(name, edit):
    args = {"map": ("map", SAMPLES / "plc.dcf"), "simulate": ("simulate", SAMPLES / "plc.bin"),
            "dump": ("dump", SAMPLES / "plc.bin")}[name]
    doc = json.loads(run(*args, "-f", "json").stdout)
    jsonschema.validate(doc, schemas.load(name))
    edit(doc)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(doc, schemas.load(name))


def test_schemas_are_package_data():
    """A non-editable install ships them: pyproject.toml lists them as package data."""
    text = (ROOT / "pyproject.toml").read_text()
    assert '"dcf2bin.schemas" = ["*.json"]' in text
    on_disk = {p.stem for p in (ROOT / "dcf2bin" / "schemas").glob("*.json")}
    assert on_disk == set(schemas.FORMATS)
    for name in schemas.FORMATS:
        assert schemas.load(name)["properties"]["format"] == {"const": schemas.FORMATS[name]}


def test_docs_list_every_json_output():
    doc = (ROOT / "docs" / "options.md").read_text()
    section = doc.split("\n## JSON outputs\n", 1)[1].split("\n## ", 1)[0]
    for name, fmt in schemas.FORMATS.items():
        assert f"| `{fmt}` | `dcf2bin/schemas/{name}.json` |" in section, name


# -- the network commands -----------------------------------------------------------------

NETWORK = ROOT / "tests" / "fixtures" / "network_show" / "bus.yml"


@pytest.mark.parametrize("extra", [(), ("--writes",)])
def test_network_show_json_matches_its_schema(extra):
    r = run("network", "show", NETWORK, "-f", "json", *extra)
    assert r.exit_code == 0, r.stderr
    doc = check("network-show", r.stdout)
    assert all(INDEX.match(v["index"]) for v in doc["variables"])
    assert (doc["slaves"][0]["writes"] is None) == (extra == ())


def test_network_check_json_is_the_validate_format():
    r = run("network", "check", NETWORK, "-f", "json")
    assert r.stdout, r.stderr
    check("validate", r.stdout)
    r = run("network", "check", "--list-rules", "-f", "json")
    assert r.exit_code == 0, r.stderr
    doc = check("rules", r.stdout)
    assert any(rule["id"].startswith("NET") for rule in doc["rules"])

"""The rule registry, its documentation and the pre-commit hooks stay in step."""
from __future__ import annotations

import re

import yaml

from conftest import ROOT
from dcf2bin.lint import all_rules
from dcf2bin.lint.registry import FAMILIES

DOC = (ROOT / "docs" / "validate.md").read_text()
MAN = (ROOT / "man" / "dcf2bin-validate.1").read_text().replace("\\-", "-").replace("\\fB", "") \
    .replace("\\fR", "")


def test_at_least_40_rules_with_unique_kebab_names_and_one_line_descriptions():
    rules = all_rules()
    assert len(rules) >= 40
    assert len({r.name for r in rules}) == len(rules)
    for r in rules:
        assert re.fullmatch(r"(DCF|CNT|CON|XDD)\d{3}|TGT0[0-9A-F]{2}|TGT1\d{2}|(IO|INT)\d{3}", r.id), r.id
        assert re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", r.name), r.name
        assert r.description and "\n" not in r.description and r.description.endswith(".")
        assert r.hint, r.id
        assert r.family != "other", r.id


def test_every_rule_is_documented_in_docs_and_man_page():
    for r in all_rules():
        row = f"| {r.id} | `{r.name}` | {r.severity.value} |"
        assert row in DOC, row
        assert f"{r.id} {r.name} ({r.severity.value})" in MAN, r.id


def test_families_formats_and_exit_codes_are_documented():
    for prefix in ("DCF0xx", "DCF1xx", "DCF2xx", "DCF3xx", "DCF4xx", "XDD0xx", "CNT0xx", "CON0xx", "TGT0xx",
                   "TGT1xx"):
        assert prefix in DOC and prefix in MAN, prefix
    for name in FAMILIES.values():
        assert name.lower() in DOC.lower() and name.lower() in MAN.lower(), name
    for fmt in ("text", "json", "sarif", "github"):
        assert f"**{fmt}**" in DOC and f".B {fmt}" in MAN, fmt
    for code in ("0", "1", "2", "3", "70"):
        assert f"| {code} |" in DOC and f".B {code}\n" in MAN, code
    assert "upload-sarif" in DOC and "security-events: write" in DOC
    assert "pre-commit" in DOC


def test_every_rule_id_the_core_emits_is_registered():
    ids = {r.id for r in all_rules()}
    used = set()
    for path in (ROOT / "dcf2bin").glob("*.py"):
        used |= set(re.findall(r'rule="((?:DCF|CNT)\d{3})"', path.read_text()))
    assert used - ids == set()


def test_pre_commit_hooks():
    hooks = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    by_id = {h["id"]: h for h in hooks}
    assert set(by_id) == {"dcf2bin-validate", "dcf2bin-validate-containers"}
    for h in hooks:
        assert h["entry"] == "dcf2bin validate" and h["language"] == "python"
    assert re.search(by_id["dcf2bin-validate"]["files"], "config/X.EDS")
    assert re.search(by_id["dcf2bin-validate"]["files"], "a.dcf")
    assert not re.search(by_id["dcf2bin-validate"]["files"], "a.bin")
    assert re.search(by_id["dcf2bin-validate-containers"]["files"], "out/plc.BIN")


def test_ci_examples_install_dcf2bin_from_a_checkout_not_from_pypi():
    # dcf2bin is not on PyPI: "pip install dcf2bin" would fail in the user's first job
    readme = (ROOT / "README.md").read_text()
    for text in (DOC, readme):
        assert "pip install dcf2bin" not in text
        block = next(b for b in re.findall(r"```yaml\n(.*?)```", text, re.S)
                     if "upload-sarif" in b)
        doc = yaml.safe_load(block)
        steps = (doc.get("jobs") or doc)["validate"]["steps"]
        path = next(s["with"]["path"] for s in steps
                    if s.get("with", {}).get("repository") == "YOUR-ORG/dcf2bin")
        assert {"run": f"python -m pip install ./{path}"} in steps

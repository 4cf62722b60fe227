"""Every link between the documentation pages leads somewhere (issue 28, "the shape of it").

README.md is the page a newcomer reads; the reference lives in docs/ beside the man pages.
A page that moves or a heading that is renamed must not leave a link, a man page, a `--help`
text, a docstring or a message pointing at nothing:

* every relative Markdown link (`[text](path)`, `![alt](path)`, `[id]: path`) in README.md,
  docs/*.md and benchmarks/README.md names a file or folder of the repository, and its
  `#anchor` the slug of a heading of that page, as GitHub makes it;
* every mention of a page with a section title, `docs/network.md, "Codes"` or
  `README "JSON outputs"`, anywhere in the repository's text (man pages, code, tests),
  names a heading of that page;
* every file of the repository named in that text by its path (`docs/network.md`,
  `man/dcf2bin-node.1`, `samples/plc.dcf`, `tests/test_fuzz.py`) exists.
"""
from __future__ import annotations

import re
import unicodedata
from pathlib import Path

import pytest
from conftest import ROOT

PAGES = sorted([ROOT / "README.md", ROOT / "benchmarks" / "README.md",
                *(ROOT / "docs").glob("*.md")])
FENCE = re.compile(r"^\s*(```|~~~)")
ATX = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
INLINE_LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_DEF = re.compile(r"^ {0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")


def prose_lines(text: str) -> list[tuple[int, str]]:
    """The lines of a Markdown page outside fenced code blocks, with their numbers."""
    out, fenced = [], None
    for n, line in enumerate(text.splitlines(), 1):
        m = FENCE.match(line)
        if m:
            if fenced is None:
                fenced = m.group(1)
            elif m.group(1) == fenced:
                fenced = None
            continue
        if fenced is None:
            out.append((n, line))
    return out


def plain(heading: str) -> str:
    """A heading's text as rendered: links become their text, code spans and emphasis lose
    their marks."""
    heading = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    return re.sub(r"[`*]|(?<!\w)_|_(?!\w)", "", heading).strip()


def slug(text: str) -> str:
    """GitHub's anchor for a heading (github-slugger): lower case, every character that is
    neither a letter, a digit, `_`, `-` nor a blank removed, each blank a `-`."""
    keep = (c for c in text.lower()
            if c in "_- " or unicodedata.category(c)[0] in "LN")
    return "".join(keep).replace(" ", "-")


def headings(page: Path) -> list[str]:
    """The plain text of every heading of a page, in order (ATX and setext)."""
    out, previous = [], ""
    for _, line in prose_lines(page.read_text(encoding="utf-8")):
        m = ATX.match(line)
        if m:
            out.append(plain(m.group(2)))
        elif (re.fullmatch(r" {0,3}(=+|-+)\s*", line) and previous.strip()
              and not re.match(r"\s*([|#>*+-]|\d+\.)", previous)):
            out.append(plain(previous))
        previous = line if not m else ""
    return out


def anchors(page: Path) -> set[str]:
    """The anchors GitHub gives a page: one per heading, a repeated slug numbered -1, -2..."""
    seen: dict[str, int] = {}
    out = set()
    for h in headings(page):
        s = slug(h)
        if s in seen:
            seen[s] += 1
            s = f"{s}-{seen[s]}"
        else:
            seen[s] = 0
        out.add(s)
    text = page.read_text(encoding="utf-8")
    out |= set(re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", text))
    return out


def links(page: Path) -> list[tuple[int, str]]:
    """Every link target of a page outside code, with its line."""
    out = []
    for n, line in prose_lines(page.read_text(encoding="utf-8")):
        bare = CODE_SPAN.sub("", line)
        out += [(n, m.group(1)) for m in INLINE_LINK.finditer(bare)]
        m = REFERENCE_DEF.match(bare)
        if m:
            out.append((n, m.group(1)))
    return out


def _relative(target: str) -> bool:
    return not re.match(r"[a-zA-Z][a-zA-Z0-9+.-]*:", target)


def broken_link(page: Path, target: str) -> str | None:
    """Why a link of a page leads nowhere, or None."""
    path, _, anchor = target.partition("#")
    dest = (page.parent / path).resolve() if path else page
    if not dest.is_relative_to(ROOT.resolve()):
        return "leads out of the repository"
    if not dest.exists():
        return "no such file"
    if anchor and (dest.suffix != ".md" or anchor not in anchors(dest)):
        return f"no heading #{anchor} in {dest.relative_to(ROOT.resolve())}"
    return None


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_and_anchor_of_a_page_resolves(page):
    bad = [f"{page.relative_to(ROOT)}:{n}: {target}: {why}"
           for n, target in links(page) if _relative(target)
           for why in [broken_link(page, target)] if why]
    assert bad == []


# -- mentions of pages and sections in the repository's text -------------------------------

TEXT_FILES = sorted(
    p for pattern in ("README.md", "docs/*.md", "benchmarks/*.md", "benchmarks/*.py",
                      "man/*.1", "dcf2bin/**/*.py", "tests/*.py", "tests/**/README*",
                      "samples/*.dcf", "pyproject.toml", ".ci/run")
    for p in ROOT.glob(pattern) if p.is_file() and p.name != "test_docs_links.py")
PAGE_NAME = r"((?:benchmarks/)?README(?:\.md)?|(?:docs/)?[a-z][\w-]*\.md)"
SECTION_AFTER = re.compile(PAGE_NAME + r"(?:\s*[,:]\s*|\s+)\(?(?:section\s+)?\"([^\"\n]+)\"")
SECTION_BEFORE = re.compile(r"the\s+\"([^\"\n]+)\"\s+section\s+of\s+" + PAGE_NAME)
PATH = re.compile(r"(?<![\w/.-])((?:docs|man|samples|tests|benchmarks|dcf2bin)/[\w./-]*"
                  r"\.(?:md|1|png|svg|py|dcf|eds|bin|yml|json|csv|writes|xdd|xdc|xpd|cpj))"
                  r"(?![\w/-])")
GENERATED = "benchmarks/out/"   # what the benchmarks write (gitignored)


def _page_of(mention: str, where: Path) -> Path | None:
    """The page a mention names: README is the top one; `x.md` in docs/ is its sibling."""
    if mention.startswith("README"):
        return ROOT / "README.md" if where.parent != ROOT / "benchmarks" else where
    if mention.startswith(("docs/", "benchmarks/")):
        return ROOT / mention
    for folder in (where.parent, ROOT / "docs"):
        if (folder / mention).exists():
            return folder / mention
    return None


def mentions(path: Path) -> list[tuple[str, str]]:
    """(page, section) for every "page, "section"" mention of a file."""
    text = path.read_text(encoding="utf-8").replace("\\-", "-")
    text = re.sub(r"\\\(lq|\\\(rq", '"', text)            # roff's quotes
    text = re.sub(r"\n(\.\w+\s)?", " ", text)                # roff requests, line breaks
    text = re.sub(r"\s*(#|\"\"\"|//)\s+", " ", text)         # comments continued over lines
    found = [(m.group(1), m.group(2)) for m in SECTION_AFTER.finditer(text)]
    found += [(m.group(2), m.group(1)) for m in SECTION_BEFORE.finditer(text)]
    return found


def names(section: str, heading: str) -> bool:
    """A mention names a heading by its whole text or by the part before a colon or a
    parenthesis ("A misbehaving bus" for "A misbehaving bus: time and size bounds")."""
    section, heading = section.lower(), heading.lower()
    return heading == section or re.match(re.escape(section) + r"(:| \()", heading) is not None


@pytest.mark.parametrize("path", TEXT_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_mention_of_a_page_and_its_section_resolves(path):
    bad = []
    for page_name, section in mentions(path):
        page = _page_of(page_name, path)
        if page is None or not page.exists():
            bad.append(f"{page_name}: no such page")
        elif not any(names(section, h) for h in headings(page)):
            bad.append(f"{page_name}, \"{section}\": no such heading in "
                       f"{page.relative_to(ROOT)}")
    text = path.read_text(encoding="utf-8").replace("\\-", "-")
    bad += [f"{p}: no such file" for p in PATH.findall(text)
            if not (ROOT / p).exists() and not p.startswith(GENERATED)]
    assert bad == []


# -- the checks themselves -------------------------------------------------------------------

def test_slug_follows_github():
    assert slug("What check reports") == "what-check-reports"
    assert slug("`dcf2bin dump` and `bin2dcf` — containers and concise DCFs back to text") \
        == "dcf2bin-dump-and-bin2dcf--containers-and-concise-dcfs-back-to-text"
    assert slug(plain("The PDOs as a CAN database (`show -f dbc`)")) \
        == "the-pdos-as-a-can-database-show--f-dbc"
    assert slug("Issue 22: whole processes (`table.py`)") == "issue-22-whole-processes-tablepy"
    assert slug("snake_case ≥ 3.10") == "snake_case--310"


def test_the_checks_find_what_is_broken(tmp_path, monkeypatch):
    page = tmp_path / "page.md"
    page.write_text("# Top\n\n## Twice\n\n## Twice\n\n```\n# not a heading\n[x](nowhere.md)\n```\n"
                    "[a](#twice-1) [b](#not-a-heading) `[c](nowhere.md)` [d](other.md)\n"
                    "[e](page.md#top) ![f](missing.png) [g](https://example.com/x.md)\n",
                    encoding="utf-8")
    (tmp_path / "other.md").write_text("Title\n=====\n", encoding="utf-8")
    monkeypatch.setattr("test_docs_links.ROOT", tmp_path)
    assert anchors(page) == {"top", "twice", "twice-1"}
    assert headings(tmp_path / "other.md") == ["Title"]
    found = {t: broken_link(page, t) for _, t in links(page) if _relative(t)}
    assert found == {"#twice-1": None, "#not-a-heading": "no heading #not-a-heading in page.md",
                     "other.md": None, "page.md#top": None, "missing.png": "no such file"}


def test_mentions_are_read_in_text_and_roff(tmp_path):
    f = tmp_path / "x.1"
    f.write_text('See\n.I docs/network.md ,\n"Codes"; README "JSON\\- outputs" and\n'
                 'the "Bench" section of README.md.\n', encoding="utf-8")
    assert mentions(f) == [("docs/network.md", "Codes"), ("README", "JSON- outputs"),
                           ("README.md", "Bench")]
    f.write_text('in benchmarks/README.md ("The long runs")', encoding="utf-8")
    assert mentions(f) == [("benchmarks/README.md", "The long runs")]
    assert PATH.findall("see man/dcf2bin-node.1, `samples/plc.dcf`; tests/test_x.py: "
                        "man/dcf2bin-<name>.1 dcf2bin/model/ x/docs/a.md") \
        == ["man/dcf2bin-node.1", "samples/plc.dcf", "tests/test_x.py"]


# -- README's command table ------------------------------------------------------------------

def _command_names() -> set[str]:
    """Every command and subcommand of dcf2bin, as a user types it after `dcf2bin`."""
    import click
    from dcf2bin.cli import main
    names = set()
    for name, cmd in main.commands.items():
        if isinstance(cmd, click.Group):
            names |= {f"{name} {sub}" for sub in cmd.commands}
        else:
            names.add(name)
    return names


def test_readme_command_table_has_one_row_per_command_with_its_man_page_and_docs_page():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    table = text.split("\n## Commands\n", 1)[1].split("\n## ", 1)[0]
    rows = {}
    names = _command_names()
    for line in table.splitlines():
        m = re.match(r"\| `dcf2bin ([^`]*)` \|", line)
        if not m:
            continue
        words = m.group(1).split()
        name = " ".join(words[:2]) if " ".join(words[:2]) in names else words[0]
        assert name not in rows, f"two rows for {name}"
        rows[name] = line
    assert set(rows) == names
    for name, line in rows.items():
        man = "man/dcf2bin.1" if name == "compile" else f"man/dcf2bin-{name.replace(' ', '-')}.1"
        assert f"[man]({man})" in line, name
        assert re.search(r"\[docs\]\(docs/[\w-]+\.md(#[\w-]+)?\)", line), name

#!/usr/bin/env python3
"""Reading a CiA 311 XDD against reading the EDS that ``dcf2bin convert`` makes of it
(issue 28: at most 3x).

    python benchmarks/xdd.py                      # CANopenNode's DS301_profile.xpd (147 KB)
    python benchmarks/xdd.py FILE.xdd --repeat 50

The EDS is what ``dcf2bin convert FILE.xdd -o FILE.eds`` writes (``formats.dump(dev,
"eds")``: the same objects, the same values, the CO_disabled objects left out as CNV004
says), so both readers build the same model. Every step is timed in one run, the steps
interleaved, each the best of 3 x ``--repeat`` runs in CPU time (the machine is shared:
the best is the least disturbed, and CPU time leaves out the time another process has the
core), with the cyclic garbage collector off as every command runs
(``cli.common.without_cyclic_gc``).
The XDD's time is then cut into its steps, to show where it goes and why the design is
what it is:

* libxml2's parse (lxml) against a tree made with the standard library's expat, whose
  handlers are Python calls (the alternative markup.py's docstring weighs);
* the sections made of the XML (the reader's own work);
* the model's builder on those sections -- the cost of handing on CiA 306 sections instead
  of building a Device directly, which the builder's share bounds from above;
* the floor of any reader written in Python on lxml: the parse, and one look (tag, line,
  attributes, text) at every element the reader needs -- what no leaner Python code can
  go below.

Prints one table, the ratio and the verdict; exit 1 when the ratio is above 3.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
DEFAULT = ROOT.parent / "shared" / "corpus" / "xdd" / "canopennode_example" / "DS301_profile.xpd"


def expat_tree(data: bytes):
    import xml.parsers.expat as expat
    parser = expat.ParserCreate()
    stack = [[None, {}, [], 0]]

    def start(name, attrs):
        node = [name, attrs, [], parser.CurrentLineNumber]
        stack[-1][2].append(node)
        stack.append(node)

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda name: stack.pop()
    parser.Parse(data, True)
    return stack[0]


def floor(data: bytes, markup):
    """The parse, and one look at every element the reader needs: each object's and
    sub-object's line and attributes, each parameter's and each of its children's tag,
    line, attributes and text."""
    root = markup.parse(data)
    out = []
    for el in root.iter("{*}CANopenObject", "{*}CANopenSubObject", "{*}parameter"):
        out.append((el.sourceline, el.items()))
        if el.tag.endswith("parameter"):
            out.extend((c.tag, c.sourceline, c.items(), c.text) for c in el)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("xdd", nargs="?", default=str(DEFAULT))
    ap.add_argument("--repeat", type=int, default=30)
    args = ap.parse_args(argv)
    path = Path(args.xdd)
    if not path.is_file():
        print(f"{path}: not found (the corpus is in ../shared/corpus/xdd)", file=sys.stderr)
        return 2
    import gc
    gc.disable()
    from dcf2bin import formats, model
    from dcf2bin.formats.xdd import markup
    from dcf2bin.formats.xdd import read as read_xdd
    xdd = path.read_bytes()
    eds = formats.dump(formats.load(str(path), data=xdd), "eds").data
    a, b = formats.load("x.xdd", data=xdd), formats.load("x.eds", data=eds)
    assert sorted(a.objects) == sorted(b.objects), "the EDS does not hold the XDD's objects"
    n = sum(len(o.entries) for o in a.objects.values())

    parsed = read_xdd(xdd, "x.xdd")
    steps = {"xdd": lambda: formats.load("x.xdd", data=xdd),
             "eds": lambda: formats.load("x.eds", data=eds),
             "lxml": lambda: markup.parse(xdd), "expat": lambda: expat_tree(xdd),
             "sections": lambda: read_xdd(xdd, "x.xdd"), "build": lambda: model.build(parsed),
             "floor": lambda: floor(xdd, markup)}
    t = dict.fromkeys(steps, float("inf"))
    for _ in range(3 * args.repeat):    # the steps interleaved: the same conditions for all
        for name, fn in steps.items():
            start = time.process_time()
            fn()
            t[name] = min(t[name], time.process_time() - start)
    t_xdd, t_eds, t_lxml, t_expat = t["xdd"], t["eds"], t["lxml"], t["expat"]
    t_sections, t_build, t_floor = t["sections"], t["build"], t["floor"]

    ms = lambda t: f"{t * 1000:8.2f} ms"                  # noqa: E731
    print(f"{path.name}: {len(xdd) / 1000:.0f} KB XML, {len(a.objects)} objects, {n} entries; "
          f"the EDS written from it: {len(eds) / 1000:.0f} KB")
    print(f"  read the EDS (formats.load)            {ms(t_eds)}")
    print(f"  read the XDD (formats.load)            {ms(t_xdd)}   {t_xdd / t_eds:.2f}x the EDS")
    print(f"    XML parse, lxml (markup.parse)       {ms(t_lxml)}")
    print(f"    XML tree, expat (the alternative)    {ms(t_expat)}   {t_expat / t_lxml:.2f}x lxml")
    print(f"    sections from the XML (incl. parse)  {ms(t_sections)}")
    print(f"    the builder on those sections        {ms(t_build)}   "
          f"{t_build / t_xdd:.0%} of the XDD's read")
    print(f"  the floor of a Python reader on lxml   {ms(t_floor + t_build)}   "
          f"{(t_floor + t_build) / t_eds:.2f}x the EDS (parse, one look at each element "
          "needed, the builder)")
    ratio = t_xdd / t_eds
    floor_ratio = (t_floor + t_build) / t_eds
    print(f"ratio XDD/EDS: {ratio:.2f} (target: at most 3): "
          f"{'met' if ratio <= 3 else 'NOT met'}"
          + ("" if floor_ratio <= 3 else
             f"; the floor alone is {floor_ratio:.2f}x (benchmarks/README.md, issue 28)"))
    return 0 if ratio <= 3 else 1


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Reading a CiA 311 XDD against reading the EDS with the same objects (issue 28: at most 3x).

    python benchmarks/xdd.py                      # CANopenNode's DS301_profile.xpd (147 KB)
    python benchmarks/xdd.py FILE.xdd --repeat 50

The EDS is written from the XDD by dcf2bin itself (``formats.ini.text`` of the sections the
XDD reader makes: the same objects, the same values), so both readers build the same model.
Both are timed in one run, alternating, best of ``--repeat`` each (the machine is shared:
the best is the least disturbed). The XDD's time is then cut into its steps, to show where
it goes and why the design is what it is:

* libxml2's parse (lxml) against a tree made with the standard library's expat, whose
  handlers are Python calls (the alternative markup.py's docstring weighs);
* the sections made of the XML (the reader's own work);
* the model's builder on those sections -- the cost of handing on CiA 306 sections instead
  of building a Device directly, which the builder's share bounds from above.

Prints one table and the ratio; exit 1 when the ratio is above 3.
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


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("xdd", nargs="?", default=str(DEFAULT))
    ap.add_argument("--repeat", type=int, default=30)
    args = ap.parse_args(argv)
    path = Path(args.xdd)
    if not path.is_file():
        print(f"{path}: not found (the corpus is in ../shared/corpus/xdd)", file=sys.stderr)
        return 2
    from dcf2bin import formats, model
    from dcf2bin.formats import ini as ini_format
    from dcf2bin.formats.xdd import markup
    from dcf2bin.formats.xdd import read as read_xdd
    xdd = path.read_bytes()
    eds = ini_format.text(formats.read(xdd, str(path))).encode()
    a, b = formats.load("x.xdd", data=xdd), formats.load("x.eds", data=eds)
    assert sorted(a.objects) == sorted(b.objects), "the EDS does not hold the XDD's objects"
    n = sum(len(o.entries) for o in a.objects.values())

    t_xdd = t_eds = float("inf")
    for _ in range(3):                                    # alternating: the same conditions
        t_xdd = min(t_xdd, best(lambda: formats.load("x.xdd", data=xdd), args.repeat))
        t_eds = min(t_eds, best(lambda: formats.load("x.eds", data=eds), args.repeat))
    t_lxml = best(lambda: markup.parse(xdd), args.repeat)
    t_expat = best(lambda: expat_tree(xdd), args.repeat)
    t_sections = best(lambda: read_xdd(xdd, "x.xdd"), args.repeat)
    parsed = read_xdd(xdd, "x.xdd")
    t_build = best(lambda: model.build(parsed), args.repeat)

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
    ratio = t_xdd / t_eds
    print(f"ratio XDD/EDS: {ratio:.2f} (target: at most 3)")
    return 0 if ratio <= 3 else 1


if __name__ == "__main__":
    sys.exit(main())

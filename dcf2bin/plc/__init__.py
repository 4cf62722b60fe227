"""The PLC side (SPEC.md §9): the variable map of the process image in the forms a PLC
build reads (text, CSV, JSON, IEC 61131-3, C header, SVG/HTML picture), the container
as C source, and the allocation of network variables (D-15).

Never imports click; the command line is ``dcf2bin/cli/map.py``, ``cli/allocate.py`` and
``compile --format c``.
"""

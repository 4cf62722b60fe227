"""dcf2bin: CANopen DCF/EDS <-> SYS TEC binary DCF segment container.

The Python API (docs/api.md) is importable from here; its names load on first use,
so importing the package stays cheap: it must not pull in canopen or construct,
so that ``dcf2bin --help`` and ``--version`` stay fast.

    >>> import dcf2bin
    >>> dcf2bin.compile_file("samples/plc.dcf") == open("samples/plc.bin", "rb").read()
    True
"""

__version__ = "0.1.0"

# the names of dcf2bin.api (tests/test_api.py checks that the two lists agree)
_API = ("BinContainer", "CompileError", "CompileOptions", "CompileResult", "DcfResult",
        "Device", "Diagnostic", "DiagnosticWarning", "ReadError", "Severity",
        "compile_file", "compile_path", "dump_json", "dump_text", "from_json", "load",
        "read_container", "to_dcf", "validate",
        "BuildResult", "Network", "build_network", "check_network", "configure_network",
        "load_network")

__all__ = ["__version__", *_API]


def __getattr__(name: str):
    if name in _API:
        from dcf2bin import api
        value = getattr(api, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'dcf2bin' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_API))

"""Small builders for test inputs."""
from __future__ import annotations

from dcf2bin import model
from dcf2bin.compiler import CompileOptions, compile_device


def dcf(text: str) -> bytes:
    """Dedent-free DCF text -> bytes (tests write sections flush left)."""
    return text.strip("\n").encode("utf-8") + b"\n"


def nv_objects(spec: dict[int, list[int]], datatype: dict[int, str] | None = None) -> str:
    """Network-variable ARRAY objects: {index: [subindexes]} -> DCF text."""
    out = []
    for idx, subs in spec.items():
        out.append(f"[{idx:04X}]\nObjectType=0x8\nSubNumber={len(subs) + 1}\n")
        for s in subs:
            dt = f"DataType={datatype[idx]}\n" if datatype and idx in datatype else ""
            out.append(f"[{idx:04X}sub{s:X}]\nParameterName=V{idx:04X}_{s}\n{dt}")
    return "\n".join(out)


def load_text(text: str, name: str = "test.dcf", **kw) -> model.Device:
    return model.load(name, data=dcf(text), **kw)


def compile_text(text: str, name: str = "test.dcf", node_id: int | None = None, **opts):
    dev = load_text(text, name, node_id=node_id)
    return compile_device(dev, CompileOptions(node_id=node_id, **opts))


def messages(result_or_diags, severity: str = "error") -> list[str]:
    diags = getattr(result_or_diags, "diagnostics", result_or_diags)
    return [d.format() for d in diags if d.severity.value == severity]

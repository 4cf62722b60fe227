"""The value problems of a ``Device`` that compile reports only for what it writes (SPEC
"Errors vs warnings"): ``text_problem`` and ``value_problems``.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt, values
from dcf2bin.diagnostics import DcfError, Diagnostic, Severity
from dcf2bin.indexes import is_pdo_mapping
from dcf2bin.model.objects import Entry, Problem, unstated_mapping_count
from dcf2bin.model.sections import _clip


class _ValueChecks:
    """The value problems of a ``Device`` that compile does not write (SPEC "Errors vs
    warnings"): ``text_problem`` and ``value_problems``.
    """

    # -- values compile does not write (SPEC "Errors vs warnings") -----------------------
    def text_problem(self, dtype: dt.DataType, text: str) -> str | None:
        """What is wrong with ``text`` as a value of ``dtype`` (None: nothing), in the
        words of validate's DCF200. Without a node-ID, a ``$NODEID`` value must fit for
        node-IDs 1 and 127. Remembered per (type, text): a file repeats few value texts."""
        key = (dtype.code, text)
        verdicts = self._verdicts
        if key in verdicts:
            return verdicts[key]
        if key in self.encoded:   # encoded once already, so nothing is wrong with it
            return None
        number = text
        if dtype.is_numeric or dtype.kind == dt.BOOL:
            number = values.split_numeric_comment(text)[0]   # DCF203 is validate's
        problem = None
        try:
            values.encode(dtype, number, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            for trial in (1, 127):
                try:
                    values.encode(dtype, number, node_id=trial, encoding=self.encoding)
                except values.ValueProblem as exc:
                    problem = f"{_clip(str(exc))} (with node-ID {trial})"
                    break
        except values.ValueProblem as exc:
            problem = _clip(str(exc))
        if len(verdicts) < 4096:
            verdicts[key] = problem
        return problem

    def value_problems(self, written, whole: set[int] | frozenset = frozenset()
                       ) -> list[Problem]:
        """The values in the file that cannot be encoded (DCF200) and the unreadable
        DownloadFiles (DCF202), as errors, except the effective value of every entry that
        ``written(index, sub)`` says is written (encoding it reports its own error);
        ``whole`` are objects written whole. ``written(index, None)``: any entry of the
        object. ``compile`` prints these as warnings; a large PLC file costs a few
        attribute reads per variable (its values are all written)."""
        out: list[Problem] = []
        seen: set = set()   # CompactSubObj: one DefaultValue line for N entries
        for idx, obj in self.objects.items():
            in_whole = idx in whole
            if in_whole and not is_pdo_mapping(idx):
                # every effective value is written (60,000 network variables): only a
                # DefaultValue behind a ParameterValue/DownloadFile is not
                for e in obj.entries.values():
                    if e.default is not None and (e.param is not None or e.download_file
                                                  is not None) and e.dtype is not None \
                            and not e.implicit:
                        self._text_check(out, seen, e, "defaultvalue", e.default)
                continue
            some = in_whole or written(idx, None)
            for sub, e in obj.entries.items():
                if e.dtype is None or e.implicit:
                    continue
                param, default = e.param, e.default
                behind = param is not None or e.download_file is not None
                if default is not None and behind:
                    self._text_check(out, seen, e, "defaultvalue", default)
                if in_whole or (some and written(idx, sub)):
                    continue   # the effective value is written
                if param is not None:
                    self._text_check(out, seen, e, "parametervalue", param)
                elif e.download_file is not None:
                    try:
                        self._download(e)
                    except DcfError as exc:
                        out.append(Problem(exc.diagnostic, idx, sub))
                elif default is not None:
                    self._text_check(out, seen, e, "defaultvalue", default)
            if is_pdo_mapping(idx) and not (some and written(idx, 0)):
                unstated = unstated_mapping_count(obj)
                if unstated is not None:
                    where, message = unstated
                    out.append(Problem(Diagnostic(Severity.ERROR, message, where.file,
                                                  where.line, rule="DCF419"), idx, 0))
        return out

    def _text_check(self, out: list, seen: set, e: Entry, key: str, text: str) -> None:
        k = (e.dtype.code, text)
        if k in self.encoded or (k in self._verdicts and self._verdicts[k] is None):
            return          # encoded already, or found fine before (text_problem's answer)
        problem = self.text_problem(e.dtype, text)
        if problem is None:
            return
        line = e.key_where(key).line
        if (line, e.dtype.code, text) in seen:
            return
        seen.add((line, e.dtype.code, text))
        shown = "ParameterValue" if key == "parametervalue" else "DefaultValue"
        out.append(Problem(Diagnostic(Severity.ERROR, f"{e.label} {shown}: {problem}",
                                      self.path, line, rule="DCF200"), e.index, e.sub))

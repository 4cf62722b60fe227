"""Commands: dump and bin2dcf: containers to text (issue 3)."""
from __future__ import annotations

COMMANDS: list = []

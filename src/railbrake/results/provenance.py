"""Who made a result: railbrake version, the C core's version and build hash, command line, date."""

from __future__ import annotations

import shlex
import sys
from datetime import datetime, timezone

import railbrake


def provenance(command_line: list[str] | None = None) -> dict:
    from railbrake import _core
    args = sys.argv if command_line is None else command_line
    # the CLI, however started (entry point, python -m, python -c): its arguments after "railbrake"
    script = args[0] if args else ""
    name = script if script.endswith(".py") and not script.endswith("__main__.py") else "railbrake"
    return {"railbrake_version": railbrake.__version__,
            "core_version": _core.rb_version().decode(),
            "core_build_hash": _core.rb_build_hash().decode(),
            "command_line": shlex.join([name, *args[1:]]) if args else "",
            "date": datetime.now(timezone.utc).isoformat(timespec="seconds")}

"""Who made a result: railbrake version, the C core's version and build hash, command line, date."""

from __future__ import annotations

import shlex
import sys
from datetime import datetime, timezone

from railbrake._version import __version__


def _current_context():
    """click's current context (typer >= 0.23 carries its own copy of click as typer._click)."""
    try:
        from typer._click.globals import get_current_context
    except ImportError:
        from click import get_current_context
    return get_current_context(silent=True)


def _from_click() -> list[str] | None:
    """The running CLI command as given (options left at their defaults omitted), rebuilt from
    click's context: sys.argv is not the command when the CLI is called in-process (tests)."""
    ctx = _current_context()
    if ctx is None:
        return None
    words = ["railbrake", *ctx.command_path.split()[1:]]
    for param in ctx.command.params:
        source = ctx.get_parameter_source(param.name)
        if source is None or source.name == "DEFAULT":
            continue
        value = ctx.params.get(param.name)
        values = list(value) if isinstance(value, (list, tuple)) else [value]
        if param.param_type_name == "argument":
            words += [str(v) for v in values]
        elif getattr(param, "is_flag", False):
            words += [param.opts[0]] if value else []
        else:
            for v in values:
                words += [param.opts[0], str(v)]
    return words


def provenance(command_line: list[str] | None = None) -> dict:
    from railbrake import _core
    words = command_line or _from_click() or ["python", *sys.argv]
    return {"railbrake_version": __version__,
            "core_version": _core.rb_version().decode(),
            "core_build_hash": _core.rb_build_hash().decode(),
            "command_line": shlex.join(words),
            "date": datetime.now(timezone.utc).isoformat(timespec="seconds")}

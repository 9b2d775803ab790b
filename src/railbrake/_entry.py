"""The `railbrake` command's entry point: Ctrl-C while the command line is still being imported or
built (a few hundred ms of numpy, typer, rich) ends with status 130 and one line, not a traceback;
once a command runs, it handles Ctrl-C itself."""

import sys


def _interrupted(exc: BaseException) -> bool:
    """A Ctrl-C, also when Python wrapped it on the way (a KeyboardInterrupt inside a class body's
    __set_name__ reaches us as the RuntimeError it caused)."""
    while exc is not None:
        if isinstance(exc, KeyboardInterrupt):
            return True
        exc = exc.__cause__ or exc.__context__
    return False


def main() -> None:
    try:
        from railbrake.cli import main as cli_main
        cli_main()
    except BaseException as exc:   # noqa: B036 (re-raised unless it is a Ctrl-C)
        if not _interrupted(exc):
            raise
        sys.stderr.write("interrupted\n")
        sys.exit(130)

"""The `railbrake` command's entry point: Ctrl-C while the command line is still being imported or
built (a few hundred ms of numpy, typer, rich) ends with status 130 and one line, not a traceback;
once a command runs, it handles Ctrl-C itself."""

import sys


def main() -> None:
    try:
        from railbrake.cli import main as cli_main
        cli_main()
    except KeyboardInterrupt:
        sys.stderr.write("interrupted\n")
        sys.exit(130)

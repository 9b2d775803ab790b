"""The `railbrake` command's entry point: Ctrl-C while the command line is still being imported (a
few hundred ms of numpy, typer, rich) ends with status 130 and one line, not a traceback."""

import sys


def main() -> None:
    try:
        from railbrake.cli import main as cli_main
    except KeyboardInterrupt:
        sys.stderr.write("interrupted\n")
        sys.exit(130)
    cli_main()

"""The ``railbrake`` command line. Each concern registers its commands in its own module, listed in
railbrake.cli.root.COMMANDS (imported when a command is used); the root command and main() are in
railbrake.cli.root."""

from railbrake.cli.root import app, main  # app: the Typer app (its tests run it)

__all__ = ["main"]

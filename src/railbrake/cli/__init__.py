"""The ``railbrake`` command line. Each concern registers its commands in its own module; the root
command and main() are in railbrake.cli.root."""

from railbrake.cli.root import app, main

__all__ = ["app", "main"]

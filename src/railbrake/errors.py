"""Exceptions raised by railbrake."""


class InputError(ValueError):
    """Bad input: the message names the argument, its value and the allowed range."""

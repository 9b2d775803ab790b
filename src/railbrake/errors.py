"""Exceptions raised by railbrake."""


class InputError(ValueError):
    """Bad input: the message names the argument, its value and the allowed range."""


class ReadOnlyError(InputError, AttributeError):
    """An assignment to a loaded configuration (scenario, train, study): they are immutable, so a
    change cannot bypass validation or be silently ignored; ``with_(...)`` makes a changed copy."""

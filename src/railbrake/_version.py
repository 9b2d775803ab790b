"""The package's version (pyproject.toml's), at the bottom so every layer may name it."""

__version__ = "0.1.0"

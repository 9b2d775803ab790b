"""Output files whole or absent. Every file railbrake writes is written under a temporary name in
its own folder (`.NAME.PID.tmp.SUFFIX`, hidden, the suffix kept for writers that infer the format
from it) and renamed to its final name only once complete: os.replace is atomic within one file
system, so a process killed at any moment leaves under the final name the whole new file, the
whole earlier one, or nothing. What a kill leaves under a temporary name is swept by sweep()."""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

_MARK = ".tmp"


def temporary_name(path: Path) -> Path:
    """The temporary beside path this process writes: .timeseries.123.tmp.csv for timeseries.csv."""
    path = Path(path)
    return path.with_name(f".{path.stem}.{os.getpid()}{_MARK}{path.suffix}")


def is_temporary(path: Path) -> bool:
    """Whether path is a temporary left by replacing() (never a finished output)."""
    name = Path(path).name
    return name.startswith(".") and _MARK in name


@contextmanager
def replacing(path: Path | str):
    """Yields the temporary path to write; renames it to path when the block ends without an
    exception, else removes it (path is then untouched)."""
    path = Path(path)
    temporary = temporary_name(path)
    try:
        yield temporary
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_text(path: Path | str, text: str, encoding: str = "utf-8") -> Path:
    with replacing(path) as temporary:
        temporary.write_text(text, encoding=encoding)
    return Path(path)


def write_bytes(path: Path | str, data: bytes) -> Path:
    with replacing(path) as temporary:
        temporary.write_bytes(data)
    return Path(path)


def save_figure(fig, path: Path | str, **kwargs) -> Path:
    """fig.savefig(path, **kwargs), whole or absent (the format from path's suffix)."""
    path = Path(path)
    with replacing(path) as temporary:
        import matplotlib
        kind = kwargs.pop("format", None) or path.suffix.lstrip(".") or matplotlib.rcParams["savefig.format"]
        fig.savefig(temporary, format=kind, **kwargs)
    return path


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def sweep(folder: Path | str) -> list[Path]:
    """Removes the temporaries in folder that no living process is writing (a killed writer's);
    returns them."""
    folder = Path(folder)
    swept = []
    for path in folder.glob(f".*{_MARK}*") if folder.is_dir() else ():
        pid = path.name[1:].split(_MARK)[0].rsplit(".", 1)[-1]
        if pid.isdigit() and not _alive(int(pid)):
            path.unlink(missing_ok=True)
            swept.append(path)
    return swept

"""One client at a time on a campaign folder. `campaign run` holds DIR/.lock while it works: an
exclusive flock on the file (the kernel releases it when the holder dies, however it dies), and in
it the holder's host, PID and start time, so that a second client is refused naming the first.
A lock left by a dead process (a flock nobody holds) is taken over."""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import socket
import time
from pathlib import Path

from railbrake.errors import InputError

LOCK = ".lock"


def _holder(handle) -> dict:
    handle.seek(0)
    try:
        holder = json.loads(handle.read() or "{}")
    except ValueError:
        holder = {}
    return holder if isinstance(holder, dict) else {}


def _refusal(out: Path, holder: dict) -> InputError:
    since = holder.get("since")
    when = f" since {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime(since))}" if isinstance(since, (int, float)) else ""
    return InputError(f"--out {out}: in use by another `railbrake campaign run` (host {holder.get('host', '?')}, "
                      f"PID {holder.get('pid', '?')}{when}; lock {out / LOCK}): wait for it to end, "
                      "or run into another folder")


@contextlib.contextmanager
def holding(out: Path):
    """Holds the campaign folder out (created) for the block; InputError naming the holder's host
    and PID when another process holds it."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file; give a folder")
    out.mkdir(parents=True, exist_ok=True)
    fd = os.open(out / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    with os.fdopen(fd, "r+") as handle:
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise _refusal(out, _holder(handle)) from None
        try:
            handle.seek(0)
            handle.truncate()
            handle.write(json.dumps({"host": socket.gethostname(), "pid": os.getpid(), "since": time.time()}))
            handle.flush()
            yield
        finally:
            handle.seek(0)
            handle.truncate()   # released: no holder named any more
            fcntl.flock(handle.fileno(), fcntl.LOCK_UN)

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


def _refusal(out: Path, holder: dict, command: str) -> InputError:
    since = holder.get("since")
    when = f" since {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime(since))}" if isinstance(since, (int, float)) else ""
    return InputError(f"--out {out}: in use by another `{command}` (host {holder.get('host', '?')}, "
                      f"PID {holder.get('pid', '?')}{when}; lock {out / LOCK}): wait for it to end, "
                      "or run into another folder")


def _open_locked(out: Path, command: str):
    """The lock file, open and flocked by this process; InputError naming the holder. A lock file
    removed by its holder between our open and our flock (released with an empty folder) is opened
    again, so that two clients never hold two files."""
    while True:
        handle = os.fdopen(os.open(out / LOCK, os.O_RDWR | os.O_CREAT, 0o644), "r+")
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(handle)
            handle.close()
            raise _refusal(out, holder, command) from None
        try:
            same = os.stat(out / LOCK).st_ino == os.fstat(handle.fileno()).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return handle
        handle.close()


@contextlib.contextmanager
def holding(out: Path, command: str = "railbrake campaign run"):
    """Holds the campaign folder out (created) for the block; InputError naming the holder's host
    and PID (and `command`, what holds such folders) when another process holds it. A folder made
    here that holds nothing else when the block ends (e.g. the scheduler did not answer) is removed
    again."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file; give a folder")
    created = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    handle = _open_locked(out, command)
    try:
        handle.seek(0)
        handle.truncate()
        handle.write(json.dumps({"host": socket.gethostname(), "pid": os.getpid(), "since": time.time()}))
        handle.flush()
        yield
    finally:
        handle.seek(0)
        handle.truncate()   # released: no holder named any more
        if created and [p.name for p in out.iterdir()] == [LOCK]:
            (out / LOCK).unlink()   # still locked: a client that opened it meanwhile opens again
            out.rmdir()
        handle.close()   # closing releases the flock

"""The HIL link's key file (docs/hil-interface.md, authentication): 128 bits both sides are given,
from which each session's key is derived. One line of 32 hexadecimal digits; lines starting with '#'
and blank lines are comments. Only a regular file, readable by its owner alone, is read."""

from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path

from railbrake import _core
from railbrake.errors import InputError

KEY_SIZE = _core.HIL_KEY_SIZE
MAX_FILE_SIZE = 4096   # bytes: a key file is one line and a comment


def read_key(path: Path | str) -> bytes:
    """The 16 key bytes of the key file at path; InputError names the file, the line and what is wrong
    (never the key)."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)   # a FIFO must not block the open
    except OSError as exc:
        raise InputError(f"key file {path}: {exc.strerror}") from None
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):   # checked on the descriptor: a directory cannot be read as a file
        os.close(fd)
        kind = "a directory" if stat.S_ISDIR(info.st_mode) else "not a regular file"
        raise InputError(f"key file {path}: {kind}: give the path of the key file (`railbrake hil-key FILE` "
                         "makes one)")
    with os.fdopen(fd, "rb") as f:
        if info.st_mode & 0o077:
            raise InputError(f"key file {path}: mode {stat.S_IMODE(info.st_mode):04o} lets others read it: "
                             f"chmod 600 {path}")
        data = f.read(MAX_FILE_SIZE + 1)
    if len(data) > MAX_FILE_SIZE:
        raise InputError(f"key file {path}: larger than {MAX_FILE_SIZE} bytes")
    return _parse(path, data)


def _parse(path: Path, data: bytes) -> bytes:
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise InputError(f"key file {path}: not ASCII text") from None
    keys = [(number, line.strip()) for number, line in enumerate(text.splitlines(), 1)
            if line.strip() and not line.strip().startswith("#")]
    if len(keys) != 1:
        raise InputError(f"key file {path}: {len(keys)} key lines: expected one line of {2 * KEY_SIZE} "
                         "hexadecimal digits")
    number, line = keys[0]
    if len(line) != 2 * KEY_SIZE or any(c not in "0123456789abcdefABCDEF" for c in line):
        raise InputError(f"key file {path}, line {number}: {len(line)} characters: expected {2 * KEY_SIZE} "
                         "hexadecimal digits (a 128-bit key)")
    key = bytes.fromhex(line)
    weak = weakness(key)
    if weak:
        raise InputError(f"key file {path}, line {number}: {weak}: make a random one with `railbrake hil-key FILE`")
    return key


MIN_DISTINCT = 6   # byte values a key holds at least (a random key holds about 15; fewer: P < 1e-17)


def weakness(key: bytes) -> str | None:
    """Why a key has too little entropy to be a secret (all one byte, a few byte values, a counting
    sequence), or None. Never shows the key."""
    if len(set(key)) == 1:
        return f"every byte the same (0x{key[0]:02x} repeated): too little entropy for a secret"
    if len(set(key)) < MIN_DISTINCT:
        return f"only {len(set(key))} distinct byte values: too little entropy for a secret (a random key " \
               f"holds about 15 of its {KEY_SIZE})"
    if len({(b - a) % 256 for a, b in zip(key, key[1:])}) == 1:
        return "bytes counting up or down by a constant step: too little entropy for a secret"
    return None


def write_key(path: Path | str) -> Path:
    """A new random key file at path (mode 600; an existing file is not overwritten)."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"key file {path}: a directory: give the path of a new file")
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        raise InputError(f"key file {path}: exists (a key is not overwritten)") from None
    except OSError as exc:
        raise InputError(f"key file {path}: {exc.strerror}") from None
    with os.fdopen(fd, "w") as f:
        f.write("# railbrake HIL key (docs/hil-interface.md): give this file to the plant and the BCU\n")
        f.write(secrets.token_bytes(KEY_SIZE).hex() + "\n")
    return path


def key_bytes(key) -> bytes:
    """A key given as its 16 bytes or as the path of a key file."""
    if isinstance(key, (bytes, bytearray)):
        if len(key) != KEY_SIZE:
            raise InputError(f"key: {len(key)} bytes: expected {KEY_SIZE}")
        weak = weakness(bytes(key))
        if weak:
            raise InputError(f"key: {weak}: use a random key (secrets.token_bytes({KEY_SIZE}) or a key file)")
        return bytes(key)
    if isinstance(key, (str, os.PathLike)):
        return read_key(key)
    raise InputError("key: the HIL link is authenticated (docs/hil-interface.md): give the key file's path "
                     f"or its {KEY_SIZE} bytes (`railbrake hil-key FILE` makes one)")

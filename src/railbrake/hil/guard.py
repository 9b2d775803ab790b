"""What keeps the HIL run's TCP servers (control socket, dashboard) open to their operator whatever
other clients do (docs/hil.md, faults at run time): a cap on the connections open at once, overall
and per peer address, where a new connection takes the place of the oldest one that has not
authenticated (so idle or hostile connections cannot lock the operator out), a read timeout per
connection, a bound on the nesting of JSON, and a count of the errors a handler did not expect
(answered, never a traceback)."""

from __future__ import annotations

import json
import socket
import sys
import threading
import time

MAX_CONNECTIONS = 16     # open at once, all peers together
MAX_PER_PEER = 8         # open at once from one address
READ_TIMEOUT = 10.0      # s a connection may stay silent (mid-request or between requests)
MAX_DEPTH = 8            # nesting of JSON objects and arrays: a command needs 2


class Guard:
    """The connections a server holds: admit() each new one (it may close the oldest one not
    authenticated to make room, or refuse the new one: False), authenticated() once it carried the
    token, release() when it ends."""

    def __init__(self, max_connections: int = MAX_CONNECTIONS, max_per_peer: int = MAX_PER_PEER):
        self.max_connections, self.max_per_peer = max_connections, max_per_peer
        self._lock = threading.Lock()
        self._open: dict[socket.socket, list] = {}   # socket -> [peer, last activity, authenticated]
        self.evicted = self.refused = self.unexpected = 0

    def admit(self, sock: socket.socket, peer: str) -> bool:
        with self._lock:
            while True:
                same = [s for s, entry in self._open.items() if entry[0] == peer]
                if len(same) >= self.max_per_peer:
                    crowded = same
                elif len(self._open) >= self.max_connections:
                    crowded = list(self._open)
                else:
                    break
                idle = [s for s in crowded if not self._open[s][2]]
                if not idle:   # all of them carried the token: the newcomer waits its turn
                    self.refused += 1
                    return False
                self._close(min(idle, key=lambda s: self._open[s][1]))
            self._open[sock] = [peer, time.monotonic(), False]
            return True

    def _close(self, sock: socket.socket) -> None:
        """Ends a connection another thread serves: its blocked read returns end of stream."""
        self._open.pop(sock, None)
        self.evicted += 1
        try:
            sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass

    def active(self, sock: socket.socket, authenticated: bool = False) -> None:
        with self._lock:
            entry = self._open.get(sock)
            if entry is not None:
                entry[1] = time.monotonic()
                entry[2] = entry[2] or authenticated

    def release(self, sock: socket.socket) -> None:
        with self._lock:
            self._open.pop(sock, None)

    def count(self) -> int:
        with self._lock:
            return len(self._open)

    def unexpected_error(self, where: str, exc: BaseException) -> None:
        """An error no check foresaw: counted and told in one line (the request got an error answer)."""
        self.unexpected += 1
        print(f"{where}: unexpected {type(exc).__name__}: {exc}", file=sys.stderr)


def no_delay(sock: socket.socket) -> None:
    """Answers leave at once (no Nagle wait for the peer's delayed acknowledgement: 40 ms a reply)."""
    try:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    except OSError:
        pass


class Guarded:
    """The part a socketserver server (this class first among its bases) shares with the other HIL
    server: each connection admitted by self.guard, a refused one answered with self.busy and closed,
    an error a handler did not expect counted under self.name."""

    guard: Guard
    name: str
    busy: bytes

    def process_request(self, request, client_address):
        if self.guard.admit(request, client_address[0]):
            no_delay(request)
            return super().process_request(request, client_address)
        try:   # every connection of this peer carried the token: the newcomer waits
            request.settimeout(1.0)
            request.sendall(self.busy)
        except OSError:
            pass
        self.shutdown_request(request)

    def handle_error(self, request, client_address):
        exc = sys.exc_info()[1]
        if not isinstance(exc, OSError):
            self.guard.unexpected_error(self.name, exc)


def json_depth(text: bytes | str, limit: int = MAX_DEPTH) -> int:
    """The deepest nesting of objects and arrays in JSON text (strings skipped), without parsing it,
    found up to limit + 1 (the scan stops there): checked before json.loads, whose recursion a deep
    text would exhaust."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    if text.count("[") + text.count("{") <= limit:
        return text.count("[") + text.count("{")   # an upper bound within the limit: no need to scan
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
            if deepest > limit:
                break
        elif ch in "]}":
            depth -= 1
    return deepest


def load_json(text: bytes, what: str):
    """JSON of at most MAX_DEPTH levels; ValueError saying what is wrong otherwise."""
    if json_depth(text) > MAX_DEPTH:
        raise ValueError(f"{what}: JSON nested more than {MAX_DEPTH} levels deep: at most {MAX_DEPTH}")
    try:
        return json.loads(text)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{what}: not JSON ({exc})") from None

"""The HIL run's control socket (docs/hil.md, faults at run time): one JSON object per line over
TCP, each answered with one JSON line. Commands carry the run's token:

    {"token": "...", "command": "inject", "fault": {"type": "vent_stuck_open", "car": 3, "axle": 2}}
    {"token": "...", "command": "clear", "fault": {"type": "vent_stuck_open", "car": 3, "axle": 2}}
    {"token": "...", "command": "faults"}            (the changes applied so far)

Answers: {"ok": true, "time_s": ..., "step": ..., "text": ...} or {"ok": false, "error": "..."}.
A bad command is refused and changes nothing; a line over MAX_LINE bytes is answered with an error
and the connection stays open. No client can lock the operator out (guard.Guard: connections
capped per peer and overall, the oldest one that never carried the token closed to make room, reads
time out, JSON nesting bounded). The plant loop never waits on this socket (it runs in its own
thread and posts changes into the loop's mailbox, faults.FaultSwitch)."""

from __future__ import annotations

import hmac
import json
import secrets
import socketserver
import threading

from railbrake.errors import InputError
from railbrake.hil import guard
from railbrake.hil.faults import FaultSwitch

MAX_LINE = 4096          # bytes of one command; a longer line is answered with an error, the connection kept
MAX_SKIPPED = 1 << 20    # bytes of one over-long line read past before the connection is closed
COMMAND_KEYS = {"inject": {"token", "command", "fault"}, "clear": {"token", "command", "fault"},
                "faults": {"token", "command"}}


def new_token() -> str:
    return secrets.token_hex(16)


def answer(switch: FaultSwitch, token: str, line: bytes, origin: str = "control") -> dict:
    """The answer to one command line (never raises for bad input: says what is wrong)."""
    return respond(switch, token, line, origin)[0]


def respond(switch: FaultSwitch, token: str, line: bytes, origin: str = "control",
            authenticated: bool = False) -> tuple[dict, bool]:
    """The answer to one command line and whether it carried the token (or came on a connection that
    did: authenticated, the dashboard's header). Bad input of any kind is answered, never raised."""
    try:
        command = _command(line)
        authenticated = _authenticate(command, token, authenticated)
        return {"ok": True, **_execute(switch, command, origin)}, True
    except InputError as exc:
        return {"ok": False, "error": str(exc)}, authenticated


def _command(line: bytes) -> dict:
    try:
        command = guard.load_json(line, "control command")
    except ValueError as exc:
        raise InputError(f"{exc}: expected one JSON object per line") from None
    if not isinstance(command, dict):
        raise InputError(f"control command: {type(command).__name__}: expected a JSON object")
    return command


def _authenticate(command: dict, token: str, authenticated: bool) -> bool:
    given = command.get("token")
    if authenticated and given is None:
        return True
    if not isinstance(given, str) or not hmac.compare_digest(given.encode(), token.encode()):
        raise InputError("control command: token missing or wrong: give the run's control token (printed "
                         "when the run starts)")
    return True


def _execute(switch: FaultSwitch, command: dict, origin: str) -> dict:
    name = command.get("command")
    if not isinstance(name, str) or name not in COMMAND_KEYS:
        raise InputError(f"control command: command = {_shown(name)}: must be one of {', '.join(COMMAND_KEYS)}")
    unknown = sorted(set(command) - COMMAND_KEYS[name])
    if unknown:
        raise InputError(f"control command {name}: unknown key(s) {', '.join(_shown(k) for k in unknown[:5])}: "
                         f"allowed {', '.join(sorted(COMMAND_KEYS[name]))}")
    if name == "faults":
        return {"changes": [c.as_dict() for c in switch.changes]}
    change = switch.change(name, command.get("fault"), origin=origin)
    return {"time_s": change.time_s, "step": change.step, "text": change.text}


def _shown(value) -> str:
    """A value for an error message, cut short (a hostile line may carry kilobytes)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class ControlServer:
    """Serves the control socket on host:port (port 0: any free one, see .port) in threads of its
    own until stop()."""

    def __init__(self, switch: FaultSwitch, host: str = "127.0.0.1", port: int = 0, token: str | None = None):
        self.token = token or new_token()
        self.guard = guard.Guard()
        switch_, token_, guard_ = switch, self.token, self.guard

        class Handler(socketserver.StreamRequestHandler):
            timeout = guard.READ_TIMEOUT   # a silent connection is closed

            def handle(self):
                try:
                    self._serve()
                except OSError:   # the peer went away or stayed silent for READ_TIMEOUT
                    pass
                except Exception as exc:   # noqa: BLE001 - counted and told in one line, never a traceback
                    guard_.unexpected_error("control", exc)
                    self._send({"ok": False, "error": f"control: internal error ({type(exc).__name__})"})
                finally:
                    guard_.release(self.request)

            def _serve(self):
                while line := self.rfile.readline(MAX_LINE + 1):
                    if len(line) > MAX_LINE and not line.endswith(b"\n"):
                        if not self._skip_line():
                            return
                        self._send({"ok": False, "error": f"control command: longer than {MAX_LINE} bytes: "
                                                          "one JSON object per line, at most that long"})
                    elif line.strip():
                        reply, authenticated = respond(switch_, token_, line)
                        guard_.active(self.request, authenticated)
                        self._send(reply)

            def _skip_line(self) -> bool:
                """Reads past the rest of an over-long line; False if it never ends (closed)."""
                skipped = 0
                while skipped < MAX_SKIPPED:
                    chunk = self.rfile.readline(MAX_LINE + 1)
                    if not chunk:
                        return False
                    if chunk.endswith(b"\n"):
                        return True
                    skipped += len(chunk)
                self._send({"ok": False, "error": f"control command: no end of line in {MAX_SKIPPED} bytes: "
                                                  "connection closed"})
                return False

            def _send(self, reply: dict):
                try:
                    self.wfile.write((json.dumps(reply) + "\n").encode())
                except OSError:
                    pass

        class Server(guard.Guarded, socketserver.ThreadingTCPServer):
            daemon_threads = True
            allow_reuse_address = True
            guard, name = guard_, "control"
            busy = json.dumps({"ok": False, "error": "control: all connections busy with authenticated clients: "
                                                     "retry"}).encode() + b"\n"

        try:
            self._server = Server((host, port), Handler)
        except (OSError, OverflowError) as exc:
            raise InputError(f"control socket {host}:{port}: {getattr(exc, 'strerror', None) or exc}") from None
        self.host, self.port = self._server.server_address[:2]
        self._thread = threading.Thread(target=self._server.serve_forever, kwargs={"poll_interval": 0.1},
                                        name="railbrake-control", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._server.shutdown()
        self._server.server_close()
        self._thread.join()

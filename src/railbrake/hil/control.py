"""The HIL run's control socket (docs/hil.md, faults at run time): one JSON object per line over
TCP, each answered with one JSON line. Commands carry the run's token:

    {"token": "...", "command": "inject", "fault": {"type": "vent_stuck_open", "car": 3, "axle": 2}}
    {"token": "...", "command": "clear", "fault": {"type": "vent_stuck_open", "car": 3, "axle": 2}}
    {"token": "...", "command": "faults"}            (the changes applied so far)

Answers: {"ok": true, "time_s": ..., "step": ..., "text": ...} or {"ok": false, "error": "..."}.
A bad command is refused and changes nothing; the plant loop never waits on this socket (it runs in
its own thread and posts changes into the loop's mailbox, faults.FaultSwitch)."""

from __future__ import annotations

import hmac
import json
import secrets
import socketserver
import threading

from railbrake.errors import InputError
from railbrake.hil.faults import FaultSwitch

MAX_LINE = 4096          # bytes of one command; a longer line is refused and the connection closed
MAX_CONNECTIONS = 8      # open at once; more are refused
COMMAND_KEYS = {"inject": {"token", "command", "fault"}, "clear": {"token", "command", "fault"},
                "faults": {"token", "command"}}


def new_token() -> str:
    return secrets.token_hex(16)


def answer(switch: FaultSwitch, token: str, line: bytes, origin: str = "control") -> dict:
    """The answer to one command line (never raises for bad input: says what is wrong)."""
    try:
        return {"ok": True, **_execute(switch, token, line, origin)}
    except InputError as exc:
        return {"ok": False, "error": str(exc)}


def _execute(switch: FaultSwitch, token: str, line: bytes, origin: str) -> dict:
    try:
        command = json.loads(line)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"control command: not JSON ({exc}): expected one JSON object per line") from None
    if not isinstance(command, dict):
        raise InputError(f"control command: {type(command).__name__}: expected a JSON object")
    given = command.get("token")
    if not isinstance(given, str) or not hmac.compare_digest(given.encode(), token.encode()):
        raise InputError("control command: token missing or wrong: give the run's control token (printed "
                         "when the run starts)")
    name = command.get("command")
    if name not in COMMAND_KEYS:
        raise InputError(f"control command: command = {name!r}: must be one of {', '.join(COMMAND_KEYS)}")
    unknown = sorted(set(command) - COMMAND_KEYS[name])
    if unknown:
        raise InputError(f"control command {name}: unknown key(s) {', '.join(unknown)}: allowed "
                         f"{', '.join(sorted(COMMAND_KEYS[name]))}")
    if name == "faults":
        return {"changes": [c.as_dict() for c in switch.changes]}
    change = switch.change(name, command.get("fault"), origin=origin)
    return {"time_s": change.time_s, "step": change.step, "text": change.text}


class ControlServer:
    """Serves the control socket on host:port (port 0: any free one, see .port) in threads of its
    own until stop()."""

    def __init__(self, switch: FaultSwitch, host: str = "127.0.0.1", port: int = 0, token: str | None = None):
        self.token = token or new_token()
        switch_, token_ = switch, self.token
        slots = threading.BoundedSemaphore(MAX_CONNECTIONS)

        class Handler(socketserver.StreamRequestHandler):
            def handle(self):
                if not slots.acquire(blocking=False):
                    self._send({"ok": False, "error": f"control: {MAX_CONNECTIONS} connections open already"})
                    return
                try:
                    while line := self.rfile.readline(MAX_LINE + 1):
                        if len(line) > MAX_LINE:
                            self._send({"ok": False, "error": f"control command: longer than {MAX_LINE} bytes"})
                            return
                        if line.strip():
                            self._send(answer(switch_, token_, line))
                finally:
                    slots.release()

            def _send(self, reply: dict):
                self.wfile.write((json.dumps(reply) + "\n").encode())

        class Server(socketserver.ThreadingTCPServer):
            daemon_threads = True
            allow_reuse_address = True

        try:
            self._server = Server((host, port), Handler)
        except OSError as exc:
            raise InputError(f"control socket {host}:{port}: {exc.strerror}") from None
        self.host, self.port = self._server.server_address[:2]
        self._thread = threading.Thread(target=self._server.serve_forever, kwargs={"poll_interval": 0.1},
                                        name="railbrake-control", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._server.shutdown()
        self._server.server_close()
        self._thread.join()

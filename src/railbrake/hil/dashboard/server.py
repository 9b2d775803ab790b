"""The dashboard's web server: the page, its static files and the API (token-checked) over
the run's live view and fault switch (railbrake.hil.dashboard)."""

from __future__ import annotations

import hmac
import ipaddress
import json
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from urllib.parse import parse_qs, urlsplit

from railbrake import _core
from railbrake.errors import InputError
from railbrake.hil import control, guard
from railbrake.hil.faults import FaultSwitch
from railbrake.hil.live import LiveView
from railbrake.scenario import FAULT_VALUE

STATIC = {"/": ("index.html", "text/html; charset=utf-8"),
          "/dashboard.js": ("dashboard.js", "text/javascript; charset=utf-8"),
          "/dashboard.css": ("dashboard.css", "text/css; charset=utf-8")}
MAX_BODY = control.MAX_LINE
MAX_QUERY_FIELDS = 20


def _static(name: str) -> bytes:
    return (resources.files("railbrake.hil.dashboard") / "static" / name).read_bytes()


class Dashboard:
    """Serves the page and its API in threads of its own until stop(); stop_requested() says
    whether the page asked to stop the run."""

    def __init__(self, host: str = "127.0.0.1", port: int = 0, token: str | None = None, cars: int = 1):
        self.token = token or control.new_token()
        self.loopback = _loopback(host, port)
        self.guard = guard.Guard()
        self.view: LiveView | None = None
        self.switch: FaultSwitch | None = None
        self.cars = cars
        self._stop = threading.Event()
        handler = _handler(self)
        try:
            self._server = _Server(self.guard, (host, port), handler)
        except (OSError, ValueError, OverflowError) as exc:
            raise InputError(f"--dashboard {host}:{port}: {getattr(exc, 'strerror', None) or exc}") from None
        self.host, self.port = self._server.server_address[:2]
        self._thread = threading.Thread(target=self._server.serve_forever, kwargs={"poll_interval": 0.1},
                                        name="railbrake-dashboard", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}/?token={self.token}"

    def attach(self, view: LiveView | None = None, switch: FaultSwitch | None = None) -> None:
        self.view = view or self.view
        self.switch = switch or self.switch

    def stop_requested(self) -> bool:
        return self._stop.is_set()

    def info(self) -> dict:
        # fault_values: the key of the value a kind reads (a quantity with its unit, e.g. "1.5 bar")
        return {"cars": self.cars, "axles_per_car": _core.AXLES_PER_CAR, "fault_kinds": list(_core.FAULT_KINDS),
                "fault_values": dict(FAULT_VALUE),
                "atmosphere": None if self.view is None else self.view.atmosphere}

    def authorised(self, token) -> bool:
        return isinstance(token, str) and hmac.compare_digest(token.encode(), self.token.encode())

    def counters(self) -> dict:
        """Connections closed to make room, refused, and errors no check foresaw (0: none)."""
        return {"evicted": self.guard.evicted, "refused": self.guard.refused, "unexpected": self.guard.unexpected}

    def request_stop(self) -> None:
        self._stop.set()

    def close(self) -> None:
        self._server.shutdown()
        self._server.server_close()
        self._thread.join()


def _loopback(host: str, port) -> bool:
    """Whether host is a loopback address; an address that is not a dotted quad (127.1) is refused."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        if host.replace(".", "").isdigit() or ":" in host or not host:
            raise InputError(f"--dashboard {host}:{port}: host = {host!r}: expected an IPv4 address a.b.c.d "
                             "(four numbers 0-255), an IPv6 address or a host name") from None
        return False


class _Server(guard.Guarded, ThreadingHTTPServer):
    daemon_threads = True
    name = "dashboard"
    _BODY = b'{"ok": false, "error": "dashboard: all connections busy with authenticated clients: retry"}'
    busy = (b"HTTP/1.0 503 Service Unavailable\r\nContent-Type: application/json\r\nContent-Length: "
            + str(len(_BODY)).encode() + b"\r\nConnection: close\r\n\r\n" + _BODY)

    def __init__(self, guard_: guard.Guard, address, handler):
        self.guard = guard_
        super().__init__(address, handler)


def _content_length(headers) -> tuple[int, int, str]:
    """(length, 0, "") or (0, HTTP status, why) for a missing, malformed, negative or too large
    Content-Length: refused before anything of the body is read."""
    values = headers.get_all("Content-Length") or []
    if not values:
        return 0, 411, "dashboard: Content-Length missing: a POST declares its body's size"
    if len(set(values)) > 1:
        return 0, 400, "dashboard: Content-Length given twice with different values"
    text = values[0].strip()
    if not text.isascii() or not text.isdigit():
        return 0, 400, f"dashboard: Content-Length = {text[:40]!r}: expected a whole number of bytes >= 0"
    if len(text) > 12 or int(text) > MAX_BODY:
        return 0, 413, f"dashboard: Content-Length = {text[:40]}: a body holds at most {MAX_BODY} bytes"
    return int(text), 0, ""


def _handler(board: Dashboard):
    class Handler(BaseHTTPRequestHandler):
        timeout = guard.READ_TIMEOUT   # a silent connection is closed
        default_request_version = "HTTP/1.0"   # an unparsable request line still gets a status line

        def log_message(self, *args):   # the run's console is the summary's
            pass

        def parse_request(self):
            if not str(self.raw_requestline, "iso-8859-1").split():   # http.server would close without a word
                self.command, self.requestline, self.request_version = None, "", self.default_request_version
                self.send_error(400, "empty request line")
                return False
            return super().parse_request()

        def handle(self):
            try:
                super().handle()
            except OSError:   # the peer went away or stayed silent for READ_TIMEOUT
                pass
            finally:
                board.guard.release(self.request)

        def _reply(self, status: int, body: bytes, kind: str = "application/json") -> None:
            self.send_response(status)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            if status >= 400:
                self.send_header("Connection", "close")
                self.close_connection = True
            self.end_headers()
            self.wfile.write(body)

        def _json(self, status: int, data) -> None:
            self._reply(status, json.dumps(data).encode())

        def _token(self, query: str):
            """The token of `Authorization: Bearer TOKEN`, else of ?token=TOKEN."""
            scheme, _, value = (self.headers.get("Authorization") or "").strip().partition(" ")
            if scheme.lower() == "bearer" and value.strip():
                return value.strip()
            try:
                return parse_qs(query, max_num_fields=MAX_QUERY_FIELDS).get("token", [None])[0]
            except ValueError:   # more fields than any call of the page has: no token taken from it
                return None

        def _guarded(self, serve) -> None:
            """serve(parts) answering any error no check foresaw with 500, counted, never a traceback."""
            try:
                serve(urlsplit(self.path))
            except OSError:
                raise
            except Exception as exc:   # noqa: BLE001 - counted and told in one line
                board.guard.unexpected_error("dashboard", exc)
                self._json(500, {"ok": False, "error": f"dashboard: internal error ({type(exc).__name__})"})

        def do_GET(self):
            self._guarded(self._get)

        def do_POST(self):
            self._guarded(self._post)

        def _unauthorised(self):
            self._json(401, {"ok": False, "error": "dashboard: token missing or wrong: Authorization: Bearer "
                                                   "TOKEN or ?token=TOKEN (the URL printed at the start)"})

        def _get(self, parts):
            token = self._token(parts.query)
            if parts.path in STATIC:
                if not board.loopback and not board.authorised(token):
                    return self._unauthorised()
                name, kind = STATIC[parts.path]
                return self._reply(200, _static(name), kind)
            if not board.authorised(token):
                return self._unauthorised()
            board.guard.active(self.request, True)
            if parts.path == "/api/info":
                return self._json(200, board.info())
            if parts.path == "/api/snapshot":
                return self._json(200, {"ok": True, "snapshot": None if board.view is None else board.view.read(),
                                        "stopping": board.stop_requested()})
            return self._json(404, {"ok": False, "error": f"dashboard: no {parts.path[:80]}"})

        def _post(self, parts):
            if not board.authorised(self._token(parts.query)):   # before anything of the body is read
                return self._unauthorised()
            board.guard.active(self.request, True)
            length, status, why = _content_length(self.headers)
            if status:
                return self._json(status, {"ok": False, "error": why})
            body = self.rfile.read(length)
            if len(body) < length:
                return self._json(400, {"ok": False, "error": f"dashboard: body of {len(body)} bytes: "
                                                              f"Content-Length said {length}"})
            if parts.path == "/api/fault":
                if board.switch is None:
                    return self._json(409, {"ok": False, "error": "dashboard: the run has not started"})
                reply, _ = control.respond(board.switch, board.token, body, origin="dashboard", authenticated=True)
                return self._json(200 if reply["ok"] else 400, reply)
            if parts.path == "/api/stop":
                board.request_stop()
                return self._json(200, {"ok": True})
            return self._json(404, {"ok": False, "error": f"dashboard: no {parts.path[:80]}"})

    return Handler

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
from railbrake.hil import control
from railbrake.hil.faults import FaultSwitch
from railbrake.hil.live import LiveView

STATIC = {"/": ("index.html", "text/html; charset=utf-8"),
          "/dashboard.js": ("dashboard.js", "text/javascript; charset=utf-8"),
          "/dashboard.css": ("dashboard.css", "text/css; charset=utf-8")}
MAX_BODY = control.MAX_LINE


def _static(name: str) -> bytes:
    return (resources.files("railbrake.hil.dashboard") / "static" / name).read_bytes()


class Dashboard:
    """Serves the page and its API in threads of its own until stop(); stop_requested() says
    whether the page asked to stop the run."""

    def __init__(self, host: str = "127.0.0.1", port: int = 0, token: str | None = None, cars: int = 1):
        self.token = token or control.new_token()
        self.loopback = ipaddress.ip_address(host).is_loopback if host.replace(".", "").isdigit() else host == "localhost"
        self.view: LiveView | None = None
        self.switch: FaultSwitch | None = None
        self.cars = cars
        self._stop = threading.Event()
        handler = _handler(self)
        try:
            self._server = ThreadingHTTPServer((host, port), handler)
        except (OSError, ValueError) as exc:
            raise InputError(f"--dashboard {host}:{port}: {getattr(exc, 'strerror', None) or exc}") from None
        self._server.daemon_threads = True
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
        return {"cars": self.cars, "axles_per_car": _core.AXLES_PER_CAR, "fault_kinds": list(_core.FAULT_KINDS),
                "atmosphere": None if self.view is None else self.view.atmosphere}

    def authorised(self, token) -> bool:
        return isinstance(token, str) and hmac.compare_digest(token.encode(), self.token.encode())

    def request_stop(self) -> None:
        self._stop.set()

    def close(self) -> None:
        self._server.shutdown()
        self._server.server_close()
        self._thread.join()


def _handler(board: Dashboard):
    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args):   # the run's console is the summary's
            pass

        def _reply(self, status: int, body: bytes, kind: str = "application/json") -> None:
            self.send_response(status)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def _json(self, status: int, data) -> None:
            self._reply(status, json.dumps(data).encode())

        def do_GET(self):
            parts = urlsplit(self.path)
            token = parse_qs(parts.query).get("token", [None])[0]
            if parts.path in STATIC:
                if not board.loopback and not board.authorised(token):
                    return self._json(403, {"ok": False, "error": "dashboard: token missing or wrong"})
                name, kind = STATIC[parts.path]
                return self._reply(200, _static(name), kind)
            if not board.authorised(token):
                return self._json(403, {"ok": False, "error": "dashboard: token missing or wrong"})
            if parts.path == "/api/info":
                return self._json(200, board.info())
            if parts.path == "/api/snapshot":
                return self._json(200, {"ok": True, "snapshot": None if board.view is None else board.view.read(),
                                        "stopping": board.stop_requested()})
            return self._json(404, {"ok": False, "error": f"dashboard: no {parts.path}"})

        def do_POST(self):
            length = int(self.headers.get("Content-Length") or 0)
            if length > MAX_BODY:
                return self._json(413, {"ok": False, "error": f"dashboard: body over {MAX_BODY} bytes"})
            body = self.rfile.read(length)
            path = urlsplit(self.path).path
            if path == "/api/fault":
                if board.switch is None:
                    return self._json(409, {"ok": False, "error": "dashboard: the run has not started"})
                reply = control.answer(board.switch, board.token, body, origin="dashboard")
                return self._json(200 if reply["ok"] else 400, reply)
            if path == "/api/stop":
                try:
                    token = json.loads(body).get("token")
                except (ValueError, AttributeError):
                    token = None
                if not board.authorised(token):
                    return self._json(403, {"ok": False, "error": "dashboard: token missing or wrong"})
                board.request_stop()
                return self._json(200, {"ok": True})
            return self._json(404, {"ok": False, "error": f"dashboard: no {path}"})

    return Handler

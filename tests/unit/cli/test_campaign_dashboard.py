"""The Dask dashboard's link is printed only when its page answers (a scheduler without the
dashboard's page, e.g. no bokeh, answers 404: that link is not shown)."""

import http.server
import threading

import pytest

from railbrake.cli import campaign


class _Page(http.server.BaseHTTPRequestHandler):
    def do_GET(self):
        self.send_response(200 if self.path == "/status" else 404)
        self.end_headers()

    def log_message(self, *args):
        pass


class _Client:
    def __init__(self, link, served=True):
        self.dashboard_link, self.served = link, served

    def scheduler_info(self):
        return {"services": {"dashboard": 1} if self.served else {}}


@pytest.fixture
def server():
    httpd = http.server.HTTPServer(("127.0.0.1", 0), _Page)
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}"
    httpd.shutdown()


def test_the_link_is_shown_only_when_its_page_answers(server, capsys):
    campaign._show_dashboard(_Client(f"{server}/status"))
    assert f"Dask dashboard: {server}/status" in capsys.readouterr().err
    for client in (_Client(f"{server}/missing"), _Client(f"{server}/status", served=False),
                   _Client("http://127.0.0.1:9/status")):
        campaign._show_dashboard(client)
        assert capsys.readouterr().err == ""

"""The Dask dashboard of `campaign run`: served by default, its link printed only once an HTTP
GET of it succeeds; otherwise one line says why (a scheduler without the dashboard's page, e.g.
no bokeh, answers 404; one serving none; one that does not answer), and `--dashboard off` says
nothing."""

import http.server
import threading

import pytest
from typer.testing import CliRunner

from railbrake.cli import app, campaign

ONE_RUN = """schema: railbrake.study/1
name: dashboard-one-run
base: emergency-250-dry
set: {train.cars: 1, stop.max_time: "5 s", initial_speed: "40 km/h"}
factors:
  adhesion.condition: [dry-medium]
design: {kind: grid}
"""


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
    campaign._dashboard_reporter(True)(_Client(f"{server}/status"))
    assert capsys.readouterr().err == f"Dask dashboard: {server}/status\n"
    whys = {f"{server}/missing": "HTTP 404 (its pages need bokeh)", "http://127.0.0.1:9/status": "no answer"}
    for link, why in whys.items():
        campaign._dashboard_reporter(True)(_Client(link))
        assert capsys.readouterr().err.startswith(f"Dask dashboard: not shown: {link} {why}")
    campaign._dashboard_reporter(True)(_Client(f"{server}/status", served=False))
    assert capsys.readouterr().err == "Dask dashboard: not shown: the scheduler serves none (Dask serves it " \
                                      "with bokeh installed)\n"
    for client in (_Client(f"{server}/missing"), _Client(f"{server}/status", served=False)):   # --dashboard off
        campaign._dashboard_reporter(False)(client)
        assert capsys.readouterr().err == ""


@pytest.mark.slow   # a local Dask cluster: worker processes (not under the sanitizers)
def test_campaign_run_serves_the_dashboard_by_default_and_prints_its_link(tmp_path):
    """A one-run study on a local cluster the command starts and stops: the link it prints
    answered its GET (the page is gone with the cluster once the command ends)."""
    study = tmp_path / "one.yaml"
    study.write_text(ONE_RUN)
    result = CliRunner().invoke(app, ["campaign", "run", str(study), "--out", str(tmp_path / "out"),
                                      "--workers", "1", "--json"])
    assert result.exit_code == 0, result.output
    lines = [line for line in result.stderr.splitlines() if line.startswith("Dask dashboard")]
    assert len(lines) == 1 and lines[0].startswith("Dask dashboard: http://127.0.0.1:"), result.stderr
    assert campaign._answers(lines[0].split(": ", 1)[1]) is not None   # stopped with the command's cluster

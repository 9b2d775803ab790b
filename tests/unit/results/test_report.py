"""report.html: one self-contained file; each KPI row's value equals kpis.json; provenance present."""

import base64
import hashlib
import json
from datetime import datetime
from html.parser import HTMLParser
from pathlib import Path

import pytest

import railbrake
from railbrake import _core


class _Report(HTMLParser):
    def __init__(self):
        super().__init__()
        self.kpis, self.images, self.links, self.table, self.cells, self.provenance = {}, [], [], None, [], {}
        self.shown, self.row, self.in_value = {}, None, False   # the KPI values as the reader sees them

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr" and "data-kpi" in a:
            self.kpis[a["data-kpi"]] = json.loads(a["data-value"])
            self.row = a["data-kpi"]
        if tag == "td" and a.get("class") == "value" and self.row is not None:
            self.in_value = True
        if tag == "img":
            self.images.append(a["src"])
        if tag in ("link", "script") and (a.get("href") or a.get("src")):
            self.links.append(a.get("href") or a.get("src"))
        if tag == "table":
            self.table = a.get("id")
        if tag == "tr":
            self.cells = []

    def handle_data(self, data):
        if self.in_value:
            self.shown[self.row] = self.shown.get(self.row, "") + data
        if self.table == "provenance" and data.strip():
            self.cells.append(data.strip())

    def handle_endtag(self, tag):
        if tag == "td":
            self.in_value = False
        if tag == "tr":
            self.row = None
        if tag == "tr" and self.table == "provenance" and len(self.cells) == 2:
            self.provenance[self.cells[0]] = self.cells[1]
        if tag == "table":
            self.table = None


def _parse(path: Path) -> _Report:
    report = _Report()
    report.feed(path.read_text(encoding="utf-8"))
    return report


def test_every_kpi_of_the_report_equals_kpis_json(saved_run):
    out, kpis = saved_run
    report = _parse(out / "report.html")
    assert json.loads((out / "kpis.json").read_text()) == kpis
    assert report.kpis == kpis
    assert report.kpis.keys() == kpis.keys() == report.shown.keys()
    for key, value in kpis.items():       # the text shown, to its 6 significant digits
        shown = report.shown[key]
        if value is None or isinstance(value, (bool, str)):
            assert shown == {None: "n/a", True: "yes", False: "no"}.get(value, value), key
        else:
            assert float(shown) == pytest.approx(value, rel=5e-6, abs=1e-300), key
    html = (out / "report.html").read_text()
    assert "did not stop within the scenario" in html                # 10 s only
    assert "the WSP safety timer tripped 1 time " in html           # at 7.3 s (the stuck vent)


def test_the_report_embeds_every_plot_and_links_nothing(saved_run):
    out, _ = saved_run
    report = _parse(out / "report.html")
    pngs = sorted(out.glob("*.png"))
    assert len(report.images) == len(pngs) >= 6
    assert report.links == []
    embedded = {base64.b64decode(src.split(",", 1)[1]) for src in report.images}
    assert embedded == {p.read_bytes() for p in pngs}
    assert all(src.startswith("data:image/png;base64,") for src in report.images)


def test_the_report_names_version_build_command_and_date(saved_run):
    out, _ = saved_run
    prov = _parse(out / "report.html").provenance
    assert prov["railbrake_version"] == railbrake.__version__
    assert prov["core_build_hash"] == _core.rb_build_hash().decode()
    assert "fault-vent-valve-stuck.yaml --cars 3" in prov["command_line"]
    assert datetime.fromisoformat(prov["date"]).tzinfo is not None


def test_the_core_build_hash_is_that_of_the_core_sources():
    """The hash CMake computed (core/CMakeLists.txt) from the sources as they are: a stale library fails."""
    core = Path(__file__).resolve().parents[3] / "core"
    files = sorted([*core.glob("src/*.c"), *core.glob("src/*.h"), *core.glob("include/railbrake/*.h")])
    text = "".join(f"{p.relative_to(core)} {hashlib.sha256(p.read_bytes()).hexdigest()}\n" for p in files)
    assert _core.rb_build_hash().decode() == hashlib.sha256(text.encode()).hexdigest()

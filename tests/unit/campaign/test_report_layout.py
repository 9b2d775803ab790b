"""The campaign report a reviewer reads: the verdict (failed assessments) leads, failed cases come
first, the verdict column is on the page on a 1400 px screen and on paper, and long distances are
plain metres. Built from assessed rows in memory (no cluster)."""

import re
import types
from html.parser import HTMLParser

import pytest

from railbrake.campaign import report, study
from railbrake.campaign.assess import assess

STUDY = """schema: railbrake.study/1
name: layout
base: emergency-250-dry
factors:
  initial_speed: ["120 km/h", "350 km/h"]
  adhesion_case:
    - {name: dry, adhesion.condition: dry-medium}
    - {name: low, adhesion.condition: oil-film}
  brake:
    - {name: emergency, demand: [{time: "0 s", emergency: true}]}
    - {name: full-service, demand: [{time: "0 s", service: 1.0}]}
  train.load_case: [tare, normal, crush]
design: {kind: grid}
assessment:
  reference: {adhesion_case: dry}
"""
KPIS = ["stopping_distance_m", "equivalent_response_time_s", "adhesion_utilisation", "air_drawn_kg",
        "min_supply_bar", "max_slip", "wheel_lock_events", "safety_timer_trips", "stopped"]


def _campaign(tmp_path) -> report.Campaign:
    """24 cases of the shape of wsp-en15595; the 350 km/h low-adhesion cases fail the utilisation."""
    s = study.parse(STUDY, "layout.yaml").spec
    rows = []
    for speed in (120 / 3.6, 350 / 3.6):
        for case in ("dry", "low"):
            for brake in ("emergency", "full-service"):
                for load in ("tare", "normal", "crush"):
                    slow, fails = case == "low", case == "low" and speed > 200 / 3.6
                    rows.append({"initial_speed": speed, "adhesion_case": case, "brake": brake,
                                 "train.load_case": load, "status": "ok", "point": len(rows), "replicate": 0, "seed": 1,
                                 "key": f"{len(rows):064x}", "stopping_distance_m": speed ** 2 * (1.4 if slow else 0.6),
                                 "equivalent_response_time_s": 2.0, "adhesion_utilisation": 0.8 if fails else 0.9 if slow else 0.5,
                                 "air_drawn_kg": 5.0, "min_supply_bar": 6.0, "max_slip": 0.1,
                                 "wheel_lock_events": 0, "safety_timer_trips": 0, "stopped": 1.0})
    c = report.Campaign.__new__(report.Campaign)
    c.folder, c.study, c.rows = tmp_path, s, rows
    c.factors = ["initial_speed", "adhesion_case", "brake", "train.load_case"]
    c.units = {"initial_speed": "m/s", "adhesion_case": "", "brake": "", "train.load_case": ""}
    c.manifest = {"railbrake_version": "test", "core_build_hash": "0" * 12}
    c.kinds, c.kpis = {}, KPIS
    c.initial_speed = lambda row: row["initial_speed"]
    c.assessed = lambda: assess(rows, c.factors, s.assessment, c.initial_speed)
    return c


class _Tables(HTMLParser):
    """The text of every table's rows, cell by cell."""

    def __init__(self):
        super().__init__()
        self.tables, self._cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self._cell = ""

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.tables[-1][-1].append(self._cell)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    tmp_path = tmp_path_factory.mktemp("report")
    c = _campaign(tmp_path)
    summary = report.render(c, tmp_path / "report.html")
    page = (tmp_path / "report.html").read_text()
    parser = _Tables()
    parser.feed(page)
    return c, summary, page, (tmp_path / "report.md").read_text(), parser.tables[0]


def test_the_headline_states_the_failed_assessments_before_the_runs(written):
    c, summary, page, md, _ = written
    failed = sum(not case["passed"] for case in c.assessed())
    assert failed == 6 and summary["failed_cases"] == 6 and summary["failed"] == 0
    verdict = f"FAILED: 6 of 24 assessed cases fail; 24 runs, 0 of them failed to run."
    assert report.headline(summary) == verdict
    body = re.sub(r"<[^>]+>", " ", page.split("<body>", 1)[1])
    assert body.index("FAILED: 6 of 24") < body.index("24 runs")      # the verdict leads the page
    assert md.splitlines()[2] == f"**{verdict}**"                       # and the Markdown summary


def test_a_study_whose_cases_all_pass_or_that_has_no_assessment_says_so():
    assert report.headline({"runs": 4, "failed": 0, "cases": 4, "failed_cases": 0}).startswith("PASSED: all 4")
    assert report.headline({"runs": 4, "failed": 1}).startswith("FAILED: 4 runs, 1 of them failed")


def test_failed_cases_come_first_with_the_verdict_in_the_first_column(written):
    _, _, _, _, table = written
    header, rows = table[0], table[1:]
    assert header[0] == "passed"
    verdicts = [row[0] for row in rows]
    assert verdicts == ["no"] * 6 + ["yes"] * 18


def test_long_distances_are_plain_grouped_metres(written):
    _, _, page, md, table = written
    column = table[0].index("s (m)")
    longest = max(table[1:], key=lambda row: float(row[column].replace("\u00a0", "")))[column]
    assert longest == f"{(350 / 3.6) ** 2 * 1.4:,.0f}".replace(",", "\u00a0")     # 13 232 m
    assert "e+0" not in page and "e+0" not in md
    assert report._fmt(13380.4) == "13\u00a0380" and report._fmt(423.04) == "423"
    assert report._fmt(0.0011) == "0.0011" and report._fmt(float("inf")) == "inf"


# Width of a 12 px sans-serif glyph (digits 0.64 em in DejaVu Sans and Arial, wider than the mean
# letter); padding 2 x 4 px and a 1 px border per cell.
GLYPH_PX, CELL_PX = 0.64 * 12, 9


def _narrowest_px(cells, header, glyph=GLYPH_PX):
    """A column's min-content width: its longest word (headers and cells wrap at spaces, headers
    anywhere; a grouped number is one word)."""
    words = [w for text in [header, *cells] for w in text.split()]
    return max(len(w) for w in words) * glyph + CELL_PX


def _widths(table, glyph=GLYPH_PX):
    return [_narrowest_px([row[i] for row in table[1:]], table[0][i], glyph) for i in range(len(table[0]))]


def test_the_verdict_column_is_on_a_1400_px_page_and_the_table_fits_it(written):
    """The verdict is the first column, so it is on the page at any width; and the table's
    min-content width, estimated from its cells' characters, fits the 1400 px body less its margins,
    so the browser's automatic table layout keeps every column on the page (CSS 2.1, 17.5.2.2)."""
    _, _, page, _, table = written
    assert sum(_widths(table)) < 1400 - 2 * 1.5 * 16
    assert "max-width:1400px" in page and ".wide{overflow-x:auto" in page


def test_in_print_the_table_shrinks_to_a_landscape_page(written):
    """On A4 landscape (277 mm less the margins, at 96 px per inch: 1047 px) the 8 px print font keeps
    every column, the verdict first."""
    _, _, page, _, table = written
    assert "@page{size:A4 landscape;margin:10mm}" in page and "@media print{" in page
    assert sum(_widths(table, glyph=0.64 * 8)) < (297 - 20) / 25.4 * 96


def test_a_utilisation_just_below_the_criterion_shows_the_digits_that_fail_it():
    from railbrake.campaign.assess import _below
    assert _below(0.8497, 0.85) == "0.8497" and _below(0.8, 0.85) == "0.800" and _below(0.84999, 0.85) == "0.84999"

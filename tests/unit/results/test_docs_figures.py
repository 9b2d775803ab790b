"""The MIL-against-HIL figures of docs/hil.md are what the code computes: the MIL column is the
MIL run of the current code, the B-A column is what `compare` reports for those two runs, and the
prose quotes that difference. The HIL run itself (paced, 167 s, its gap to MIL varies with the
machine's load: docs/hil.md) is not repeated here; tests/unit/hil/test_hil_outputs.py compares a
short paced MIL/HIL pair end to end."""

import re
from pathlib import Path

import pytest

from railbrake import simulation
from railbrake.resolve import resolve
from railbrake.results import from_simulation
from railbrake.results.compare import kpi_difference

DOCS = Path(__file__).resolve().parents[3] / "docs" / "hil.md"
COMMAND = "$ railbrake compare out/mil8 out/hil8"


def _compare_table() -> dict[str, list[str]]:
    """{KPI: [A, B, B-A]} as printed in the docs' console block of the compare command."""
    text = DOCS.read_text(encoding="utf-8")
    block = text[text.index(COMMAND):]
    block = block[:block.index("```")]
    rows = {}
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip().strip("│").split("│")]
        if len(cells) == 4 and line.startswith("│"):
            rows[cells[0].split(" (")[0]] = cells[1:]
    return rows


def _digits(cell: str) -> float:
    """Half a unit of the last printed digit: the rounding of a printed number."""
    mantissa = cell.lower().split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(cell.lower().split("e")[1]) if "e" in cell.lower() else 0
    return 0.5 * 10.0 ** (exponent - decimals)


@pytest.mark.slow
def test_the_mil_hil_stopping_distance_difference_of_the_docs_is_what_compare_reports():
    rows = _compare_table()
    a, b, shown = rows["stopping_distance_m"]
    resolved = resolve("emergency-300-heavy-rain", 8)
    mil = from_simulation(simulation.run(resolved), resolved.scenario).kpis
    assert float(a) == pytest.approx(mil["stopping_distance_m"], abs=_digits(a))   # the MIL run of this code
    difference = kpi_difference(mil["stopping_distance_m"], float(b))              # what compare computes
    assert float(shown) == pytest.approx(difference, abs=_digits(shown) + _digits(a) + _digits(b))
    prose = re.search(r"The HIL stop is ([\d.]+) m \(([\d.]+) %\) (longer|shorter) than the MIL stop",
                      DOCS.read_text(encoding="utf-8"))
    assert prose, "docs/hil.md no longer states the MIL-HIL difference"
    sign = 1.0 if prose[3] == "longer" else -1.0
    metres, percent = sign * float(prose[1]), sign * float(prose[2])
    assert metres == pytest.approx(difference, abs=0.05 + _digits(a) + _digits(b))
    assert percent == pytest.approx(100 * difference / mil["stopping_distance_m"], abs=0.005 + 1e-4)
    for key in ("stopping_time_s", "adhesion_utilisation", "air_drawn_kg"):   # the other MIL figures quoted
        assert float(rows[key][0]) == pytest.approx(mil[key], abs=_digits(rows[key][0])), key

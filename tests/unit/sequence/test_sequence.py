"""Test sequences (railbrake.sequence/1) against the MIL plant: the shipped wsp-vent-stuck preset
passes with the reference BCU's WSP and fails, naming what failed, without it; its JUnit XML
validates against the common JUnit schema; bad files are refused naming file, line and key."""

import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from railbrake import sequence
from railbrake.errors import InputError
from railbrake.sequence import engine, reports

RAILBRAKE = str(Path(sys.executable).parent / "railbrake")
SCHEMA = etree.XMLSchema(etree.parse(str(Path(__file__).with_name("junit.xsd"))))


def run_cli(*args, cwd):
    return subprocess.run([RAILBRAKE, "sequence", "run", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


def verdicts(junit: Path) -> dict:
    tree = etree.parse(str(junit))
    SCHEMA.assertValid(tree)
    return {case.get("name"): ("fail" if case.find("failure") is not None else
                               "error" if case.find("error") is not None else "pass")
            for case in tree.iter("testcase")}


def test_preset_passes_against_the_reference_bcu(tmp_path):
    done = run_cli("wsp-vent-stuck", "--junit", "out.xml", "--html", "out.html", cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    cases = verdicts(tmp_path / "out.xml")
    expectations = [name for name in cases if ": expect " in name]
    assert len(expectations) >= 3 and all(cases[name] == "pass" for name in cases)
    for words in ("slip", "safety timer", "stops"):
        assert any(words in name for name in expectations), (words, expectations)
    page = (tmp_path / "out.html").read_text()
    assert page.count("data:image/png;base64,") >= 3 and "PASS" in page


def test_preset_fails_clearly_without_wsp(tmp_path):
    done = run_cli("wsp-vent-stuck", "--junit", "out.xml", "--set", "wsp.enabled=false", cwd=tmp_path)
    assert done.returncode == 1
    tree = etree.parse(str(tmp_path / "out.xml"))
    SCHEMA.assertValid(tree)
    failures = {f.getparent().get("name"): f.get("message") for f in tree.iter("failure")}
    slip = next(m for n, m in failures.items() if "slip" in n)
    assert "slip_* at most 0.3" in slip and "slip_* = 1 at t =" in slip   # a wheel locked: slip 1
    assert any("wheel_lock_events = " in m for m in failures.values())
    assert "FAIL" in done.stdout


def test_junit_counts_match_the_verdicts():
    seq = sequence.load("wsp-vent-stuck")
    results = engine.run(seq, ["wsp.enabled=false"])
    root = etree.fromstring(reports.junit_xml(seq, results, "MIL").encode())
    SCHEMA.assertValid(root)
    steps = [s for r in results for s in r.steps]
    assert int(root.get("tests")) == len(steps)
    assert int(root.get("failures")) == sum(s.verdict == "fail" for s in steps) > 0
    assert results[0].verdict == "fail"


GOOD = """format: railbrake.sequence/1
name: t
scenario: emergency-250-dry
cars: 1
tests:
  - name: a
    steps:
      - set_demand: {emergency: true}
      - wait: 1 s
"""


@pytest.mark.parametrize("change, words", [
    (("format: railbrake.sequence/1", "format: railbrake.sequence/2"), ["line 1", "format"]),
    (("      - wait: 1 s", "      - wait: 1 s\n        expect: {kpi: max_slip, below: 1}"), ["line 9", "2 actions"]),
    (("      - wait: 1 s", "      - wait: 1 furlong"), ["line 9", "steps.1.wait", "'1 furlong'", "s, ms"]),
    (("      - wait: 1 s", "      - expect: {signal: slipz_*, below: 0.2}"), ["line 9", "signal", "slipz_*"]),
    (("      - wait: 1 s", "      - expect: {signal: speed, below: 0.2}"), ["line 9", "below", "km/h"]),
    (("      - wait: 1 s", "      - inject: {type: vent_on_fire, car: 1}"), ["line 9", "fault.type"]),
    (("      - wait: 1 s", "      - inject: {type: vent_stuck_open, car: 2}"), ["line 9", "cars 1..1"]),
    (("      - wait: 1 s", "      - clear: {type: sensor_noisy, car: 1, noise: 1 m/s}"), ["line 9", "noise"]),
    (("      - wait: 1 s", "      - inject: {type: relay_valve_failed, car: 1}"),
     ["line 9", "needs pressure", "must lie in [0, 10] bar"]),
    (("      - wait: 1 s", "      - inject: {type: pressure_limiter_failed, car: 1, pressure: 20 bar}"),
     ["line 9", "fault.pressure", "'20 bar'", "must lie in [0, 10] bar"]),
    (("      - wait: 1 s", "      - inject: {type: emergency_loop_lost, car: 1, axle: 2}"), ["line 9", "remove axle"]),
    (("      - wait: 1 s", "      - wait: {until: {signal: speed, below: 1 m/s}}"), ["line 9", "timeout"]),
    (("      - wait: 1 s", "      - set_adhesion: marmalade"), ["line 9", "marmalade"]),
    (("      - wait: 1 s", "      - teleport: 3 km"), ["line 9", "teleport"]),
    (("      - wait: 1 s", "      - wait: \u0661 s"), ["line 9", "steps.1.wait", "ASCII"]),   # Arabic-Indic 1
    (("      - wait: 1 s", "      - wait: \u0968.5 s"), ["line 9", "steps.1.wait", "ASCII"]),   # Devanagari 2
])
def test_bad_sequence_files_are_refused_with_file_line_and_key(tmp_path, change, words):
    path = tmp_path / "bad.yaml"
    path.write_text(GOOD.replace(*change))
    with pytest.raises(InputError) as caught:
        engine.check(sequence.load(path), engine.resolve("emergency-250-dry", 1))
    message = str(caught.value)
    assert str(path) in message and all(w in message for w in words), message


def test_a_relay_valve_failed_at_a_pressure_holds_the_cylinders_there(tmp_path):
    """A fault of the emergency path injected by a test step with its pressure (gauge, as in a
    scenario file): the emergency fills the cylinders to that pressure and no further; cleared, the
    relay follows its control chamber (filled meanwhile) again."""
    path = tmp_path / "relay.yaml"
    path.write_text(GOOD.replace("      - set_demand: {emergency: true}\n      - wait: 1 s\n", """\
      - inject: {type: relay_valve_failed, car: 1, pressure: 1.2 bar}
      - set_demand: {emergency: true}
      - expect: {signal: "cylinder_c1a*", at_most: 1.22 bar, during: 4 s}
      - expect: {signal: "cylinder_c1a*", at_least: 1.18 bar}
      - kpi: {name: stuck, signal: cylinder_c1a1, stat: final}
      - clear: {type: relay_valve_failed, car: 1}
      - wait: 3 s
      - kpi: {name: cylinder, signal: cylinder_c1a1, stat: final}
      - kpi: {name: pilot, signal: pilot_c1, stat: final}
"""))
    result = engine.run(sequence.load(path))[0]
    assert [step.verdict for step in result.steps if step.action == "expect"] == ["pass"] * 2, result.steps
    kpis = result.kpis   # Pa
    assert kpis["pilot"] > kpis["stuck"] + 0.2e5   # the control chamber filled above the stuck output
    assert kpis["cylinder"] == pytest.approx(kpis["pilot"], abs=0.02e5)

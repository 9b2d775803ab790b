"""A sequence run against the paced HIL loop and the reference BCU process (`railbrake sequence run
--bcu`): faults injected and cleared through the loop's mailbox, expectations judged on the
recorded rows (plant time, not wall time), the verdicts in the JUnit XML."""

import subprocess
import xml.etree.ElementTree as ET

from conftest import SECRET

SEQUENCE = """format: railbrake.sequence/1
name: short-hil
scenario: emergency-300-heavy-rain
cars: 1
tests:
  - name: vent-stuck
    steps:
      - set_demand: {emergency: true}
      - wait: 1 s
      - inject: {type: vent_stuck_open, car: 1, axle: 2}
      - expect: {name: the stuck vent empties its cylinder, signal: cylinder_c1a2, below: 0.2 bar, within: 1 s}
      - wait: {at: 2.5 s}
      - clear: {type: vent_stuck_open, car: 1, axle: 2}
      - expect: {name: the cylinder refills, signal: cylinder_c1a2, above: 0.5 bar, within: 2 s}
"""


def test_sequence_against_the_hil_loop_and_the_reference_bcu(bcu_process, railbrake_cli, hil_key, tmp_path):
    _, port = bcu_process("emergency-300-heavy-rain", "--cars", "1", "--idle-timeout", "5")
    (tmp_path / "short.yaml").write_text(SEQUENCE)
    done = subprocess.run([railbrake_cli, "sequence", "run", "short.yaml", "--bcu", f"udp://127.0.0.1:{port}",
                           "--key", str(hil_key), "--junit", "out.xml"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    root = ET.parse(tmp_path / "out.xml").getroot()
    assert root.get("failures") == "0" and root.get("errors") == "0" and root.get("tests") == "7"
    mode = {p.get("name"): p.get("value") for p in root.iter("property")}["mode"]
    assert mode == f"HIL against udp://127.0.0.1:{port}"
    outputs = [case.findtext("system-out") for case in root.iter("testcase")]
    assert "vent_stuck_open on car 1, axle 2: injected at t = " in outputs[2]
    assert "vent_stuck_open on car 1, axle 2: cleared at t = " in outputs[5]


def test_a_demand_other_than_the_bcus_is_refused_in_hil(tmp_path):
    """No BCU needed: the plant runs in the safe state; the step errs naming the BCU's demand."""
    from railbrake import sequence
    from railbrake.sequence import engine
    (tmp_path / "s.yaml").write_text(SEQUENCE.replace("{emergency: true}", "{service: 0.5}"))
    results = engine.run(sequence.load(tmp_path / "s.yaml"), bcu=("127.0.0.1", 9), key=SECRET)
    step = results[0].steps[0]
    assert step.verdict == "error" and "the demand is the BCU's" in step.message and "emergency" in step.message
    assert len(results[0].steps) == 1   # an error ends the test

"""`railbrake hil` and `railbrake bcu`: bad addresses and values are one-line errors (exit code 2);
a BCU with a duration stops on its own. The paced runs themselves: tests/unit/hil/."""

import json

import pytest
from typer.testing import CliRunner

from railbrake.cli import app


@pytest.mark.parametrize("args, words", [
    (["hil", "--bcu", "tcp://127.0.0.1:5000"], "--bcu = 'tcp://127.0.0.1:5000': expected udp://HOST:PORT"),
    (["hil", "--bcu", "udp://127.0.0.1:0"], "port = '0': must lie in [1, 65535]"),
    (["hil", "--bcu", "udp://bad host:5000"], "host = 'bad host'"),
    (["hil", "--bcu", "udp://127.0.0.1:5000", "--duration", "-1"], "--duration = -1.0: must be > 0 s"),
    (["hil", "--bcu", "udp://127.0.0.1:5000", "--hold-time", "-0.5", "--priority", "0"],
     "hold_time = -0.5"),
    (["hil", "--bcu", "udp://127.0.0.1:5000", "--cars", "40"], "cars"),
    (["hil", "--bcu", "udp://127.0.0.1:9", "--record-interval", "0.0015"],
     "record_interval = 0.0015 s: must be a multiple of 1 ms"),
    (["bcu", "--listen", "udp://127.0.0.1:99999"], "port = '99999': must lie in [0, 65535]"),
    (["bcu", "--listen", "udp://127.0.0.1:0", "--idle-timeout", "-1"], "idle_timeout = -1.0"),
])
def test_bad_input_is_a_one_line_error(args, words):
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2
    assert words in result.output


def test_hil_without_a_bcu_runs_in_the_safe_state_and_says_so():
    result = CliRunner().invoke(app, ["hil", "emergency-250-dry", "--cars", "1", "--bcu", "udp://127.0.0.1:9",
                                      "--duration", "0.1", "--priority", "0", "--json"])
    assert result.exit_code == 0, result.output
    assert "no frame came from the BCU at udp://127.0.0.1:9" in result.output
    report = json.loads(result.output[result.output.index("{"):])
    assert report["counters"]["safe_state_steps"] == report["counters"]["steps"] == 100
    assert report["kpis"]["stopping_distance_m"] is None  # cut short by --duration: not stopped
    assert report["kpis"]["braked_distance_m"] > 0        # the safe state brakes
    assert report["kpis"]["min_supply_bar"] > 7.0


def test_bcu_stops_after_its_duration_without_a_plant():
    result = CliRunner().invoke(app, ["bcu", "emergency-250-dry", "--cars", "1", "--listen", "udp://127.0.0.1:0",
                                      "--duration", "0.3", "--priority", "0", "--json"])
    assert result.exit_code == 0, result.output
    first, rest = result.output.split("\n", 1)
    assert first.startswith("listening on udp://127.0.0.1:")
    assert json.loads(rest) == {"received": 0, "malformed": 0, "stale": 0, "sent": 0, "send_errors": 0, "cycles": 0,
                                "foreign": 0, "refused": 0}

"""`railbrake hil` and `railbrake bcu`: bad addresses and values are one-line errors (exit code 2);
a BCU with a duration stops on its own. The paced runs themselves: tests/unit/hil/."""

import json
import os
import tempfile
from pathlib import Path

import pytest
from typer.testing import CliRunner

from railbrake.cli import app
from railbrake.hil.keys import write_key

KEY = str(write_key(Path(tempfile.mkdtemp(prefix="railbrake-cli-key-")) / "hil.key"))


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
    (["hil", "--bcu", "udp://127.0.0.1:9", "--cars", "1", "--priority", "0", "--duration", "0.05", "--cpu", "4096"],
     "cpu = 4096: must be one of this process's CPUs"),
    (["bcu", "--listen", "udp://127.0.0.1:99999"], "port = '99999': must lie in [0, 65535]"),
    (["bcu", "--listen", "udp://127.0.0.1:0", "--idle-timeout", "-1"], "idle_timeout = -1.0"),
])
def test_bad_input_is_a_one_line_error(args, words):
    result = CliRunner().invoke(app, [*args, "--key", KEY])
    assert result.exit_code == 2
    assert words in result.output


def test_hil_without_a_bcu_runs_in_the_safe_state_and_says_so():
    result = CliRunner().invoke(app, ["hil", "emergency-250-dry", "--cars", "1", "--bcu", "udp://127.0.0.1:9",
                                      "--duration", "0.3", "--priority", "0", "--json", "--key", KEY])
    assert result.exit_code == 3, result.output   # the BCU lost (never answered): docs/hil.md
    assert "no frame came from the BCU at udp://127.0.0.1:9" in result.output
    assert "BCU lost at t = 0.101 s (no valid frame from it before)" in " ".join(result.output.split())
    report = json.loads(result.output[result.output.index("{"):result.output.rindex("}") + 1])
    loss = report["bcu_loss"]   # lost once the hold time (0.1 s) passed without a frame
    assert loss["lost"] and loss["at_s"] == 0.101 and loss["safe_s"] == pytest.approx(0.199)
    assert 0 < loss["distance_m"] < report["kpis"]["braked_distance_m"]
    assert report["counters"]["safe_state_steps"] == report["counters"]["steps"] == 300
    assert report["kpis"]["stopping_distance_m"] is None  # cut short by --duration: not stopped
    assert report["kpis"]["braked_distance_m"] > 0        # the safe state brakes
    assert report["kpis"]["min_supply_bar"] > 7.0


def test_bcu_stops_after_its_duration_without_a_plant():
    result = CliRunner().invoke(app, ["bcu", "emergency-250-dry", "--cars", "1", "--listen", "udp://127.0.0.1:0",
                                      "--duration", "0.3", "--priority", "0", "--json", "--key", KEY])
    assert result.exit_code == 0, result.output
    first, rest = result.output.split("\n", 1)
    assert first.startswith("listening on udp://127.0.0.1:")
    assert json.loads(rest) == {"received": 0, "malformed": 0, "stale": 0, "sent": 0, "send_errors": 0, "cycles": 0,
                                "foreign": 0, "refused": 0, "forged": 0, "challenges": 0}


@pytest.mark.parametrize("content, mode, words", [
    ("00" * 16 + "\n", 0o644, "mode 0644 lets others read it: chmod 600"),
    ("00" * 15 + "\n", 0o600, "line 1: 30 characters: expected 32 hexadecimal digits"),
    ("# comment\n" + "zz" * 16 + "\n", 0o600, "line 2: 32 characters: expected 32 hexadecimal digits"),
    ("# only a comment\n", 0o600, "0 key lines"),
    ("00" * 16 + "\n", 0o600, "line 1: every byte the same (0x00 repeated): too little entropy"),
    ("# a comment\n" + "ab" * 16 + "\n", 0o600, "line 2: every byte the same (0xab repeated)"),
    ("0102" * 8 + "\n", 0o600, "line 1: only 2 distinct byte values: too little entropy"),
    ("000102030405060708090a0b0c0d0e0f\n", 0o600, "line 1: bytes counting up or down by a constant step"),
])
def test_bad_key_files_are_refused_naming_file_and_line(tmp_path, content, mode, words):
    key = tmp_path / "bad.key"
    key.write_text(content)
    key.chmod(mode)
    result = CliRunner().invoke(app, ["bcu", "--listen", "udp://127.0.0.1:0", "--key", str(key)])
    assert result.exit_code == 2 and f"key file {key}" in result.output and words in result.output


@pytest.mark.parametrize("where", ["directory", "missing"])
def test_a_key_path_that_is_no_file_is_named(tmp_path, where):
    key = tmp_path / "keys" if where == "directory" else tmp_path / "none.key"
    if where == "directory":
        key.mkdir()
    words = {"directory": "a directory: give the path of the key file", "missing": "No such file or directory"}
    for command in (["bcu", "--listen", "udp://127.0.0.1:0"],
                    ["hil", "--bcu", "udp://127.0.0.1:9", "--cars", "1", "--duration", "0.05", "--priority", "0"]):
        result = CliRunner().invoke(app, [*command, "--key", str(key)])
        text = " ".join(result.output.split())
        assert result.exit_code == 2 and f"key file {key}: {words[where]}" in text, result.output


def test_weak_key_bytes_are_refused_by_the_api():
    from railbrake.errors import InputError
    from railbrake.hil.keys import key_bytes
    for weak in (bytes(16), b"\x5a" * 16, bytes(range(16))):
        with pytest.raises(InputError, match="key: .*too little entropy"):
            key_bytes(weak)
    assert key_bytes(bytes.fromhex("9f3c01d2e47a5b68c0ffee1234abcd77")) == bytes.fromhex("9f3c01d2e47a5b68c0ffee1234abcd77")


def test_hil_key_makes_a_private_key_and_never_overwrites(tmp_path):
    key = tmp_path / "new.key"
    assert CliRunner().invoke(app, ["hil-key", str(key)]).exit_code == 0
    assert key.stat().st_mode & 0o777 == 0o600
    again = CliRunner().invoke(app, ["hil-key", str(key)])
    assert again.exit_code == 2 and "exists" in again.output


@pytest.mark.parametrize("cpu", [[], ["--cpu", "1"]])
def test_hil_with_a_dashboard_says_how_to_give_the_loop_its_own_cpu(cpu):
    if cpu and len(os.sched_getaffinity(0)) < 2:
        pytest.skip("needs two CPUs")
    result = CliRunner().invoke(app, ["hil", "emergency-250-dry", "--cars", "1", "--bcu", "udp://127.0.0.1:9",
                                      "--duration", "0.2", "--priority", "0", "--dashboard", "0", "--key", KEY,
                                      *cpu])
    assert result.exit_code == 3, result.output   # no BCU: lost, as above
    text = " ".join(result.output.split())
    assert "dashboard on http://127.0.0.1:" in text
    assert ("--cpu N gives the loop one to itself" in text) is not bool(cpu)

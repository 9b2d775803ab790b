"""An FMU export is reproducible: two exports of one configuration are the same bytes (no debug
information holding the build's temporary paths, no build id, zip entries dated by the generation
time, a generationDateAndTime that is not the clock's), and an export built without the portable
toolchain (zig, the `fmu` extra) says what its binary needs."""

import hashlib
import os
import shutil
import subprocess
import zipfile

import pytest
from typer.testing import CliRunner

from railbrake.cli import app
from railbrake.fmu import binaries
from railbrake.fmu.export import export_fmu


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.slow
def test_two_exports_of_one_configuration_are_the_same_bytes(tmp_path):
    first = export_fmu("emergency-250-dry", tmp_path / "a" / "plant.fmu", "2", 1)
    second = export_fmu("emergency-250-dry", tmp_path / "b" / "plant.fmu", "2", 1)
    assert sha256(first) == sha256(second)
    with zipfile.ZipFile(first) as zf:
        dates = {info.date_time for info in zf.infolist()}
        binary = next(n for n in zf.namelist() if n.startswith("binaries/linux64/"))
        zf.extract(binary, tmp_path / "x")
    assert len(dates) == 1
    if shutil.which("readelf"):
        sections = subprocess.run(["readelf", "-S", str(tmp_path / "x" / binary)], capture_output=True,
                                  text=True).stdout
        assert ".debug_info" not in sections and ".note.gnu.build-id" not in sections
    assert b"/tmp" not in (tmp_path / "x" / binary).read_bytes()


def test_source_date_epoch_dates_the_fmu(monkeypatch):
    from railbrake.fmu.description import generation_time
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    assert generation_time().timestamp() == 1700000000


@pytest.mark.skipif(shutil.which(os.environ.get("CC", "cc")) is None, reason="no system C compiler")
def test_an_export_without_zig_says_what_its_binary_needs(tmp_path, monkeypatch):
    monkeypatch.setattr(binaries, "have_zig", lambda: False)
    out = CliRunner().invoke(app, ["export-fmu", "emergency-250-dry", "--cars", "1",
                                      "-o", str(tmp_path / "p.fmu")])
    assert out.exit_code == 0, out.output
    assert "note: the linux64 binary was built with the system C compiler" in out.stderr
    assert "it needs glibc 2." in out.stderr and "glibc 2.17" in out.stderr

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
REFERENCE = REPO.parent / "shared" / "reference"


@pytest.fixture(scope="session")
def reference_dir() -> Path:
    """shared/reference beside the repository (published data with sources)."""
    assert REFERENCE.is_dir(), f"{REFERENCE} is missing: the reference data sit beside the repo"
    return REFERENCE


def pytest_report_header(config):
    from railbrake import _core
    return f"railbrake C core: {_core.lib._name}"

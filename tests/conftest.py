from pathlib import Path


REPO = Path(__file__).resolve().parents[1]


def pytest_report_header(config):
    from railbrake import _core
    return f"railbrake C core: {_core.lib._name}"
